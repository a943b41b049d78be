"""Amorphous films cut from a quenched block (`md.amorphous`), for the slabs of `md.structures`.

A film is a slice of a periodic block. The block is tiled m_x x m_y times laterally (m the
whole number of block edges nearest the slab's box edge) and as often as needed along z,
strained in x and y to the box and along z by 1 / ((1 + e_x)(1 + e_y)) - 1, so that the
film keeps the block's density (`FilmCut.strain` reports the three strains), and the atoms
whose height lies in [0, thickness) are kept. `md.structures.build_slab` places the slice
``gap`` above the highest atom of the layer below. The two cut surfaces carry dangling bonds
until a relaxation (the indentation's minimisation and equilibration, or
`md.film_relax.relax_slab`) rebonds them.

Tiling a periodic block joins it to its own images, so the slice has no seam; a lateral
strain beyond `MAX_STRAIN` is refused (choose a lateral size near a multiple of the block's
edge, or a larger block).

A film may instead name its recipe (`md.amorphous.AmorphousRecipe`): until the block is made
(a store unit, `workflows.amorphous_units`), the layer carries a stand-in block (a simple
cubic lattice of the recipe's atoms in the recipe's box), so that a spec's geometry is
checked before any LAMMPS work; no run starts on a stand-in (`check_made`).
"""

from __future__ import annotations

import hashlib
import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np
from ase import Atoms
from ase.data import atomic_masses, atomic_numbers

from filmscale.core.checks import check_real
from filmscale.core.errors import InputError
from filmscale.md.lammps_units import lammps_to_si, si_to_lammps
from filmscale.potentials.lammps_words import shown

#: the largest lateral strain accepted when the block is fitted to the box
MAX_STRAIN = 0.1
#: the default height of the film's lowest atom above the highest atom below, m: near the
#: C-C bond (1.54 Angstrom); the relaxation sets the interface
DEFAULT_GAP = 1.5e-10
#: the accepted range of ``gap``, m
GAP_RANGE = (5e-11, 5e-10)


class AmorphousBlock:
    """A quenched periodic block: ``element``, ``positions`` (m, in [0, box)), ``box`` (the
    three edges of its orthogonal box, m), the name and SHA-256 of the potential it was
    quenched with, and ``source`` (the record it was read from). Blocks compare equal by
    their content (`checksum`)."""

    def __init__(self, element: str, positions, box, potential: str, potential_sha256: str,
                 source: str = "", stand_in: bool = False):
        if not isinstance(element, str) or element not in atomic_numbers:
            raise InputError(f"element = {shown(element)} is not a chemical element symbol")
        positions = np.asarray(positions, float)
        box = np.asarray(box, float)
        if positions.ndim != 2 or positions.shape[1] != 3 or len(positions) < 1 or \
                box.shape != (3,) or not np.all(box > 0) or not np.all(np.isfinite(positions)):
            raise InputError(f"block = {source or 'the block'} needs (n, 3) positions and "
                             "three positive box edges")
        self.element, self.source, self.stand_in = element, str(source), bool(stand_in)
        self.positions, self.box = np.mod(positions, box), box
        self.potential, self.potential_sha256 = str(potential), str(potential_sha256)
        digest = hashlib.sha256(element.encode())
        digest.update(self.positions.tobytes())
        digest.update(box.tobytes())
        self.checksum = digest.hexdigest()

    @classmethod
    def stand_in_for(cls, recipe) -> AmorphousBlock:
        """A simple cubic lattice of about the recipe's atoms in its box: the geometry of
        the block the recipe will make, for the checks of a spec before its quench."""
        n = max(1, round(recipe.n_atoms ** (1.0 / 3.0)))
        edge = recipe.box_edge
        grid = (np.stack(np.meshgrid(*[np.arange(n)] * 3, indexing="ij"), -1).reshape(-1, 3)
                + 0.5) * edge / n
        return cls(recipe.element, grid, [edge] * 3, recipe.potential.name,
                   recipe.potential.sha256, f"the stand-in of recipe {recipe.name!r}",
                   stand_in=True)

    @property
    def n_atoms(self) -> int:
        return len(self.positions)

    @property
    def density(self) -> float:
        """Mass over box volume, kg/m^3."""
        mass = float(lammps_to_si(atomic_masses[atomic_numbers[self.element]], "mass"))
        return self.n_atoms * mass / float(np.prod(self.box))

    def __eq__(self, other) -> bool:
        return isinstance(other, AmorphousBlock) and other.checksum == self.checksum

    def __hash__(self) -> int:
        return hash(self.checksum)

    def __repr__(self) -> str:
        return (f"AmorphousBlock({self.n_atoms} {self.element}, {self.density:.1f} kg/m^3, "
                f"{self.potential}, {self.source or 'in memory'}, sha256 {self.checksum[:16]})")


