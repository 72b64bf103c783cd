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
from scipy import linalg
from scipy.optimize import brentq

from analytical.banded import upper_band
from analytical.column import Column
from analytical.column_fem import column_model
from analytical.impact_bodies import ColumnTarget
from analytical.impact_results import ImpactHistory
from analytical.newmark import phase_limited_step
from analytical.pulses import Tabulated

__all__ = ["ColumnBlock", "NormalIntegrator", "column_blocks"]


class ColumnBlock:
    """One bending direction of the column: banded matrices and the contact coupling vector.

    ``b = g f``: ``f`` the consistent load vector of a unit force at the contact height,
    ``g`` the component of ``-n`` along this direction; the column's displacement along
    ``-n`` at the contact point is ``b . u`` and the contact force F loads it as ``b F``.
    """

    def __init__(self, column: Column, height_m: float, gain: float):
        model = column_model(column)
        self.gain = gain
        self.k = model.stiffness
        self.m = model.mass
        self.c = model.damping
        self.a0 = model.rayleigh_a0_1_s
        self.inertia = np.asarray(model.inertia_vector)
        self.b = gain * model.load_vector(height_m)[model.free_dofs]
        self.k_band = upper_band(self.k)
        self.m_band = upper_band(self.m)
        self.c_band = upper_band(self.c)
        self.m_chol = linalg.cholesky_banded(self.m_band)
        k_chol = linalg.cholesky_banded(self.k_band)
        self.compliance = float(self.b @ linalg.cho_solve_banded((k_chol, False), self.b))
        self.dt_limit = phase_limited_step(model)
        self.size = len(self.b)

    def effective_chol(self, dt: float) -> np.ndarray:
        return linalg.cholesky_banded(self.k_band + (2.0 / dt) * self.c_band + (4.0 / dt**2) * self.m_band)

    def energy(self, u, v) -> float:
        return 0.5 * float(v @ (self.m @ v) + u @ (self.k @ u))


def column_blocks(target: ColumnTarget, n: np.ndarray) -> tuple[ColumnBlock | None, ...]:
    blocks = []
    for axis in (0, 1):
        gain = -float(n[axis])
        if abs(gain) > 1e-12:
            blocks.append(ColumnBlock(target.axis_column(axis), target.height_m, gain))
        else:
            blocks.append(None)
    return tuple(blocks)


