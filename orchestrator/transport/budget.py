"""The force budget of a body carried one-way: each term of the forcing along a recorded track.

:func:`force_budget` takes a track (bodies.csv's rows of one body: centre, velocity, angular
velocity and rotation at each output time) and the flow it was carried through, and evaluates
at every row the forces :mod:`analytical.hydrodynamics` applies, term by term, with the same
function (:func:`~analytical.hydrodynamics.hydro_loads`) on the same sampled water (the flow at
each sub-volume's centre, as :mod:`orchestrator.transport.engine` samples it). The terms are
separated by switching coefficients off, so they add up to the engine's force exactly:

* ``weight``: ``-m g`` (vertical);
* ``buoyancy``: ``rho g V_sub`` (vertical, the local surface's hydrostatic pressure);
* ``froude_krylov``: ``rho sum f_i dV_i Du/Dt_i``, the pressure gradient that accelerates the water
  (loads with drag and added mass off, less the buoyancy);
* ``added_mass_flow``: ``rho sum f_i dV_i R C R^T Du/Dt_i``, the water the body carries accelerated
  with the flow (loads with drag off, less those with added mass off too);
* ``drag``: the rest of the loads;
* ``inertia``: ``(m + m_a) a``, the body's mass and the world-diagonal of its added mass
  (``R diag(A) R^T``, the armature the engine integrates with) times its acceleration, from
  central differences of the track's velocity;
* ``contact``: ``inertia`` less every other term: what the bed (normal force and Coulomb
  friction), the walls and the column gave. On a track without contact it is the budget's
  error, which :func:`force_budget`'s tests hold near zero (a conservation check on the engine
  and on this decomposition: the forcing is held for 1 ms between updates, so the check holds
  to that order).

World frame; N. Rows at the track's output times (the first and last dropped: no central
difference there).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pandas as pd

from analytical.hydrodynamics import HydroCoefficients, added_mass_table, hydro_loads, sub_volumes, submerged_fraction
from orchestrator.transport.flow import FlowField

__all__ = ["BUDGET_TERMS", "force_budget", "sample_flow_at"]

#: The terms of :func:`force_budget`, each with _x, _y, _z columns (N).
BUDGET_TERMS = ("weight", "buoyancy", "froude_krylov", "added_mass_flow", "drag", "contact", "inertia")


def sample_flow_at(flow, pts: np.ndarray, t_flow: float, half_z: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(eta (N,), u (N, 3), Du/Dt (N, 3)) at the sub-volume centres ``pts`` (N, 3), read only where
    wet, as the engine reads them."""
    eta = flow.surface(pts[:, 0], pts[:, 1], t_flow)
    wet = submerged_fraction(pts[:, 2], half_z, eta) > 0.0
    u = np.zeros_like(pts)
    a = np.zeros_like(pts)
    if np.any(wet):
        sample = flow.sample(pts[wet], t_flow, eta_m=eta[wet])
        u[wet] = sample.velocity_m_s
        a[wet] = sample.material_acceleration_m_s2
    return eta, u, a


def force_budget(track: pd.DataFrame, flow: FlowField, size_m, mass_kg: float,
                 coefficients: HydroCoefficients, flow_start_s: float | None = None) -> pd.DataFrame:
    """Each force on the body along ``track`` (module notes): columns ``time_s``, ``x_m``, ``y_m``,
    ``z_m``, ``u_m_s``, ``added_mass_<axis>_kg`` (the world diagonal) and ``<term>_<axis>`` for every term of
    :data:`BUDGET_TERMS`. ``flow_start_s``: the flow time of the track's t = 0 (default the
    record's first frame, as the engine's)."""
    c = dataclasses.replace(coefficients, water_density_kg_m3=flow.water_density_kg_m3,
                            gravity_m_s2=flow.gravity_m_s2)
    t0 = float(flow.t_s[0]) if flow_start_s is None else float(flow_start_s)
    size = np.asarray(size_m, float).reshape(1, 3)
    local = sub_volumes(size[0], c.sub_volumes).centres_m
    cell = size[0] / np.asarray(c.sub_volumes, float)
    tables = added_mass_table(size[0], c.water_density_kg_m3)[None] if c.added_mass_coefficient is None else None
    no_drag = dataclasses.replace(c, drag_coefficient=0.0)
    bare = dataclasses.replace(c, drag_coefficient=0.0, added_mass_coefficient=0.0)
    t = track["time_s"].to_numpy(float)
    com = track[["x_m", "y_m", "z_m"]].to_numpy(float)
    vel = track[["u_m_s", "v_m_s", "w_m_s"]].to_numpy(float)
    omega = track[["omega_x_rad_s", "omega_y_rad_s", "omega_z_rad_s"]].to_numpy(float)
    rot = track[[f"q_{a}{b}" for a in "xyz" for b in "xyz"]].to_numpy(float).reshape(-1, 3, 3)
    g = c.gravity_m_s2
    rows = []
    for k in range(1, len(t) - 1):
        pts = com[k] + local @ rot[k].T
        half_z = 0.5 * float(np.abs(rot[k, 2, :]) @ cell)
        eta, u, a = sample_flow_at(flow, pts, t0 + t[k], half_z)
        args = (com[k][None], rot[k][None], vel[k][None], omega[k][None], size, pts[None], eta[None], u[None],
                a[None])
        full = hydro_loads(*args, c, tables)
        dry = hydro_loads(*args, no_drag, tables)
        plain = hydro_loads(*args, bare, tables)
        buoyancy = np.array([0.0, 0.0, c.water_density_kg_m3 * g * float(full.submerged_volume_m3[0])])
        world_added = (rot[k] * rot[k]) @ full.added_mass_kg[0]
        accel = (vel[k + 1] - vel[k - 1]) / (t[k + 1] - t[k - 1])
        inertia = (mass_kg + world_added) * accel
        terms = {
            "weight": np.array([0.0, 0.0, -mass_kg * g]),
            "buoyancy": buoyancy,
            "froude_krylov": plain.force_N[0] - buoyancy,
            "added_mass_flow": dry.force_N[0] - plain.force_N[0],
            "drag": full.force_N[0] - dry.force_N[0],
            "inertia": inertia,
        }
        terms["contact"] = inertia - sum(v for n, v in terms.items() if n != "inertia")
        row = {"time_s": t[k], "x_m": com[k, 0], "y_m": com[k, 1], "z_m": com[k, 2], "u_m_s": vel[k, 0],
               **{f"added_mass_{axis}_kg": float(world_added[i]) for i, axis in enumerate("xyz")}}
        for name in BUDGET_TERMS:
            for i, axis in enumerate("xyz"):
                row[f"{name}_{axis}"] = float(terms[name][i])
        rows.append(row)
    return pd.DataFrame(rows)
