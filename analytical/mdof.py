"""MDOF model of the impacted column: Timoshenko beam elements, base shear at the load cell.

The column (:class:`analytical.column.Column`) is a cantilever of ``column.elements``
equal two-node Timoshenko beam elements (seed section 3.2.2: 160 elements, consistent
mass, Rayleigh damping, Newmark constant average acceleration). A point force ``P(t)``
(a pulse from :mod:`analytical.pulses`) acts along ``+x`` at a height ``z`` above the base,
and the output is the *base shear*: the force the column transmits to its base support
(the load cell), positive in the load direction.

Element
-------
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

Supports
--------
``base="rigid"`` fixes both base DOFs (the seed's MDOF). ``base="calibrated"`` fixes the
base displacement and restrains the base rotation by a rotational spring ``k_theta``
(N m/rad) found with Brent's method so that the model's first frequency equals
``column.natural_frequency_Hz`` (the measured 70 Hz; the rigid-base beam gives about
88 Hz). Damping is Rayleigh, ``C = a0 M + a1 K``, with
``column.damping_ratio`` on modes 1 and 2 of the model (Chopra 2017, section 11.4).

Base shear: which formula and why
---------------------------------
Two exact, algebraically identical expressions exist for the force ``V`` the beam
applies to the support (``F`` = nodal loads over all DOFs, ``e`` = rigid translation,
1 on every ``w`` DOF, 0 on every ``theta`` DOF, ``0`` = the constrained base ``w``):

* reaction:    ``V = F_0 - (K_0f u + C_0f v + M_0f a)``  (row 0 of the unconstrained
  equations of motion);
* equilibrium: ``V = P(t) - e^T M (a + a0 v)``  (sum of all ``w`` rows; ``e^T K = 0``
  because a rigid translation strains nothing, and ``e^T C = a0 e^T M``).

Both are computed by the Newmark integrator (their agreement to round-off is tested).
The model reports the **equilibrium** form. In modal superposition it is the
*mode-acceleration* method (Chopra 2017, 12.12): a mode left out contributes no inertia
``a + a0 v`` but its static share of the load is still carried through ``P(t)``, so no
separate static correction is needed, ``V = P`` exactly for a slowly applied load with any
number of modes, and the peak converges much faster with the number of modes than with the
reaction (mode-displacement) form, whose truncated modes would each lose their static
share ``K_0f phi_n q_n``. With all modes both forms are the same number. (``a0 e^T M v`` is
the mass-proportional Rayleigh force; it is part of the model's C and so of its support
reaction; ``a0 / omega_1`` is about ``2 zeta``, so it is small.)

Time integration
----------------
``method="modal"``: modal superposition, exact per mode: underdamped modes with
:func:`analytical.sdof.oscillator_response`, the overdamped high modes that Rayleigh damping
produces (``zeta_n = a0 / (2 omega_n) + a1 omega_n / 2`` exceeds 1 above about 10 kHz for
the seed's column) with the real-root closed form of :func:`_overdamped_response`; the
number of modes is chosen adaptively (see :func:`mdof_response`). ``method="newmark"``:
direct integration of the full equations with Newmark's constant average acceleration
(beta = 1/4, gamma = 1/2; Chopra 2017, Table 15.3.3), the effective stiffness factorised
once (banded Cholesky, LAPACK ``dpbtrf``/``dpbtrs``; BLAS ``dsbmv`` products), the output
interpolated linearly onto the requested times.

References
----------
Chopra, A.K. (2017). Dynamics of Structures, 5th ed. Pearson. (Rayleigh damping 11.4;
    modal analysis ch. 12-13, mode-acceleration superposition 12.12; Newmark 5.4, 15.3.)
Friedman, Z. & Kosmatka, J.B. (1993). An improved two-node Timoshenko beam finite
    element. Computers & Structures 47(3), 473-481.
Przemieniecki, J.S. (1968). Theory of Matrix Structural Analysis. McGraw-Hill, ch. 5.
Cowper, G.R. (1966). The shear coefficient in Timoshenko's beam theory. J. Appl. Mech.
    33(2), 335-340.
Joynt et al. (2021) and the seed study, section 3.2.2 (160 elements, dt = 1e-6 s).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np
from scipy import linalg, sparse
from scipy.linalg import blas, lapack
from scipy.optimize import brentq

from analytical.column import Column
from analytical.errors import InputError, require_finite, require_positive
from analytical.sdof import ForceResponse, oscillator_response

__all__ = [
    "METHODS",
    "ColumnModel",
    "NewmarkHistory",
    "assemble_beam",
    "column_model",
    "lateral_stiffness",
    "mdof_response",
    "modes",
    "newmark_history",
    "shape_functions",
    "static_deflection",
    "timoshenko_element",
]

#: Accepted values of ``method`` in :func:`mdof_response`.
METHODS = ("modal", "newmark")

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


def _shear_parameter(length_m: float, bending_stiffness_Nm2: float, shear_stiffness_N: float) -> float:
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
    phi = _shear_parameter(L, EI, kGA)

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


# --------------------------------------------------------------------------- model
@dataclass(frozen=True, eq=False)
class ColumnModel:
    """Assembled MDOF model of a :class:`Column` (cached by :func:`column_model`).

    Matrices are over the free DOFs (supports applied), sparse CSR, in SI units
    (K: N/m, N, N m/rad; M: kg, kg m, kg m^2; C: N s/m ...). Arrays are read-only; the
    sparse matrices are shared by every user of the cached model: do not modify them.

    Attributes
    ----------
    column:
        The column this model describes.
    node_height_m:
        Node heights above the base (m), ``elements + 1`` values.
    free_dofs:
        Indices of the free DOFs in the interleaved full DOF vector
        ``(w_0, theta_0, w_1, theta_1, ...)``.
    stiffness, mass, damping:
        Free-DOF K (including the base spring), consistent M and Rayleigh C.
    beam_stiffness_full, mass_full:
        Unsupported beam K (no spring) and M over all DOFs; row 0 gives the base
        reaction.
    base_spring_Nm_rad:
        Calibrated base rotational stiffness k_theta (N m/rad); None for a rigid base.
    rayleigh_a0_1_s, rayleigh_a1_s:
        Rayleigh coefficients of ``C = a0 M + a1 K`` (1/s and s).
    frequencies_Hz:
        Undamped natural frequencies, ascending (Hz), one per free DOF.
    mode_shapes:
        Mass-normalised mode shapes (``Phi^T M Phi = I``), one column per frequency, sign
        chosen so the top displacement is >= 0.
    damping_ratios:
        Modal damping ratios of the Rayleigh damping, ``a0/(2 w) + a1 w / 2`` (-).
    inertia_vector:
        ``(e^T M_full)`` restricted to the free DOFs (kg, kg m): the base shear is
        ``P(t) - inertia_vector . (a + a0 v)``.
    """

    column: Column
    node_height_m: np.ndarray
    free_dofs: np.ndarray
    stiffness: sparse.csr_array
    mass: sparse.csr_array
    damping: sparse.csr_array
    beam_stiffness_full: sparse.csr_array
    mass_full: sparse.csr_array
    base_spring_Nm_rad: float | None
    rayleigh_a0_1_s: float
    rayleigh_a1_s: float
    frequencies_Hz: np.ndarray
    mode_shapes: np.ndarray
    damping_ratios: np.ndarray
    inertia_vector: np.ndarray
    _cache: dict = field(default_factory=dict, repr=False)

    @property
    def circular_frequencies_rad_s(self) -> np.ndarray:
        """Undamped natural circular frequencies (rad/s), ascending."""
        return 2.0 * math.pi * self.frequencies_Hz

    def load_vector(self, height_m: float) -> np.ndarray:
        """Consistent nodal loads (full DOFs) of a unit force along +x at ``height_m``.

        ``0 < height_m <= column.height_m``; a point force at ``z`` in element ``e`` at
        local ``xi`` gives ``N_w(xi)`` on that element's four DOFs (N, N m per N).
        """
        z = _load_height(self.column, height_m)
        n = self.column.elements
        le = self.column.height_m / n
        e = min(int(z / le), n - 1)
        xi = min(max(z / le - e, 0.0), 1.0)
        n_w, _ = shape_functions(xi, le, _column_phi(self.column))
        f = np.zeros(2 * (n + 1))
        f[2 * e : 2 * e + 4] = n_w
        return f


def _column_phi(column: Column) -> float:
    le = column.height_m / column.elements
    return _shear_parameter(le, column.bending_stiffness_Nm2, column.shear_stiffness_N)


@lru_cache(maxsize=32)
def column_model(column: Column) -> ColumnModel:
    """Assemble (once per distinct ``column``; cached) the MDOF model of ``column``.

    Builds the Timoshenko cantilever, applies the base (rigid, or calibrated rotational
    spring), solves the generalised eigenproblem ``K phi = w^2 M phi``
    (:func:`scipy.linalg.eigh`) and sets Rayleigh damping on modes 1 and 2.

    Raises
    ------
    InputError
        ``column`` is not a Column; or ``base="calibrated"`` with a target frequency the
        rotational spring cannot reach (at or above the rigid-base f1).
    """
    if not isinstance(column, Column):
        raise InputError("column", f"must be an analytical.column.Column, got {type(column).__name__}")
    n = column.elements
    k_full, m_full = assemble_beam(
        n,
        column.height_m,
        column.bending_stiffness_Nm2,
        column.shear_stiffness_N,
        column.mass_per_length_kg_m,
        column.rotary_inertia_kg_m,
    )
    size = 2 * (n + 1)
    if column.base == "rigid":
        free = np.arange(2, size)
    else:
        free = np.arange(1, size)
    k_beam = k_full[free][:, free].toarray()
    m_ff = m_full[free][:, free].toarray()

    spring = None
    if column.base == "calibrated":
        spring = _calibrate_base_spring(column, k_beam, m_ff)
        k_beam[0, 0] += spring
    w2, phi = linalg.eigh(k_beam, m_ff, driver="gvd")
    w2 = np.clip(w2, 0.0, None)
    omega = np.sqrt(w2)
    top = phi[-2, :]
    phi = phi * np.where(top < 0.0, -1.0, 1.0)[None, :]

    # Rayleigh damping with zeta on modes 1 and 2 (Chopra 2017, eq. 11.4.9); every model
    # has at least two free DOFs, hence two modes.
    zeta = column.damping_ratio
    w1, w2_ = omega[0], omega[1]
    a0 = 2.0 * zeta * w1 * w2_ / (w1 + w2_)
    a1 = 2.0 * zeta / (w1 + w2_)
    ratios = a0 / (2.0 * omega) + a1 * omega / 2.0

    k_ff = sparse.csr_array(k_beam)
    m_sp = sparse.csr_array(m_ff)
    c_ff = (a0 * m_sp + a1 * k_ff).tocsr()
    e = np.zeros(size)
    e[0::2] = 1.0
    inertia = (m_full.T @ e)[free]

    arrays = dict(
        node_height_m=np.linspace(0.0, column.height_m, n + 1),
        free_dofs=free,
        frequencies_Hz=omega / (2.0 * math.pi),
        mode_shapes=phi,
        damping_ratios=ratios,
        inertia_vector=inertia,
    )
    for a in arrays.values():
        a.setflags(write=False)
    return ColumnModel(
        column=column,
        stiffness=k_ff,
        mass=m_sp,
        damping=c_ff,
        beam_stiffness_full=k_full,
        mass_full=m_full,
        base_spring_Nm_rad=spring,
        rayleigh_a0_1_s=float(a0),
        rayleigh_a1_s=float(a1),
        **arrays,
    )


def _calibrate_base_spring(column: Column, k_beam: np.ndarray, m_ff: np.ndarray) -> float:
    """k_theta (N m/rad) on the base rotation (free DOF 0) giving f1 = natural_frequency_Hz.

    Brent's method on ``log10 k_theta``; each trial f1 comes from inverse iteration with
    the banded Cholesky factor of K (a few banded solves instead of a dense eigen-solve).
    """
    target = column.natural_frequency_Hz
    k_band = _upper_band(k_beam)
    m_band = _upper_band(m_ff)
    start = _banded_solve(_cholesky_band(k_band[:, 1:].copy()), m_ff[1:, :] @ _lateral(len(m_ff)))

    def f1(log_k: float) -> float:
        band = k_band.copy()
        band[-1, 0] += 10.0**log_k
        return _first_frequency_Hz(band, m_band, np.concatenate([[0.0], start]))

    f_rigid = _first_frequency_Hz(k_band[:, 1:].copy(), m_band[:, 1:].copy(), start)
    if not target < f_rigid * (1.0 - 1e-9):
        raise InputError(
            "column.natural_frequency_Hz",
            f"must be below the rigid-base first frequency {f_rigid:.4g} Hz for base='calibrated', "
            f"got {target!r}",
        )
    ref = math.log10(column.bending_stiffness_Nm2 / column.height_m)
    lo, hi = ref - 4.0, ref + 2.0
    while f1(hi) < target:
        hi += 2.0
        if hi > ref + 30.0:  # pragma: no cover - f1 -> f_rigid > target as k -> inf
            raise InputError("column.natural_frequency_Hz", f"cannot be reached by a base spring: {target!r}")
    while f1(lo) > target:
        lo -= 4.0
        if lo < ref - 40.0:
            raise InputError("column.natural_frequency_Hz", f"too low to be reached by a base spring: {target!r}")
    log_k = brentq(lambda s: f1(s) - target, lo, hi, xtol=1e-14, rtol=4 * np.finfo(float).eps, maxiter=200)
    return 10.0**log_k


def _lateral(size: int) -> np.ndarray:
    """Unit lateral translation over free DOFs that start with a rotation (calibrated base)."""
    e = np.zeros(size)
    e[1::2] = 1.0
    return e


def _first_frequency_Hz(k_band: np.ndarray, m_band: np.ndarray, start: np.ndarray) -> float:
    """Lowest natural frequency (Hz) of banded K, M by inverse iteration (Rayleigh quotient).

    Converges by the factor ``(w1 / w2)^2`` (about 0.06 for the column) per iteration in
    the vector and its square in the eigenvalue.
    """
    chol = _cholesky_band(k_band)
    x = start / math.sqrt(abs(float(start @ blas.dsbmv(_BANDWIDTH, 1.0, m_band, start))))
    previous = math.inf
    for _ in range(200):
        y = _banded_solve(chol, blas.dsbmv(_BANDWIDTH, 1.0, m_band, x))
        my = blas.dsbmv(_BANDWIDTH, 1.0, m_band, y)
        ymy = float(y @ my)
        rayleigh = float(y @ blas.dsbmv(_BANDWIDTH, 1.0, k_band, y)) / ymy
        x = y / math.sqrt(ymy)
        if abs(rayleigh - previous) <= 1e-15 * rayleigh:
            break
        previous = rayleigh
    return math.sqrt(max(rayleigh, 0.0)) / (2.0 * math.pi)


def modes(column: Column) -> np.ndarray:
    """Natural frequencies (Hz, ascending) of the column's MDOF model (a read-only array).

    The seed's column (rigid base, 160 elements) gives f1 = 88.36 Hz, f2 = 360.3 Hz,
    f3 = 762.4 Hz; an Euler-Bernoulli cantilever with the same E I and rho A would have
    f1 = 1.8751^2 sqrt(E I / (rho A H^4)) / (2 pi) = 100.5 Hz: shear deformation (kappa =
    0.5) and rotary inertia lower it. ``base="calibrated"`` returns f1 =
    ``column.natural_frequency_Hz``.
    """
    return column_model(column).frequencies_Hz


# --------------------------------------------------------------------------- statics
def static_deflection(column: Column, load_height_m: float, at_height_m: float, force_N: float = 1.0) -> float:
    """Static lateral deflection (m) at ``at_height_m`` under ``force_N`` at ``load_height_m``.

    Timoshenko statics for the model's support (rigid, or the calibrated base spring);
    positive along the load. ``0 < load_height_m <= H``, ``0 <= at_height_m <= H``. Nodal
    values are exact wherever the load acts; between nodes the element's shape functions
    interpolate, which is exact except inside the element that carries the load.
    """
    model = column_model(column)
    f = model.load_vector(load_height_m)[model.free_dofs] * require_finite("force_N", force_N)
    u = _static_solve(model, f)
    return _deflection_at(model, u, at_height_m)


def lateral_stiffness(column: Column, height_m: float) -> float:
    """Static lateral stiffness (N/m) of the model at ``height_m``: force / deflection there."""
    return 1.0 / static_deflection(column, height_m, height_m, 1.0)


def _static_solve(model: ColumnModel, f: np.ndarray) -> np.ndarray:
    chol = model._cache.get("k_chol")
    if chol is None:
        chol = _banded_cholesky(model.stiffness)
        model._cache["k_chol"] = chol
    return _banded_solve(chol, f)


def _deflection_at(model: ColumnModel, u_free: np.ndarray, z: float) -> float:
    column = model.column
    z = require_finite("at_height_m", z)
    if not 0.0 <= z <= column.height_m * (1 + 1e-12):
        raise InputError("at_height_m", f"must be in [0, {column.height_m:g}] m, got {z!r}")
    n = column.elements
    u = np.zeros(2 * (n + 1))
    u[model.free_dofs] = u_free
    le = column.height_m / n
    e = min(int(z / le), n - 1)
    xi = min(max(z / le - e, 0.0), 1.0)
    n_w, _ = shape_functions(xi, le, _column_phi(column))
    return float(n_w @ u[2 * e : 2 * e + 4])


# --------------------------------------------------------------------------- responses
def mdof_response(
    pulse,
    column: Column,
    height_m: float,
    t,
    method: str | None = None,
    n_modes: int | None = None,
    dt: float | None = None,
) -> ForceResponse:
    """Base shear (N) at the load cell of ``column`` hit by ``pulse`` at ``height_m``.

    The column is at rest before the pulse; the force acts along +x.

    Parameters
    ----------
    pulse:
        An impact pulse (:mod:`analytical.pulses`): ``.force(t)`` in N, t in s.
    column:
        The column (its MDOF model is built once and cached).
    height_m:
        Load height above the base (m), ``0 < height_m <= column.height_m``.
    t:
        Output times (s), 1-D, strictly increasing.
    method:
        ``"modal"``: exact modal superposition (mode-acceleration form, see the module
        docstring); it needs damped modes. ``"newmark"``: direct Newmark
        constant-average-acceleration integration of the full matrices. None (default):
        modal for a damped column, Newmark for an undamped one (``damping_ratio = 0``).
    n_modes:
        Modal only: number of lowest modes (1 .. number of free DOFs); default None
        chooses them adaptively: all modes below 2 kHz (at least 10), then further bands
        of doubling frequency until two bands in a row each change the base shear by less
        than 1e-5 of its peak (or all modes are in). Smooth pulses stop at about 8 kHz;
        pulses with jumps (rectangular) take all modes. Either way the peak agrees with
        fine-step Newmark to about 1e-5 (benchmarks/mdof_convergence.md), well inside
        0.1 %.
    dt:
        Newmark only: time step (s); default None chooses one for 0.1 % in the peak (see
        :func:`newmark_history`). The grid starts one step before the pulse (or at the
        first output time if earlier) and the output is interpolated linearly onto ``t``.

    Returns
    -------
    ForceResponse
        ``time_s = t``, ``response_N`` = base shear, positive in the load direction.
    """
    if method is None:
        method = "modal" if column.damping_ratio > 0.0 or n_modes is not None else "newmark"
    if method not in METHODS:
        raise InputError("method", f"must be one of {', '.join(METHODS)}; got {method!r}")
    times = _times("t", t)
    model = column_model(column)
    if method == "newmark":
        if n_modes is not None:
            raise InputError("n_modes", "applies to method='modal' only")
        start = min(float(times[0]), _pulse_start(pulse, float(times[0])))
        hist = newmark_history(pulse, column, height_m, float(times[-1]), dt=dt, start_s=start)
        shear = np.interp(times, hist.time_s, hist.base_shear_N)
        return ForceResponse(times, shear, direction=_direction(pulse))
    if dt is not None:
        raise InputError("dt", "applies to method='newmark' only")
    shear = _modal_base_shear(model, pulse, height_m, times, n_modes)
    return ForceResponse(times, shear, direction=_direction(pulse))


def _modal_weights(model: ColumnModel, height_m: float) -> np.ndarray:
    """Per-mode weights c_n = (inertia . phi_n)(phi_n . f): V = P - sum c_n (q''_n + a0 q'_n)."""
    weights = model._cache.setdefault("weights", {})
    key = float(height_m)
    c = weights.get(key)
    if c is None:
        f = model.load_vector(height_m)[model.free_dofs]
        c = (model.inertia_vector @ model.mode_shapes) * (f @ model.mode_shapes)
        if len(weights) >= 256:  # many heights (e.g. a fit varying the height): keep it bounded
            weights.clear()
        weights[key] = c
    return c


def _modal_block(model: ColumnModel, pulse, times: np.ndarray, weights: np.ndarray, idx: np.ndarray, end) -> np.ndarray:
    """``sum_n c_n (q''_n + a0 q'_n)`` over the modes ``idx`` at ``times`` (increasing), N.

    Underdamped modes (zeta < 1) use :func:`analytical.sdof.oscillator_response`; the
    overdamped ones that Rayleigh damping gives the high modes use
    :func:`_overdamped_response`. Once the pulse has ended (``end``, s) a mode only rings
    down, as ``exp(-s tau)`` with ``s`` its slowest decay rate, so each mode is evaluated
    only up to ``end + 25 / s`` (a decay to 1e-11): the many short-lived high modes cost
    little.
    """
    out = np.zeros(times.size)
    if idx.size == 0:
        return out
    omega = model.circular_frequencies_rad_s[idx]
    zeta = model.damping_ratios[idx]
    over = zeta >= 1.0
    rate = np.where(over, omega * (zeta - np.sqrt(np.where(over, zeta * zeta - 1.0, 0.0))), zeta * omega)
    if end is None:
        counts = np.full(idx.size, times.size)
    else:
        counts = np.searchsorted(times, end + _RING_DOWN / rate, side="right")
    # Group the modes by kind and by the (rounded up to a power of 2) number of samples.
    bins = np.ceil(np.log2(np.maximum(counts, 1))).astype(int)
    a0 = model.rayleigh_a0_1_s
    atoms = None
    for kind in (False, True):
        for b in np.unique(bins[over == kind]):
            sel = (bins == b) & (over == kind)
            n = int(counts[sel].max())
            if n == 0:
                continue
            if kind:
                if atoms is None:
                    atoms = tuple(pulse.atoms())
                qd, qdd = _overdamped_response(atoms, times[:n], omega[sel], zeta[sel])
            else:
                _, qd, qdd = oscillator_response(pulse, times[:n], omega[sel], zeta[sel], derivatives=True)
            out[:n] += weights[idx[sel]] @ (qdd + a0 * qd)
    return out


def _overdamped_response(atoms, t: np.ndarray, omega: np.ndarray, zeta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Exact velocity and acceleration of overdamped unit-mass oscillators (zeta >= 1).

    ``q'' + 2 zeta w q' + w^2 q = p(t)``, at rest before the first atom. With the real
    roots ``r1, r2 = -w (zeta -+ sqrt(zeta^2 - 1))`` the transfer function splits into
    first-order parts, ``q = (y1 - y2) / (r1 - r2)`` with ``y_i' = r_i y_i + p``, hence
    ``q' = (r1 y1 - r2 y2) / (r1 - r2)`` and ``q'' = p + (r1^2 y1 - r2^2 y2) / (r1 - r2)``.
    Each ``y_i`` is a closed form per atom switched on at ``t0`` (``tau = t - t0 >= 0``):
    step ``a expm1(r tau) / r``; ramp ``b (expm1(r tau) - r tau) / r^2``; sinusoid
    ``Re[(d - i c)(e^{i W tau} - e^{r tau}) / (i W - r)]``. All exponents are <= 0.
    ``zeta == 1`` is moved to ``1 + 1e-9`` (a relative change of order 1e-9).

    Returns ``(q', q'')``, arrays of shape ``(len(omega), len(t))``.
    """
    z = np.maximum(zeta, 1.0 + 1e-9)[:, None]
    w = omega[:, None]
    root = np.sqrt(z * z - 1.0)
    r1 = -w * (z - root)  # slow
    r2 = -w * (z + root)  # fast
    y1 = np.zeros((omega.size, t.size))
    y2 = np.zeros_like(y1)
    load = np.zeros(t.size)
    for atom in atoms:
        first = int(np.searchsorted(t, atom.t0, side="left"))
        if first >= t.size:
            continue
        tau = t[first:] - atom.t0
        load[first:] += atom.force(t[first:])
        sinusoid = atom.omega > 0.0 and (atom.c != 0.0 or atom.d != 0.0)
        if sinusoid:
            cos_t, sin_t = np.cos(atom.omega * tau), np.sin(atom.omega * tau)
        for r, y in ((r1, y1), (r2, y2)):
            rt = r * tau[None, :]
            em1 = np.expm1(rt)
            part = y[:, first:]
            if atom.a != 0.0:
                part += (atom.a / r) * em1
            if atom.b != 0.0:
                part += (atom.b / (r * r)) * (em1 - rt)
            if sinusoid:
                # Re[g (e^{i W tau} - e^{r tau})], g = (d - i c) / (i W - r), per mode.
                g = (atom.d - 1j * atom.c) / (1j * atom.omega - r)
                part += g.real * (cos_t[None, :] - em1 - 1.0) - g.imag * sin_t[None, :]
    diff = r1 - r2
    qd = (r1 * y1 - r2 * y2) / diff
    qdd = load[None, :] + (r1 * r1 * y1 - r2 * r2 * y2) / diff
    return qd, qdd


def _modal_base_shear(model: ColumnModel, pulse, height_m: float, times: np.ndarray, n_modes) -> np.ndarray:
    if model.column.damping_ratio == 0.0:
        raise InputError(
            "column.damping_ratio",
            "must be > 0 for method='modal' (the exact oscillator responses need damped modes); "
            "use method='newmark' for an undamped column",
        )
    weights = _modal_weights(model, height_m)
    force = np.asarray(pulse.force(times), dtype=float)
    end = getattr(pulse, "end_s", None)
    end = float(end) if end is not None else None
    n_all = len(weights)
    if n_modes is not None:
        if isinstance(n_modes, bool) or not isinstance(n_modes, (int, np.integer)) or not 1 <= n_modes <= n_all:
            raise InputError("n_modes", f"must be an integer in [1, {n_all}], got {n_modes!r}")
        return force - _modal_block(model, pulse, times, weights, np.arange(int(n_modes)), end)

    # Adaptive: modes below the first band, then bands of doubling frequency until two
    # bands in a row change the base shear by less than _MODAL_BLOCK_TOLERANCE of its peak.
    freq = model.frequencies_Hz
    f_cut = _MODAL_FIRST_BAND_HZ
    n_used = min(max(int(np.searchsorted(freq, f_cut, side="right")), 10), n_all)
    shear = force - _modal_block(model, pulse, times, weights, np.arange(n_used), end)
    small = 0
    while n_used < n_all and small < 2:
        f_cut *= 2.0
        n_next = min(max(int(np.searchsorted(freq, f_cut, side="right")), n_used + 1), n_all)
        block = _modal_block(model, pulse, times, weights, np.arange(n_used, n_next), end)
        shear -= block
        n_used = n_next
        peak = np.max(np.abs(shear))
        small = small + 1 if np.max(np.abs(block)) <= _MODAL_BLOCK_TOLERANCE * peak else 0
    return shear


#: First band of the adaptive modal superposition (Hz); relative size below which a further
#: band counts as negligible; ring-down (in units of the slowest decay time) after the end.
_MODAL_FIRST_BAND_HZ = 2000.0
_MODAL_BLOCK_TOLERANCE = 1.0e-5
_RING_DOWN = 25.0


# --------------------------------------------------------------------------- Newmark
@dataclass(frozen=True)
class NewmarkHistory:
    """Newmark (constant average acceleration) history on its own uniform time grid.

    Attributes
    ----------
    time_s:
        Grid times (s), ``start_s + k dt``.
    force_N:
        Applied force P at the grid times (mean of the left and right limits, so a jump
        on a grid point is integrated without a time shift) (N).
    base_shear_N:
        Base shear, equilibrium form ``P - e^T M (a + a0 v)`` (N).
    base_shear_reaction_N:
        Base shear, reaction form ``F_0 - (K_0f u + C_0f v + M_0f a)`` (N).
    energy_J:
        Kinetic + strain energy ``(v^T M v + u^T K u) / 2`` (J) if requested, else None.
    dt_s:
        The time step (s).
    """

    time_s: np.ndarray
    force_N: np.ndarray
    base_shear_N: np.ndarray
    base_shear_reaction_N: np.ndarray
    energy_J: np.ndarray | None
    dt_s: float


def newmark_history(
    pulse,
    column: Column,
    height_m: float,
    end_s: float,
    dt: float | None = None,
    start_s: float | None = None,
    energy: bool = False,
) -> NewmarkHistory:
    """Integrate the column's equations of motion with Newmark's average acceleration.

    Full free-DOF matrices, beta = 1/4, gamma = 1/2 (unconditionally stable, no numerical
    damping, exactly energy-conserving for an undamped linear system), incremental form
    with the effective stiffness ``K + (2/dt) C + (4/dt^2) M`` factorised once (banded
    Cholesky). The grid is anchored on the pulse start (so the pulse's jumps fall on grid
    points) and begins at least one step before it, at rest.

    Parameters
    ----------
    pulse, column, height_m:
        As in :func:`mdof_response`.
    end_s:
        Last time to reach (s).
    dt:
        Time step (s). Default: ``omega dt <= 0.1`` up to the first mode above 4 kHz, at
        least 200 steps per pulse duration and at most 1e-5 s, rounded so that the pulse
        lasts a whole number of steps. The Newmark period error is about
        ``(omega dt)^2 / 12`` (0.08 % at ``omega dt = 0.1``), so the modes that carry the
        peak are phased to better than 0.1 %; against the modal solution the peak errors
        measured for the seed's Table 1 pulses at 0.16, 0.40 and 0.80 m were below 2e-4.
        For the seed's column this gives dt of about 3.9e-6 s.
    start_s:
        The column is at rest up to the first grid time: one step before the pulse, or
        earlier to reach ``start_s`` (s).
    energy:
        Also return the mechanical energy per step (costs two more products per step).
    """
    model = column_model(column)
    f_full = model.load_vector(height_m)
    end = require_finite("end_s", end_s)
    pulse_start = _pulse_start(pulse, None)
    if dt is None:
        dt = _default_dt(model, pulse)
    else:
        dt = require_positive("dt", dt)
    if start_s is not None:
        start_s = require_finite("start_s", start_s)
    if pulse_start is None:  # a load without a start time: begin at start_s (or 0), at rest
        first = start_s if start_s is not None else 0.0
    else:  # anchor the grid on the pulse start, one step or more before it
        back = 1 if start_s is None else max(1, math.ceil((pulse_start - start_s) / dt - 1e-9))
        first = pulse_start - back * dt
    steps = max(int(math.ceil((end - first) / dt - 1e-9)), 1)
    grid = first + dt * np.arange(steps + 1)
    eps = 1e-6 * dt
    force = 0.5 * (np.asarray(pulse.force(grid - eps), float) + np.asarray(pulse.force(grid + eps), float))
    shear_eq, shear_re, work = _newmark_loop(model, f_full, force, dt, energy)
    for a in (grid, force, shear_eq, shear_re) + ((work,) if work is not None else ()):
        a.setflags(write=False)
    return NewmarkHistory(grid, force, shear_eq, shear_re, work, float(dt))


def _default_dt(model: ColumnModel, pulse) -> float:
    """Default Newmark step (s): ``omega dt <= 0.1`` up to the first mode above 4 kHz, at
    least 200 steps per pulse duration, at most 1e-5 s; the pulse duration is made a whole
    number of steps so that both ends of the pulse fall on grid points."""
    freq = model.frequencies_Hz
    f_hi = freq[min(int(np.searchsorted(freq, _DT_BAND_HZ, side="right")), len(freq) - 1)]
    dt = min(_DT_MAX_S, _DT_PHASE / (2.0 * math.pi * f_hi))
    duration = getattr(pulse, "duration_s", None)
    if duration is not None and duration > 0:
        steps = max(_DT_STEPS_PER_PULSE, math.ceil(duration / dt))
        dt = duration / steps
    return dt


#: Default Newmark step rule (see _default_dt): the Newmark period error is about
#: (omega dt)^2 / 12, i.e. 0.08 % at omega dt = 0.1 in the highest mode of the band.
_DT_BAND_HZ = 4000.0
_DT_PHASE = 0.1
_DT_MAX_S = 1.0e-5
_DT_STEPS_PER_PULSE = 200


def _newmark_loop(model: ColumnModel, f_full: np.ndarray, force: np.ndarray, dt: float, energy: bool):
    """Run the Newmark recurrence; return (equilibrium shear, reaction shear, energy or None)."""
    free = model.free_dofs
    k, m = model.stiffness, model.mass
    a0, a1 = model.rayleigh_a0_1_s, model.rayleigh_a1_s
    f = f_full[free]
    f_base = f_full[0]
    loaded = np.flatnonzero(f)
    lo, hi = (int(loaded[0]), int(loaded[-1]) + 1) if loaded.size else (0, 0)
    f_local = f[lo:hi].copy()

    # Incremental Newmark (Chopra 2017, Table 15.3.3) with gamma = 1/2, beta = 1/4:
    #   K_hat = K + (2/dt) C + (4/dt^2) M,   C = a0 M + a1 K
    #   dp_hat = f dP + [(4/dt) M + 2 C] v + 2 M a ;  K_hat du = dp_hat
    #   v_new = (2/dt) du - v ;  a_new = (4/dt^2) du - (4/dt) v - a
    # Banded storage throughout: LAPACK dpbtrf/dpbtrs for the solve, BLAS dsbmv for the
    # products (half-bandwidth 3 with interleaved DOFs).
    chol = _banded_cholesky((1.0 + 2.0 * a1 / dt) * k + (2.0 * a0 / dt + 4.0 / dt**2) * m)
    band = _BANDWIDTH
    band_v = _upper_band((4.0 / dt + 2.0 * a0) * m + 2.0 * a1 * k, band)
    band_a = _upper_band(2.0 * m, band)

    # Reaction row of the constrained base w: nonzero on the first element's free DOFs only.
    k_row = model.beam_stiffness_full[[0]][:, free].toarray().ravel()
    m_row = model.mass_full[[0]][:, free].toarray().ravel()
    width = int(np.flatnonzero((k_row != 0) | (m_row != 0)).max()) + 1
    k_row, m_row = k_row[:width], m_row[:width]
    c_row = a0 * m_row + a1 * k_row
    inertia = model.inertia_vector

    n_steps = len(force)
    u = np.zeros(len(free))
    v = np.zeros(len(free))
    m_chol = model._cache.get("m_chol")
    if m_chol is None:
        m_chol = _banded_cholesky(m)
        model._cache["m_chol"] = m_chol
    a = _banded_solve(m_chol, f * force[0])  # from the equation of motion at rest

    inertia_a = np.empty(n_steps)
    inertia_v = np.empty(n_steps)
    base_u = np.empty((n_steps, width))
    base_v = np.empty((n_steps, width))
    base_a = np.empty((n_steps, width))
    work = np.empty(n_steps) if energy else None
    dforce = np.diff(force, prepend=force[0])
    c2, c4, c44 = 2.0 / dt, 4.0 / dt, 4.0 / dt**2
    dsbmv, dpbtrs, dot = blas.dsbmv, lapack.dpbtrs, np.dot

    for i in range(n_steps):
        if i:
            rhs = dsbmv(band, 1.0, band_v, v)
            rhs = dsbmv(band, 1.0, band_a, a, beta=1.0, y=rhs, overwrite_y=1)
            rhs[lo:hi] += f_local * dforce[i]
            du = dpbtrs(chol, rhs, overwrite_b=1)[0]
            a = c44 * du - c4 * v - a
            v = c2 * du - v
            u += du
        inertia_a[i] = dot(inertia, a)
        inertia_v[i] = dot(inertia, v)
        base_u[i] = u[:width]
        base_v[i] = v[:width]
        base_a[i] = a[:width]
        if energy:
            work[i] = 0.5 * (dot(v, m @ v) + dot(u, k @ u))

    shear_eq = force - (inertia_a + a0 * inertia_v)
    shear_re = f_base * force - (base_u @ k_row + base_v @ c_row + base_a @ m_row)
    return shear_eq, shear_re, work


#: Half-bandwidth of the assembled matrices (interleaved w, theta DOFs, two-node elements).
_BANDWIDTH = 3


def _upper_band(matrix, band: int = _BANDWIDTH) -> np.ndarray:
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


def _banded_cholesky(matrix) -> np.ndarray:
    """Upper banded Cholesky factor (LAPACK dpbtrf layout) of a symmetric band matrix."""
    return _cholesky_band(_upper_band(matrix))


def _cholesky_band(ab: np.ndarray) -> np.ndarray:
    """Upper banded Cholesky factor of a matrix already in upper band storage."""
    chol, info = lapack.dpbtrf(ab, lower=0)
    if info != 0:
        raise np.linalg.LinAlgError(f"banded Cholesky failed (info={info}): matrix not positive definite")
    return chol


def _banded_solve(chol: np.ndarray, b: np.ndarray) -> np.ndarray:
    x, info = lapack.dpbtrs(chol, np.asarray(b, float)[:, None])
    if info != 0:  # pragma: no cover - only on malformed input
        raise np.linalg.LinAlgError(f"banded solve failed (info={info})")
    return x[:, 0]


# --------------------------------------------------------------------------- helpers
def _direction(pulse) -> int:
    """+1, or -1 for a pulse whose peak is negative (a load along -x)."""
    peak = getattr(pulse, "peak_N", None)
    return -1 if peak is not None and float(peak) < 0.0 else 1


def _pulse_start(pulse, default):
    """Time (s) at which the pulse begins, if the pulse says so."""
    start = getattr(pulse, "start_s", None)
    if start is None:
        times = getattr(pulse, "time_s", None)
        if times is not None and len(times):
            start = float(np.asarray(times, float)[0])
    return float(start) if start is not None else default


def _load_height(column: Column, height_m: float) -> float:
    z = require_finite("height_m", height_m)
    if not 0.0 < z <= column.height_m * (1 + 1e-12):
        raise InputError("height_m", f"must be in (0, {column.height_m:g}] m (the column height), got {height_m!r}")
    return min(z, column.height_m)


def _times(name: str, t) -> np.ndarray:
    try:
        times = np.asarray(t, dtype=float)
    except (TypeError, ValueError):
        raise InputError(name, "must be an array of numbers (s)") from None
    if times.ndim != 1 or times.size == 0:
        raise InputError(name, f"must be a non-empty 1-D array of times (s), got shape {times.shape}")
    if not np.all(np.isfinite(times)):
        raise InputError(name, "must be finite")
    if times.size > 1 and np.any(np.diff(times) <= 0):
        raise InputError(name, "must be strictly increasing")
    return times



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
