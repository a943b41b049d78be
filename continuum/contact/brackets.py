"""Vectorised bracketed root and maximum finding for the impact fast path.

`scipy.optimize.elementwise` does the same (Chandrupatla's method), but importing
scipy.optimize costs 0.45 s, half of the second that a 100 x 100 impact map may take as a
whole command (issue 21; benchmarks/startup.py). These two solvers are what the map needs:
every point's bracket is solved together, in numpy, to a few ulps. Tests compare them with
scipy.optimize.elementwise.

T. R. Chandrupatla, A new hybrid quadratic/bisection algorithm for finding the zero of a
nonlinear function without using derivatives, Adv. Eng. Softw. 28 (1997) 145-149;
J. Kiefer, Sequential minimax search for a maximum, Proc. Am. Math. Soc. 4 (1953) 502-506
(golden-section search). Units are those of the caller's f and x.
"""

from __future__ import annotations

import numpy as np

_EPS = np.finfo(float).eps
_TINY = 4.0 * np.finfo(float).smallest_normal
_INV_PHI = (np.sqrt(5.0) - 1.0) / 2.0     # golden-section ratio, 0.618...


def find_root(f, lo, hi, args=(), *, max_iter=100):
    """x in [lo, hi] with f(x, *args) = 0 at every element, f(lo) and f(hi) of opposite
    signs (or one of them zero), by Chandrupatla's (1997) method: inverse quadratic
    interpolation when the last three points make it safe, bisection otherwise.

    ``f`` takes arrays x and args of the bracket's shape, one element per problem. The result
    is the end of a final bracket narrower than 4 eps |x| (as scipy's default) with
    the smaller |f|, or a zero of f. Raises ValueError when a bracket
    holds no sign change or a problem does not converge in ``max_iter`` steps.
    """
    shape = np.broadcast(lo, hi, *args).shape
    a, b = (np.array(np.broadcast_to(v, shape), dtype=float).ravel() for v in (lo, hi))
    args = tuple(np.broadcast_to(arg, shape).ravel() for arg in args)
    fa, fb = f(a, *args), f(b, *args)
    if np.any(np.sign(fa) * np.sign(fb) > 0) or not np.all(np.isfinite(fa) & np.isfinite(fb)):
        raise ValueError("find_root: f(lo) and f(hi) must be finite and of opposite signs")
    x = np.where(fb == 0, b, a)
    c, fc = a.copy(), fa.copy()
    t = np.full(a.shape, 0.5)
    active = np.nonzero((fa != 0) & (fb != 0))[0]
    for _ in range(max_iter):
        if active.size == 0:
            return x.reshape(shape)
        ak, bk, ck, fak, fbk, fck = a[active], b[active], c[active], fa[active], fb[active], \
            fc[active]
        xt = ak + t[active] * (bk - ak)
        ft = f(xt, *(arg[active] for arg in args))
        same = np.sign(ft) == np.sign(fak)
        # the new point replaces a; the old a moves to b where the sign changed
        ck, fck = np.where(same, ak, bk), np.where(same, fak, fbk)
        bk, fbk = np.where(same, bk, ak), np.where(same, fbk, fak)
        ak, fak = xt, ft
        best_a = np.abs(fak) < np.abs(fbk)
        xm, fm = np.where(best_a, ak, bk), np.where(best_a, fak, fbk)
        width = np.abs(bk - ak)
        tol = 4.0 * _EPS * np.abs(xm) + _TINY
        with np.errstate(divide="ignore", invalid="ignore"):
            tl = 0.5 * tol / width
            xi = (ak - bk) / (ck - bk)
            phi = (fak - fbk) / (fck - fbk)
            iqi = (phi * phi < xi) & ((1.0 - phi) ** 2 < 1.0 - xi)
            t_iqi = (fak / (fbk - fak) * fck / (fbk - fck)
                     + (ck - ak) / (bk - ak) * fak / (fck - fak) * fbk / (fck - fbk))
        tk = np.clip(np.where(iqi, t_iqi, 0.5), tl, 1.0 - tl)
        a[active], b[active], c[active] = ak, bk, ck
        fa[active], fb[active], fc[active] = fak, fbk, fck
        x[active], t[active] = xm, tk
        done = (fm == 0) | (width < tol)
        active = active[~done]
    raise ValueError(f"find_root did not converge at {active.size} point(s) in {max_iter} "
                     f"steps")


def find_maximum(f, lo, mid, hi, args=(), *, xrtol=1e-7):
    """(x, f(x)) at a local maximum of f(x, *args) inside each bracket lo < mid < hi with
    f(mid) >= f(lo), f(hi), by golden-section search.

    Stops when the bracket is narrower than ``xrtol`` |x|: for a smooth peak the value is
    then exact to about xrtol^2 (1e-14 relative at the default). The value returned is the
    largest one evaluated, never below f(mid).
    """
    shape = np.broadcast(lo, mid, hi, *args).shape
    a, x, b = (np.array(np.broadcast_to(v, shape), dtype=float).ravel() for v in (lo, mid, hi))
    args = tuple(np.broadcast_to(arg, shape).ravel() for arg in args)
    fx = f(x, *args)
    active = np.arange(a.size)
    # at most log(1/xrtol) / log(1/0.618) steps once the bracket is within a factor of 2
    steps = int(np.ceil(np.log(xrtol) / np.log(_INV_PHI))) + 60
    for _ in range(steps):
        ak, bk, xk = a[active], b[active], x[active]
        # probe the larger side of the bracket at the golden ratio from the best point
        right = bk - xk > xk - ak
        probe = np.where(right, xk + (1.0 - _INV_PHI) * (bk - xk),
                         xk - (1.0 - _INV_PHI) * (xk - ak))
        fp = f(probe, *(arg[active] for arg in args))
        better = fp > fx[active]
        # better: the probe is the new best and the old best bounds the bracket on its side;
        # worse: the probe bounds the bracket
        new_a = np.where(better, np.where(right, xk, ak), np.where(right, ak, probe))
        new_b = np.where(better, np.where(right, bk, xk), np.where(right, probe, bk))
        a[active], b[active] = new_a, new_b
        x[active] = np.where(better, probe, xk)
        fx[active] = np.where(better, fp, fx[active])
        done = (new_b - new_a <= xrtol * np.abs(x[active])) | ~np.isfinite(fp)
        active = active[~done]
        if active.size == 0:
            break
    return x.reshape(shape), fx.reshape(shape)
