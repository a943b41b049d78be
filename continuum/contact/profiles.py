"""Depth profiles of a target's effective properties: what a sphere pressing to approach delta
feels of a layered (or homogeneous) half-space.

A profile answers ``properties(delta, R) -> (E_p, sigma_y, nu)``: the target's effective
plane-strain modulus E_p = E/(1 - nu^2) (Pa), yield strength (Pa) and Poisson ratio. The impact
model combines E_p with the impactor into the reduced modulus. Three kinds:

- `UniformProfile`: a homogeneous half-space.
- `StackProfile`: a layer stack with the Gao, Chiu & Lee (1992) weights [C2] and their
  multilayer extension [R] (docs/physics.md section 7), at the contact radius a = sqrt(R delta)
  of Hertz contact. Weighted quantities: E_p and sigma_y with I0, nu with I1. The weighting of
  sigma_y is the same heuristic as that of the modulus [R]. Optionally each layer's sigma_y
  carries the Nix-Gao size effect sigma_y sqrt(1 + h*/delta) (Nix & Gao 1998, hardness taken
  proportional to sigma_y, depth read as the approach), so that nanometre (MD) and
  micrometre strengths are one profile.
- `TableProfile`: measured (or simulated) indentation tables (contact depth, E_r, H), fitted
  piecewise linearly and read with contact depth = delta, sigma_y = H / k_T, as in the seed
  dissertation (section 3.5), with k_T the plateau of the contact law in use.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from filmscale.continuum.materials import DIAMOND, ElasticPlastic, LayerStack, check_plausible
from filmscale.core.checks import check_indent_depths, check_modulus, check_positive, check_real
from filmscale.core.errors import InputError

_X_MAX = 1e15   # I0(x), I1(x) equal 1 to double precision well before this


def _material_dict(m: ElasticPlastic) -> dict:
    return {"name": m.name, "E": m.E, "nu": m.nu, "sigma_y": m.sigma_y, "n": m.n}


def _layer_weights(cumulative):
    """Differences of a cumulative weight at the interfaces (last axis): layer shares, then
    the substrate's 1 - I(z_N/a)."""
    zeros = np.zeros(cumulative.shape[:-1] + (1,))
    return np.diff(np.concatenate([zeros, cumulative, zeros + 1.0], axis=-1), axis=-1)


def _gao_terms(x):
    """(2/pi) atan(x) and x ln((1+x^2)/x^2), shared by I0 and I1 (0 at x = 0)."""
    x = np.asarray(x, dtype=float)
    safe = np.where(x > 0, x, 1.0)
    return (2.0 / np.pi) * np.arctan(x), np.where(x > 0, x * np.log1p(1.0 / (safe * safe)), 0.0)


def _i0(x, nu, angle, log_term):
    return angle + ((1.0 - 2.0 * nu) * log_term - x / (1.0 + x * x)) / (2.0 * np.pi * (1.0 - nu))


def gao_i0(x, nu):
    """Gao weight I0(x) for the shear modulus, x = t/a (docs/physics.md section 7):
    (2/pi) atan(x) + [(1-2nu) x ln((1+x^2)/x^2) - x/(1+x^2)] / (2 pi (1-nu)).
    I0(0) = 0, I0(inf) = 1, I0(1, nu=0.3) = 0.4494."""
    x = np.asarray(x, dtype=float)
    return _i0(x, nu, *_gao_terms(x))


def gao_i1(x):
    """Gao weight I1(x) for the Poisson ratio: (2/pi) atan(x) + (x/pi) ln((1+x^2)/x^2).
    I1(1) = 0.7206."""
    angle, log_term = _gao_terms(x)
    return angle + log_term / np.pi


class DepthProfile:
    """Effective target properties against approach delta (m) for a sphere of radius R (m)."""

    #: properties do not depend on delta or R
    uniform: bool = False

    def properties(self, delta, R):
        """(E_p, sigma_y, nu) at approach delta; E_p and sigma_y in Pa."""
        raise NotImplementedError

    def knots(self) -> np.ndarray:
        """Depths (m) where the properties have kinks: quadrature must not straddle them."""
        return np.empty(0)

    def materials(self) -> tuple[ElasticPlastic, ...]:
        """The materials behind the profile (none for a measured table)."""
        return ()

    def describe(self) -> dict:
        raise NotImplementedError


