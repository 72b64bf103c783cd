"""The column's finite-element model: assembled matrices, supports, modes, damping and statics.

:func:`column_model` builds (once per :class:`analytical.column.Column`; cached) a cantilever
of ``column.elements`` equal Timoshenko elements (:mod:`analytical.beam`; study section
3.2.2: 160 elements, consistent mass, Rayleigh damping) and solves its eigenproblem. The
dynamic responses (:mod:`analytical.mdof`, :mod:`analytical.newmark`) and the impact model
(:mod:`analytical.impact`) all work on this one :class:`ColumnModel`.

Supports
--------
``base="rigid"`` fixes both base DOFs (the study's MDOF). ``base="calibrated"`` fixes the
base displacement and restrains the base rotation by a rotational spring ``k_theta``
(N m/rad) found with Brent's method so that the model's first frequency equals
``column.natural_frequency_Hz`` (the measured 70 Hz; the rigid-base beam gives about
88 Hz). ``base="spring"`` puts the given ``column.base_spring_Nm_rad`` there instead. Damping is Rayleigh, ``C = a0 M + a1 K``, with
``column.damping_ratio`` on modes 1 and 2 of the model (Chopra 2017, section 11.4).
``column.ends`` restrains the top as well: ``"fixed-fixed"`` fixes both DOFs at both ends,
``"pinned"`` the translation at both ends. :func:`lateral_stiffness` at a height is then the
member's point stiffness there (Euler-Bernoulli: ``3 E I / a^3`` for a cantilever,
``3 E I L^3 / (a^3 b^3)`` fixed-fixed, ``3 E I L / (a^2 b^2)`` pinned, ``b = L - a``; shear
deformation adds to the flexibility).

Base reactions
--------------
The base shear the responses report is ``V = s(h) P - g . (a + a0 v)``: for a cantilever ``s = 1``
and ``g`` the rigid translation's inertia ``e^T M`` (:mod:`analytical.mdof`); for a member also
held at its top, the mode-acceleration form of the base row's reaction,
``g = M_0f - K_0f K_ff^-1 M_ff`` and ``s(h) = f_0 - K_0f K_ff^-1 f`` (the static share of the
load the base takes; both exact with all modes, as the reaction ``F_0 - K_0f u - C_0f v - M_0f a``).
A fixed-fixed member's base moment is the same form on the base rotation's row.

References
----------
Chopra, A.K. (2017). Dynamics of Structures, 5th ed. Pearson. (Rayleigh damping 11.4.)
Joynt et al. (2021) and the study, section 3.2.2 (160 elements).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np
from scipy import linalg, sparse
from scipy.linalg import blas
from scipy.optimize import brentq

from analytical.banded import BANDWIDTH, banded_cholesky, banded_solve, cholesky_band, upper_band
from analytical.beam import assemble_beam, shape_functions, shear_parameter
from analytical.column import Column
from analytical.errors import InputError, require_finite

__all__ = ["ColumnModel", "column_model", "lateral_stiffness", "modes", "static_deflection"]


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
        Base rotational stiffness k_theta (N m/rad), calibrated or given; None for a rigid base.
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
        The base shear's inertia weights ``g`` over the free DOFs (kg, kg m): the base shear is
        ``s(h) P(t) - inertia_vector . (a + a0 v)`` (module notes; a cantilever's is
        ``(e^T M_full)`` restricted to the free DOFs and ``s = 1``).
    base_influence:
        ``K_ff^-1 K_f0`` (one column per base row: the base translation and, fixed-fixed, the base
        rotation) giving the static share ``s(h)``; None for a cantilever.
    moment_vector:
        A fixed-fixed member's base moment weights, as ``inertia_vector`` for the base rotation's
        row; None otherwise.
    solver_cache:
        Factors and modal weights the solvers keep between calls on this model.
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
    base_influence: np.ndarray | None
    moment_vector: np.ndarray | None
    solver_cache: dict = field(default_factory=dict, repr=False)

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

    def base_shear_factor(self, height_m: float) -> float:
        """``s(h)``: the static base shear per unit load at ``height_m`` (1 for a cantilever)."""
        if self.base_influence is None:
            return 1.0
        f = self.load_vector(height_m)
        return float(f[0] - self.base_influence[:, 0] @ f[self.free_dofs])

    def base_moment_factor(self, height_m: float) -> float:
        """A fixed-fixed member's static base moment per unit load at ``height_m`` (m; 0 pinned).

        Positive in the sense of a cantilever's ``h P``: ``a b^2 / L^2`` for Euler-Bernoulli."""
        if self.moment_vector is None:
            return 0.0
        f = self.load_vector(height_m)
        return float(f[1] - self.base_influence[:, 1] @ f[self.free_dofs])


