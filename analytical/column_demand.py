"""A column's design demands under an impact pulse: base shear, base moment and displacement.

:func:`column_demands` carries a point load ``P(t)`` at a height ``h`` on the column's MDOF
model (:func:`analytical.column_fem.column_model`: Timoshenko elements, rigid or calibrated
base, Rayleigh damping) by exact modal superposition, and gives three histories along the load:

* **base shear** ``V(t) = P - e^T M (a + a0 v)`` (``e`` the rigid translation): the
  equilibrium (mode-acceleration) form of :mod:`analytical.mdof`, the same number as
  :func:`analytical.mdof.mdof_response`;
* **base moment** ``M(t) = h P - r^T M (a + a0 v)`` (``r`` the rigid rotation about the base:
  ``w = z``, ``theta = 1`` on every node). Why this is the support's moment: the beam's
  stiffness does no work on a rigid rotation (``r^T K_beam = 0``), so the moment about the base
  of every force on the column (the load, ``h P``; the inertia; the Rayleigh forces, whose
  stiffness part reaches the base only through the base spring) is what the support takes. With
  a calibrated base that is the rotational spring's moment plus its Rayleigh share, the same
  accounting as the base shear's. Slowly applied, ``M = P h`` exactly (the static cantilever);
* **displacement** ``u(z, t) = sum_n phi_n(z) Gamma_n q_n(t)`` (mode displacement; the modes'
  shares fall as ``1 / omega_n^2``, so it converges fast) at every node and at the load point;
  slowly applied, the static deflection (:func:`analytical.column_fem.static_deflection`). Its
  peaks: at the top (``peak_top_displacement_m``), at the load, where ``k_s`` is taken
  (``peak_strike_displacement_m``), and the member's largest over both and time
  (``peak_displacement_m``: a cantilever's top; between the load and mid-height for a member
  held at its top as well, whose top does not move).

A member held at its top as well (``column.ends`` fixed-fixed or pinned) takes the base row's
reaction in the same mode-acceleration form (:mod:`analytical.column_fem`, "Base reactions"):
``V = s_V(h) P - g_V . (a + a0 v)``, and fixed-fixed ``M = s_M(h) P - g_M . (a + a0 v)`` (0 for a
pinned base); slowly applied, the static reactions ``P b^2 (3a + b) / L^3`` and ``P a b^2 / L^2``
(Euler-Bernoulli).

Each mode ``q_n'' + 2 zeta_n omega_n q_n' + omega_n^2 q_n = P(t)`` is carried exactly over the
pulse's samples (:func:`analytical.oscillator.piecewise_linear_response`; a rectangular pulse is
two samples, the jumps exact). The modes are taken in bands of doubling frequency, as
:func:`analytical.mdof.mdof_response` takes them, until two bands in a row each change all three
histories by less than 1e-5 of their peaks; every node's displacement (the member's largest)
takes the bands until two in a row change the top's and the load point's by less than that.

The output times are the pulse's samples, times through the pulse at the tail's step, and a tail
after its end long enough for the slowest mode's peak response: ``max(0.05 s, 1.5 T_1)`` at steps of ``max(1e-5 s, T_1 / 2000)``, so a
prototype column whose first period is longer than the pulse still reaches its peak (a
short pulse on a flexible column peaks after the load has gone).

References
----------
Chopra, A.K. (2017). Dynamics of Structures, 5th ed. Pearson. (Modal analysis ch. 12-13;
mode-acceleration superposition 12.12.)
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from analytical.column import Column
from analytical.column_fem import ColumnModel, column_model
from analytical.errors import InputError, require_finite
from analytical.oscillator import piecewise_linear_response
from analytical.pulses import Rectangular, Tabulated

__all__ = ["ColumnDemands", "column_demands", "demand_times", "rigid_rotation", "strike_demands"]

#: Modes below this frequency (Hz; at least 10) form the first band; bands then double.
_FIRST_BAND_HZ = 2000.0
#: A band whose largest change is below this fraction of every history's peak counts as negligible.
_BAND_TOLERANCE = 1.0e-5
#: Samples of a smooth pulse (neither tabulated nor rectangular) over its support.
_PULSE_SAMPLES = 400
#: After the pulse a mode is carried for this many of its slowest decay times (exp(-25) = 1e-11).
_RING_DOWN = 25.0


@dataclass(frozen=True)
class ColumnDemands:
    """Histories along the load (N, N m, m) at ``time_s`` (s) and their peaks (absolute values).
    ``displacement_m`` holds the displacement of every node (rows ``0..elements``, base to top)
    and, in its last row, of the load point, at ``displacement_height_m`` (module notes)."""

    time_s: np.ndarray
    base_shear_N: np.ndarray
    base_moment_Nm: np.ndarray
    displacement_m: np.ndarray
    displacement_height_m: np.ndarray
    height_m: float
    modes: int

    @property
    def top_displacement_m(self) -> np.ndarray:
        """The top's displacement (0 for a member held at its top)."""
        return self.displacement_m[-2]

    @property
    def strike_displacement_m(self) -> np.ndarray:
        """The displacement at the load (the strike point), where ``k_s`` is taken."""
        return self.displacement_m[-1]

    @property
    def peak_base_shear_N(self) -> float:
        return float(np.max(np.abs(self.base_shear_N)))

    @property
    def peak_base_moment_Nm(self) -> float:
        return float(np.max(np.abs(self.base_moment_Nm)))

    @property
    def peak_top_displacement_m(self) -> float:
        return float(np.max(np.abs(self.top_displacement_m)))

    @property
    def peak_strike_displacement_m(self) -> float:
        return float(np.max(np.abs(self.strike_displacement_m)))

    @property
    def peak_displacement_m(self) -> float:
        """The member's largest displacement: over its nodes and the load point, and over time."""
        return float(np.max(np.abs(self.displacement_m)))