@dataclass(frozen=True)
class UniformProfile(DepthProfile):
    """A homogeneous half-space of one material."""

    material: ElasticPlastic
    uniform = True

    def properties(self, delta, R):
        shape = np.broadcast(delta, R).shape
        m = self.material
        return (np.full(shape, m.plane_strain_modulus), np.full(shape, m.sigma_y),
                np.full(shape, m.nu))

    def materials(self) -> tuple[ElasticPlastic, ...]:
        return (self.material,)

    def describe(self) -> dict:
        return {"kind": "uniform", **_material_dict(self.material)}


@dataclass(frozen=True)
class StackProfile(DepthProfile):
    """Layer stack weighted with Gao's I0 (E_p, sigma_y) and I1 (nu) at a = sqrt(R delta)."""

    stack: LayerStack
    #: Nix-Gao length h* (m) of each layer, top first, then the substrate; missing = 0
    h_star: tuple[float, ...] = ()
    _depths: np.ndarray = field(init=False, repr=False, compare=False)
    _inverse_depths_squared: np.ndarray = field(init=False, repr=False, compare=False)
    #: (E_p, sigma_y, nu) of the material above each interface minus that below
    _jumps: np.ndarray = field(init=False, repr=False, compare=False)
    _a2_min: float = field(init=False, repr=False, compare=False)
    _props: np.ndarray = field(init=False, repr=False, compare=False)

    def __post_init__(self):
        mats = self.stack.materials()
        if len(self.h_star) > len(mats):
            raise InputError(f"h_star has {len(self.h_star)} values for {len(mats)} materials "
                             "(layers and substrate)")
        h_star = tuple(check_real(f"h_star[{i}]", h, low=0.0, high=1e-3, unit="m")
                       for i, h in enumerate(self.h_star))
        object.__setattr__(self, "h_star", h_star + (0.0,) * (len(mats) - len(h_star)))
        object.__setattr__(self, "_depths", np.asarray(self.stack.interface_depths, dtype=float))
        object.__setattr__(self, "_inverse_depths_squared", self._depths**-2.0)
        object.__setattr__(self, "_a2_min",
                           (self._depths[0] / _X_MAX) ** 2 if self._depths.size else 0.0)
        object.__setattr__(self, "_props", np.array(
            [[m.plane_strain_modulus for m in mats], [m.sigma_y for m in mats],
             [m.nu for m in mats]]))
        object.__setattr__(self, "_jumps", self._props[:, :-1] - self._props[:, 1:])

    def _interface_terms(self, delta, R):
        """(shape, x, (2/pi) atan x, x ln((1+x^2)/x^2), x/(1+x^2)) at every interface (last
        axis) for the broadcast points flattened to rows: x = z_k/a with a^2 = R delta,
        floored where z_1/a would pass 1e15 (I0 = I1 = 1 to double precision there), so the
        surface, delta = 0, has the top layer's properties."""
        a2 = np.asarray(R) * np.asarray(delta, dtype=float)
        shape = a2.shape
        a2 = np.maximum(a2.reshape(-1, 1), self._a2_min)
        x = self._depths * (1.0 / np.sqrt(a2))
        return (shape, x, (2.0 / np.pi) * np.arctan(x),
                x * np.log1p(a2 * self._inverse_depths_squared), x / (1.0 + x * x))

    def weights(self, delta, R):
        """(I1 weights, I0 weights) of each layer and the substrate (last axis), each summing
        to 1; I0 uses the I1-weighted Poisson ratio."""
        shape, x, angle, log_term, _ = self._interface_terms(delta, R)
        w1 = _layer_weights(angle + log_term / np.pi)
        w0 = _layer_weights(_i0(x, (w1 @ self._props[2])[:, None], angle, log_term))
        return w1.reshape(shape + w1.shape[-1:]), w0.reshape(shape + w0.shape[-1:])

    def strengths(self, delta):
        """Each material's sigma_y at approach delta (last axis), Pa, Nix-Gao scaled."""
        s_y = self._props[1]
        if not any(self.h_star):
            return s_y
        return s_y * np.sqrt(1.0 + np.asarray(self.h_star)
                             / np.asarray(delta, dtype=float)[..., None])

    def properties(self, delta, R):
        s_y = self.strengths(delta)
        if self._depths.size == 0:
            e, _, nu = UniformProfile(self.stack.substrate).properties(delta, R)
            return e, np.broadcast_to(s_y[..., -1], e.shape).copy(), nu
        # The impact map's hot loop. sum_j w_j p_j with w_j = C_(j+1) - C_j (C_0 = 0,
        # C_(N+1) = 1) telescopes to p_N + sum_k C_k (p_(k-1) - p_k) over the N interfaces:
        # three small matrix products, no (points x materials) weights as in `weights`
        shape, x, angle, log_term, bend = self._interface_terms(delta, R)
        # rows (E_p, sigma_y, nu) of jumps x sums over the interfaces: contiguous per quantity
        angle_sum, log_sum = self._jumps @ angle.T, self._jumps @ log_term.T
        e_base, s_base, nu_base = self._props[:, -1]
        nu = nu_base + angle_sum[2] + log_sum[2] / np.pi
        c = 1.0 / (2.0 * np.pi * (1.0 - nu))
        log_weight = c * (1.0 - 2.0 * nu)
        if any(self.h_star):
            cumulative = angle + log_weight[:, None] * log_term - c[:, None] * bend
            s_y = np.broadcast_to(s_y, shape + s_y.shape[-1:]).reshape(-1, s_y.shape[-1])
            sigma = s_y[:, -1] + np.sum(cumulative * (s_y[:, :-1] - s_y[:, 1:]), axis=-1)
            e_p = e_base + cumulative @ self._jumps[0]
        else:
            bend_sum = self._jumps[:2] @ bend.T
            e_p = e_base + angle_sum[0] + log_weight * log_sum[0] - c * bend_sum[0]
            sigma = s_base + angle_sum[1] + log_weight * log_sum[1] - c * bend_sum[1]
        return e_p.reshape(shape), sigma.reshape(shape), nu.reshape(shape)

    def materials(self) -> tuple[ElasticPlastic, ...]:
        return self.stack.materials()

    def describe(self) -> dict:
        return {"kind": "stack", "weighting": "gao-multilayer",
                "contact_radius": "sqrt(R delta)", "nix_gao_h_star": list(self.h_star),
                "layers": [{"thickness": lay.thickness, **_material_dict(lay.material)}
                           for lay in self.stack.layers],
                "substrate": _material_dict(self.stack.substrate)}