def _column_phi(column: Column) -> float:
    le = column.height_m / column.elements
    return shear_parameter(le, column.bending_stiffness_Nm2, column.shear_stiffness_N)


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
    held = [0, 1] if column.base == "rigid" else [0]
    if column.ends == "fixed-fixed":
        held += [size - 2, size - 1]
    elif column.ends == "pinned":
        held = [0, size - 2]
    free = np.setdiff1d(np.arange(size), held)
    k_beam = k_full[free][:, free].toarray()
    m_ff = m_full[free][:, free].toarray()

    spring = None
    if column.base == "calibrated":
        spring = _calibrate_base_spring(column, k_beam, m_ff)
    elif column.base == "spring":
        spring = column.base_spring_Nm_rad
    if spring is not None:
        k_beam[0, 0] += spring
    w2, phi = linalg.eigh(k_beam, m_ff, driver="gvd")
    w2 = np.clip(w2, 0.0, None)
    omega = np.sqrt(w2)
    if column.ends == "cantilever":
        top = phi[-2, :]
    else:  # the sign of each mode's largest translation
        w = phi[free % 2 == 0, :]
        top = w[np.argmax(np.abs(w), axis=0), np.arange(w.shape[1])]
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
    influence = moment = None
    if column.ends == "cantilever":
        e = np.zeros(size)
        e[0::2] = 1.0
        inertia = (m_full.T @ e)[free]
    else:
        rows = [0, 1] if column.ends == "fixed-fixed" else [0]
        k_rows = k_full[rows][:, free].toarray()
        m_rows = m_full[rows][:, free].toarray()
        influence = linalg.solve(k_beam, k_rows.T, assume_a="pos")
        weights = m_rows - influence.T @ m_ff
        inertia = weights[0]
        moment = weights[1] if column.ends == "fixed-fixed" else None

    arrays = dict(
        node_height_m=np.linspace(0.0, column.height_m, n + 1),
        free_dofs=free,
        frequencies_Hz=omega / (2.0 * math.pi),
        mode_shapes=phi,
        damping_ratios=ratios,
        inertia_vector=inertia,
        base_influence=influence,
        moment_vector=moment,
    )
    for a in arrays.values():
        if a is not None:
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
    k_band = upper_band(k_beam)
    m_band = upper_band(m_ff)
    start = banded_solve(cholesky_band(k_band[:, 1:].copy()), m_ff[1:, :] @ _lateral(len(m_ff)))

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
    chol = cholesky_band(k_band)
    x = start / math.sqrt(abs(float(start @ blas.dsbmv(BANDWIDTH, 1.0, m_band, start))))
    previous = math.inf
    for _ in range(200):
        y = banded_solve(chol, blas.dsbmv(BANDWIDTH, 1.0, m_band, x))
        my = blas.dsbmv(BANDWIDTH, 1.0, m_band, y)
        ymy = float(y @ my)
        rayleigh = float(y @ blas.dsbmv(BANDWIDTH, 1.0, k_band, y)) / ymy
        x = y / math.sqrt(ymy)
        if abs(rayleigh - previous) <= 1e-15 * rayleigh:
            break
        previous = rayleigh
    return math.sqrt(max(rayleigh, 0.0)) / (2.0 * math.pi)


def modes(column: Column) -> np.ndarray:
    """Natural frequencies (Hz, ascending) of the column's MDOF model (a read-only array).

    The study's column (rigid base, 160 elements) gives f1 = 88.36 Hz, f2 = 360.3 Hz,
    f3 = 762.4 Hz; an Euler-Bernoulli cantilever with the same E I and rho A would have
    f1 = 1.8751^2 sqrt(E I / (rho A H^4)) / (2 pi) = 100.5 Hz: shear deformation (kappa =
    0.5) and rotary inertia lower it. ``base="calibrated"`` returns f1 =
    ``column.natural_frequency_Hz``.
    """
    return column_model(column).frequencies_Hz


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
    """Static lateral stiffness (N/m) of the model at ``height_m``: force / deflection there (the
    member's point stiffness with its ends, module notes); InputError at a held end."""
    deflection = static_deflection(column, height_m, height_m, 1.0)
    if not deflection > 0.0:
        raise InputError("height_m", f"{height_m!r} m is a held end of the {column.ends} member: it does not deflect")
    return 1.0 / deflection


def _static_solve(model: ColumnModel, f: np.ndarray) -> np.ndarray:
    chol = model.solver_cache.get("k_chol")
    if chol is None:
        chol = banded_cholesky(model.stiffness)
        model.solver_cache["k_chol"] = chol
    return banded_solve(chol, f)


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


def _load_height(column: Column, height_m: float) -> float:
    z = require_finite("height_m", height_m)
    if not 0.0 < z <= column.height_m * (1 + 1e-12):
        raise InputError("height_m", f"must be in (0, {column.height_m:g}] m (the column height), got {height_m!r}")
    return min(z, column.height_m)
