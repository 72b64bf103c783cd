"""The Timoshenko beam element of the column model: shape functions, stiffness, mass, assembly.

Degrees of freedom per node: lateral displacement ``w`` (m, along ``x``) and cross-section
rotation ``theta`` (rad, positive in the sense of ``dw/dz``). The element uses the
interdependent interpolation (IIE) of Friedman & Kosmatka (1993): cubic ``w`` and
quadratic ``theta`` that solve the homogeneous static Timoshenko equations exactly, with
the shear-deformation parameter ``phi = 12 E I / (kappa G A L^2)``. Hence

* stiffness: the exact Timoshenko element stiffness (Przemieniecki 1968)
  ``EI / ((1 + phi) L^3) [[12, 6L, -12, 6L], [6L, (4 + phi) L^2, -6L, (2 - phi) L^2], ...]``;
  nodal displacements under static point loads are exact for any mesh;
* mass: the consistent mass of the same shape functions,
  ``M = int (rho A N_w^T N_w + rho I N_theta^T N_theta) dz`` (translational and rotary
  inertia), integrated exactly by 4-point Gauss quadrature (Friedman & Kosmatka 1993
  give the same matrix in closed form; the tests compare with it);
* loads: a point force at ``z`` inside an element gives the consistent nodal loads
  ``P N_w(xi)``; with the exact static shape functions the static nodal response is
  exact wherever the load acts.

References
----------
Friedman, Z. & Kosmatka, J.B. (1993). An improved two-node Timoshenko beam finite
    element. Computers & Structures 47(3), 473-481.
Przemieniecki, J.S. (1968). Theory of Matrix Structural Analysis. McGraw-Hill, ch. 5.
Cowper, G.R. (1966). The shear coefficient in Timoshenko's beam theory. J. Appl. Mech.
    33(2), 335-340.
"""

from __future__ import annotations

import math

import numpy as np
from scipy import sparse

from analytical.errors import InputError, require_finite, require_positive

__all__ = ["assemble_beam", "shape_functions", "shear_parameter", "timoshenko_element"]

# 4-point Gauss-Legendre rule on [0, 1]: exact for polynomials of degree <= 7 (the mass
# integrands are of degree 6).
_GAUSS_X, _GAUSS_W = np.polynomial.legendre.leggauss(4)
_GAUSS_X = 0.5 * (_GAUSS_X + 1.0)
_GAUSS_W = 0.5 * _GAUSS_W

# --------------------------------------------------------------------------- element
def shape_functions(xi, length_m: float, phi: float) -> tuple[np.ndarray, np.ndarray]:
    """Interdependent Timoshenko shape functions (Friedman & Kosmatka 1993).

    Parameters
    ----------
    xi:
        Local coordinate(s) ``z / L`` in [0, 1] (scalar or array).
    length_m:
        Element length L (m).
    phi:
        Shear-deformation parameter ``12 E I / (kappa G A L^2)`` (-); 0 gives the
        Euler-Bernoulli (Hermite) element.

    Returns
    -------
    (N_w, N_theta):
        Arrays of shape ``xi.shape + (4,)``; element DOFs are ``(w1, theta1, w2,
        theta2)``. ``w(xi) = N_w . d`` (m), ``theta(xi) = N_theta . d`` (rad).
    """
    x = np.asarray(xi, dtype=float)
    L = float(length_m)
    mu = 1.0 / (1.0 + phi)
    x2, x3 = x * x, x * x * x
    n_w = np.stack(
        [
            mu * (2 * x3 - 3 * x2 - phi * x + 1 + phi),
            L * mu * (x3 - (2 + phi / 2) * x2 + (1 + phi / 2) * x),
            -mu * (2 * x3 - 3 * x2 - phi * x),
            L * mu * (x3 - (1 - phi / 2) * x2 - (phi / 2) * x),
        ],
        axis=-1,
    )
    n_t = np.stack(
        [
            6 * mu / L * (x2 - x),
            mu * (3 * x2 - (4 + phi) * x + 1 + phi),
            -6 * mu / L * (x2 - x),
            mu * (3 * x2 - (2 - phi) * x),
        ],
        axis=-1,
    )
    return n_w, n_t


def shear_parameter(length_m: float, bending_stiffness_Nm2: float, shear_stiffness_N: float) -> float:
    """``phi = 12 E I / (kappa G A L^2)`` of an element of length L; 0 for an infinite shear stiffness."""
    if math.isinf(shear_stiffness_N):
        return 0.0
    return 12.0 * bending_stiffness_Nm2 / (shear_stiffness_N * length_m**2)


