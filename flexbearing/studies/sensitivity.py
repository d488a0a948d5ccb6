"""Variance-based global sensitivity on a surrogate: Sobol' indices, Saltelli's design, a quadratic
surrogate fitted by least squares.

Sample: a scrambled Sobol' sequence (scipy.stats.qmc.Sobol, Owen scrambling) of n points in the
unit cube [0, 1)^d (`unit_sample`).

Indices of f: [0, 1)^d -> R on Saltelli's design (n·(d + 2) evaluations; `sobol_indices`), with
A, B two independent (n, d) samples and A_B^i = A with column i from B:

    first order  S_i  = mean(f(B)·(f(A_B^i) − f(A)))/V              (Saltelli et al., Comput. Phys.
                                                                     Commun. 181 (2010) 259, eq. (b))
    total        ST_i = mean((f(A) − f(A_B^i))²)/(2V)              (Jansen, Comput. Phys. Commun.
                                                                     117 (1999) 35)

V the variance of f over A and B together. Confidence: bootstrap over the design's rows, the
2.5–97.5 % percentiles.

Surrogate (`QuadraticSurrogate`): a quadratic polynomial in the unit coordinates, choice inputs
as indicators of their non-first values, least squares per output on its finite values, with the
leave-one-out residuals e_i/(1 − h_ii) of the hat matrix as its error. The indices computed on it
are those of the surrogate: its LOO error bounds how far they describe the model.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.stats import qmc

from flexbearing.common.validation import InputError


def unit_sample(n: int, d: int, seed: int) -> np.ndarray:
    """(n, d) scrambled Sobol' points in [0, 1)^d (scipy.stats.qmc, Owen scrambling)."""
    if n < 1:
        raise InputError(f"sample size n = {n} is not allowed; allowed: >= 1")
    sob = qmc.Sobol(d, scramble=True, seed=seed)
    m = int(math.log2(n))
    return sob.random_base2(m) if 2 ** m == n else sob.random(n)


