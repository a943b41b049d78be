"""Contact area, contact radius and pile-up of a spherical indenter from atom positions.

LAMMPS's ``fix indent`` sphere pushes every atom closer than R to its centre with the force
F(r) = -K (r - R)^2 (LAMMPS documentation, ``fix indent``); it has no atoms, so the contact is
read off the film's atoms: those within R + tolerance of the centre. Their lateral convex hull
gives the projected contact area A, the quantity that nanoindentation analysis needs
(Oliver & Pharr, J. Mater. Res. 7 (1992) 1564: H = P / A, E_r = sqrt(pi) S / (2 sqrt(A))).

`contact_geometry` is the pure per-frame computation in whatever length unit the caller uses
(the md code passes Angstrom, LAMMPS ``metal`` units). `ContactAnalysis` runs it over the
frames of an MDAnalysis trajectory and reports SI results; `read_dumps` opens LAMMPS dump
files as such a trajectory.
"""

from __future__ import annotations

import math
import os
import warnings
from collections.abc import Callable, Iterable, Sequence
from dataclasses import asdict, dataclass

import MDAnalysis as mda
import numpy as np
from MDAnalysis.analysis.base import AnalysisBase
from MDAnalysis.coordinates.LAMMPS import DumpReader
from MDAnalysis.lib.util import anyopen
from scipy.spatial import ConvexHull, QhullError

from filmscale.core.checks import check_path, check_positive, check_real
from filmscale.core.errors import InputError
from filmscale.core.files import excerpt

from .lammps_units import si_to_lammps, lammps_to_si

#: default contact tolerance of `contact_geometry`, in the caller's length unit: meant for
#: Angstrom (0.5 A); `ContactAnalysis` takes it in metres (0.5e-10 m)
DEFAULT_TOLERANCE = 0.5
#: default outer radius of the pile-up ring, in units of the contact radius radius_max
DEFAULT_PILE_UP_RING = 3.0
#: ``ts.data`` key under which `read_dumps` stores each frame's box corner (xlo, ylo, zlo), A
ORIGIN_KEY = "lammps_origin"


@dataclass(frozen=True)
class ContactFrame:
    """Contact of a spherical indenter with the atoms of one frame.

    Every length is in the caller's length unit L (Angstrom when called from the md code),
    areas in L^2.
    """

    n_contact: int        #: number of atoms within radius + tolerance of the indenter centre
    area_hull: float      #: projected (xy) area of the convex hull of the contact atoms, L^2
    radius_hull: float    #: equivalent contact radius sqrt(area_hull / pi), L
    radius_max: float     #: largest lateral distance of a contact atom from the axis, L
    depth: float          #: penetration of the sphere's apex below surface_z, L (< 0: above)
    pile_up: float        #: height of the highest atom around the contact above surface_z, L

    def to_dict(self) -> dict:
        return {k: (int(v) if k == "n_contact" else float(v)) for k, v in asdict(self).items()}


