"""Symmetric band matrices in LAPACK/BLAS upper band storage: conversion, Cholesky, solve.

The column's Timoshenko model (interleaved ``w, theta`` DOFs, two-node elements) has a
half-bandwidth of 3; its Newmark integrators (:mod:`analytical.newmark`,
:mod:`analytical.contact_integration`) and its statics factorise such matrices once and then
solve or multiply in band storage (LAPACK ``dpbtrf``/``dpbtrs``, BLAS ``dsbmv``).
"""

from __future__ import annotations

import numpy as np
from scipy import sparse
from scipy.linalg import lapack

__all__ = ["BANDWIDTH", "upper_band", "banded_cholesky", "cholesky_band", "banded_solve"]

#: Half-bandwidth of the assembled matrices (interleaved w, theta DOFs, two-node elements).
BANDWIDTH = 3


def upper_band(matrix, band: int = BANDWIDTH) -> np.ndarray:
    """Upper banded storage (LAPACK/BLAS layout, ``ab[band + i - j, j] = A[i, j]``)."""
    coo = sparse.coo_array(matrix)
    n = matrix.shape[0]
    upper = coo.row <= coo.col
    r, c, d = coo.row[upper], coo.col[upper], coo.data[upper]
    if np.any(c - r > band):
        raise ValueError(f"matrix bandwidth exceeds {band}")  # pragma: no cover - internal invariant
    ab = np.zeros((band + 1, n))
    np.add.at(ab, (band + r - c, c), d)
    return ab


def banded_cholesky(matrix) -> np.ndarray:
    """Upper banded Cholesky factor (LAPACK dpbtrf layout) of a symmetric band matrix."""
    return cholesky_band(upper_band(matrix))


def cholesky_band(ab: np.ndarray) -> np.ndarray:
    """Upper banded Cholesky factor of a matrix already in upper band storage."""
    chol, info = lapack.dpbtrf(ab, lower=0)
    if info != 0:
        raise np.linalg.LinAlgError(f"banded Cholesky failed (info={info}): matrix not positive definite")
    return chol


def banded_solve(chol: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Solve ``A x = b`` with the upper banded Cholesky factor of ``A``."""
    x, info = lapack.dpbtrs(chol, np.asarray(b, float)[:, None])
    if info != 0:  # pragma: no cover - only on malformed input
        raise np.linalg.LinAlgError(f"banded solve failed (info={info})")
    return x[:, 0]
