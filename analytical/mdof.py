"""Base shear at the load cell of the impacted column: the MDOF response to an impact pulse.

The column (:class:`analytical.column.Column`) is modelled by Timoshenko beam elements
(:mod:`analytical.beam`, assembled with its support and damping by
:func:`analytical.column_fem.column_model`; study section 3.2.2). A point force ``P(t)`` (a
pulse from :mod:`analytical.pulses`) acts along ``+x`` at a height ``z`` above the base,
and :func:`mdof_response` gives the *base shear*: the force the column transmits to its
base support (the load cell), positive in the load direction. This module is the entry
point of the column model: its element, model, statics and Newmark functions are
importable from here too.

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
:func:`analytical.oscillator.oscillator_response`, the overdamped high modes that Rayleigh
damping produces (``zeta_n = a0 / (2 omega_n) + a1 omega_n / 2`` exceeds 1 above about 10 kHz
for the study's column) with the real-root closed form of :func:`_overdamped_response`; a sampled
pulse (:class:`~analytical.pulses.Tabulated`, as the impact integration gives) has every mode
carried over its samples by the exact recurrence of
:func:`analytical.oscillator.piecewise_linear_response`, whose cost grows as (samples + times)
x modes rather than samples x times x modes. The number of modes is chosen adaptively (see
:func:`mdof_response`). ``method="newmark"``:
direct integration of the full equations with Newmark's constant average acceleration
(:func:`analytical.newmark.newmark_history`), the output interpolated linearly onto the
requested times.

References
----------
Chopra, A.K. (2017). Dynamics of Structures, 5th ed. Pearson. (Modal analysis ch. 12-13,
    mode-acceleration superposition 12.12; Newmark 5.4, 15.3.)
"""

from __future__ import annotations

import numpy as np

from analytical.beam import assemble_beam, shape_functions, timoshenko_element
from analytical.column import Column
from analytical.column_fem import ColumnModel, column_model, lateral_stiffness, modes, static_deflection
from analytical.errors import InputError
from analytical.newmark import newmark_history, pulse_start
from analytical.oscillator import oscillator_response, piecewise_linear_response
from analytical.pulses import Tabulated
from analytical.sdof import ForceResponse, load_direction

__all__ = [
    "METHODS",
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
        start = min(float(times[0]), pulse_start(pulse, float(times[0])))
        hist = newmark_history(pulse, column, height_m, float(times[-1]), dt=dt, start_s=start)
        shear = np.interp(times, hist.time_s, hist.base_shear_N)
        return ForceResponse(times, shear, direction=load_direction(pulse))
    if dt is not None:
        raise InputError("dt", "applies to method='newmark' only")
    shear = _modal_base_shear(model, pulse, height_m, times, n_modes)
    return ForceResponse(times, shear, direction=load_direction(pulse))


def _modal_weights(model: ColumnModel, height_m: float) -> np.ndarray:
    """Per-mode weights c_n = (inertia . phi_n)(phi_n . f): V = P - sum c_n (q''_n + a0 q'_n)."""
    weights = model.solver_cache.setdefault("weights", {})
    key = float(height_m)
    c = weights.get(key)
    if c is None:
        f = model.load_vector(height_m)[model.free_dofs]
        c = (model.inertia_vector @ model.mode_shapes) * (f @ model.mode_shapes)
        if len(weights) >= 256:  # many heights (e.g. a fit varying the height): keep it bounded
            weights.clear()
        weights[key] = c
    return c


class _OneWalk:
    """One walk over a sampled pulse's samples for all the modes a base shear may take
    (:func:`~analytical.oscillator.piecewise_linear_response`'s ``walk``): the first call,
    with every mode, walks their roots; the bands after it read their roots' columns. The
    recurrence is element-wise, so a column is the same number either way."""

    def __init__(self):
        self.known: dict = {}

    def __call__(self, r: np.ndarray, carry) -> np.ndarray:
        kind = r.dtype.kind
        if kind not in self.known:
            states = carry(r)
            self.known[kind] = (states, {v: i for i, v in enumerate(r[:, 0].tolist())})
        states, column = self.known[kind]
        return states[[column[v] for v in r[:, 0].tolist()]]


def _modal_block(model: ColumnModel, pulse, times: np.ndarray, weights: np.ndarray, idx: np.ndarray, end,
                 walk=None) -> np.ndarray:
    """``sum_n c_n (q''_n + a0 q'_n)`` over the modes ``idx`` at ``times`` (increasing), N.

    A sampled pulse (:class:`~analytical.pulses.Tabulated`) uses the recurrence of
    :func:`analytical.oscillator.piecewise_linear_response` for all modes. Other pulses:
    underdamped modes (zeta < 1) use :func:`analytical.oscillator.oscillator_response`, the
    overdamped ones that Rayleigh damping gives the high modes :func:`_overdamped_response`.
    Once the pulse has ended (``end``, s) a mode only rings down, as ``exp(-s tau)`` with ``s``
    its slowest decay rate, so each mode is evaluated only up to ``end + 25 / s`` (a decay to
    1e-11): the many short-lived high modes cost little.
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
    a0 = model.rayleigh_a0_1_s
    if isinstance(pulse, Tabulated):
        # A sampled load: one exact recurrence over the samples serves every mode, under- or
        # overdamped. Its cost is per sample, so the block is one call, evaluated up to the
        # longest ring-down in it.
        n = int(counts.max())
        if n:
            _, qd, qdd = piecewise_linear_response(pulse.time_s, pulse.force_N, times[:n], omega, zeta, walk)
            out[:n] = weights[idx] @ (qdd + a0 * qd)
        return out
    # Group the modes by kind and by the (rounded up to a power of 2) number of samples.
    bins = np.ceil(np.log2(np.maximum(counts, 1))).astype(int)
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
    force = np.asarray(pulse.force(times), dtype=float) * model.base_shear_factor(height_m)
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
    walk = None
    if isinstance(pulse, Tabulated):  # the samples walked once for every mode (_OneWalk)
        walk = _OneWalk()
        piecewise_linear_response(pulse.time_s, pulse.force_N, times[:0], model.circular_frequencies_rad_s,
                                  model.damping_ratios, walk)
    shear = force - _modal_block(model, pulse, times, weights, np.arange(n_used), end, walk)
    small = 0
    while n_used < n_all and small < 2:
        f_cut *= 2.0
        n_next = min(max(int(np.searchsorted(freq, f_cut, side="right")), n_used + 1), n_all)
        block = _modal_block(model, pulse, times, weights, np.arange(n_used, n_next), end, walk)
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
