"""The ASCE 7-22 6.11 section of a run's report.md and of its results page (`report case`): one
answer, the design value first, from :mod:`orchestrator.results.asce_design`'s table."""

from __future__ import annotations

import math

import pandas as pd

from analytical.asce7 import asce7_design
from analytical.study import STUDY_DEBRIS_STIFFNESS_N_M
from orchestrator.results.asce_design import SiteFlow

__all__ = ["asce_markdown"]


def _n(value, spec: str = ".0f") -> str:
    return "-" if value is None or (isinstance(value, float) and not math.isfinite(value)) else format(value, spec)


def asce_markdown(table: pd.DataFrame, site: SiteFlow | None, heading: str = "###") -> list[str]:
    """Markdown lines: what governs and why, u_max beside the impact speed, the table, the cap."""
    out = [f"{heading} ASCE 7-22 6.11: the design impact force", ""]
    if table is None or table.empty:
        return out + ["No column strike with a known mass and speed: no ASCE 7-22 design force.", ""]
    first = table.iloc[0]
    gov, other = first["governing_stiffness"], first["other_stiffness"]
    names = {"k_s": "the column's lateral stiffness k_s", "k_d": "the debris stiffness k_d"}
    flow = site.describe() if site is not None else (
        "not recorded: only a one-way run records the flow at the column; the design force below takes the "
        "body's impact speed in its place, as the study did")
    cap = asce7_design(1.0, float(first["mass_kg"]), STUDY_DEBRIS_STIFFNESS_N_M, float(first["stiffness_N_m"]))
    out += [f"F_i = I_tsu C_o u_max sqrt(k m_d) (I_tsu = 1.0, risk category II; C_o = 0.65, containers), k the lesser "
            f"of k_d = {STUDY_DEBRIS_STIFFNESS_N_M:.4g} N/m (the study's container) and the column's k_s: here "
            f"**{names[gov]} governs** ({first['stiffness_N_m']:.4g} N/m), so its F_i is the design value and "
            f"the {other} force is context only.", "",
            f"- u_max, the flow's maximum velocity at the column (what the standard's formula takes): {flow}.",
            "- The body's impact speed (its centre's speed at the strike): what the study put in place of u_max "
            "(its Table 2 rows), shown beside it.",
            f"- Scale: {cap.cap_note()}.", "",
            "| event | t (s) | body | u_max (m/s) | impact speed (m/s) | **design F_i (N)**, "
            f"{gov} | t_d (ms) | impulse (N s) | F_i with {other} (N), context | F_i at the impact speed, {gov} (N), "
            "the study's way |", "|---|---|---|---|---|---|---|---|---|---|"]
    for r in table.itertuples():
        out.append(f"| {r.event} | {_n(r.time_s, '.3f')} | {r.body} | {_n(r.u_max_m_s, '.2f')} | "
                   f"{_n(r.impact_speed_m_s, '.2f')} | **{_n(r.design_force_N)}** | {_n(r.duration_s * 1e3, '.2f')} | "
                   f"{_n(r.impulse_Ns, '.3f')} | {_n(r.other_force_N)} | {_n(r.force_at_impact_speed_N)} |")
    out += ["", f"Design value: **F_i = {first['design_force_N']:.0f} N** ({first['governing_stiffness']} governs; "
                f"{first['design_basis']}).", ""]
    return out