def contact_geometry(positions, center, radius, surface_z, *, box_xy=None,
                     tolerance: float = DEFAULT_TOLERANCE,
                     pile_up_ring: float = DEFAULT_PILE_UP_RING) -> ContactFrame:
    """Contact area, contact radius, depth and pile-up of a spherical indenter in one frame.

    All lengths share one unit L chosen by the caller (the md code uses Angstrom); areas come
    back in L^2. The indenter axis is the vertical line through `center`; z points up, out of
    the film.

    Parameters
    ----------
    positions : array_like, shape (n, 3)
        Atom positions, L.
    center : array_like, shape (3,)
        Centre of the spherical indenter, L.
    radius : float
        Indenter radius R, L.
    surface_z : float
        Height of the undeformed free surface, L: the reference for `depth` and `pile_up`.
    box_xy : (float, float), optional
        Periodic box lengths (L_x, L_y), L. When given, lateral distances from the axis use
        the minimum image, so a contact that straddles the periodic boundary is whole. None:
        no lateral periodicity. z is never periodic.
    tolerance : float
        Contact tolerance delta, L (default 0.5, meant for Angstrom): an atom is in contact
        when its distance r from the centre satisfies r < R + delta. ``fix indent`` repels
        only for r < R, so an atom pressed by the indenter sits at r < R on average, but at
        room temperature it vibrates by about 0.1 A rms in a metal, and the contact edge is
        where the surface leaves the sphere gradually; delta = 0.5 A (about a fifth of a
        metal's nearest-neighbour distance, 2.5-2.9 A) keeps these atoms while staying well
        below the spacing of the next surface atoms. It biases the contact edge outwards:
        where a flat surface meets the sphere, the apparent contact radius grows from
        sqrt(2 R d - d^2) to sqrt((R + delta)^2 - (R - d)^2) at depth d, i.e. by about
        R delta / a; pass a smaller delta for a cold, relaxed configuration.
    pile_up_ring : float
        Outer radius of the pile-up ring in units of `radius_max` (default 3).

    Returns
    -------
    ContactFrame
        - ``n_contact``: atoms with r < R + delta.
        - ``area_hull``: area of the convex hull of the contact atoms' (x, y) positions
          relative to the axis; 0 for fewer than 3 atoms or collinear atoms. A hull of
          discrete atoms underestimates the continuum area by a band of about one atomic
          spacing at the edge.
        - ``radius_hull`` = sqrt(area_hull / pi); ``radius_max``: largest lateral distance
          rho = sqrt(dx^2 + dy^2) of a contact atom from the axis (0 without contact).
        - ``depth`` = surface_z - (center_z - R), the penetration of the apex below the
          reference surface (negative while the sphere is above it).
        - ``pile_up``: among the atoms outside the contact laterally, in the ring
          radius_max + delta < rho <= pile_up_ring * radius_max, the height of the highest
          one above surface_z, or 0 when none rises above it (or there is no contact). The
          highest atom of the ring is a surface atom unless atoms have left the film;
          select the film's atoms to exclude sputtered ones.

    Raises
    ------
    InputError
        A malformed array or a parameter outside its range.
    """
    pos = _as_array("positions", positions, (None, 3))
    c = _as_array("center", center, (3,))
    R = check_positive("radius", radius)
    z0 = check_real("surface_z", surface_z)
    tol = check_real("tolerance", tolerance, low=0.0)
    ring = check_real("pile_up_ring", pile_up_ring, low=1.0, high=math.inf, high_open=True)

    d = pos - c
    if box_xy is not None:
        L = _as_array("box_xy", box_xy, (2,))
        if np.any(L <= 0):
            raise InputError(f"box_xy = {tuple(L.tolist())} must be two positive box lengths")
        d[:, :2] -= L * np.round(d[:, :2] / L)
    r = np.sqrt(np.einsum("ij,ij->i", d, d))
    rho = np.hypot(d[:, 0], d[:, 1])
    contact = r < R + tol
    n = int(np.count_nonzero(contact))
    depth = z0 - (c[2] - R)
    if n == 0:
        return ContactFrame(n_contact=0, area_hull=0.0, radius_hull=0.0, radius_max=0.0,
                            depth=float(depth), pile_up=0.0)

    area = _hull_area(d[contact, :2])
    rho_max = float(rho[contact].max())
    in_ring = (rho > rho_max + tol) & (rho <= ring * rho_max)
    pile_up = 0.0
    if np.any(in_ring):
        pile_up = max(0.0, float(pos[in_ring, 2].max() - z0))
    return ContactFrame(n_contact=n, area_hull=area, radius_hull=math.sqrt(area / math.pi),
                        radius_max=rho_max, depth=float(depth), pile_up=pile_up)


def _hull_area(xy: np.ndarray) -> float:
    if len(xy) < 3:
        return 0.0
    try:
        return float(ConvexHull(xy).volume)      # in 2-D, "volume" is the area
    except QhullError:                           # collinear (flat initial simplex)
        return 0.0