def saltelli_matrices(n: int, d: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """(A, B): two independent (n, d) unit samples, the halves of one 2d-dimensional scrambled
    Sobol' sample (Saltelli et al. 2010)."""
    ab = unit_sample(n, 2 * d, seed)
    return ab[:, :d], ab[:, d:]


def sobol_from_values(fa: np.ndarray, fb: np.ndarray, fab: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(S, ST) from f(A) (n,), f(B) (n,), f(A_B^i) (d, n): Saltelli 2010 first order and Jansen
    1999 total (module docstring). V is the variance of f over A and B together."""
    v = np.var(np.concatenate([fa, fb]))
    if v <= 0.0:
        return np.zeros(fab.shape[0]), np.zeros(fab.shape[0])
    s = np.mean(fb[None, :] * (fab - fa[None, :]), axis=1) / v
    st = 0.5 * np.mean((fa[None, :] - fab) ** 2, axis=1) / v
    return s, st


def sobol_indices(f, d: int, n: int = 2 ** 13, seed: int = 0, n_boot: int = 200,
                  rng_seed: int = 1) -> dict:
    """Sobol' indices of f: (m, d) unit points -> (m,) or (m, k) values, on Saltelli's design
    (n·(d + 2) evaluations). Returns {"S", "ST"} of shape (d,) or (k, d) and their bootstrap
    2.5/97.5 % limits "S_ci", "ST_ci" (rows of the design resampled, n_boot times)."""
    a, b = saltelli_matrices(n, d, seed)
    fa, fb = np.asarray(f(a)), np.asarray(f(b))
    fab = []
    for i in range(d):
        abi = a.copy()
        abi[:, i] = b[:, i]
        fab.append(np.asarray(f(abi)))
    fab = np.stack(fab)                           # (d, n) or (d, n, k)
    return sobol_with_bootstrap(fa, fb, fab, n_boot, np.random.default_rng(rng_seed))


def sobol_of_columns(fa, fb, fab, rows=None):
    """sobol_from_values per output column (f of shape (n, k)), on the design rows `rows` (all: None)."""
    if rows is not None:
        fa, fb, fab = fa[rows], fb[rows], fab[:, rows]
    if fa.ndim == 1:
        return sobol_from_values(fa, fb, fab)
    out = [sobol_from_values(fa[:, j], fb[:, j], fab[:, :, j]) for j in range(fa.shape[1])]
    return np.array([o[0] for o in out]), np.array([o[1] for o in out])


def sobol_with_bootstrap(fa, fb, fab, n_boot, rng):
    """The indices and their bootstrap 2.5/97.5 % limits (the design's rows resampled n_boot times)."""
    s, st = sobol_of_columns(fa, fb, fab)
    n = fa.shape[0]
    bs, bst = [], []
    for _ in range(n_boot):
        rows = rng.integers(0, n, n)
        x, y = sobol_of_columns(fa, fb, fab, rows)
        bs.append(x)
        bst.append(y)
    bs, bst = np.array(bs), np.array(bst)
    return {"S": s, "ST": st, "S_ci": np.percentile(bs, [2.5, 97.5], axis=0),
            "ST_ci": np.percentile(bst, [2.5, 97.5], axis=0)}


SURROGATE_FORMS = ("all", "choice", "none")     # QuadraticSurrogate.interactions, preferred first


@dataclass
class QuadraticSurrogate:
    """Quadratic polynomial in the unit coordinates, least squares (module docstring). Choice
    unknowns enter as indicators of their non-first values (no square: an indicator's square is
    itself). interactions: "all" = the full quadratic (every product of two inputs; 27 terms for
    the six unknowns), "choice" = linear and square terms plus the products of the choice with each
    other input (17 terms), "none" = linear and square terms (12 terms: additive, S = ST); the
    smaller forms serve a case with fewer converged points. coef: (p, k) for k outputs."""
    unknowns: tuple
    interactions: str = "all"
    coef: np.ndarray = field(default=None)

    def features(self, u: np.ndarray) -> np.ndarray:
        cols = [np.ones(len(u))]
        lin, is_choice = [], []
        for j, k in enumerate(self.unknowns):
            if k.kind == "choice":
                m = len(k.values)
                idx = np.minimum((u[:, j] * m).astype(int), m - 1)
                lin += [(idx == i).astype(float) for i in range(1, m)]
                is_choice += [True] * (m - 1)
            else:
                lin.append(u[:, j] - 0.5)
                is_choice.append(False)
        cols += lin
        for i in range(len(lin)):
            for j in range(i, len(lin)):
                if i == j and is_choice[i]:
                    continue
                if i != j and (self.interactions == "none" or
                               (self.interactions == "choice" and not (is_choice[i] or is_choice[j]))):
                    continue
                cols.append(lin[i] * lin[j])
        return np.column_stack(cols)

    def n_terms(self) -> int:
        """Number of terms (columns of `features`)."""
        return self.features(unit_sample(8, len(self.unknowns), 0)).shape[1]

    def fit(self, u: np.ndarray, y: np.ndarray) -> "QuadraticSurrogate":
        """Least squares per output column on that column's finite values (NaN = a (point, case)
        that did not converge: each case's fit uses the points where it converged)."""
        x = self.features(u)
        y2 = y.reshape(len(y), -1)
        coef = np.empty((x.shape[1], y2.shape[1]))
        for j in range(y2.shape[1]):
            ok = np.isfinite(y2[:, j])
            coef[:, j] = np.linalg.lstsq(x[ok], y2[ok, j], rcond=None)[0]
        self.coef = coef if y.ndim == 2 else coef[:, 0]
        return self

    def __call__(self, u: np.ndarray) -> np.ndarray:
        return self.features(u) @ self.coef

    def loo_residuals(self, u: np.ndarray, y: np.ndarray) -> np.ndarray:
        """Leave-one-out residuals e_i/(1 − h_ii) (the hat matrix of each column's least-squares
        fit on its finite values; NaN where y is NaN)."""
        x = self.features(u)
        y2 = y.reshape(len(y), -1)
        out = np.full(y2.shape, np.nan)
        for j in range(y2.shape[1]):
            ok = np.isfinite(y2[:, j])
            h = x[ok] @ np.linalg.pinv(x[ok])
            out[ok, j] = (y2[ok, j] - h @ y2[ok, j]) / (1.0 - np.diag(h))
        return out if y.ndim == 2 else out[:, 0]