@dataclass(frozen=True)
class TableProfile(DepthProfile):
    """Piecewise-linear properties between ``depths`` (m), constant beyond the end knots."""

    depths: np.ndarray          #: knots, m, increasing
    plane_strain_modulus: np.ndarray  #: E_p at the knots, Pa
    hardness: np.ndarray        #: H at the knots, Pa
    hardness_factor: float      #: k_T in sigma_y = H / k_T
    nu: float                   #: Poisson ratio of the target (one value)
    fit_std: dict = field(default_factory=dict)  #: residual std of each fit (Pa)

    def properties(self, delta, R):
        delta = np.broadcast_to(np.asarray(delta, dtype=float), np.broadcast(delta, R).shape)
        e_p = np.interp(delta, self.depths, self.plane_strain_modulus)
        s_y = np.interp(delta, self.depths, self.hardness) / self.hardness_factor
        return e_p, s_y, np.full(delta.shape, self.nu)

    def knots(self) -> np.ndarray:
        return np.asarray(self.depths)

    def describe(self) -> dict:
        return {"kind": "table", "depths": list(map(float, self.depths)),
                "E_p": list(map(float, self.plane_strain_modulus)),
                "H": list(map(float, self.hardness)), "hardness_factor": self.hardness_factor,
                "nu": self.nu, "fit_std": dict(self.fit_std)}

    @classmethod
    def from_measurements(cls, h_c, E_r, H, *, breakpoints=(), indenter=DIAMOND, nu=0.3,
                          hardness_factor=2.8) -> "TableProfile":
        """Fit measured (h_c, E_r, H) with continuous piecewise-linear least squares.

        Parameters
        ----------
        h_c, E_r, H : array_like
            Contact depth (m), reduced modulus (Pa) and hardness (Pa) of each indent.
        breakpoints : sequence of float
            Depths (m) where the slope may change, e.g. layer interfaces; those outside the
            measured depth range are dropped. None given: one straight line.
        indenter : ElasticPlastic or None
            The indenter that E_r was measured against (diamond by default); None if E_r is
            already against a rigid indenter.
        nu : float
            Poisson ratio of the target, used by the yield criteria of the contact laws.
        hardness_factor : float
            k_T in sigma_y = H / k_T; pass the contact law's ``hardness_factor``.

        The profile never leaves the range of its data: each knot's value of E_p and H is
        clipped to [min, max] of the measured values of the indents in the pieces that meet
        at that knot (the indents its value is fitted from), so a least-squares line cannot
        dip below (or rise above) every indent near it, nor go to zero.
        """
        h_c, E_r, H = (np.asarray(v, dtype=float) for v in (h_c, E_r, H))
        if not (h_c.ndim == E_r.ndim == H.ndim == 1):
            raise InputError("profile table columns h_c, E_r and H must be 1-D arrays")
        if not (h_c.size == E_r.size == H.size):
            raise InputError(f"profile table columns differ in length: h_c {h_c.size}, "
                             f"E_r {E_r.size}, H {H.size}")
        if h_c.size < 2:
            raise InputError(f"profile table needs at least 2 rows, got {h_c.size}")
        for name, values in (("h_c", h_c), ("E_r", E_r), ("H", H)):
            bad = ~np.isfinite(values) | (values <= 0)
            if bad.any():
                raise InputError(f"profile table {name} has {values[bad][0]!r} at row "
                                 f"{int(np.argmax(bad))}: values must be finite and > 0")
        check_indent_depths("profile table h_c", h_c)
        for row in (int(np.argmin(E_r)), int(np.argmax(E_r))):
            check_modulus(f"profile table E_r[{row}]", E_r[row], "reduced modulus")
        hard = H >= E_r
        if hard.any():
            row = int(np.argmax(hard))
            raise InputError(f"profile table H = {H[row]:.4g} Pa at row {row} is not below "
                             f"E_r = {E_r[row]:.4g} Pa: no solid is harder than its modulus "
                             f"(H/E_r stays below about 0.2); check the units of H")
        nu = check_real("profile nu", nu, low=-1.0, high=0.5, low_open=True, high_open=True)
        hardness_factor = check_positive("hardness_factor", hardness_factor)
        e_p = 1.0 / E_r if indenter is None else 1.0 / E_r - indenter.compliance
        if np.any(e_p <= 0):
            raise InputError(f"profile table E_r = {E_r[e_p <= 0][0]:.4g} Pa is not below "
                             f"what the {indenter.name or 'given'} indenter allows "
                             f"({1.0 / indenter.compliance:.4g} Pa)")
        e_p = 1.0 / e_p
        lo, hi = float(h_c.min()), float(h_c.max())
        if hi <= lo:
            raise InputError("profile table h_c must span more than one depth")
        inner = [float(b) for b in breakpoints if lo < float(b) < hi]
        knots = np.unique(np.array([lo, *inner, hi]))
        basis = np.stack([np.interp(h_c, knots, np.eye(knots.size)[k])
                          for k in range(knots.size)], axis=1)
        if np.linalg.matrix_rank(basis) < knots.size:
            raise InputError(f"profile breakpoints {inner} leave a depth range without "
                             f"enough indents to fit a line")
        fits, std = [], {}
        for name, values in (("E_p", e_p), ("H", H)):
            coef = _clip_to_pieces(np.linalg.lstsq(basis, values, rcond=None)[0], knots,
                                   h_c, values)
            fits.append(coef)
            std[name] = float(np.std(values - basis @ coef))
        return cls(depths=knots, plane_strain_modulus=fits[0], hardness=fits[1],
                   hardness_factor=hardness_factor, nu=nu, fit_std=std)