def timoshenko_element(
    length_m: float,
    bending_stiffness_Nm2: float,
    shear_stiffness_N: float,
    mass_per_length_kg_m: float,
    rotary_inertia_kg_m: float,
) -> tuple[np.ndarray, np.ndarray]:
    """Stiffness and consistent mass matrices (4 x 4) of one Timoshenko beam element.

    Parameters
    ----------
    length_m:
        Element length L (m), > 0.
    bending_stiffness_Nm2:
        E I (N m^2), > 0.
    shear_stiffness_N:
        kappa G A (N), > 0; ``math.inf`` gives the Euler-Bernoulli element (phi = 0).
    mass_per_length_kg_m:
        rho A (kg/m), > 0.
    rotary_inertia_kg_m:
        rho I (kg m), >= 0; 0 switches rotary inertia off.

    Returns
    -------
    (K, M):
        DOFs ``(w1, theta1, w2, theta2)``; K in N/m, N, N m/rad; M in kg, kg m, kg m^2.
    """
    L = require_positive("length_m", length_m)
    EI = require_positive("bending_stiffness_Nm2", bending_stiffness_Nm2)
    kGA = _positive_or_inf("shear_stiffness_N", shear_stiffness_N)
    rhoA = require_positive("mass_per_length_kg_m", mass_per_length_kg_m)
    rhoI = _non_negative("rotary_inertia_kg_m", rotary_inertia_kg_m)
    phi = shear_parameter(L, EI, kGA)

    c = EI / ((1.0 + phi) * L**3)
    k = c * np.array(
        [
            [12.0, 6 * L, -12.0, 6 * L],
            [6 * L, (4 + phi) * L**2, -6 * L, (2 - phi) * L**2],
            [-12.0, -6 * L, 12.0, -6 * L],
            [6 * L, (2 - phi) * L**2, -6 * L, (4 + phi) * L**2],
        ]
    )
    n_w, n_t = shape_functions(_GAUSS_X, L, phi)
    m = L * (
        rhoA * np.einsum("g,gi,gj->ij", _GAUSS_W, n_w, n_w)
        + rhoI * np.einsum("g,gi,gj->ij", _GAUSS_W, n_t, n_t)
    )
    return k, 0.5 * (m + m.T)


def assemble_beam(
    elements: int,
    length_m: float,
    bending_stiffness_Nm2: float,
    shear_stiffness_N: float,
    mass_per_length_kg_m: float,
    rotary_inertia_kg_m: float,
) -> tuple[sparse.csr_array, sparse.csr_array]:
    """Stiffness and mass of a free (unsupported) beam of equal Timoshenko elements.

    Nodes ``i = 0 .. elements`` at ``z_i = i L / elements``; DOFs interleaved
    ``(w_0, theta_0, w_1, theta_1, ...)``. Returns sparse CSR matrices of size
    ``2 (elements + 1)`` (banded: half-bandwidth 3). Arguments as in
    :func:`timoshenko_element`, with ``length_m`` the whole beam's length.
    """
    n = _element_count("elements", elements)
    k_e, m_e = timoshenko_element(
        require_positive("length_m", length_m) / n,
        bending_stiffness_Nm2,
        shear_stiffness_N,
        mass_per_length_kg_m,
        rotary_inertia_kg_m,
    )
    dof = 2 * np.arange(n)[:, None] + np.arange(4)[None, :]  # (n, 4)
    rows = np.repeat(dof, 4, axis=1).ravel()
    cols = np.tile(dof, (1, 4)).ravel()
    size = 2 * (n + 1)
    k = sparse.coo_array((np.tile(k_e.ravel(), n), (rows, cols)), shape=(size, size)).tocsr()
    m = sparse.coo_array((np.tile(m_e.ravel(), n), (rows, cols)), shape=(size, size)).tocsr()
    return k, m


def _positive_or_inf(name: str, value) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(name, f"must be a number, got {value!r}") from None
    if math.isnan(v) or v <= 0.0:
        raise InputError(name, f"must be > 0 (inf allowed), got {value!r}")
    return v


def _non_negative(name: str, value) -> float:
    v = require_finite(name, value)
    if v < 0.0:
        raise InputError(name, f"must be >= 0, got {value!r}")
    return v


def _element_count(name: str, value) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 1:
        raise InputError(name, f"must be an integer >= 1, got {value!r}")
    return int(value)