def _as_array(name: str, values, shape: tuple) -> np.ndarray:
    if isinstance(values, str):
        raise InputError(f"{name} must be an array of numbers, got {values!r}")
    try:
        arr = np.array(values, dtype=float)       # a copy: callers' arrays stay untouched
    except (TypeError, ValueError):
        raise InputError(f"{name} must be an array of numbers") from None
    if arr.ndim != len(shape) or any(s is not None and s != t for s, t in zip(shape, arr.shape)):
        want = "(" + ", ".join("n" if s is None else str(s) for s in shape) + ")"
        raise InputError(f"{name} must have shape {want}, got {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise InputError(f"{name} contains non-finite values")
    return arr


_RAW_DUMP_MESSAGE = ("this LAMMPS dump was opened without read_dumps: MDAnalysis moves dump "
                     "coordinates by the box's lower corner, so the indenter centre and "
                     "surface height would not match them; open it with "
                     "filmscale.md.contact.read_dumps")

#: per-frame result arrays of `ContactAnalysis` and their dimension in `units.METAL`
_RESULT_DIMENSIONS = {"depth": "length", "area": "area", "radius": "length",
                      "radius_max": "length", "pile_up": "length"}


class ContactAnalysis(AnalysisBase):
    """Contact area, radius, depth and pile-up of a ``fix indent`` sphere over a trajectory.

    Inputs are SI (m); `contact_geometry` runs on each frame in Angstrom (positions as
    MDAnalysis reads a LAMMPS ``metal`` dump) and the results come back in SI.

    Parameters
    ----------
    atomgroup : MDAnalysis.AtomGroup
        The film's atoms (all atoms of a dump, or a selection that leaves out, e.g., a rigid
        base layer or sputtered atoms).
    radius : float
        Indenter radius R, m.
    center_xy : (float, float)
        Lateral position of the indenter axis, m (LAMMPS coordinates, converted).
    center_z : float or callable
        Height of the indenter centre, m: a constant, or ``center_z(step) -> float`` of the
        LAMMPS timestep ``step`` (an int) for an indenter that moves, e.g.
        ``lambda step: z_start - v * step * dt`` with everything in SI.
    surface_z : float
        Height of the undeformed free surface, m.
    tolerance : float
        Contact tolerance delta, m (default 0.5e-10 m = 0.5 A); see `contact_geometry`.
    pile_up_ring : float
        Outer radius of the pile-up ring in units of the contact radius (default 3).
    periodic_xy : bool
        Use each frame's box lengths for minimum-image lateral distances (default True, as
        for the ``pp pp`` boundaries of an indentation cell); the box must be orthogonal.
    **kwargs
        Passed to `MDAnalysis.analysis.base.AnalysisBase` (``verbose``).

    Notes
    -----
    The LAMMPS timestep of a frame is ``ts.data["step"]``: MDAnalysis's LAMMPS dump reader
    (``DumpReader``, MDAnalysis 2.11) stores the number under ``ITEM: TIMESTEP`` there, and
    ``ts.data["time"] = step * dt`` (ps). ``ts.frame`` is only the frame index in the
    (chained) trajectory. For a trajectory without a LAMMPS step the frame index stands in
    for ``results.step``, and a callable `center_z` is refused.

    The same reader moves every position by the box's lower corner, x_MDA = x_LAMMPS - xlo
    (and likewise y, z), and ``ss`` (shrink-wrapped) z bounds move that corner from frame to
    frame. `center_xy`, `center_z` and `surface_z` are LAMMPS coordinates, as in the LAMMPS
    input; they are moved by each frame's corner, which `read_dumps` records in
    ``ts.data["lammps_origin"]``. A dump opened otherwise is refused.

    After ``run()``, ``results`` holds one entry per analysed frame (NumPy arrays):
    ``step`` (LAMMPS timestep), ``depth`` (m), ``n_contact``, ``area`` (hull area, m^2),
    ``radius`` (sqrt(area/pi), m), ``radius_max`` (m), ``pile_up`` (m).
    """

    def __init__(self, atomgroup, *, radius, center_xy,
                 center_z: float | Callable[[int], float], surface_z,
                 tolerance=DEFAULT_TOLERANCE * 1e-10, pile_up_ring=DEFAULT_PILE_UP_RING,
                 periodic_xy: bool = True, **kwargs):
        if not hasattr(atomgroup, "universe") or not hasattr(atomgroup, "positions"):
            raise InputError(f"atomgroup must be an MDAnalysis AtomGroup, got "
                             f"{type(atomgroup).__name__}")
        super().__init__(atomgroup.universe.trajectory, **kwargs)
        self._ag = atomgroup
        self._radius = si_to_lammps(check_positive("radius", radius, unit="m"), "length")
        xy = _as_array("center_xy", center_xy, (2,))
        self._center_xy = si_to_lammps(xy, "length")
        self._surface_z = si_to_lammps(check_real("surface_z", surface_z, unit="m"), "length")
        self._tolerance = si_to_lammps(check_real("tolerance", tolerance, low=0.0, unit="m"),
                                  "length")
        self._pile_up_ring = check_real("pile_up_ring", pile_up_ring, low=1.0,
                                        high=math.inf, high_open=True)
        if callable(center_z):
            self._center_z = center_z
        else:
            z = check_real("center_z", center_z, unit="m")
            self._center_z = lambda step: z
        self._center_z_is_callable = callable(center_z)
        self._periodic_xy = bool(periodic_xy)
        readers = getattr(self._trajectory, "readers", [self._trajectory])
        self._raw_dump = any(isinstance(r, DumpReader) for r in readers)
        if self._raw_dump and not any(isinstance(t, _RecordOrigin)
                                      for t in getattr(self._trajectory, "transformations", ())):
            raise InputError(_RAW_DUMP_MESSAGE)

    def _prepare(self):
        self._step = np.zeros(self.n_frames, dtype=np.int64)
        self._n_contact = np.zeros(self.n_frames, dtype=np.int64)
        self._metal = {k: np.full(self.n_frames, np.nan) for k in _RESULT_DIMENSIONS}

    def _single_frame(self):
        ts = self._ts
        step = ts.data.get("step")
        if step is None:
            if self._center_z_is_callable:
                raise InputError("center_z is a function of the LAMMPS timestep, but this "
                                 "trajectory carries none (ts.data['step']); read a LAMMPS "
                                 "dump or pass a constant center_z")
            step = ts.frame
        origin = ts.data.get(ORIGIN_KEY)
        if origin is None:
            if self._raw_dump:
                raise InputError(_RAW_DUMP_MESSAGE)
            origin = np.zeros(3)
        z_c = check_real(f"center_z({step})", self._center_z(int(step)), unit="m")
        # inputs are LAMMPS coordinates; MDAnalysis positions are relative to the box corner
        center = np.array([*self._center_xy, si_to_lammps(z_c, "length")]) - origin
        frame = contact_geometry(np.asarray(self._ag.positions, dtype=float), center,
                                 self._radius, self._surface_z - origin[2],
                                 box_xy=self._box_xy(ts), tolerance=self._tolerance,
                                 pile_up_ring=self._pile_up_ring)
        i = self._frame_index
        self._step[i] = int(step)
        self._n_contact[i] = frame.n_contact
        for key, value in (("depth", frame.depth), ("area", frame.area_hull),
                           ("radius", frame.radius_hull), ("radius_max", frame.radius_max),
                           ("pile_up", frame.pile_up)):
            self._metal[key][i] = value

    def _box_xy(self, ts):
        if not self._periodic_xy:
            return None
        dims = ts.dimensions
        if dims is None or not np.all(dims[:2] > 0):
            raise InputError(f"periodic_xy needs the box of frame {ts.frame}, which has none; "
                             f"pass periodic_xy=False")
        if not np.allclose(dims[3:], 90.0):
            raise InputError(f"periodic_xy needs an orthogonal box; frame {ts.frame} has "
                             f"angles {tuple(float(a) for a in dims[3:])}")
        return (float(dims[0]), float(dims[1]))

    def _conclude(self):
        self.results.step = self._step
        self.results.n_contact = self._n_contact
        for key, dim in _RESULT_DIMENSIONS.items():
            self.results[key] = lammps_to_si(self._metal[key], dim)


def read_dumps(paths: str | os.PathLike | Sequence[str | os.PathLike], *, dt=None,
               additional_columns=None) -> mda.Universe:
    """Open one or several LAMMPS dump files as one MDAnalysis Universe.

    Parameters
    ----------
    paths : path or sequence of paths
        LAMMPS ``dump custom`` text files (optionally gzip or bzip2 compressed) with columns
        ``id type x y z`` and any extra ones (``c_pe``, ...), in ``metal`` units. Several
        files are chained in the order given (MDAnalysis ``ChainReader``); the first one also
        provides the topology (ids, types). Atoms are sorted by id in every frame.
    dt : float, optional
        The LAMMPS integration timestep, s; frames then carry ``ts.time = step * dt`` (in ps,
        MDAnalysis's unit). None gives MDAnalysis dt = 1 ps, so that ``ts.time`` equals the
        step number; `ContactAnalysis` uses ``ts.data["step"]`` either way.
    additional_columns : None, True or list of str
        Extra per-atom columns to read into ``ts.data`` (``True``: all), as in MDAnalysis's
        ``DumpReader``.

    Returns
    -------
    MDAnalysis.Universe
        Positions in Angstrom, relative to each frame's box corner (MDAnalysis's convention);
        ``ts.data["step"]`` is the frame's LAMMPS timestep and ``ts.data["lammps_origin"]``
        its box corner (xlo, ylo, zlo) in A, so that x_LAMMPS = x + xlo.

    Notes
    -----
    A dump carries no masses, so MDAnalysis sets them all to 1.0 and warns; that warning is
    silenced here (contact geometry needs no masses). The box corners come from a scan of
    the files' frame headers, attached as an MDAnalysis on-the-fly transformation.
    """
    if isinstance(paths, (str, os.PathLike)):
        paths = [paths]
    if isinstance(paths, (bytes, dict)) or not isinstance(paths, Iterable):
        raise InputError(f"paths must be a file path (str or os.PathLike) or a sequence of "
                         f"them, got {type(paths).__name__}")
    paths = [str(check_path(f"paths[{k}]", p)) for k, p in enumerate(paths)]
    if not paths:
        raise InputError("paths is empty: give at least one LAMMPS dump file")
    for p in paths:
        if not os.path.isfile(p):
            raise FileNotFoundError(f"LAMMPS dump file not found: {p}")
    dt_ps = 1.0 if dt is None else si_to_lammps(check_positive("dt", dt, unit="s"), "time")
    coordinates = paths[0] if len(paths) == 1 else paths
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message="Guessed all Masses to 1.0",
                                category=UserWarning)
        u = mda.Universe(paths[0], coordinates, topology_format="LAMMPSDUMP",
                         format="LAMMPSDUMP", dt=dt_ps, additional_columns=additional_columns)
    origins = [o for p in paths for o in _box_origins(p)]
    if len(origins) != u.trajectory.n_frames:
        raise InputError(f"found {len(origins)} frame headers in {', '.join(paths)} but "
                         f"MDAnalysis reads {u.trajectory.n_frames} frames")
    u.trajectory.add_transformations(_RecordOrigin(np.array(origins)))
    return u