class NormalIntegrator:
    """Newmark (average acceleration) on [column blocks..., body], contact on/off.

    Coordinates: ``u_i`` per column block, ``s`` the body's displacement along ``-n`` (into
    the obstacle). Compression ``delta = s - sum b_i . u_i = w . q`` with ``w = (-b_1, ...,
    1)``; contact force ``F = k delta + c delta'`` while in contact (F >= 0).
    """

    def __init__(self, m_eff, k, c, blocks):
        self.m = m_eff
        self.k = k
        self.c = c
        self.slots = blocks  # per axis: ColumnBlock or None
        self.blocks = [b for b in blocks if b is not None]
        self._factors = {}

    # -- linear algebra for one dt
    def _factor(self, dt):
        key = float(dt)
        fac = self._factors.get(key)
        if fac is None:
            chols = [b.effective_chol(dt) for b in self.blocks]
            z_blocks = [-linalg.cho_solve_banded((ch, False), b.b) for ch, b in zip(chols, self.blocks)]
            z_s = 1.0 / (4.0 * self.m / dt**2)
            w_dw = sum(float(-b.b @ z) for b, z in zip(self.blocks, z_blocks)) + z_s
            fac = (chols, z_blocks, z_s, w_dw)
            if len(self._factors) < 4:
                self._factors[key] = fac
        return fac

    def _step(self, state, dt, contact):
        """One Newmark step of length dt from ``state`` (a dict) in the given contact mode."""
        chols, z_blocks, z_s, w_dw = self._factor(dt)
        c44, c4, c2 = 4.0 / dt**2, 4.0 / dt, 2.0 / dt
        rhs = []
        for blk, u, v, a in zip(self.blocks, state["u"], state["v"], state["a"]):
            rhs.append(blk.m @ (c44 * u + c4 * v + a) + blk.c @ (c2 * u + v))
        rhs_s = self.m * (c44 * state["s"] + c4 * state["vs"] + state["as"])
        if contact and self.c > 0.0:
            wq = c2 * state["s"] + state["vs"] - sum(
                float(b.b @ (c2 * u + v)) for b, u, v in zip(self.blocks, state["u"], state["v"])
            )
            for i, blk in enumerate(self.blocks):
                rhs[i] = rhs[i] - self.c * wq * blk.b
            rhs_s += self.c * wq
        y = [linalg.cho_solve_banded((ch, False), r) for ch, r in zip(chols, rhs)]
        y_s = z_s * rhs_s
        if contact:
            alpha = self.k + c2 * self.c
            w_y = y_s - sum(float(b.b @ yy) for b, yy in zip(self.blocks, y))
            scale = alpha * w_y / (1.0 + alpha * w_dw)
            y = [yy - scale * z for yy, z in zip(y, z_blocks)]
            y_s = y_s - scale * z_s
        new = {"u": [], "v": [], "a": []}
        for u, v, a, un in zip(state["u"], state["v"], state["a"], y):
            du = un - u
            new["u"].append(un)
            new["v"].append(c2 * du - v)
            new["a"].append(c44 * du - c4 * v - a)
        ds = y_s - state["s"]
        new["s"] = y_s
        new["vs"] = c2 * ds - state["vs"]
        new["as"] = c44 * ds - c4 * state["vs"] - state["as"]
        return new

    def _delta(self, st):
        return st["s"] - sum(float(b.b @ u) for b, u in zip(self.blocks, st["u"]))

    def _delta_rate(self, st):
        return st["vs"] - sum(float(b.b @ v) for b, v in zip(self.blocks, st["v"]))

    def _force(self, st, contact):
        if not contact:
            return 0.0
        return self.k * self._delta(st) + self.c * self._delta_rate(st)

    def _equilibrate(self, st, contact):
        """Accelerations from the equations of motion (after a switch of the contact mode)."""
        f = self._force(st, contact)
        st["a"] = [
            linalg.cho_solve_banded((b.m_chol, False), b.b * f - b.c @ v - b.k @ u)
            for b, u, v in zip(self.blocks, st["u"], st["v"])
        ]
        st["as"] = -f / self.m
        return f

    def _column_energy(self, st):
        return sum(b.energy(u, v) for b, u, v in zip(self.blocks, st["u"], st["v"]))

    def _damping_work(self, old, new, dt, contact):
        col = 0.0
        for b, v0, v1 in zip(self.blocks, old["v"], new["v"]):
            va = 0.5 * (v0 + v1)
            col += dt * float(va @ (b.c @ va))
        con = 0.0
        if contact and self.c > 0.0:
            rate = 0.5 * (self._delta_rate(old) + self._delta_rate(new))
            con = dt * self.c * rate * rate
        return col, con

    def _base_shear(self, st, f):
        out = []
        it = iter(zip(self.blocks, st["u"], st["v"], st["a"]))
        for slot in self.slots:
            if slot is None:
                out.append(0.0)
                continue
            b, _, v, a = next(it)
            out.append(b.gain * f - float(b.inertia @ (a + b.a0 * v)))
        while len(out) < 2:
            out.append(0.0)
        return out

    def _first_contact(self, approach_speed):
        """The state at first contact: column at rest, body moving into the obstacle."""
        return {
            "u": [np.zeros(b.size) for b in self.blocks],
            "v": [np.zeros(b.size) for b in self.blocks],
            "a": [np.zeros(b.size) for b in self.blocks],
            "s": 0.0,
            "vs": float(approach_speed),
            "as": 0.0,
        }

    def _record(self, rec, time, state, force):
        """Append one sample of the history."""
        rec["t"].append(time)
        rec["f"].append(force)
        d = self._delta(state)
        rec["d"].append(d)
        rec["s"].append(state["s"])
        rec["o"].append(state["s"] - d)
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
        compliance = sum(b.compliance for b in self.blocks)
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
                switch = self._delta(trial) - rest(t + dt) > 0.0
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
                    delta = self._delta(st)
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
                    if f != 0.0:  # a force jump (dashpot): keep the sample times increasing
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
                if st["s"] < -reach and st["vs"] <= 0.0:
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
            body_velocity=st["vs"],
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
            return self._delta(trial) - rest(t + theta * dt)

        lo = 1e-9
        g_lo = g(lo)
        if (contact and g_lo <= 0.0) or (not contact and g_lo >= 0.0):
            return lo if abs(g_lo) > 1e-12 * scale else None
        return brentq(g, lo, 1.0, xtol=1e-15, rtol=4 * np.finfo(float).eps, maxiter=200)
