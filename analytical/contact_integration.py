"""The normal part of one contact in time: a body on a compression-only spring against its obstacle.

Along the contact normal the body is a single mass (its normal mass) pressing on a linear
contact spring ``k``, optionally with a dashpot ``c``. Against a rigid wall (or another body)
the spring is grounded; against the column it is in series with the column's bending
models (:func:`analytical.column_fem.column_model`, one per horizontal direction that the
load has a part in), loaded at the contact height.

Time integration: Newmark constant average acceleration on the whole coupled system (the
column's banded matrices plus the body DOF; the contact spring is a rank-one term handled by
Sherman-Morrison). On a linear system this scheme conserves ``1/2 v'Mv + 1/2 u'Ku`` exactly
apart from the damping work, and its velocity update is the trapezoidal rule, so the
impulse of the recorded force equals the body's momentum change to rounding. The contact
switches on when the spring's compression reaches zero from below and off when its force
returns to zero; each switch is located inside its time step by Brent's method on a
fractional step, so no spring energy is lost or created at a switch. After the body leaves,
the column keeps ringing; the integration watches for the column catching up with the body
(re-contact) and stops when that has become impossible: the column's
contact point can never move further than ``sqrt(2 E_col c)`` (``E_col`` its mechanical
energy, ``c`` its static compliance there), so once the body is further away than that the
impact is over. :mod:`analytical.impact` builds the problem and reads the outcome.

References
----------
Chopra, A.K. (2017). Dynamics of Structures, 5th ed. (Newmark's method, 5.4 and 15.3).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
from scipy.linalg import blas, lapack
from scipy.optimize import brentq

from analytical.banded import BANDWIDTH, banded_solve, cholesky_band, upper_band
from analytical.column import Column
from analytical.column_fem import column_model
from analytical.impact_bodies import ColumnTarget
from analytical.impact_results import ImpactHistory
from analytical.pulses import Tabulated

__all__ = ["ColumnBlock", "ContactState", "NormalIntegrator", "column_blocks", "distinct_blocks"]

_dsbmv, _dpbtrs = blas.dsbmv, lapack.dpbtrs


class ColumnBlock:
    """One bending direction of the column: banded matrices and the contact coupling vector.

    ``b = g f``: ``f`` the consistent load vector of a unit force at the contact height,
    ``g`` the component of ``-n`` along this direction; the column's displacement along
    ``-n`` at the contact point is ``b . u`` and the contact force F loads it as ``b F``.
    """

    def __init__(self, column: Column, height_m: float, gain: float):
        model = column_model(column)
        self.gain = gain
        self.a0 = model.rayleigh_a0_1_s
        self.inertia = np.asarray(model.inertia_vector)
        self.shear_gain = gain * model.base_shear_factor(height_m)  # the base's static share (1: cantilever)
        self.b = gain * model.load_vector(height_m)[model.free_dofs]
        self.k_band = upper_band(model.stiffness)
        self.m_band = upper_band(model.mass)
        self.c_band = upper_band(model.damping)
        self.compliance = float(self.b @ banded_solve(cholesky_band(self.k_band), self.b))
        self.size = len(self.b)


def column_blocks(target: ColumnTarget, n: np.ndarray, block_type=None) -> tuple[tuple[ColumnBlock, float] | None, ...]:
    """Per horizontal axis, the column block that axis loads and its share of the block's base
    shear, or None where ``-n`` has no part along the axis. ``block_type``: the block to build
    (``ColumnBlock``, the default, or another taking (column, height, gain)).

    A column that bends alike both ways (a square or circular section) is one model loaded
    by ``g_x f`` and ``g_y f`` from rest, so ``u_y = (g_y / g_x) u_x``: one block with the
    combined gain ``hypot(g_x, g_y)`` carries both exactly, at half the cost, and each axis
    takes the share ``g_i / hypot(g_x, g_y)`` of its base shear.
    """
    block_type = block_type or ColumnBlock
    gains = [-float(n[axis]) for axis in (0, 1)]
    loaded = [abs(g) > 1e-12 for g in gains]
    if all(loaded) and target.axis_column(0) == target.axis_column(1):
        gain = math.hypot(*gains)
        block = block_type(target.axis_column(0), target.height_m, gain)
        return tuple((block, g / gain) for g in gains)
    return tuple(
        (block_type(target.axis_column(axis), target.height_m, g), 1.0) if ok else None
        for axis, (g, ok) in enumerate(zip(gains, loaded))
    )


class ContactState:
    """The stacked column DOFs (``u, v, a``) and the body's (``s, vs, as_``) at one time, with
    the compression ``delta = s - b . u`` and its rate."""

    __slots__ = ("u", "v", "a", "s", "vs", "as_", "delta", "delta_rate")

    def __init__(self, u, v, a, s, vs, as_, b):
        self.u, self.v, self.a = u, v, a
        self.s, self.vs, self.as_ = s, vs, as_
        if b.size:
            self.delta = s - float(b @ u)
            self.delta_rate = vs - float(b @ v)
        else:
            self.delta, self.delta_rate = s, vs


def distinct_blocks(slots) -> tuple[list, list]:
    """The distinct column blocks of ``slots`` (per axis: (block, share of its base shear) or None)
    and the slots as (index into those blocks, share) or None."""
    blocks, out = [], []
    for slot in slots:
        if slot is None:
            out.append(None)
            continue
        block, share = slot
        index = next((i for i, b in enumerate(blocks) if b is block), None)
        if index is None:
            index = len(blocks)
            blocks.append(block)
        out.append((index, share))
    return blocks, out


class NormalIntegrator:
    """Newmark (average acceleration) on [column blocks..., body], contact on/off.

    Coordinates: ``u_i`` per column block, ``s`` the body's displacement along ``-n`` (into
    the obstacle). Compression ``delta = s - sum b_i . u_i = w . q`` with ``w = (-b_1, ...,
    1)``; contact force ``F = k delta + c delta'`` while in contact (F >= 0).
    """

    def __init__(self, m_eff, k, c, slots):
        self.m = m_eff
        self.k = k
        self.c = c
        blocks, self.slots = distinct_blocks(slots)
        self.blocks = blocks
        # The blocks side by side as one block-diagonal band system (each block's band
        # storage is zero above its first columns, so the bands simply concatenate).
        self.size = sum(b.size for b in blocks)
        ends = np.cumsum([0] + [b.size for b in blocks])
        self.segments = [(int(lo), int(hi)) for lo, hi in zip(ends[:-1], ends[1:])]
        if blocks:
            self.b = np.concatenate([b.b for b in blocks])
            self.k_band = np.hstack([b.k_band for b in blocks])
            self.m_band = np.hstack([b.m_band for b in blocks])
            self.c_band = np.hstack([b.c_band for b in blocks])
            self.m_chol = cholesky_band(self.m_band)
            self.compliance = sum(b.compliance for b in blocks)
        else:
            self.b = np.zeros(0)
            self.compliance = 0.0
        self._factors = {}

    # -- linear algebra on the stacked column DOFs
    def _times(self, band, x):
        return _dsbmv(BANDWIDTH, 1.0, band, x)

    def _factor(self, dt):
        key = float(dt)
        fac = self._factors.get(key)
        if fac is None:
            z_s = 1.0 / (4.0 * self.m / dt**2)
            if self.size:
                chol = cholesky_band(self.k_band + (2.0 / dt) * self.c_band + (4.0 / dt**2) * self.m_band)
                z = -banded_solve(chol, self.b)
                w_dw = float(-self.b @ z) + z_s
            else:
                chol, z, w_dw = None, np.zeros(0), z_s
            fac = (chol, z, z_s, w_dw)
            if len(self._factors) < 4:
                self._factors[key] = fac
        return fac

    def _step(self, st, dt, contact):
        """One Newmark step of length dt from the state ``st`` in the given contact mode."""
        chol, z, z_s, w_dw = self._factor(dt)
        c44, c4, c2 = 4.0 / dt**2, 4.0 / dt, 2.0 / dt
        u, v, a = st.u, st.v, st.a
        rhs_s = self.m * (c44 * st.s + c4 * st.vs + st.as_)
        if self.size:
            uv = c2 * u + v
            rhs = self._times(self.m_band, c44 * u + c4 * v + a)
            rhs = _dsbmv(BANDWIDTH, 1.0, self.c_band, uv, beta=1.0, y=rhs, overwrite_y=1)
            if contact and self.c > 0.0:
                wq = c2 * st.s + st.vs - float(self.b @ uv)
                rhs -= (self.c * wq) * self.b
                rhs_s += self.c * wq
            y = _dpbtrs(chol, rhs, overwrite_b=1)[0]
        else:
            y = u
            if contact and self.c > 0.0:
                rhs_s += self.c * (c2 * st.s + st.vs)
        y_s = z_s * rhs_s
        if contact:
            alpha = self.k + c2 * self.c
            w_y = y_s - (float(self.b @ y) if self.size else 0.0)
            scale = alpha * w_y / (1.0 + alpha * w_dw)
            if self.size:
                y = y - scale * z
            y_s = y_s - scale * z_s
        du = y - u
        ds = y_s - st.s
        return ContactState(
            y, c2 * du - v, c44 * du - c4 * v - a, y_s, c2 * ds - st.vs, c44 * ds - c4 * st.vs - st.as_, self.b
        )

    def _force(self, st, contact):
        if not contact:
            return 0.0
        return self.k * st.delta + self.c * st.delta_rate

    def _equilibrate(self, st, contact):
        """Accelerations from the equations of motion (after a switch of the contact mode)."""
        f = self._force(st, contact)
        if self.size:
            load = self.b * f - self._times(self.c_band, st.v) - self._times(self.k_band, st.u)
            st.a = banded_solve(self.m_chol, load)
        st.as_ = -f / self.m
        return f

    def _column_energy(self, st):
        if not self.size:
            return 0.0
        return 0.5 * float(st.v @ self._times(self.m_band, st.v) + st.u @ self._times(self.k_band, st.u))

    def _damping_work(self, old, new, dt, contact):
        col = 0.0
        if self.size:
            va = 0.5 * (old.v + new.v)
            col = dt * float(va @ self._times(self.c_band, va))
        con = 0.0
        if contact and self.c > 0.0:
            rate = 0.5 * (old.delta_rate + new.delta_rate)
            con = dt * self.c * rate * rate
        return col, con

    def _base_shear(self, st, f):
        shears = [
            b.shear_gain * f - float(b.inertia @ (st.a[lo:hi] + b.a0 * st.v[lo:hi]))
            for b, (lo, hi) in zip(self.blocks, self.segments)
        ]
        out = [0.0 if slot is None else slot[1] * shears[slot[0]] for slot in self.slots]
        while len(out) < 2:
            out.append(0.0)
        return out

    def _first_contact(self, approach_speed):
        """The state at first contact: column at rest, body moving into the obstacle."""
        zero = np.zeros(self.size)
        return ContactState(zero, zero, zero, 0.0, float(approach_speed), 0.0, self.b)

    def _record(self, rec, time, state, force):
        """Append one sample of the history."""
        rec["t"].append(time)
        rec["f"].append(force)
        d = state.delta
        rec["d"].append(d)
        rec["s"].append(state.s)
        rec["o"].append(state.s - d)
        vx, vy = self._base_shear(state, force)
        rec["vx"].append(vx)
        rec["vy"].append(vy)

    def run(self, approach_speed, dt, max_watch):
        """Integrate from first contact (``approach_speed`` m/s along ``-n``) until re-contact
        has become impossible or ``max_watch`` (s) has passed; return the outcome (a dict)."""
        st = self._first_contact(approach_speed)
        contact = True
        f = self._equilibrate(st, contact)
        t = 0.0
        rec = {"t": [], "f": [], "d": [], "s": [], "o": [], "vx": [], "vy": []}

        def record(time, state, force):
            self._record(rec, time, state, force)

        record(t, st, f)
        col_damp = 0.0
        con_damp = 0.0
        contacts = 1
        last_separation = None
        settled = False
        compliance = self.compliance
        rigid = not self.blocks
        scale_f = max(self.k * approach_speed * math.sqrt(self.m / self.k), 1e-300)
        scale_d = approach_speed * math.sqrt(self.m / self.k)
        # After a damped contact opens, the massless spring-dashpot relaxes freely
        # (k x + c x' = 0) from the compression it had: the body touches it again when the
        # overlap reaches x(t). Undamped, x = 0 at once.
        sep_delta, sep_time = 0.0, 0.0

        def rest(time):
            if self.c <= 0.0 or sep_delta <= 0.0:
                return 0.0
            return sep_delta * math.exp(-(self.k / self.c) * (time - sep_time))

        while t < max_watch:
            trial = self._step(st, dt, contact)
            if contact:
                switch = self._force(trial, True) < 0.0
            else:
                switch = trial.delta - rest(t + dt) > 0.0
            h = dt
            if switch:
                theta = self._crossing(st, t, dt, contact, rest, scale_f if contact else scale_d)
                if theta is None:  # a touch shorter than rounding: no switch
                    switch = False
                else:
                    h = theta * dt
                    trial = self._step(st, h, contact)
            cd, kd = self._damping_work(st, trial, h, contact)
            col_damp += cd
            con_damp += kd
            st = trial
            t += h
            if switch:
                if contact:  # the contact opens: F = 0 here
                    delta = st.delta
                    # (Undamped, the force is k delta = 0 here: delta is zero to rounding.)
                    sep_delta, sep_time = (max(delta, 0.0) if self.c > 0.0 else 0.0), t
                    # The spring energy left is dissipated by the free dashpot (returned
                    # below if the body meets the spring again before it has relaxed).
                    con_damp += 0.5 * self.k * sep_delta * sep_delta
                    contact = False
                    f = self._equilibrate(st, contact)
                    last_separation = t
                    record(t, st, 0.0)
                else:  # the column caught the body again
                    x = rest(t)
                    con_damp -= 0.5 * self.k * x * x
                    contact = True
                    record(t, st, 0.0)
                    f = self._equilibrate(st, contact)
                    contacts += 1
                    # Only a dashpot makes the force jump at the touch; undamped, f is the
                    # spring's rounding residue and a second sample would only add noise.
                    if self.c > 0.0 and f != 0.0:  # keep the sample times increasing
                        t += 1e-9 * dt
                        record(t, st, f)
                continue
            f = self._force(st, contact)
            record(t, st, f)
            if not contact:
                if rigid:
                    settled = True
                    break
                # The column's contact point can never move further than `reach`.
                reach = math.sqrt(2.0 * max(self._column_energy(st), 0.0) * compliance)
                if st.s < -reach and st.vs <= 0.0:
                    settled = True
                    break
        duration = last_separation if (last_separation is not None and not contact) else t
        return self._outcome(rec, st, duration, col_damp, con_damp, contacts, settled)

    def _outcome(self, rec, st, duration, col_damp, con_damp, contacts, settled):
        """The force pulse up to the final separation, the history and the energy terms."""
        column_energy = self._column_energy(st)
        times = np.asarray(rec["t"])
        forces = np.asarray(rec["f"])
        end = int(np.searchsorted(times, duration, side="right"))
        end = max(end, 2)
        pulse = Tabulated(times[:end], np.maximum(forces[:end], 0.0))
        hist = ImpactHistory(
            time_s=times,
            force_N=forces,
            compression_m=np.asarray(rec["d"]),
            approach_m=np.asarray(rec["s"]),
            obstacle_m=np.asarray(rec["o"]),
            base_shear_x_N=np.asarray(rec["vx"]),
            base_shear_y_N=np.asarray(rec["vy"]),
        )
        for a in dataclasses.astuple(hist):
            a.setflags(write=False)
        return dict(
            pulse=pulse,
            history=hist,
            body_velocity=st.vs,
            column_energy=column_energy,
            column_damping=col_damp,
            contact_damping=con_damp,
            contacts=contacts,
            duration=float(duration),
            settled=settled,
        )

    def _crossing(self, st, t, dt, contact, rest, scale):
        """Fraction of the step at which the contact switches (Brent), or None."""

        def g(theta):
            trial = self._step(st, theta * dt, contact)
            if contact:
                return self._force(trial, True)
            return trial.delta - rest(t + theta * dt)

        lo = 1e-9
        g_lo = g(lo)
        if (contact and g_lo <= 0.0) or (not contact and g_lo >= 0.0):
            return lo if abs(g_lo) > 1e-12 * scale else None
        return brentq(g, lo, 1.0, xtol=1e-15, rtol=4 * np.finfo(float).eps, maxiter=200)
