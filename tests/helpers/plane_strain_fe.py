"""A plane-strain finite-element model of a film bonded on a substrate under the sliding Hertz
tractions, written with scikit-fem: the independent oracle of
tests/continuum/test_sliding_fe.py for `continuum.contact.sliding_layered`.

Units: lengths in b (the contact half-width), stresses in p0, moduli scaled by the
substrate's E (the stresses of a traction-loaded body depend on modulus ratios only).
Coordinates (x, z): x the sliding direction, z >= 0 the depth (scikit-fem's second coordinate;
the body lies in 0 <= z <= depth). Tension positive.

Model
-----
- Domain: the rectangle [-half_width, half_width] x [0, depth], a tensor-product mesh of
  biquadratic (Q2, 9-node) quadrilaterals whose rows include z = h, so the film (z < h) and the
  substrate share the interface's nodes (perfect bonding), each element one material.
- Grading: the node spacing is the smallest of `size(x) = h_k + growth * distance(x, I_k)`
  over features (interval I_k, size h_k): in x the contact edges x = +-b (where the load's
  square root sits) and the core |x| <= 2b; in z the surface, the interface and the core
  z <= 2b + h. Away from them the spacing grows by `growth` per unit length (about a
  geometric ratio 1 + growth), up to the far boundary.
- Load: the top face carries the traction (mu p, p), p = sqrt(1 - x^2) (b = p0 = 1), i.e.
  sigma_zz = -p, tau_xz = -mu p as in the package; mesh nodes sit at x = +-1 so the root is at
  a facet end, integrated with Gauss order `load_order` per facet.
- Far boundary (the sides and the bottom): the traction of the Flamant line-load solution of a
  half-space (Johnson 1985, eqs 2.15 and 2.21) for P' = pi/2 (the Hertz resultant) and
  Q' = mu P' at the origin; its stresses do not depend on the elastic constants. The far field
  of the layered body is Flamant's up to terms O(P' b^2/R^3) (the load's spread) and
  O(P' h/R^2) (the film), so the truncation error falls fast with the domain size R.
  The problem is then a pure traction one in equilibrium; three displacement components at
  the bottom corners remove the rigid-body motions (their reactions are the quadrature's
  imbalance, ~3e-8 P' from the square root at x = +-b, checked by `reaction`).
- Normal and tangential loads are solved separately on one factorisation and superposed.
- Stresses at any point: from the gradient of the FE displacement in the element holding the
  point (on a mesh line the element on the requested side: `side="below"`, larger z, or
  "above"), Hooke's law of that element's material; sigma_yy = nu (sigma_xx + sigma_zz).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.sparse.linalg import splu

FLAMANT_P = math.pi / 2          # the Hertz resultant P' = pi p0 b / 2 (b = p0 = 1)


def graded_nodes(lo, hi, features, growth, refine=1.0, samples=20_000):
    """Nodes on [lo, hi]; spacing min_k (h_k + growth * dist(x, [a_k, c_k])) / refine for
    features (a_k, c_k, h_k); every feature end inside (lo, hi) is a node."""
    def size(x):
        s = np.full_like(x, np.inf)
        for a, c, h in features:
            d = np.maximum(np.maximum(a - x, x - c), 0.0)
            s = np.minimum(s, h + growth * d)
        return s / refine

    breaks = sorted({lo, hi, *(v for a, c, _ in features for v in (a, c) if lo < v < hi)})
    nodes = [np.array([lo])]
    for a, c in zip(breaks[:-1], breaks[1:]):
        t = np.linspace(a, c, samples)
        f = 1.0 / size(t)
        cum = np.concatenate(([0.0], np.cumsum(0.5 * (f[1:] + f[:-1]) * np.diff(t))))
        n = max(int(math.ceil(cum[-1])), 1)
        nodes.append(np.interp(np.linspace(0.0, cum[-1], n + 1)[1:], cum, t))
    out = np.concatenate(nodes)
    out[-1] = hi
    return out


def flamant_stresses(x, z, P, Q):
    """Flamant line load (P into the body, Q in +x) at the origin: (sxx, szz, txz)."""
    r4 = (x * x + z * z) ** 2
    c = -2.0 / (math.pi * r4)
    return (c * (P * x * x * z + Q * x ** 3), c * (P * z ** 3 + Q * x * z * z),
            c * (P * x * z * z + Q * x * x * z))


def lame(E, nu):
    """Plane-strain Lame constants (lambda, G)."""
    return E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))


@dataclass
class FilmFE:
    """The solved model: `stresses(x, z, mu, side)` gives the FE field (units p0)."""

    xs: np.ndarray
    zs: np.ndarray
    h: float
    mats: tuple            # ((E, nu) film, (E, nu) substrate), E scaled
    basis: object
    u_normal: np.ndarray   # displacement under p alone (and the far Flamant P')
    u_tang: np.ndarray     # under q = p alone (and the far Flamant Q' = P'), per unit mu
    ndofs: int
    reaction: float        # largest rigid-body constraint reaction / P'
    hertz_load: np.ndarray  # [[Fx, Fz] of the normal load, [Fx, Fz] of the tangential]

    def _grad(self, u, x, z, side):
        nx, nz = self.xs.size - 1, self.zs.size - 1
        ix = np.clip(np.searchsorted(self.xs, x, side="right") - 1, 0, nx - 1)
        zside = "right" if side == "below" else "left"
        iz = np.clip(np.searchsorted(self.zs, z, side=zside) - 1, 0, nz - 1)
        cells = iz + ix * nz                       # MeshQuad.init_tensor's element order
        mesh, basis = self.basis.mesh, self.basis
        ctr = mesh.p[:, mesh.t[:, cells]].mean(axis=1)
        assert np.all(np.abs(ctr[0] - 0.5 * (self.xs[ix] + self.xs[ix + 1])) < 1e-9)
        assert np.all(np.abs(ctr[1] - 0.5 * (self.zs[iz] + self.zs[iz + 1])) < 1e-9)
        pts = basis.mapping.invF(np.vstack((x, z))[:, :, None], tind=cells)
        G = np.zeros((2, 2, x.size))
        for k in range(basis.Nbfun):
            g = basis.elem.gbasis(basis.mapping, pts, k, tind=cells)[0].grad[..., 0]
            G += u[basis.element_dofs[k, cells]] * g
        return G, iz

    def stresses(self, x, z, mu, side="below"):
        x, z = (np.asarray(a, float).ravel() for a in np.broadcast_arrays(x, z))
        if side not in ("below", "above"):
            raise ValueError(side)
        G, iz = self._grad(self.u_normal + mu * self.u_tang, x, z, side)
        film = 0.5 * (self.zs[iz] + self.zs[iz + 1]) < self.h
        E = np.where(film, self.mats[0][0], self.mats[1][0])
        nu = np.where(film, self.mats[0][1], self.mats[1][1])
        lam, G_ = lame(E, nu)
        exx, ezz, exz = G[0, 0], G[1, 1], 0.5 * (G[0, 1] + G[1, 0])
        sxx = lam * (exx + ezz) + 2 * G_ * exx
        szz = lam * (exx + ezz) + 2 * G_ * ezz
        zero = np.zeros_like(sxx)
        return {"sxx": sxx, "szz": szz, "txz": 2 * G_ * exz, "syy": nu * (sxx + szz),
                "sxy": zero, "syz": zero}


def solve_film(h, film, substrate, half_width=80.0, depth=80.0, refine=1.0,
               h_core=0.05, h_edge=0.005, h_surface=0.01, h_interface=0.02, growth=0.2,
               load_order=24) -> FilmFE:
    """Solve the film (thickness h, in b) on a substrate; film and substrate are (E, nu)
    with E in any common unit. ``refine`` divides every mesh spacing."""
    from skfem import (Basis, BilinearForm, ElementQuad2, ElementVector, FacetBasis,
                       LinearForm, MeshQuad, asm)

    E_ref = substrate[0]
    mats = ((film[0] / E_ref, film[1]), (substrate[0] / E_ref, substrate[1]))
    xs = graded_nodes(-half_width, half_width,
                      [(-1.0, -1.0, h_edge), (1.0, 1.0, h_edge), (-2.0, 2.0, h_core)],
                      growth, refine)
    zs = graded_nodes(0.0, depth, [(0.0, 0.0, h_surface), (h, h, h_interface),
                                   (0.0, 2.0 + h, h_core)], growth, refine)
    mesh = MeshQuad.init_tensor(xs, zs)
    e = ElementVector(ElementQuad2())
    zc = mesh.p[1, mesh.t].mean(axis=0)

    def elastic(E, nu):
        lam, G = lame(E, nu)

        @BilinearForm
        def form(u, v, w):
            du, dv = u.grad, v.grad
            return (lam * (du[0, 0] + du[1, 1]) * (dv[0, 0] + dv[1, 1])
                    + 2 * G * (du[0, 0] * dv[0, 0] + du[1, 1] * dv[1, 1])
                    + G * (du[0, 1] + du[1, 0]) * (dv[0, 1] + dv[1, 0]))
        return form

    K = None
    for (E, nu), sel in zip(mats, (zc < h, zc > h)):
        Kj = asm(elastic(E, nu), Basis(mesh, e, elements=np.nonzero(sel)[0]))
        K = Kj if K is None else K + Kj
    basis = Basis(mesh, e)

    def near(a, v):
        return np.abs(a - v) < 1e-9

    top = mesh.facets_satisfying(lambda p: near(p[1], 0.0) & (np.abs(p[0]) < 1.0))
    far = mesh.facets_satisfying(lambda p: near(p[1], depth) | near(np.abs(p[0]), half_width))
    fb_top = FacetBasis(mesh, e, facets=top, intorder=load_order)
    fb_far = FacetBasis(mesh, e, facets=far, intorder=8)

    def hertz(direction):
        @LinearForm
        def form(v, w):
            p = np.sqrt(np.clip(1.0 - w.x[0] ** 2, 0.0, None))
            return p * np.asarray(v)[direction]
        return form

    def flamant(P, Q):
        @LinearForm
        def form(v, w):
            sxx, szz, txz = flamant_stresses(w.x[0], w.x[1], P, Q)
            n = w.n
            return ((sxx * n[0] + txz * n[1]) * np.asarray(v)[0]
                    + (txz * n[0] + szz * n[1]) * np.asarray(v)[1])
        return form

    h_n, h_t = asm(hertz(1), fb_top), asm(hertz(0), fb_top)
    ix, iz = basis.split_indices()
    hertz_load = np.array([[h.sum() for h in (h_n[ix], h_n[iz])],
                           [h.sum() for h in (h_t[ix], h_t[iz])]])
    f_n = h_n + asm(flamant(FLAMANT_P, 0.0), fb_far)
    f_t = h_t + asm(flamant(0.0, FLAMANT_P), fb_far)

    # rigid-body modes: both components at (-W, D), u_z at (+W, D)
    nd = basis.nodal_dofs
    c0 = int(np.nonzero(near(mesh.p[0], -half_width) & near(mesh.p[1], depth))[0][0])
    c1 = int(np.nonzero(near(mesh.p[0], half_width) & near(mesh.p[1], depth))[0][0])
    fixed = np.array([nd[0, c0], nd[1, c0], nd[1, c1]])
    K = K.tocsr()
    F = np.column_stack((f_n, f_t))
    free = np.setdiff1d(np.arange(K.shape[0]), fixed)
    lu = splu(K[free][:, free].tocsc(), permc_spec="MMD_AT_PLUS_A")
    U = np.zeros_like(F)
    U[free] = lu.solve(F[free])
    reaction = float(np.max(np.abs((K @ U - F)[fixed]))) / FLAMANT_P
    return FilmFE(xs, zs, float(h), mats, basis, U[:, 0], U[:, 1], K.shape[0], reaction,
                  hertz_load)
