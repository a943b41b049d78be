"""Atomistic slabs for indentation: crystalline (and amorphous) films on a substrate, built
with ASE.

A `SlabSpec` names the layers (top film first, substrate last), the surface orientation and
the lateral size; `build_slab` returns the atoms with the regions an indentation run needs:
fixed bottom layers, a thermostatted layer above them, the mobile rest, and the top atomic
layer that defines the undeformed surface. The lateral box is set by the substrate; each
film is strained to it (coherent interface) and its misfit strain is reported. A film may be
an `md.amorphous_film.AmorphousLayer`: a slice of a quenched block (`md.amorphous`), strained
to the box at constant volume and placed its ``gap`` above the layer below.

Lengths are SI (m) in the specs and results; the ASE atoms are in Angstrom, as ASE and LAMMPS
metal units use them.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field, fields

import numpy as np
from ase import Atoms
from ase.build import bulk
from ase.data import atomic_masses, atomic_numbers
from ase.lattice.cubic import BodyCenteredCubic, Diamond, FaceCenteredCubic

from filmscale.core.checks import check_positive, check_real
from filmscale.core.errors import InputError
from filmscale.md.amorphous_film import AmorphousLayer, cut_film
from filmscale.md.lammps_units import si_to_lammps, lammps_to_si
from filmscale.potentials import Potential
from filmscale.potentials.lammps_words import shown
from filmscale.potentials.registry import PotentialError, registry

#: Crystal axes (x, y, z) for each surface orientation of the cubic lattices; z is the
#: surface normal.
CUBIC_ORIENTATIONS = {
    "001": ([1, 0, 0], [0, 1, 0], [0, 0, 1]),
    "110": ([0, 0, 1], [1, -1, 0], [1, 1, 0]),
    "111": ([1, -1, 0], [1, 1, -2], [1, 1, 1]),
}
STRUCTURES = ("fcc", "bcc", "hcp", "diamond")
CUBIC_FACTORIES = {"fcc": FaceCenteredCubic, "bcc": BodyCenteredCubic, "diamond": Diamond}


def surface_normal(orientation: str) -> tuple[float, float, float]:
    """The surface normal of an orientation in the crystal axes in which `md.elastic`
    computes C (cube axes; for hcp, the c axis is z)."""
    if orientation == "0001":
        return (0.0, 0.0, 1.0)
    if not isinstance(orientation, str) or orientation not in CUBIC_ORIENTATIONS:
        raise InputError(f"orientation = {shown(orientation)} is not one of "
                         f"{', '.join([*CUBIC_ORIENTATIONS, '0001'])}")
    return tuple(float(x) for x in CUBIC_ORIENTATIONS[orientation][2])
ORIENTATIONS = {"fcc": tuple(CUBIC_ORIENTATIONS), "bcc": tuple(CUBIC_ORIENTATIONS),
                "diamond": tuple(CUBIC_ORIENTATIONS), "hcp": ("0001",)}


@dataclass(frozen=True)
class Crystal:
    """A pure-element crystal: ``structure`` fcc, bcc, hcp or diamond (cubic, as C and Si),
    lattice constant ``a`` (m) and, for hcp, ``c`` (m; ideal c/a = sqrt(8/3) when not
    given)."""

    element: str
    structure: str
    a: float
    c: float | None = None

    def __post_init__(self):
        if not isinstance(self.element, str) or self.element not in atomic_numbers:
            raise InputError(f"element = {shown(self.element)} is not a chemical element "
                             "symbol")
        if self.structure not in STRUCTURES:
            raise InputError(f"structure = {shown(self.structure)} must be one of "
                             f"{', '.join(STRUCTURES)}")
        check_real("a", self.a, low=1e-10, high=1e-9, unit="m")
        if self.c is not None:
            check_real("c", self.c, low=1e-10, high=2e-9, unit="m")

    def unit_cell(self, orientation: str) -> Atoms:
        """The smallest orthogonal cell with z along the surface normal (Angstrom)."""
        if orientation not in ORIENTATIONS[self.structure]:
            raise InputError(f"orientation = {shown(orientation)} is not available for "
                             f"{self.structure}; choose one of "
                             f"{', '.join(ORIENTATIONS[self.structure])}")
        a = si_to_lammps(self.a, "length")
        if self.structure == "hcp":
            c = si_to_lammps(self.c, "length") if self.c is not None else a * math.sqrt(8.0 / 3.0)
            cell = bulk(self.element, "hcp", a=a, c=c, orthorhombic=True)
        else:
            factory = CUBIC_FACTORIES[self.structure]
            cell = factory(directions=CUBIC_ORIENTATIONS[orientation], size=(1, 1, 1),
                           symbol=self.element, latticeconstant=a, pbc=True)
            if self.structure == "diamond":     # ASE leaves an atom at z = Lz for [110]
                cell.wrap(eps=1e-6)
        cell.positions[:, 2] -= cell.positions[:, 2].min()
        return cell


@dataclass(frozen=True)
class SlabLayer:
    """One layer of the slab: a crystal and its thickness (m)."""

    crystal: Crystal
    thickness: float

    @property
    def element(self) -> str:
        return self.crystal.element

    @property
    def structure(self) -> str:
        return self.crystal.structure


@dataclass(frozen=True)
class SlabSpec:
    """Films (top first: crystal `SlabLayer` or `AmorphousLayer`) on a crystal substrate,
    with the lateral size and the boundary regions.

    ``lateral_size`` (m) is the target box edge in x and y (rounded to whole substrate
    cells); ``fixed_thickness`` (m) of the bottom is held rigid and ``thermostat_thickness``
    (m) above it is thermostatted; both should exceed the potential cutoff so that mobile
    atoms never see the bottom surface. ``vacuum`` (m) is kept above the surface in the box.
    """

    films: tuple[SlabLayer | AmorphousLayer, ...]
    substrate: SlabLayer
    orientation: str = "001"
    lateral_size: float = 4e-9
    fixed_thickness: float = 6e-10
    thermostat_thickness: float = 6e-10
    vacuum: float = 3e-9

    def __post_init__(self):
        object.__setattr__(self, "films", tuple(self.films))
        check_real("lateral_size", self.lateral_size, low=5e-10, high=1e-6, unit="m")
        check_real("fixed_thickness", self.fixed_thickness, low=0.0, high=1e-6, unit="m")
        check_real("thermostat_thickness", self.thermostat_thickness, low=0.0, high=1e-6,
                   unit="m")
        check_real("vacuum", self.vacuum, low=0.0, high=1e-6, unit="m")
        if not isinstance(self.substrate, SlabLayer):
            raise InputError(f"substrate = {shown(self.substrate)} must be a crystal layer "
                             "(SlabLayer)")
        for label, layer in self.layers():
            if not isinstance(layer, (SlabLayer, AmorphousLayer)):
                raise InputError(f"{label} = {shown(layer)} must be a SlabLayer or an "
                                 "AmorphousLayer")
            check_positive(f"{label}.thickness", layer.thickness, "m")
        structures = {layer.structure for _, layer in self.layers()} - {"amorphous"}
        hexagonal = structures & {"hcp"}
        if hexagonal and structures != hexagonal:
            raise InputError("films and substrate must all be cubic or all hcp to share a "
                             f"lateral cell; got {', '.join(sorted(structures))}")

    def layers(self) -> list[tuple[str, SlabLayer | AmorphousLayer]]:
        """(label, layer) from the top film down to the substrate."""
        return [(f"films[{i}]", f) for i, f in enumerate(self.films)] + \
            [("substrate", self.substrate)]

    def to_dict(self) -> dict:
        """The spec as records and unit hashes hold it (an amorphous film by
        `AmorphousLayer.to_dict`)."""
        d = {f.name: getattr(self, f.name) for f in fields(self)}
        d["films"] = [f.to_dict() if isinstance(f, AmorphousLayer) else asdict(f)
                      for f in self.films]
        d["substrate"] = asdict(self.substrate)
        return d

    @property
    def elements(self) -> tuple[str, ...]:
        seen: list[str] = []
        for _, layer in self.layers():
            if layer.element not in seen:
                seen.append(layer.element)
        return tuple(seen)


@dataclass(frozen=True)
class Slab:
    """A built slab. Atoms are in Angstrom; every length attribute is SI (m)."""

    atoms: Atoms
    box: tuple[float, float, float]      #: box edges Lx, Ly (periodic) and Lz (with vacuum), m
    z_fixed: float         #: top of the fixed region, m
    z_thermostat: float    #: top of the thermostatted region, m
    z_surface: float       #: mean height of the top atomic layer as built, m
    surface_layer_gap: float   #: spacing between the two top atomic layers (an amorphous
    #: top: the mean interatomic spacing, the depth of its top layer), m
    layer_tops: tuple[float, ...]   #: top of each layer (films then substrate), m
    misfit: tuple[tuple[float, float], ...]   #: in-plane strain (x, y) of each film (an
    #: amorphous film's z strain is 1 / ((1 + x)(1 + y)) - 1: it keeps its block's density)
    lattice_period: tuple[float, ...]   #: repeat length along the normal, per layer (an
    #: amorphous film: its strained block's height), m
    element_counts: dict = field(default_factory=dict)

    @property
    def n_atoms(self) -> int:
        return len(self.atoms)

    @property
    def thickness(self) -> float:
        """Height of the atoms, bottom to surface, m."""
        return self.z_surface - float(lammps_to_si(self.atoms.positions[:, 2].min(), "length"))

    def to_dict(self) -> dict:
        return {"n_atoms": self.n_atoms, "box": list(self.box), "z_fixed": self.z_fixed,
                "z_thermostat": self.z_thermostat, "z_surface": self.z_surface,
                "layer_tops": list(self.layer_tops),
                "misfit": [list(m) for m in self.misfit],
                "element_counts": dict(self.element_counts)}


def _layer_spacings(cell: Atoms) -> np.ndarray:
    z = np.unique(np.round(cell.positions[:, 2], 6))
    return np.diff(np.append(z, z[0] + cell.cell[2, 2]))


def _crystal_block(layer: SlabLayer, label: str, orientation: str, Lx: float,
                   Ly: float) -> tuple[Atoms, tuple[float, float], np.ndarray, float]:
    """A crystal layer's atoms (Angstrom, from z = 0) strained to the box Lx, Ly (A), its
    strain, its interplanar spacings (A) and its period along the normal (m)."""
    cell = layer.crystal.unit_cell(orientation)
    pz = cell.cell[2, 2]
    thickness = si_to_lammps(layer.thickness, "length")
    if thickness < pz * (1 - 1e-9):
        raise InputError(
            f"{label}.thickness = {layer.thickness:.4g} m is thinner than one lattice "
            f"period along [{orientation}] of {layer.crystal.element} "
            f"({lammps_to_si(pz, 'length'):.4g} m)")
    nz = max(1, round(thickness / pz))
    mx, my = max(1, round(Lx / cell.cell[0, 0])), max(1, round(Ly / cell.cell[1, 1]))
    block = cell.repeat((mx, my, nz))
    strain = (Lx / (mx * cell.cell[0, 0]) - 1.0, Ly / (my * cell.cell[1, 1]) - 1.0)
    block.positions[:, 0] *= 1.0 + strain[0]
    block.positions[:, 1] *= 1.0 + strain[1]
    return block, strain, _layer_spacings(cell), lammps_to_si(pz, "length")


def check_stack(spec: SlabSpec, potential: Potential) -> None:
    """Refuse, before any LAMMPS work, a stack whose elements ``potential`` does not all
    cover (one line naming the layers, their elements, the potential and those registry
    potentials that would cover them: no mixing rule is ever applied), and an amorphous film
    whose block was quenched with another potential."""
    missing = [e for e in spec.elements if e not in potential.elements]
    if missing:
        stack = ", ".join(f"{label} {layer.structure} {layer.element}"
                          for label, layer in spec.layers())
        covering = [name for name, p in registry().items()
                    if set(spec.elements) <= set(p.elements)]
        hint = (f"potential {' or '.join(covering)} of the registry covers them" if covering
                else "no potential of the registry covers them all, and no mixing rule is "
                "applied")
        raise PotentialError(f"slab: the layers {stack} need {', '.join(spec.elements)}; potential "
                         f"{potential.name!r} covers {', '.join(potential.elements)}, not "
                         f"{', '.join(missing)}: {hint}")
    for label, layer in spec.layers():
        if isinstance(layer, AmorphousLayer) and \
                layer.block.potential_sha256 != potential.sha256:
            raise InputError(f"{label}.block = {layer.block.source or 'the block'} was "
                             f"quenched with potential {layer.block.potential!r}, not with "
                             f"{potential.name!r} of this slab; quench it with "
                             f"{potential.name!r}")


def build_slab(spec: SlabSpec) -> Slab:
    """Stack the substrate and the films, strained laterally to the substrate."""
    sub_cell = spec.substrate.crystal.unit_cell(spec.orientation)
    px, py = sub_cell.cell[0, 0], sub_cell.cell[1, 1]
    target = si_to_lammps(spec.lateral_size, "length")
    nx, ny = max(1, round(target / px)), max(1, round(target / py))
    Lx, Ly = nx * px, ny * py

    pieces, tops, misfits, periods = [], [], [], []
    z_top, below_spacing, surface_depth = None, 0.0, 0.0
    for label, layer in reversed(spec.layers()):          # substrate first, bottom up
        if isinstance(layer, AmorphousLayer):
            cut = cut_film(layer, lammps_to_si(Lx, "length"), lammps_to_si(Ly, "length"),
                           label)
            block, strain = cut.atoms, cut.strain[:2]
            periods.append(cut.period)
            shift = z_top + si_to_lammps(layer.gap, "length")
            top_spacing = surface_depth = si_to_lammps(cut.spacing, "length")
        else:
            block, strain, spacings, period = _crystal_block(layer, label, spec.orientation,
                                                             Lx, Ly)
            periods.append(period)
            # the interface gap: the mean of the two layers' interplanar spacings
            shift = 0.0 if z_top is None else z_top + 0.5 * (below_spacing + spacings[0])
            top_spacing = float(spacings[-1])
            surface_depth = 0.25 * top_spacing
        block.positions[:, 2] += shift
        pieces.append(block)
        z_top = float(block.positions[:, 2].max())
        below_spacing = top_spacing
        tops.append(lammps_to_si(z_top, "length"))
        if label != "substrate":
            misfits.append(strain)

    atoms = pieces[0]
    for block in pieces[1:]:
        atoms += block
    vacuum = si_to_lammps(spec.vacuum, "length")
    atoms.set_cell([Lx, Ly, z_top + vacuum])
    atoms.pbc = (True, True, False)
    atoms.set_masses([atomic_masses[atomic_numbers[s]] for s in atoms.get_chemical_symbols()])

    z = atoms.positions[:, 2]
    top_layer = z > z_top - surface_depth
    z_fixed = si_to_lammps(spec.fixed_thickness, "length")
    z_thermo = z_fixed + si_to_lammps(spec.thermostat_thickness, "length")
    if z_thermo >= z_top - below_spacing:
        raise InputError(
            f"fixed_thickness + thermostat_thickness = "
            f"{spec.fixed_thickness + spec.thermostat_thickness:.4g} m leaves no mobile atoms "
            f"in a slab {lammps_to_si(z_top, 'length'):.4g} m thick")
    symbols = atoms.get_chemical_symbols()
    counts = {e: symbols.count(e) for e in spec.elements}
    return Slab(atoms=atoms, box=(lammps_to_si(Lx, "length"), lammps_to_si(Ly, "length"),
                                  lammps_to_si(z_top + vacuum, "length")),
                z_fixed=spec.fixed_thickness, z_thermostat=lammps_to_si(z_thermo, "length"),
                z_surface=lammps_to_si(float(z[top_layer].mean()), "length"),
                surface_layer_gap=lammps_to_si(below_spacing, "length"),
                layer_tops=tuple(reversed(tops)),
                misfit=tuple(reversed(misfits)),
                lattice_period=tuple(reversed(periods)), element_counts=counts)
