"""Sub-surface damage from atoms: the atomic von Mises (local shear) strain and the plastically
deformed region per layer of a slab.

Atomic strain (Shimizu, Ogata & Li, Mater. Trans. 48, 2923 (2007); the same definition as
OVITO's "Atomic strain" modifier): for atom i with neighbours j within ``cutoff`` of it in the
reference configuration, d0_j = X_j - X_i and d_j = x_j - x_i (minimum image in the periodic
directions) are row vectors and the local transformation matrix J_i minimises
sum_j |d0_j J_i - d_j|^2:

    J_i = (sum_j d0_j^T d0_j)^-1 (sum_j d0_j^T d_j)

so that d ~ d0 J, i.e. J = F^T with F the deformation gradient of column vectors. The
Lagrangian strain is eta_i = (J_i J_i^T - I) / 2 = (F^T F - I) / 2 and the von Mises shear
invariant

    eta_Mises = sqrt(eta_yz^2 + eta_xz^2 + eta_xy^2
                     + ((eta_yy - eta_zz)^2 + (eta_xx - eta_zz)^2 + (eta_xx - eta_yy)^2) / 6)

It is exact (to rounding) for any homogeneous deformation, whatever the neighbour set, as long
as the neighbours of an atom are not coplanar; an atom whose reference neighbours do not span
three dimensions gets NaN.

The damaged region: atoms with eta_Mises above ``threshold`` (default `THRESHOLD`), assigned
to the layer of the slab they sat in in the reference configuration (by height, from the
slab's ``layer_tops``). Per layer, ``width`` is the extent in y of its damaged atoms
(max - min of their y, in the reference configuration, measured from the groove axis with the
minimum image across the periodic y boundary) and ``depth`` how far below the undeformed
surface the deepest of them sat (z_surface - min z0; an atom of the top atomic layer has depth
0); zeros where a layer has no damaged atom. max - min, not a percentile range, because the
region is the set of atoms over a stated strain and its full extent is what chapter 7 compares
with the groove; at the low temperature of the runs (10 K) thermal strain is far below the
threshold, so isolated outliers do not arise.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np
from scipy.spatial import cKDTree

#: eta_Mises above which an atom counts as plastically deformed. 0.1 is the usual choice for
#: metals: a crystal cannot hold an elastic shear beyond its ideal shear strain (about 0.14
#: engineering strain for Cu, Ogata et al., Science 298, 807 (2002): eta_Mises ~ 0.07), and
#: thermal strain at the runs' 10 K is near 0.005, while an atom next to a slipped plane (a
#: partial dislocation's shear of 1/sqrt(6) a over a plane spacing) carries 0.1 or more.
THRESHOLD = 0.1


def von_mises(eta: np.ndarray) -> np.ndarray:
    """The von Mises invariant of strain tensors eta (..., 3, 3) (Shimizu 2007, eq. 7)."""
    e = eta
    return np.sqrt(e[..., 1, 2] ** 2 + e[..., 0, 2] ** 2 + e[..., 0, 1] ** 2
                   + ((e[..., 1, 1] - e[..., 2, 2]) ** 2 + (e[..., 0, 0] - e[..., 2, 2]) ** 2
                      + (e[..., 0, 0] - e[..., 1, 1]) ** 2) / 6.0)


def _periodic(box, pbc) -> np.ndarray:
    """Per-direction period (inf where not periodic)."""
    if box is None:
        return np.full(3, np.inf)
    box = np.asarray(box, float)
    pbc = np.asarray(pbc, bool)
    return np.where(pbc, box, np.inf)


def _min_image(d: np.ndarray, period: np.ndarray) -> np.ndarray:
    finite = np.isfinite(period)
    if np.any(finite):
        p = period[finite]
        d = d.copy()
        d[:, finite] -= p * np.round(d[:, finite] / p)
    return d


def neighbour_pairs(x0: np.ndarray, cutoff: float, box=None,
                    pbc=(True, True, False)) -> np.ndarray:
    """Every ordered pair (i, j), i != j, within ``cutoff`` in ``x0`` (N, 3), with the box
    edges ``box`` (3,) periodic where ``pbc`` says (``box`` None: no periodicity)."""
    period = _periodic(box, pbc)
    pts = np.asarray(x0, float).copy()
    lo = pts.min(axis=0)
    pts -= lo
    size = np.empty(3)
    for k in range(3):
        if np.isfinite(period[k]):
            if cutoff >= 0.5 * period[k]:
                raise ValueError(f"cutoff {cutoff} is not below half the period "
                                 f"{period[k]} along axis {k}")
            pts[:, k] %= period[k]
            size[k] = period[k]
        else:                  # a box wide enough that nothing wraps
            size[k] = pts[:, k].max() + 2.0 * cutoff + 1.0
    tree = cKDTree(pts, boxsize=size)
    pairs = tree.query_pairs(cutoff, output_type="ndarray")
    return np.concatenate([pairs, pairs[:, ::-1]])


def atomic_strain(x0: np.ndarray, x: np.ndarray, cutoff: float, box=None,
                  pbc=(True, True, False), box_current=None) -> np.ndarray:
    """eta_Mises of every atom (N,), from reference positions ``x0`` and current ``x`` (N, 3;
    the same atoms in the same order, any length unit, ``cutoff`` in it). ``box`` (3,) gives
    the reference periods where ``pbc``; ``box_current`` the current ones (default: the same).
    NaN for an atom whose reference neighbours are coplanar (or fewer than three)."""
    x0, x = np.asarray(x0, float), np.asarray(x, float)
    if x0.shape != x.shape or x0.ndim != 2 or x0.shape[1] != 3:
        raise ValueError("x0 and x must both be (N, 3) arrays of the same atoms")
    n = len(x0)
    pairs = neighbour_pairs(x0, cutoff, box, pbc)
    i, j = pairs[:, 0], pairs[:, 1]
    d0 = _min_image(x0[j] - x0[i], _periodic(box, pbc))
    d = _min_image(x[j] - x[i], _periodic(box if box_current is None else box_current, pbc))
    V = np.zeros((n, 9))
    W = np.zeros((n, 9))
    outer0 = (d0[:, :, None] * d0[:, None, :]).reshape(-1, 9)
    outer = (d0[:, :, None] * d[:, None, :]).reshape(-1, 9)
    for k in range(9):                       # sums over each atom's pairs, per component
        V[:, k] = np.bincount(i, outer0[:, k], minlength=n)
        W[:, k] = np.bincount(i, outer[:, k], minlength=n)
    V, W = V.reshape(n, 3, 3), W.reshape(n, 3, 3)
    # coplanar or too few neighbours: V singular (relative to its own scale)
    scale = np.maximum(np.trace(V, axis1=1, axis2=2), np.finfo(float).tiny)
    ok = np.abs(np.linalg.det(V)) > 1e-8 * scale ** 3
    out = np.full(n, np.nan)
    if np.any(ok):
        J = np.linalg.solve(V[ok], W[ok])
        eta = 0.5 * (J @ np.swapaxes(J, 1, 2) - np.eye(3))
        out[ok] = von_mises(eta)
    return out


#: neighbours an amorphous layer's cutoff encloses on average (`amorphous_cutoff`): the bcc
#: shell's count, enough for a well-posed fit where the first shell is planar (sp2)
AMORPHOUS_NEIGHBOURS = 14


def shell_cutoff(structure: str, a: float) -> float:
    """A neighbour cutoff between two neighbour shells of a crystal of lattice constant a:
    fcc between the 1st (a/sqrt 2) and 2nd (a) shells, 12 neighbours; bcc between the 2nd (a)
    and 3rd (a sqrt 2) shells, 14; hcp (ideal) between a and a sqrt 2, 12; diamond between
    the 2nd (a/sqrt 2) and 3rd (a sqrt 11 / 4) shells, 16."""
    if structure == "fcc":
        return 0.5 * (1.0 / math.sqrt(2.0) + 1.0) * a
    if structure in ("bcc", "hcp"):
        return 0.5 * (1.0 + math.sqrt(2.0)) * a
    if structure == "diamond":
        return 0.5 * (1.0 / math.sqrt(2.0) + math.sqrt(11.0) / 4.0) * a
    raise ValueError(f"structure {structure!r} is not fcc, bcc, hcp or diamond")


def amorphous_cutoff(number_density: float, neighbours: int = AMORPHOUS_NEIGHBOURS) -> float:
    """The radius whose sphere holds ``neighbours`` atoms on average at ``number_density``
    (atoms per unit volume; the radius comes in the inverse unit's length): an amorphous
    layer has no shells to fall between."""
    return (3.0 * neighbours / (4.0 * math.pi * number_density)) ** (1.0 / 3.0)


@dataclass(frozen=True)
class LayerDamage:
    """The damaged region of one layer (SI): ``width`` its extent in y, ``depth`` how far below
    the undeformed surface its deepest atom sat, ``atoms`` how many atoms it holds."""

    layer: str
    width: float
    depth: float
    atoms: int

    def to_dict(self) -> dict:
        return asdict(self)


def layer_index(z0: np.ndarray, layer_tops) -> np.ndarray:
    """The layer (0: top film, ..., last: substrate) of each reference height z0, from each
    layer's top (``layer_tops``, top layer first, as `Slab.layer_tops`): an atom belongs to the
    lowest layer whose top is not below it."""
    tops = np.asarray(layer_tops, float)[::-1]            # substrate first, ascending
    tol = 1e-6 * (np.abs(tops).max() if tops.size else 1.0)
    below = np.searchsorted(tops + tol, np.asarray(z0, float), side="left")
    return len(tops) - 1 - np.minimum(below, len(tops) - 1)


def damaged_region(x0: np.ndarray, eta: np.ndarray, layers: list[str], layer_of: np.ndarray,
                   z_surface: float, y_axis: float, period_y: float | None = None,
                   threshold: float = THRESHOLD, select: np.ndarray | None = None
                   ) -> list[LayerDamage]:
    """Per layer, the atoms with eta > ``threshold`` (among ``select``, default all): width in
    y (max - min of y0 measured from ``y_axis``, minimum image when ``period_y``) and depth
    below ``z_surface`` (z_surface - min z0), both in the unit of ``x0``; zeros where a layer
    has none."""
    x0 = np.asarray(x0, float)
    hit = np.nan_to_num(eta, nan=0.0) > threshold
    if select is not None:
        hit &= select
    dy = x0[:, 1] - y_axis
    if period_y:
        dy -= period_y * np.round(dy / period_y)
    out = []
    for k, name in enumerate(layers):
        m = hit & (layer_of == k)
        if not np.any(m):
            out.append(LayerDamage(name, 0.0, 0.0, 0))
            continue
        out.append(LayerDamage(name, float(dy[m].max() - dy[m].min()),
                               float(max(0.0, z_surface - x0[m, 2].min())), int(m.sum())))
    return out