def rigid_rotation(model: ColumnModel) -> np.ndarray:
    """The rigid rotation about the base over all DOFs: ``w = z``, ``theta = 1`` on every node."""
    r = np.ones(model.mass_full.shape[0])
    r[0::2] = model.node_height_m
    return r


def _tabulated(pulse) -> Tabulated:
    if isinstance(pulse, Tabulated):
        return pulse
    if isinstance(pulse, Rectangular):
        return Tabulated(np.array([pulse.start_s, pulse.end_s]), np.full(2, pulse.magnitude_N))
    start, end = getattr(pulse, "start_s", None), getattr(pulse, "end_s", None)
    if start is None or end is None:
        raise InputError("pulse", f"must be a pulse of analytical.pulses with a start and an end, got {pulse!r}")
    t = np.linspace(float(start), float(end), _PULSE_SAMPLES)
    return Tabulated(t, np.asarray(pulse.force(t), dtype=float))


def demand_times(pulse: Tabulated, model: ColumnModel) -> np.ndarray:
    """The pulse's samples, times through it at the tail's step (a pulse sampled only at its ends,
    the code's rectangular one, peaks in between) and the tail after it (module notes)."""
    period = 1.0 / float(model.frequencies_Hz[0])
    step = max(1.0e-5, period / 2000.0)
    length = max(0.05, 1.5 * period)
    inside = pulse.start_s + np.arange(1, int(math.ceil((pulse.end_s - pulse.start_s) / step))) * step
    tail = pulse.end_s + np.arange(1, int(math.ceil(length / step)) + 1) * step
    return np.concatenate([np.union1d(pulse.time_s, inside[inside < pulse.end_s]), tail])