def _clip_to_pieces(coef, knots, h_c, values):
    """Each knot's value clipped to [min, max] of ``values`` at the indents between its
    neighbouring knots (the support of its piecewise-linear basis function)."""
    out = coef.copy()
    for k in range(knots.size):
        lo, hi = knots[max(k - 1, 0)], knots[min(k + 1, knots.size - 1)]
        near = values[(h_c >= lo) & (h_c <= hi)]
        out[k] = np.clip(coef[k], near.min(), near.max())
    return out


def profile_for(target) -> DepthProfile:
    """A profile for a material, a stack (uniform when it has no layers) or a profile."""
    if isinstance(target, DepthProfile):
        return target
    if isinstance(target, ElasticPlastic):
        return UniformProfile(target)
    if isinstance(target, LayerStack):
        return UniformProfile(target.substrate) if target.is_homogeneous else StackProfile(target)
    raise InputError(f"target must be a material, a layer stack or a depth profile, "
                     f"got {type(target).__name__}")


def checked_bodies(target, impactor) -> DepthProfile:
    """The target as a profile, with every material of target and impactor checked for
    plausibility (`check_plausible`); ``impactor`` is an ElasticPlastic or None (rigid)."""
    profile = profile_for(target)
    for material in profile.materials():
        check_plausible(material, material.name or "target")
    if impactor is not None:
        if not isinstance(impactor, ElasticPlastic):
            raise InputError(f"impactor must be an ElasticPlastic material or None "
                             f"(rigid), got {type(impactor).__name__}")
        check_plausible(impactor, impactor.name or "impactor")
    return profile
