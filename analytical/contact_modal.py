"""The contact integration of :mod:`analytical.contact_integration` in the column's modal coordinates.

The column's model is ``M u'' + C u' + K u = b F`` with Rayleigh damping ``C = a0 M + a1 K``
(:mod:`analytical.column_fem`), so its mass-normalised modes ``Phi`` (``Phi^T M Phi = I``,
``Phi^T K Phi = diag(w^2)``) diagonalise all three matrices: in ``u = Phi q`` every mode is its own
oscillator ``q_i'' + (a0 + a1 w_i^2) q_i' + w_i^2 q_i = (Phi^T b)_i F``, and the modes meet only in
the contact force. Newmark's scheme is linear and the same in every coordinate system, so
stepping the modes is the same scheme on the same system as stepping the physical DOFs
(:class:`~analytical.contact_integration.NormalIntegrator`): the same steps, the same switches,
the same pulse, to rounding (tests/test_impact.py holds the two to 1e-9). What changes is the
cost: a step is a handful of element-wise operations on the modal vectors instead of banded
products and a banded solve, and a step of another length (each switch is found by Brent's
method on fractional steps) needs no new Cholesky factor. A column strike in the ensembles
costs about a fifth of the banded integration's time.

:class:`ModalIntegrator` keeps :class:`~analytical.contact_integration.NormalIntegrator`'s
algorithm (``run``: the switches, the re-contact watch, the stop once re-contact is impossible,
the record) and replaces only its linear algebra. The column's displacement along ``-n`` at the
contact point is ``b_q . q`` with ``b_q = Phi^T b``; its energy ``(q'.q' + q.diag(w^2) q) / 2``;
the base shear ``g F - (Phi^T e_M) . (q'' + a0 q')`` (``e_M`` the model's inertia vector).
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from analytical.column import Column
from analytical.column_fem import column_model
from analytical.contact_integration import ContactState, NormalIntegrator, column_blocks, distinct_blocks
from analytical.impact_bodies import ColumnTarget

__all__ = ["ModalBlock", "ModalIntegrator", "column_modes", "modal_blocks"]


@lru_cache(maxsize=32)
def column_modes(column: Column):
    """The column's model and modal data (cached per column; the model's eigenproblem is most
    of the cost, about 2 s at 160 elements): circular frequencies squared, modal damping
    ``a0 + a1 w^2`` and the inertia vector in modal coordinates. An ensemble builds them once
    before it forks its workers."""
    model = column_model(column)
    omega = model.circular_frequencies_rad_s
    w2 = omega * omega
    damping = model.rayleigh_a0_1_s + model.rayleigh_a1_s * w2
    inertia = model.mode_shapes.T @ np.asarray(model.inertia_vector)
    return model, w2, damping, inertia


class ModalBlock:
    """One bending direction of the column in modal coordinates, loaded at ``height_m`` with
    ``gain`` (the part of ``-n`` along it): the modal counterpart of
    :class:`~analytical.contact_integration.ColumnBlock`."""

    def __init__(self, column: Column, height_m: float, gain: float):
        model, self.w2, self.damping, self.inertia = column_modes(column)
        self.gain = gain
        self.a0 = model.rayleigh_a0_1_s
        self.shear_gain = gain * model.base_shear_factor(height_m)  # the base's static share (1: cantilever)
        load = model.load_vector(height_m)[model.free_dofs]
        rows = np.nonzero(load)[0]
        self.b = gain * (load[rows] @ model.mode_shapes[rows, :])
        self.compliance = float(np.sum(self.b * self.b / self.w2))
        self.size = len(self.b)


def modal_blocks(target: ColumnTarget, n: np.ndarray) -> tuple[tuple[ModalBlock, float] | None, ...]:
    """:func:`~analytical.contact_integration.column_blocks` with modal blocks (the same merging
    of a column that bends alike both ways into one block)."""
    return column_blocks(target, n, ModalBlock)


class ModalIntegrator(NormalIntegrator):
    """:class:`~analytical.contact_integration.NormalIntegrator` on modal blocks (module notes).
    ``slots`` as there, from :func:`modal_blocks`; at least one block."""

    def __init__(self, m_eff, k, c, slots):
        self.m, self.k, self.c = m_eff, k, c
        blocks, self.slots = distinct_blocks(slots)
        if not blocks:
            raise ValueError("ModalIntegrator needs a column block; a rigid obstacle is NormalIntegrator's")
        self.blocks = blocks
        self.size = sum(b.size for b in blocks)
        ends = np.cumsum([0] + [b.size for b in blocks])
        self.segments = [(int(lo), int(hi)) for lo, hi in zip(ends[:-1], ends[1:])]
        self.b = np.concatenate([b.b for b in blocks])
        self.w2 = np.concatenate([b.w2 for b in blocks])
        self.cm = np.concatenate([b.damping for b in blocks])
        self.compliance = sum(b.compliance for b in blocks)
        self._factors = {}

    def _factor(self, dt):
        """Per step length: ``y0 = p1 u + p2 v + p3 a`` is the column's Newmark predictor
        without the contact, ``z`` its response to the contact (``-b / k_hat``)."""
        key = float(dt)
        fac = self._factors.get(key)
        if fac is None:
            c44, c4, c2 = 4.0 / dt**2, 4.0 / dt, 2.0 / dt
            khat_inv = 1.0 / (self.w2 + c2 * self.cm + c44)
            z = -self.b * khat_inv
            z_s = 1.0 / (4.0 * self.m / dt**2)
            bz = float(self.b @ z)
            fac = ((c44 + c2 * self.cm) * khat_inv, (c4 + self.cm) * khat_inv, khat_inv, z, z_s, bz, z_s - bz)
            if len(self._factors) < 4:
                self._factors[key] = fac
        return fac

    def _step(self, st, dt, contact):
        """One Newmark step (as the banded one); the contact point's ``b . u`` and ``b . v``
        are carried as scalars (``s - delta`` and ``vs - delta'``) instead of dot products."""
        p1, p2, p3, z, z_s, bz, w_dw = self._factor(dt)
        c44, c4, c2 = 4.0 / dt**2, 4.0 / dt, 2.0 / dt
        u, v, a = st.u, st.v, st.a
        bu, bv = st.s - st.delta, st.vs - st.delta_rate
        y = p1 * u
        y += p2 * v
        y += p3 * a
        by = float(self.b @ y)
        rhs_s = self.m * (c44 * st.s + c4 * st.vs + st.as_)
        coef = 0.0
        if contact and self.c > 0.0:
            wq = c2 * st.delta + st.delta_rate  # c2 s + vs - b . (c2 u + v)
            coef = self.c * wq
            rhs_s += coef
        y_s = z_s * rhs_s
        if contact:
            alpha = self.k + c2 * self.c
            scale = alpha * (y_s - (by + coef * bz)) / (1.0 + alpha * w_dw)
            coef -= scale
            y_s -= scale * z_s
        if coef != 0.0:
            y += coef * z
            by += coef * bz
        du = y - u
        v_new = c2 * du - v
        a_new = c2 * (v_new - v) - a
        ds = y_s - st.s
        vs_new = c2 * ds - st.vs
        out = ContactState.__new__(ContactState)
        out.u, out.v, out.a = y, v_new, a_new
        out.s, out.vs, out.as_ = y_s, vs_new, c2 * (vs_new - st.vs) - st.as_
        out.delta = y_s - by
        out.delta_rate = vs_new - (c2 * (by - bu) - bv)
        return out

    def _equilibrate(self, st, contact):
        f = self._force(st, contact)
        st.a = self.b * f - self.cm * st.v - self.w2 * st.u
        st.as_ = -f / self.m
        return f

    def _column_energy(self, st):
        return 0.5 * float(st.v @ st.v + st.u @ (self.w2 * st.u))

    def _damping_work(self, old, new, dt, contact):
        """The contact dashpot's work now; the column's, ``dt va . C va``, summed at the end
        (:meth:`_outcome`) over the steps kept here."""
        self._steps.append((dt, old.v, new.v))
        con = 0.0
        if contact and self.c > 0.0:
            rate = 0.5 * (old.delta_rate + new.delta_rate)
            con = dt * self.c * rate * rate
        return 0.0, con

    def _record(self, rec, time, state, force):
        """As the banded record; the base shears from the kept ``a`` and ``v`` at the end."""
        rec["t"].append(time)
        rec["f"].append(force)
        rec["d"].append(state.delta)
        rec["s"].append(state.s)
        rec["o"].append(state.s - state.delta)
        self._kept.append((state.a, state.v))

    def run(self, approach_speed, dt, max_watch):
        self._steps, self._kept = [], []
        return super().run(approach_speed, dt, max_watch)

    def _outcome(self, rec, st, duration, col_damp, con_damp, contacts, settled):
        if self._steps:
            h = np.array([s[0] for s in self._steps])
            va = 0.5 * (np.stack([s[1] for s in self._steps]) + np.stack([s[2] for s in self._steps]))
            col_damp += float(h @ ((va * va) @ self.cm))
        acc = np.stack([k[0] for k in self._kept])
        vel = np.stack([k[1] for k in self._kept])
        force = np.asarray(rec["f"])
        shears = [b.shear_gain * force - (acc[:, lo:hi] + b.a0 * vel[:, lo:hi]) @ b.inertia
                  for b, (lo, hi) in zip(self.blocks, self.segments)]
        zero = np.zeros_like(force)
        out = [zero if slot is None else slot[1] * shears[slot[0]] for slot in self.slots]
        rec["vx"], rec["vy"] = (list(out) + [zero, zero])[:2]
        self._steps, self._kept = [], []
        return super()._outcome(rec, st, duration, col_damp, con_damp, contacts, settled)