class _RecordOrigin:
    """On-the-fly transformation: store the frame's LAMMPS box corner in ``ts.data``."""

    def __init__(self, origins: np.ndarray):
        self.origins = origins

    def __call__(self, ts):
        ts.data[ORIGIN_KEY] = self.origins[ts.frame].copy()
        return ts


def _box_origins(path: str) -> list[np.ndarray]:
    """The corner (xlo, ylo, zlo) of every frame of a dump, A, as MDAnalysis's DumpReader
    computes it (for a triclinic box: xlo = xlo_bound - min(0, xy, xz, xy + xz),
    ylo = ylo_bound - min(0, yz))."""
    origins = []
    with anyopen(path) as f:
        while True:
            line = f.readline()
            if not line.strip():
                break
            if not line.startswith("ITEM: TIMESTEP"):
                raise InputError(f"{path}: expected 'ITEM: TIMESTEP', got "
                                 f"{excerpt(line.strip())}")
            f.readline()                                  # the step
            f.readline()                                  # ITEM: NUMBER OF ATOMS
            n_atoms = int(f.readline())
            triclinic = len(f.readline().split()) == 9    # ITEM: BOX BOUNDS [xy xz yz] ..
            bounds = [[float(v) for v in f.readline().split()] for _ in range(3)]
            lo = np.array([b[0] for b in bounds])
            if triclinic:
                xy, xz, yz = bounds[0][2], bounds[1][2], bounds[2][2]
                lo[0] -= min(0.0, xy, xz, xy + xz)
                lo[1] -= min(0.0, yz)
            origins.append(lo)
            for _ in range(n_atoms + 1):                  # ITEM: ATOMS and the atoms
                f.readline()
    return origins
