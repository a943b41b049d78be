"""A ridge-regularised polynomial surrogate of the reverse analysis, fitted to the packaged FE
cases: it maps (ln(c* C h_m / (dP/dh)), W_p/W_t) to ln(c* E* h_m / (dP/dh)), replacing the
Pi4/Pi5 area route where most of the closed form's E* error arises; sigma_0.033 then follows
from Dao's Pi1 as in the closed form."""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np
from scipy.spatial import Delaunay

from filmscale.continuum.indentation.reverse.data import fe_reverse_cases
from filmscale.continuum.indentation.reverse.functions import (SURROGATE_DEGREES,
                                                               SURROGATE_FALLBACK, SURROGATE_RIDGES,
                                                               SURROGATE_SELECTION_FOLDS,
                                                               SURROGATE_SELECTION_REPEATS,
                                                               SURROGATE_SELECTION_SEED)

# --- surrogate --------------------------------------------------------------------------------

def surrogate_features(C, S, W, hm, c_star):
    """Surrogate inputs: ln(c* C h_m / (dP/dh)) and W_p/W_t (c* takes out the tip's shape)."""
    C, S, W, hm = np.broadcast_arrays(*(np.asarray(a, dtype=float) for a in (C, S, W, hm)))
    return np.stack([np.log(c_star * C * hm / S), W], axis=-1)


def _targets(E_star, sigma_r, C, S, hm, c_star):
    """ln(c* E* h_m / (dP/dh)) (= ln(h_m / sqrt(A_m))) and ln(sigma_0.033 / C)."""
    return np.stack([np.log(c_star * E_star * hm / S), np.log(sigma_r / C)], axis=-1)


def _design(Z, degree):
    return np.stack([Z[:, 0] ** i * Z[:, 1] ** j for i in range(degree + 1)
                     for j in range(degree + 1 - i)], axis=-1)


def _ridge_solve(XtX, Xty, ridge):
    """Ridge coefficients; the constant term (column 0) is not shrunk."""
    A = XtX + ridge * np.eye(XtX.shape[0])
    A[0, 0] -= ridge
    return np.linalg.solve(A, Xty)


@dataclass(frozen=True)
class _PolyRidge:
    """Ridge-regularised polynomial of total degree ``degree`` on standardised inputs."""

    mean: np.ndarray
    scale: np.ndarray
    degree: int
    ridge: float
    coef: np.ndarray

    @classmethod
    def fit(cls, F, y, degree, ridge):
        mean, scale = F.mean(axis=0), F.std(axis=0)
        X = _design((F - mean) / scale, degree)
        return cls(mean, scale, degree, ridge, _ridge_solve(X.T @ X, X.T @ y, ridge))

    def predict(self, F):
        return _design((F - self.mean) / self.scale, self.degree) @ self.coef


def grouped_folds(groups, k, seed):
    """Fold index per case: whole groups shuffled by ``seed`` (int or int sequence), dealt
    round-robin."""
    rng = np.random.default_rng(seed)
    order = rng.permutation(np.unique(groups))
    fold_of = np.empty(order.max() + 1, dtype=int)
    fold_of[order] = np.arange(order.size) % k
    return fold_of[groups]


def select_hyperparameters(F, y, groups, seed):
    """(degree, ridge) minimising the median |relative error| of exp(y) in grouped 5-fold CV,
    averaged over SURROGATE_SELECTION_REPEATS splits (seeds [seed, r]) to steady the choice.

    Same fits as `_PolyRidge.fit`, sharing each fold's standardisation and normal equations
    across the grid.
    """
    grid = [(d, r) for d in SURROGATE_DEGREES for r in SURROGATE_RIDGES]
    score = np.zeros(len(grid))
    for rep in range(SURROGATE_SELECTION_REPEATS):
        folds = grouped_folds(groups, SURROGATE_SELECTION_FOLDS, [seed, rep])
        pred = np.empty((len(grid), y.size))
        for f in range(SURROGATE_SELECTION_FOLDS):
            te = folds == f
            mean, scale = F[~te].mean(axis=0), F[~te].std(axis=0)
            Ztr, Zte = (F[~te] - mean) / scale, (F[te] - mean) / scale
            for degree in SURROGATE_DEGREES:
                Xtr, Xte = _design(Ztr, degree), _design(Zte, degree)
                XtX, Xty = Xtr.T @ Xtr, Xtr.T @ y[~te]
                for ridge in SURROGATE_RIDGES:
                    pred[grid.index((degree, ridge)), te] = Xte @ _ridge_solve(XtX, Xty, ridge)
        score += np.median(np.abs(np.expm1(pred - y)), axis=1)
    return grid[int(np.argmin(score))]


@dataclass(frozen=True)
class _Surrogate:
    models: tuple[_PolyRidge, _PolyRidge]   #: ln(c* E* h_m/(dP/dh)); fallback ln(sigma/C)
    hull: Delaunay                          #: training inputs, to flag extrapolation

    def predict(self, F):
        F = np.atleast_2d(F)
        return np.stack([m.predict(F) for m in self.models], axis=-1)

    def inside(self, F) -> bool:
        return bool(np.all(self.hull.find_simplex(np.atleast_2d(F)) >= 0))


def train_surrogate(F, Y, groups, seed, hyper=None) -> _Surrogate:
    """Fit on (F, Y); ``hyper`` = (degree, ridge) of the E* polynomial, else selected."""
    if hyper is None:
        hyper = select_hyperparameters(F, Y[:, 0], groups, seed)
    return _Surrogate((_PolyRidge.fit(F, Y[:, 0], *hyper),
                       _PolyRidge.fit(F, Y[:, 1], *SURROGATE_FALLBACK)), Delaunay(F))


def fe_training_data():
    """(FE cases, surrogate features, targets) of the packaged FE cases the surrogate is
    trained and cross-validated on."""
    d = fe_reverse_cases()
    F = surrogate_features(d["C"], d["dPdh"], d["WpWt"], d["h_m"], d["c_star"])
    Y = _targets(d["E_star"], d["sigma_r"], d["C"], d["dPdh"], d["h_m"], d["c_star"])
    return d, F, Y


@functools.cache
def deployed_surrogate() -> _Surrogate:
    """The deployed surrogate: all FE cases, hyper-parameters by repeated grouped 5-fold CV."""
    d, F, Y = fe_training_data()
    return train_surrogate(F, Y, d["group"], SURROGATE_SELECTION_SEED)


def surrogate_hyperparameters() -> dict:
    """Degree and ridge of the deployed surrogate's E* polynomial and of the fallback
    regression of sigma_0.033, and the number of training cases."""
    s = deployed_surrogate()
    return {"E_star": {"degree": s.models[0].degree, "ridge": s.models[0].ridge},
            "sigma_r_fallback": {"degree": s.models[1].degree, "ridge": s.models[1].ridge},
            "cases": int(s.hull.points.shape[0])}