@dataclass(frozen=True)
class AmorphousLayer:
    """An amorphous film of ``thickness`` (m) cut from ``block``, its lowest atom ``gap`` (m)
    above the highest atom of the layer below; ``recipe`` when the film is named by the
    recipe that makes its block (the block a stand-in until it is made: `named_by`)."""

    block: AmorphousBlock
    thickness: float
    gap: float = DEFAULT_GAP
    recipe: object = None          #: an `md.amorphous.AmorphousRecipe`, or None
    structure: ClassVar[str] = "amorphous"

    def __post_init__(self):
        if not isinstance(self.block, AmorphousBlock):
            raise InputError(f"block = {shown(self.block)} must be an AmorphousBlock")
        check_real("gap", self.gap, low=GAP_RANGE[0], high=GAP_RANGE[1], unit="m")

    @classmethod
    def named_by(cls, recipe, thickness: float, gap: float = DEFAULT_GAP) -> AmorphousLayer:
        """A film of the block ``recipe`` makes, with a stand-in block until it is made."""
        return cls(AmorphousBlock.stand_in_for(recipe), thickness, gap, recipe)

    @property
    def element(self) -> str:
        return self.block.element

    def to_dict(self) -> dict:
        """The film as a spec's record and unit hash hold it: the block by its checksum (none
        for a stand-in), the recipe by `AmorphousRecipe.to_dict`."""
        return {"structure": self.structure, "thickness": self.thickness, "gap": self.gap,
                "block": None if self.block.stand_in else
                {"sha256": self.block.checksum, "source": self.block.source},
                "recipe": None if self.recipe is None else
                {"name": self.recipe.name, **self.recipe.to_dict()}}


def check_made(layers, where: str) -> None:
    """InputError when a film's block is still the stand-in of its recipe: a run needs the
    quenched block (`workflows.amorphous_units.with_blocks` makes it)."""
    for label, layer in layers:
        if isinstance(layer, AmorphousLayer) and layer.block.stand_in:
            raise InputError(f"{where}: {label} is named by recipe {layer.recipe.name!r}, "
                             "whose block is not made yet; `filmscale md indent`, `md "
                             "scratch` and `run` make it first (workflows.amorphous_units."
                             "with_blocks)")


@dataclass(frozen=True)
class FilmCut:
    """A slice as cut: ``atoms`` in Angstrom from z = 0; ``strain`` (x, y, z) of the block;
    ``copies`` of the block along x, y, z; ``spacing`` the mean interatomic spacing
    (volume per atom)^(1/3), m; ``period`` the strained block's height, m."""

    atoms: Atoms
    strain: tuple[float, float, float]
    copies: tuple[int, int, int]
    spacing: float
    period: float


def cut_film(layer: AmorphousLayer, Lx: float, Ly: float, label: str = "film") -> FilmCut:
    """The slice of ``layer`` for a box of edges ``Lx``, ``Ly`` (m); ``label`` names the
    layer in the messages (InputError for a strain beyond `MAX_STRAIN` or an empty slice)."""
    block = layer.block
    edges = si_to_lammps(block.box, "length")
    copies, strain = [], []
    for axis, L in (("x", Lx), ("y", Ly)):
        edge = float(edges["xy".index(axis)])
        m = max(1, round(si_to_lammps(L, "length") / edge))
        e = si_to_lammps(L, "length") / (m * edge) - 1.0
        if abs(e) > MAX_STRAIN:
            raise InputError(
                f"{label}: the block's edge {lammps_to_si(edge, 'length'):.4g} m fits the box "
                f"edge L{axis} = {L:.4g} m only with a strain of {e:+.3f} (valid: within "
                f"+-{MAX_STRAIN:g}); choose slab.lateral_size near a multiple of the edge")
        copies.append(m)
        strain.append(e)
    ez = 1.0 / ((1.0 + strain[0]) * (1.0 + strain[1])) - 1.0
    height = float(edges[2]) * (1.0 + ez)
    thickness = si_to_lammps(layer.thickness, "length")
    copies.append(max(1, math.ceil(thickness / height)))
    scale = np.array([1.0 + strain[0], 1.0 + strain[1], 1.0 + ez])
    piece = Atoms([block.element] * block.n_atoms,
                  positions=si_to_lammps(block.positions, "length"), cell=edges, pbc=True)
    piece = piece.repeat(copies)
    piece.set_cell(np.diag(piece.cell.lengths() * scale), scale_atoms=True)
    piece = piece[piece.positions[:, 2] < thickness]
    if len(piece) == 0:
        raise InputError(f"{label}.thickness = {layer.thickness:.4g} m holds no atom of the "
                         "block")
    piece.positions[:, 2] -= piece.positions[:, 2].min()
    piece.set_masses([atomic_masses[atomic_numbers[block.element]]] * len(piece))
    spacing = (float(np.prod(block.box)) / block.n_atoms) ** (1.0 / 3.0)
    return FilmCut(atoms=piece, strain=(strain[0], strain[1], ez), copies=tuple(copies),
                   spacing=spacing, period=float(lammps_to_si(height, "length")))