def column_demands(pulse, column: Column, height_m: float, t=None) -> ColumnDemands:
    """Base shear, base moment and displacement of ``column`` under ``pulse`` (N, along +x)
    at ``height_m`` above its base (module notes). ``t``: output times (s, increasing); None:
    the pulse's samples and a tail (:func:`demand_times`).

    Examples
    --------
    A load held for many periods gives the static cantilever: ``M = P h``.

    >>> from analytical.column import Column
    >>> d = column_demands(Tabulated([0.0, 2.0, 4.0], [0.0, 100.0, 100.0]), Column(), 0.4, t=[3.9])
    >>> round(float(d.base_moment_Nm[0]), 3)
    40.0
    """
    if not isinstance(column, Column):
        raise InputError("column", f"must be an analytical.column.Column, got {type(column).__name__}")
    if column.damping_ratio <= 0.0:
        raise InputError("column.damping_ratio", "must be > 0: the exact modal responses need damped modes")
    h = require_finite("height_m", height_m)
    if not 0.0 < h <= column.height_m * (1.0 + 1e-12):
        raise InputError("height_m", f"must be in (0, {column.height_m:g}] m, got {height_m!r}")
    h = min(h, column.height_m)
    model = column_model(column)
    load = _tabulated(pulse)
    times = demand_times(load, model) if t is None else np.asarray(t, dtype=float)
    if times.ndim != 1 or times.size == 0 or not np.all(np.isfinite(times)) or np.any(np.diff(times) <= 0):
        raise InputError("t", "must be a non-empty 1-D array of strictly increasing finite times (s)")
    phi = model.mode_shapes
    gamma = model.load_vector(h)[model.free_dofs] @ phi
    w_shear = (model.inertia_vector @ phi) * gamma
    force = np.asarray(load.force(times), dtype=float)
    if column.ends == "cantilever":
        w_moment = ((model.mass_full.T @ rigid_rotation(model))[model.free_dofs] @ phi) * gamma
        shear, moment = force.copy(), h * force
    else:  # the base row's reactions (module notes)
        w_moment = np.zeros_like(gamma) if model.moment_vector is None else (model.moment_vector @ phi) * gamma
        shear, moment = model.base_shear_factor(h) * force, model.base_moment_factor(h) * force
    w_disp = np.vstack([_nodal_w(model), gamma]) * gamma  # every node's w (base to top), then the load point's
    watch = w_disp[-2:]  # the top's and the load point's, carried through every band
    disp, nodes, nodes_quiet = np.zeros((2, times.size)), np.zeros((w_disp.shape[0], times.size)), 0
    omega, zeta, a0 = model.circular_frequencies_rad_s, model.damping_ratios, model.rayleigh_a0_1_s
    freq = model.frequencies_Hz
    over = zeta >= 1.0
    rate = np.where(over, omega * (zeta - np.sqrt(np.where(over, zeta * zeta - 1.0, 0.0))), zeta * omega)
    n_all = freq.size
    done, cut, quiet = 0, _FIRST_BAND_HZ, 0
    while done < n_all and quiet < 2:
        upto = min(max(int(np.searchsorted(freq, cut, side="right")), 10 if done == 0 else done + 1), n_all)
        idx = np.arange(done, upto)
        # after the pulse a mode only rings down: evaluated until it has decayed to 1e-11
        n = int(np.searchsorted(times, load.end_s + _RING_DOWN / float(rate[idx].min()), side="right"))
        parts = (np.zeros(times.size), np.zeros(times.size), np.zeros(disp.shape))
        if n:
            q, qd, qdd = piecewise_linear_response(load.time_s, load.force_N, times[:n], omega[idx], zeta[idx])
            inertial = qdd + a0 * qd
            parts[0][:n], parts[1][:n], parts[2][:, :n] = w_shear[idx] @ inertial, w_moment[idx] @ inertial, \
                watch[:, idx] @ q
            if nodes_quiet < 2:  # every node's, until two bands in a row leave the top and load point alone
                nodes[:, :n] += w_disp[:, idx] @ q
        shear -= parts[0]
        moment -= parts[1]
        disp += parts[2]
        if done > 0:
            still = np.max(np.abs(parts[2])) <= _BAND_TOLERANCE * max(np.max(np.abs(disp)), 1e-300)
            nodes_quiet = nodes_quiet + 1 if still else 0
            small = all(np.max(np.abs(p)) <= _BAND_TOLERANCE * max(np.max(np.abs(h_)), 1e-300)
                        for p, h_ in zip(parts, (shear, moment, disp)))
            quiet = quiet + 1 if small else 0
        done, cut = upto, cut * 2.0
    nodes[-2:] = disp
    heights = np.append(model.node_height_m, h)
    return ColumnDemands(times, shear, moment, nodes, heights, h, done)


def _nodal_w(model: ColumnModel) -> np.ndarray:
    """The mode shapes' lateral displacement ``w`` at every node, base to top (0 at a held DOF)."""
    w = np.zeros((model.node_height_m.size, model.mode_shapes.shape[1]))
    free = np.asarray(model.free_dofs)
    lateral = free % 2 == 0
    w[free[lateral] // 2] = model.mode_shapes[lateral]
    return w


def strike_demands(force: Tabulated, normal, column: Column, height_m: float) -> dict[str, float]:
    """Peak base shear (N), base moment (N m) and displacement (m, the member's largest, over its
    nodes and the strike point) of a column strike: the contact force ``force`` acting along
    ``-normal`` (the unit normal from the column into the body) at ``height_m``. The horizontal
    load's x part bends the column's x model, its y part the same column turned by 90 degrees
    (as :class:`analytical.impact_bodies.ColumnTarget` does); each peak is of the resultant of
    the two directions' histories (the displacement's point by point along the member); a column
    that bends alike both ways is carried once, at the resultant gain (the same peaks)."""
    n = np.asarray(normal, dtype=float)
    if n.shape != (3,) or not np.all(np.isfinite(n)):
        raise InputError("normal", f"must be a finite 3-vector, got {normal!r}")
    histories = []
    for axis in (0, 1):
        gain = -float(n[axis])
        if abs(gain) <= 1e-12:
            continue
        turned = column if axis == 0 else _turned(column)
        if histories and turned == column:  # a column that bends alike both ways: one history, its resultant gain
            histories = [(math.hypot(histories[0][0], gain), histories[0][1])]
            break
        histories.append((gain, column_demands(force, turned, height_m)))
    if not histories:
        return {"base_shear_N": 0.0, "base_moment_Nm": 0.0, "displacement_m": 0.0}
    out = {}
    times = histories[0][1].time_s
    for name in ("base_shear_N", "base_moment_Nm", "displacement_m"):
        squares = 0.0
        for gain, d in histories:
            values = np.atleast_2d(getattr(d, name))
            if d.time_s.size != times.size or np.any(d.time_s != times):
                values = np.array([np.interp(times, d.time_s, row) for row in values])
            squares = squares + (gain * values) ** 2
        out[name] = float(np.sqrt(np.max(squares)))
    return out


def _turned(column: Column) -> Column:
    return dataclasses.replace(column, size_x_m=column.size_y_m, size_y_m=column.size_x_m)
