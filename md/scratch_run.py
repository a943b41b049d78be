"""Running a nanoscratch, what it says, and its HDF5 record.

`run_scratch` drives LAMMPS like `md.run.run_indentation` (the same run directory layout:
``in.scratch``, ``in.resume.K``, ``scratch.dat`` / ``scratch.K.dat``, restart files, dumps,
``state.json``; an interrupted run resumes from its newest readable restart file, a finished
one is read back without LAMMPS). `analyze_scratch` gives the friction and the residual
groove; `write_scratch_record` the record (``scratch.h5``, SI).

A constant-load scratch (``scratch.normal_load``) first computes the top layer's reduced
modulus with the potential (`md.elastic`, in ``elastic/`` of the run directory) for the
gains of its feedback (`md.scratch.load_control`), kept in ``control.json`` for the
resumed parts and the record; a tip deeper than ``scratch.max_depth`` stops it with a
`ModelRangeError`.

Friction: over the steady part of the first pass, the middle `STEADY` of its stroke length
(the indenter's x between 20 % and 80 % of the length from its start), mu_i = F_lat,i /
F_n,i at every recorded point; ``friction_mean`` and ``friction_std`` are their mean and
standard deviation, ``normal_force_mean`` and ``lateral_force_mean`` the mean forces there,
``depth_mean`` and ``depth_std`` the indenter's depth below the undeformed surface (the
output of a constant-load scratch). ``normal_force_sem`` is the standard error of
``normal_force_mean`` from `BLOCKS` block means (the force is correlated over many recorded
points, so the points' own std / sqrt(n) would understate it); ``normal_load`` is the
target (NaN at constant depth).

Groove: from the atoms after the withdrawal and relaxation, those within `WINDOW` of the
mid-stroke x are binned in y (`BIN` wide); each bin's surface height is the mean z of its
top k atoms, k the top layer's areal density (counted in the as-built slab) times the bin's
area. Heights are relative to the undeformed surface (``z_surface``: the mean height of the
top atomic layer after equilibration, the zero of depth), the far field of an unscratched
sample; ``edge_height`` is the mean height of the bins farther than the contact radius +
`FAR_FIELD` from the axis, which stays near zero only where the sample is wide enough for
the pile-up to die out (the ci sample is not: its edges carry the pile-up). ``groove_depth`` is minus the lowest
height within the contact radius of the axis, ``groove_width`` the distance between the
points either side of that minimum where the profile first rises through zero (linear
interpolation), ``pileup_height`` the highest height of the profile.

Damage (`md.damage`): the atomic von Mises strain eta_Mises (Shimizu, Ogata & Li 2007, as
OVITO's atomic strain) of every final atom against its as-built position (the slab written to
``slab.data``, 0 K; the runs are at 10 K, so thermal strain stays near 0.01) or, on a slab with
an amorphous film, against the minimised and equilibrated sample dumped before the approach
(a film cut from a block rebonds its cut surfaces in the minimisation, which is no damage),
neighbours within `damage.shell_cutoff` of the slab's crystals or `damage.amorphous_cutoff`
of its amorphous films (the largest over its layers). Atoms with
eta_Mises > `damage.THRESHOLD` are damaged; per layer (the layer an atom was built in),
``width`` is the y extent and ``depth`` the depth below the as-built surface of the damaged
atoms in the groove profile's cross-section (within `WINDOW` of mid-stroke x, as built), so
that ``width`` compares with ``groove_width``.
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np
from ase.io import write as ase_write

from filmscale import __version__
from filmscale.core.errors import InputError, ModelRangeError
from filmscale.core.files import atomic_h5, write_json
from filmscale.core.jsonable import to_jsonable
from filmscale.md.amorphous_film import check_made
from filmscale.md.damage import (THRESHOLD, LayerDamage, atomic_strain, damaged_region,
                                 amorphous_cutoff, layer_index, shell_cutoff)
from filmscale.md.engine import EngineOptions, LammpsError
from filmscale.md.indentation import DATA_FILE, SURFACE_FILE, derive_seeds
from filmscale.md.lammps_input import write_input
from filmscale.md.lammps_units import lammps_to_si
from filmscale.md.record import write_attrs, run_provenance
from filmscale.md.run import STATE_FILE, run_resumable, stitched_record
from filmscale.md.scratch import (FAR_FIELD, LOAD_RECORD_COLUMNS, RECORD_COLUMNS, RECORD_FILE,
                                  STROKE, LoadControl, ScratchSpec, dump_name, load_control,
                                  record_to_si, scratch_input, scratch_resume_input)

RECORD_FORMAT = "filmscale.md_scratch/1"
RECORD_NAME = "scratch.h5"
STEADY = (0.2, 0.8)      #: the steady part of a pass, as fractions of its length
WINDOW = 5e-10           #: half-width in x of the atoms of the groove profile, m
BIN = 2e-10              #: width of the profile's bins in y, m
BLOCKS = 6               #: blocks of the steady part for the standard error of its mean force
CONTROL_FILE = "control.json"


@dataclass(frozen=True)
class ScratchRun:
    """A finished scratch: the forces in SI against time and indenter position, and the
    atoms after relaxation (ids, types, positions in m)."""

    spec: ScratchSpec
    run_dir: Path
    data: dict              #: step, time (s), x_tip, z_tip, depth (m), fx, fy, fz (N), temp
    z_surface: float        #: undeformed surface height, m
    final_atoms: dict       #: id, type, x, y, z (m) after the relaxation
    parts: tuple[dict, ...]
    wall_time: float
    engine: dict = field(default_factory=dict)
    control: dict | None = None   #: the constant-load feedback (`LoadControl.to_dict`)

    @property
    def n_atoms(self) -> int:
        return self.spec.indent.slab_built.n_atoms

    @property
    def n_steps(self) -> int:
        return self.spec.schedule().s_end

    @property
    def normal_force(self) -> np.ndarray:
        return self.data["fz"]

    @property
    def lateral_force(self) -> np.ndarray:
        """Force resisting the motion (positive against it), N; zero off the stroke."""
        return -self.spec.schedule().direction(self.data["step"]) * self.data["fx"]

    def inputs(self) -> dict[str, str]:
        return {p["input"]: (self.run_dir / p["input"]).read_text() for p in self.parts}


def _spec_dict(spec: ScratchSpec) -> dict:
    return to_jsonable(json.loads(json.dumps(spec.to_dict(), default=str)))


def _control(spec: ScratchSpec, run_dir: Path, engine: EngineOptions) -> LoadControl | None:
    """The feedback of a constant-load scratch: designed with the top layer's E* (computed,
    or read back from ``elastic/``) and kept in `CONTROL_FILE`."""
    if not spec.stroke.load_controlled:
        return None
    from filmscale.md.amorphous_run import layer_elastic_constants
    ind = spec.indent
    top = (ind.slab.films or (ind.slab.substrate,))[0]
    elastic = layer_elastic_constants(ind.potential, top, run_dir / "elastic", engine)
    control = load_control(spec, elastic.E_star)
    write_json(run_dir / CONTROL_FILE, control.to_dict())
    return control


def _saved_control(spec: ScratchSpec, run_dir: Path) -> LoadControl | None:
    if not spec.stroke.load_controlled:
        return None
    saved = json.loads((run_dir / CONTROL_FILE).read_text())
    return LoadControl(**{k: saved[k] for k in LoadControl.__dataclass_fields__})


def _fresh(spec: ScratchSpec, run_dir: Path, engine: EngineOptions) -> dict:
    ind = spec.indent
    ase_write(run_dir / DATA_FILE, ind.slab_built.atoms, format="lammps-data",
              specorder=list(ind.type_elements), masses=True, units="metal",
              atom_style="atomic")
    control = _control(spec, run_dir, engine)
    write_input(run_dir / "in.scratch", scratch_input(spec, version=__version__,
                                                      control=control))
    write_json(run_dir / "spec.json", _spec_dict(spec))
    seeds = derive_seeds(ind.protocol.seed, ("velocity", "langevin"))
    return {"input": "in.scratch", "record": RECORD_FILE, "start": 0, "seeds": seeds}


def _resume_part(spec: ScratchSpec, run_dir: Path, k: int, step: int, restart: Path) -> dict:
    z_surface = float((run_dir / SURFACE_FILE).read_text().split()[0])
    name, record = f"in.resume.{k}", f"scratch.{k}.dat"
    write_input(run_dir / name, scratch_resume_input(
        spec, restart_file=restart.name, restart_step=step, z_surface=z_surface, part=k,
        record=record, version=__version__, control=_saved_control(spec, run_dir)))
    return {"input": name, "record": record, "start": step, "restart": restart.name,
            "seeds": derive_seeds(spec.indent.protocol.seed, ("langevin",), part=k)}


def run_scratch(spec: ScratchSpec, run_dir: Path | str,
                engine: EngineOptions = EngineOptions(), *,
                progress: Callable[[int, int], None] | None = None) -> ScratchRun:
    """Run ``spec`` in ``run_dir``, resume it there, or read a finished run back
    (`run.run_resumable`, as an indentation)."""
    check_made(spec.indent.slab.layers(), "run_scratch")
    run_dir = Path(run_dir).resolve()
    (run_dir / "dumps").mkdir(parents=True, exist_ok=True)
    try:
        run_resumable(run_dir, _spec_dict(spec), spec.schedule().s_end,
                      lambda: _fresh(spec, run_dir, engine),
                      lambda k, step, restart: _resume_part(spec, run_dir, k, step, restart),
                      engine, progress)
    except LammpsError as exc:
        if "depth_limit" not in exc.message:
            raise
        raise ModelRangeError(
            f"scratch.max_depth = {spec.stroke.max_depth:.4g} m was passed under "
            f"scratch.normal_load = {spec.stroke.normal_load:.4g} N ({exc.message.strip()}): "
            f"raise max_depth (and the slab with it) or lower the load; run directory "
            f"{run_dir}") from None
    return read_scratch(spec, run_dir)


def read_dump_atoms(path: Path) -> dict:
    """id, type, x, y, z (m) of a ``write_dump ... id type x y z ...`` file."""
    lines = path.read_text().splitlines()
    head = next(i for i, line in enumerate(lines) if line.startswith("ITEM: ATOMS"))
    cols = lines[head].split()[2:]
    data = np.loadtxt(lines[head + 1:], ndmin=2)
    c = {name: data[:, i] for i, name in enumerate(cols)}
    out = {"id": c["id"].astype(int), "type": c["type"].astype(int)}
    out.update({k: lammps_to_si(c[k], "length") for k in ("x", "y", "z")})
    return out


def read_scratch(spec: ScratchSpec, run_dir: Path | str) -> ScratchRun:
    """The forces and the final atoms of a finished run directory (no LAMMPS)."""
    run_dir = Path(run_dir).resolve()
    state = json.loads((run_dir / STATE_FILE).read_text())
    parts = state["parts"]
    control = _saved_control(spec, run_dir)
    columns = RECORD_COLUMNS if control is None else LOAD_RECORD_COLUMNS
    data = stitched_record(run_dir, parts, columns)
    z_surface = float((run_dir / SURFACE_FILE).read_text().split()[0])
    return ScratchRun(spec=spec, run_dir=run_dir,
                      data=record_to_si({n: data[:, i] for i, n in enumerate(columns)}),
                      z_surface=float(lammps_to_si(z_surface, "length")),
                      final_atoms=read_dump_atoms(run_dir / dump_name(spec.schedule().s_end)),
                      parts=tuple(parts), wall_time=sum(p.get("wall_time", 0.0) for p in parts),
                      engine=state.get("engine", {}),
                      control=None if control is None else control.to_dict())


# ---- analysis ---------------------------------------------------------------------------------

@dataclass(frozen=True)
class ScratchAnalysis:
    """The figures of a scratch, SI; NaN where a figure cannot be found."""

    friction_mean: float
    friction_std: float
    normal_force_mean: float      #: N
    lateral_force_mean: float     #: N, positive against the motion
    steady_points: int
    normal_force_sem: float       #: standard error of normal_force_mean (`BLOCKS` blocks), N
    normal_load: float            #: the constant-load target, N (NaN at constant depth)
    depth_mean: float             #: the indenter's depth over the steady part, m
    depth_std: float              #: its standard deviation there, m
    groove_depth: float           #: m, positive below the far field
    groove_width: float           #: m, between the zero crossings either side
    pileup_height: float          #: m, above the far field
    edge_height: float            #: mean height of the profile's outer bins, m
    profile_y: np.ndarray         #: bin centres, m from the groove axis
    profile_h: np.ndarray         #: surface height relative to the far field, m
    damage: tuple[LayerDamage, ...] = ()   #: per layer, top film first (SI)
    scratch_hardness: float = math.nan     #: 8 F_n / (pi w^2), Pa (`scratch_hardness`)
    passes: tuple[PassFigures, ...] = ()   #: per pass (the first is the figures above)
    eta_mises: np.ndarray | None = None    #: per final atom (the order of ``final_atoms``)
    damage_threshold: float = THRESHOLD
    damage_cutoff: float = math.nan        #: neighbour cutoff of eta_Mises, m

    def to_dict(self) -> dict:
        d = {k: getattr(self, k) for k in self.__dataclass_fields__ if k != "eta_mises"}
        d["profile_y"], d["profile_h"] = self.profile_y.tolist(), self.profile_h.tolist()
        d["damage"] = [x.to_dict() for x in self.damage]
        d["passes"] = [x.to_dict() for x in self.passes]
        return d


def steady_mask(run: ScratchRun) -> np.ndarray:
    """The recorded points of the first pass with the indenter between `STEADY` of it."""
    spec = run.spec
    s = spec.schedule()
    travel = run.data["x_tip"] - spec.x_start
    first = (run.data["step"] > s.s_stroke) & (run.data["step"] <= s.s_stroke + s.n_slide)
    L = spec.stroke.length
    return first & (travel >= STEADY[0] * L) & (travel <= STEADY[1] * L)


@dataclass(frozen=True)
class PassFigures:
    """Friction and forces over the steady part of one pass (`STEADY` of its travel), SI."""

    number: int                   #: 1 for the first pass along +x, 2 back, ...
    friction_mean: float
    friction_std: float
    normal_force_mean: float      #: N
    lateral_force_mean: float     #: N, positive against the motion
    points: int

    def to_dict(self) -> dict:
        return asdict(self)


def pass_figures(on_pass: list[np.ndarray], travel: np.ndarray, length: float,
                 normal: np.ndarray, lateral: np.ndarray) -> tuple[PassFigures, ...]:
    """Per pass (``on_pass[k]``: its recorded points; ``travel``: the distance slid since
    the pass began, m), the figures over its steady part."""
    out = []
    nan = math.nan
    for k, on in enumerate(on_pass):
        steady = on & (travel >= STEADY[0] * length) & (travel <= STEADY[1] * length)
        Fn, Fl = normal[steady], lateral[steady]
        with np.errstate(divide="ignore", invalid="ignore"):
            mu = Fl / Fn
        mu = mu[np.isfinite(mu)]
        out.append(PassFigures(k + 1, float(mu.mean()) if mu.size else nan,
                               float(mu.std(ddof=1)) if mu.size > 1 else nan,
                               float(Fn.mean()) if Fn.size else nan,
                               float(Fl.mean()) if Fl.size else nan, int(steady.sum())))
    return tuple(out)


def scratch_passes(run: ScratchRun) -> tuple[PassFigures, ...]:
    """The friction and forces over the steady part of every pass of an MD scratch."""
    s = run.spec.schedule()
    step, L = run.data["step"], run.spec.stroke.length
    from_start = run.data["x_tip"] - run.spec.x_start
    on_pass, travel = [], np.zeros_like(from_start)
    for k, start in enumerate(s.pass_starts()):
        on = (step > start) & (step <= start + s.n_slide)
        on_pass.append(on)
        travel[on] = from_start[on] if k % 2 == 0 else L - from_start[on]
    return pass_figures(on_pass, travel, L, run.normal_force, run.lateral_force)


def block_sem(values: np.ndarray, blocks: int = BLOCKS) -> float:
    """Standard error of the mean of a correlated series: the standard deviation of the means
    of ``blocks`` consecutive blocks over sqrt(blocks); NaN for fewer than two points a
    block."""
    if values.size < 2 * blocks:
        return math.nan
    means = [b.mean() for b in np.array_split(values, blocks)]
    return float(np.std(means, ddof=1) / math.sqrt(blocks))


def _top_density(spec: ScratchSpec) -> float:
    """Atoms per m^2 in the top atomic layer of the as-built slab."""
    slab = spec.indent.slab_built
    z = lammps_to_si(slab.atoms.positions[:, 2], "length")
    n = int(np.sum(z > slab.z_surface - 0.5 * slab.surface_layer_gap))
    return n / (slab.box[0] * slab.box[1])


def groove_profile(run: ScratchRun) -> tuple[np.ndarray, np.ndarray, float]:
    """(y from the axis, height relative to the undeformed surface) per bin at mid-stroke,
    and the mean height of the outer bins (NaN when there are none)."""
    spec = run.spec
    Lx, Ly = spec.indent.slab_built.box[:2]
    a = run.final_atoms
    x_mid = spec.x_start + 0.5 * spec.stroke.length
    dx = (a["x"] - x_mid + 0.5 * Lx) % Lx - 0.5 * Lx
    dy = (a["y"] - spec.y_center + 0.5 * Ly) % Ly - 0.5 * Ly
    sel = np.abs(dx) <= WINDOW
    n_bins = max(3, int(Ly // BIN))
    edges = np.linspace(-0.5 * Ly, 0.5 * Ly, n_bins + 1)
    k = max(1, round(_top_density(spec) * 2 * WINDOW * (Ly / n_bins)))
    idx = np.digitize(dy[sel], edges) - 1
    z = a["z"][sel]
    heights = np.array([np.mean(np.sort(z[idx == i])[-k:]) if np.any(idx == i) else np.nan
                        for i in range(n_bins)])
    centres = 0.5 * (edges[1:] + edges[:-1])
    far = np.abs(centres) > spec.contact_radius + FAR_FIELD
    h = heights - run.z_surface
    return centres, h, float(np.nanmean(h[far])) if np.any(far) else math.nan


def groove_edges(y: np.ndarray, h: np.ndarray, i0: int) -> tuple[float, float]:
    """The y either side of index ``i0`` (the groove's lowest point) where the profile h(y)
    (sorted in y) first rises through zero, interpolated linearly; NaN on a side that never
    rises within the profile. The groove width is their difference (`scratch_run`,
    `particle_scratch_run` and the scratch figure measure it so)."""
    ends = []
    for step in (-1, 1):
        i = i0
        while 0 <= i + step < len(h) and h[i + step] < 0:
            i += step
        j = i + step
        if not 0 <= j < len(h) or not np.isfinite(h[j]):
            ends.append(math.nan)
            continue
        ends.append(float(y[i] + (y[j] - y[i]) * (0 - h[i]) / (h[j] - h[i])))
    return ends[0], ends[1]


def scratch_json(analysis, keys: tuple[str, ...]) -> dict:
    """The figures `--json` prints of an MD or particle scratch analysis: ``keys``, the
    damaged or plastic region per layer (layer, width, depth) and the figures of each pass."""
    return {**{k: getattr(analysis, k) for k in keys},
            "damage": [{"layer": d.layer, "width": d.width, "depth": d.depth}
                       for d in analysis.damage],
            "passes": [x.to_dict() for x in analysis.passes]}


def scratch_hardness(normal_force: float, groove_width: float, plastic: bool,
                     contact_radius: float) -> float:
    """The scratch hardness 8 F_n / (pi w^2), Pa (Williams 1996; ASTM G171 for a spherical
    stylus): the normal force over the front half of a contact as wide as the residual
    groove. NaN unless the groove is plastic (``plastic``: damaged atoms or plastic particles
    under it) and at least as wide as the contact radius at the scratch depth: a narrower
    "groove" is the surface's roughness or an atom's dip, not a ploughed track, and would put
    a hardness of its noise."""
    if not plastic or not np.isfinite(groove_width) or groove_width < contact_radius:
        return math.nan
    return 8 * normal_force / (math.pi * groove_width**2)


def groove_bottom(y: np.ndarray, h: np.ndarray, contact_radius: float) -> int | None:
    """Index of the profile's lowest finite point within ``contact_radius`` of the groove
    axis; None where there is none."""
    inside = (np.abs(y) <= contact_radius) & np.isfinite(h)
    if not np.any(inside):
        return None
    return int(np.flatnonzero(inside)[np.argmin(h[inside])])


def groove_depth_width(y: np.ndarray, h: np.ndarray,
                       contact_radius: float) -> tuple[float, float]:
    """(depth, width) of a groove profile h(y), m: minus its lowest height within the contact
    radius, and the distance between the zero crossings either side of it (0 when that point
    is not below zero); NaN and NaN without a point there."""
    i0 = groove_bottom(y, h, contact_radius)
    if i0 is None:
        return math.nan, math.nan
    if h[i0] >= 0:
        return float(-h[i0]), 0.0
    left, right = groove_edges(y, h, i0)
    return float(-h[i0]), right - left


def layer_cutoff(layer) -> float:
    """The atomic-strain neighbour cutoff of one slab layer, m: between two shells of a
    crystal, or enclosing `damage.AMORPHOUS_NEIGHBOURS` atoms of an amorphous film."""
    if layer.structure == "amorphous":
        return amorphous_cutoff(layer.block.n_atoms / float(np.prod(layer.block.box)))
    return shell_cutoff(layer.crystal.structure, layer.crystal.a)


def damage_reference(run: ScratchRun) -> np.ndarray:
    """The reference position (m) of each final atom for its atomic strain: as built, or on
    a slab with an amorphous film the equilibrated sample before the approach (module
    docstring)."""
    a = run.final_atoms
    equilibrated = run.run_dir / dump_name(run.spec.schedule().s_load)
    if any(layer.structure == "amorphous" for _, layer in run.spec.indent.slab.layers()) \
            and equilibrated.exists():
        ref = read_dump_atoms(equilibrated)
        return np.column_stack([ref["x"], ref["y"], ref["z"]])[np.searchsorted(ref["id"],
                                                                              a["id"])]
    return lammps_to_si(run.spec.indent.slab_built.atoms.positions, "length")[a["id"] - 1]


def scratch_damage(run: ScratchRun, threshold: float = THRESHOLD
                   ) -> tuple[tuple[LayerDamage, ...], np.ndarray, float]:
    """(per-layer damage, eta_Mises per final atom, cutoff m): see the module docstring."""
    spec = run.spec
    slab = spec.indent.slab_built
    a = run.final_atoms
    layers = spec.indent.slab.layers()
    x0 = damage_reference(run)
    x = np.column_stack([a["x"], a["y"], a["z"]])
    cutoff = max(layer_cutoff(layer) for _, layer in layers)
    eta = atomic_strain(x0, x, cutoff, box=slab.box)
    Lx = slab.box[0]
    x_mid = spec.x_start + 0.5 * spec.stroke.length
    section = np.abs((x0[:, 0] - x_mid + 0.5 * Lx) % Lx - 0.5 * Lx) <= WINDOW
    damage = damaged_region(x0, eta, [label for label, _ in layers],
                            layer_index(x0[:, 2], slab.layer_tops), slab.z_surface,
                            spec.y_center, slab.box[1], threshold, select=section)
    return tuple(damage), eta, cutoff


def analyze_scratch(run: ScratchRun) -> ScratchAnalysis:
    """Friction over the steady stroke, the residual groove and the sub-surface damage (see
    the module docstring)."""
    steady = steady_mask(run)
    depth = run.data["depth"][steady]
    passes = scratch_passes(run)
    first = passes[0]                  # the steady stroke: the first pass's steady part
    nan = math.nan
    y, h, edge = groove_profile(run)
    damage, eta, cutoff = scratch_damage(run)
    groove, width = groove_depth_width(y, h, run.spec.contact_radius)
    target = run.spec.stroke.normal_load
    return ScratchAnalysis(
        friction_mean=first.friction_mean, friction_std=first.friction_std,
        normal_force_mean=first.normal_force_mean,
        lateral_force_mean=first.lateral_force_mean, steady_points=first.points,
        normal_force_sem=block_sem(run.normal_force[steady]),
        normal_load=nan if target is None else target,
        depth_mean=float(depth.mean()) if depth.size else nan,
        depth_std=float(depth.std(ddof=1)) if depth.size > 1 else nan,
        groove_depth=groove, groove_width=width,
        pileup_height=float(np.nanmax(h)), edge_height=edge, profile_y=y, profile_h=h,
        damage=damage, eta_mises=eta, damage_cutoff=cutoff,
        scratch_hardness=scratch_hardness(first.normal_force_mean, width, groove > 0 and
                                          any(d.atoms for d in damage),
                                          run.spec.contact_radius),
        passes=passes)


def stroke_mask(run: ScratchRun) -> np.ndarray:
    return run.spec.schedule().segment(run.data["step"]) == STROKE


# ---- the record -------------------------------------------------------------------------------

def write_scratch_record(run: ScratchRun, analysis: ScratchAnalysis,
                         path: Path | str | None = None,
                         provenance: dict | None = None) -> Path:
    """Write ``scratch.h5`` (or ``path``): ``forces`` (time s, step, x_tip, z_tip, depth m,
    normal_force, lateral_force, fx, fy, fz N, segment; normal_force_target N under load),
    ``control`` (attributes: ``mode`` depth or load; under load the feedback's target,
    E*, stiffness, omega, zeta, K_i, K_p in SI), ``analysis`` (figures as attributes,
    the groove profile as datasets; ``analysis/damage``: layer, width, depth m, atoms per
    layer), ``final_atoms`` (id, type, x, y, z m, eta_mises), ``inputs``;
    provenance as root attributes (as the indentation record)."""
    import h5py
    path = Path(path) if path is not None else run.run_dir / RECORD_NAME
    s = run.spec.schedule()
    with atomic_h5(path) as f:
        f.attrs["format"] = RECORD_FORMAT
        write_attrs(f, run_provenance(run_as_indent(run), provenance))
        for key, value in (("run_dir", str(run.run_dir)), ("n_atoms", run.n_atoms),
                           ("n_steps", run.n_steps), ("wall_time", run.wall_time),
                           ("z_surface", run.z_surface), ("units", "SI"),
                           ("lateral_sign", "positive against the motion")):
            f.attrs[key] = value
        g = f.create_group("forces")
        units = {"time": "s", "x_tip": "m", "z_tip": "m", "depth": "m", "fx": "N",
                 "fy": "N", "fz": "N", "temp": "K"}
        for key, unit in units.items():
            g[key] = run.data[key]
            g[key].attrs["units"] = unit
        g["step"] = run.data["step"]
        g["segment"] = s.segment(run.data["step"])
        g["normal_force"], g["lateral_force"] = run.normal_force, run.lateral_force
        g["normal_force"].attrs["units"] = g["lateral_force"].attrs["units"] = "N"
        if "fn_target" in run.data:
            g["normal_force_target"] = run.data["fn_target"]
            g["normal_force_target"].attrs["units"] = "N"
        c = f.create_group("control")
        c.attrs["mode"] = "depth" if run.control is None else "load"
        if run.control is not None:
            write_attrs(c, run.control)
        a = f.create_group("analysis")
        d = analysis.to_dict()
        a["profile_y"], a["profile_h"] = d.pop("profile_y"), d.pop("profile_h")
        rows = d.pop("damage")
        a.attrs["passes"] = json.dumps(d.pop("passes"))
        write_attrs(a, {k: float(v) for k, v in d.items()})
        dmg = a.create_group("damage")
        dmg.attrs["criterion"] = (f"atomic von Mises strain (Shimizu, Ogata & Li 2007) > "
                                  f"{analysis.damage_threshold:g} against the as-built slab, "
                                  f"neighbours within {analysis.damage_cutoff:.6g} m; atoms "
                                  f"within {WINDOW:g} m of mid-stroke x")
        dmg.create_dataset("layer", data=[r["layer"] for r in rows],
                           dtype=h5py.string_dtype())
        for key, unit in (("width", "m"), ("depth", "m"), ("atoms", "1")):
            dmg[key] = np.array([r[key] for r in rows], float if unit == "m" else int)
            dmg[key].attrs["units"] = unit
        atoms = f.create_group("final_atoms")
        for key, value in run.final_atoms.items():
            atoms[key] = value
        if analysis.eta_mises is not None:
            atoms["eta_mises"] = analysis.eta_mises
            atoms["eta_mises"].attrs["units"] = "1"
        inputs = f.create_group("inputs")
        for name, text in run.inputs().items():
            inputs[name] = text
        inputs["spec.json"] = json.dumps(run.spec.to_dict(), default=str)
        inputs.attrs["slab"] = json.dumps(run.spec.indent.slab_built.to_dict())
    return path


def run_as_indent(run: ScratchRun):
    """What `record.run_provenance` reads (spec with potential and protocol, parts, engine)."""
    from types import SimpleNamespace
    return SimpleNamespace(spec=run.spec.indent, parts=run.parts, engine=run.engine)


@dataclass(frozen=True)
class ScratchFriction:
    """The friction a scratch record measured over its steady stroke: mean and standard
    deviation of F_lat/F_n over ``points`` recorded points."""

    mean: float
    std: float
    points: int


def read_scratch_friction(path, name: str = "scratch record") -> ScratchFriction:
    """The friction of the scratch record ``path`` (the scratch.h5 of `filmscale md
    scratch` or the particle_scratch.h5 of `filmscale particles scratch`: both keep it in
    ``analysis``); InputError naming ``name`` for a file that is not one."""
    import h5py

    from filmscale.md.particle_scratch_run import RECORD_FORMAT as PARTICLE_FORMAT
    path = Path(path)
    if not path.is_file():
        raise InputError(f"{name} = {str(path)!r} is not a file (give the scratch.h5 of "
                         "`filmscale md scratch` or the particle_scratch.h5 of `filmscale "
                         "particles scratch`)")
    try:
        with h5py.File(path, "r") as f:
            fmt = f.attrs.get("format", "")
            if fmt not in (RECORD_FORMAT, PARTICLE_FORMAT):
                raise InputError(f"{name} = {str(path)!r} is not a scratch record (format "
                                 f"{fmt or 'none'!r}, expected {RECORD_FORMAT!r} or "
                                 f"{PARTICLE_FORMAT!r})")
            a = f["analysis"].attrs
            out = ScratchFriction(float(a["friction_mean"]), float(a["friction_std"]),
                                  int(a["steady_points"]))
    except (OSError, KeyError) as err:
        raise InputError(f"{name} = {str(path)!r} cannot be read as a scratch record: "
                         f"{err}") from None
    if not (math.isfinite(out.mean) and out.mean >= 0.0):
        raise InputError(f"{name} = {str(path)!r} holds no friction coefficient (its steady "
                         f"stroke gave {out.mean!r})")
    return out
