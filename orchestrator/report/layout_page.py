"""The page of :mod:`orchestrator.report.layouts` (``report.md``): the runs, the flow of every
layout overlaid and what their agreement means, then per layout its tracks, strikes and
contacts between bodies. The layouts are :class:`orchestrator.report.layouts.Layout` objects,
read before; this module only writes text.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from orchestrator.results.compare import SPREADING_ANGLES_DEG

__all__ = ["CONTACT_ROWS", "figure_text", "markdown", "minutes_text"]


def figure_text(value, spec: str = ".3f", unit: str = "") -> str:
    """``value`` formatted with ``spec`` and ``unit``; "-" for a missing or non-finite one."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        return "-"
    return f"{v:{spec}}{unit}" if np.isfinite(v) else "-"


def minutes_text(seconds) -> str:
    """Seconds as minutes to 0.1 min; "-" when missing."""
    return figure_text(seconds / 60 if seconds is not None else None, ".1f", " min")


#: Records of two layouts whose largest difference is under this fraction of their peak are the same.
SAME_RECORD_FRACTION = 1e-6
#: Rows of a layout's body-body contact table on the page (all of them in body_contacts.csv).
CONTACT_ROWS = 12


def _ranks(done: list) -> str:
    ranks = sorted({int(lay.run.ranks or 1) for lay in done})
    return " or ".join(str(r) for r in ranks) + (" core" if ranks == [1] else " cores")


def _transport(row: dict) -> str:
    """The transport's wall time, and its MuJoCo stepping and column pulses where run.json has them."""
    total = figure_text(row.get("transport_wall_s"), ".1f", " s")
    if row.get("transport_stepping_s") is None or row.get("transport_pulses_s") is None:
        return total
    return f"{total} ({figure_text(row['transport_stepping_s'], '.1f')} stepping + {figure_text(row['transport_pulses_s'], '.2f')} pulses)"


def _runs_table(layouts: list, table: pd.DataFrame) -> list[str]:
    lines = ["| layout | bodies | cells | flow (solver) | mesh | transport | strikes on the column (per body) | "
             "first strike: body, time, velocity, peak force | largest base shear of a strike | body-body contacts | "
             "contacts with the side walls / the record's ends | largest spreading angle |", "|" + "---|" * 12]
    for lay, row in zip(layouts, table.to_dict("records")):
        if not lay.ok:
            lines.append(f"| {lay.name} | {row['bodies']} | - | {lay.status} | | | | | | | | |")
            continue
        first = "-"
        if row.get("column_strikes"):
            first = (f"{row['first_strike_body']}, {figure_text(row['first_strike_time_s'])} s, "
                     f"{figure_text(row['first_strike_velocity_m_s'], '.2f')} m/s, {figure_text(row['first_strike_peak_force_N'], '.0f')} N")
        lines.append(
            f"| {lay.name} | {row['bodies']} | {figure_text(row['cells'], ',.0f')} | {minutes_text(row['flow_wall_s'])} (CPU {minutes_text(row.get('flow_cpu_s'))}) | "
            f"{figure_text(row['mesh_wall_s'], '.0f', ' s')} | {_transport(row)} | "
            f"{row['column_strikes']} ({row['strikes_per_body']}) | {first} | "
            f"{figure_text(row.get('max_base_shear_N'), '.0f', ' N')} | {row['body_contacts']} | {row['wall_contacts']} / {row['record_end_contacts']} | "
            f"{figure_text(row.get('max_spread_deg'), '.1f', ' deg')} |")
    return lines


def _worst(agreement: pd.DataFrame) -> tuple[float, float, float, float]:
    """(largest gauge difference m, as a fraction of its peak, largest force difference N, fraction)."""
    if agreement.empty:
        return (float("nan"),) * 4
    gauges = agreement[agreement["quantity"] != "hydro_force_x_N"]
    force = agreement[agreement["quantity"] == "hydro_force_x_N"]
    return (float(gauges["max_abs_diff"].max()), float(gauges["max_abs_diff_fraction_of_peak"].max()),
            float(force["max_abs_diff"].max()), float(force["max_abs_diff_fraction_of_peak"].max()))


def _differences(agreement: pd.DataFrame) -> str:
    g, gf, f, ff = _worst(agreement)
    return (f"the gauges by at most {figure_text(1e3 * g, '.1f', ' mm')} ({figure_text(100 * gf, '.1f', ' %')} of a peak), the "
            f"hydrodynamic force by at most {figure_text(f, '.2f', ' N')} ({figure_text(100 * ff, '.1f', ' %')} of its peak)")


def _flow_text(layouts: list, agreement: pd.DataFrame, agree) -> list[str]:
    """The peaks and differences table and what they mean; ``agree``: the agreement of a list of
    layouts (:func:`orchestrator.report.layouts.flow_agreement`)."""
    done = [lay for lay in layouts if lay.ok]
    if agreement.empty or len(done) < 2:
        return ["Fewer than two layouts have results: nothing to overlay."]
    ref = done[0].name
    lines = ["| quantity | " + " | ".join(f"{lay.name}: peak" for lay in done) +
             f" | largest difference from {ref} |", "|" + "---|" * (len(done) + 2)]
    for quantity, rows in agreement.groupby("quantity", sort=False):
        unit = rows["unit"].iloc[0]
        peaks = {r.layout: r for r in rows.itertuples()}
        spec = ".3f" if unit == "m" else ".1f"
        cells = [f"{figure_text(peaks[lay.name].peak, spec, ' ' + unit)} at {figure_text(peaks[lay.name].time_of_peak_s, '.2f')} s"
                 if lay.name in peaks else "-" for lay in done]
        w = rows.loc[rows["max_abs_diff"].fillna(-1).idxmax()]
        lines.append(f"| {quantity} | " + " | ".join(cells) +
                     f" | {figure_text(w['max_abs_diff'], '.4f' if unit == 'm' else '.2f', ' ' + unit)} "
                     f"({figure_text(100 * w['max_abs_diff_fraction_of_peak'], '.1f', ' %')} of the peak; {w['layout']}) |")
    groups = _plan_groups(done)
    same = [g for g in groups.values() if len(g) > 1]
    text = (f"Against {ref}, the other layouts' records differ: {_differences(agreement)}. The plans: "
            + "; ".join(f"{', '.join(lay.name for lay in g)}: {cells:,} cells, domain x {figure_text(x0, '.2f')} to "
                        f"{figure_text(x1, '.2f')} m, run to {figure_text(end, 'g')} s" for (cells, x0, x1, end), g in groups.items())
            + ("" if len(groups) < 2 else " (the planner truncates the reservoir so that the wave reflected from its "
               "upstream end does not reach the gate region within the run's end time: plan.json, "
               "reasons.reservoir_length)") + ".")
    for g in same:
        text += (f" {_names(g)} run the same plan: between them, "
                 f"{_differences(agree(g))}.")
    lines += ["", text, ""]
    identical = [g for g in same if max(_worst(agree(g))[1], _worst(agree(g))[3]) < SAME_RECORD_FRACTION]
    if all(lay.coupling == "one-way" for lay in done):
        lines += [
            "All layouts ran one-way: each layout's flow is its scene run without the bodies, so the bodies cannot "
            "change the water levels or the force on the column; the records can differ only where the plans "
            "differ" + (f" ({'; '.join(_names(g) for g in identical)}: the same plan, records equal to a "
                        "millionth of their peaks)" if identical else "") + ".", "",
            "The study found that six containers changed neither the water levels nor the column's force. Here that "
            "finding is an assumption of the one-way model, not a result: the planner sends a layout one-way because "
            "its bodies displace under 0.1 % of the reservoir's water and block under 40 % of the flume's width "
            "(plan.json, `debris_coupling`), i.e. because the study's finding is expected to hold. These runs can "
            "neither confirm nor refute it; a two-way (overset) run of the 6-body layout would, and v1912 stalls on "
            "it."]
    else:
        lines.append("Not every layout ran one-way: the differences above include the bodies' effect on the flow.")
    return lines


def _names(layouts: list) -> str:
    names = [lay.name for lay in layouts]
    return names[0] if len(names) == 1 else ", ".join(names[:-1]) + " and " + names[-1]


def _plan_groups(done: list) -> dict[tuple, list]:
    """The layouts by plan: (cells, domain x0, x1, end time) -> layouts (one group: one flow computation)."""
    groups: dict[tuple, list] = {}
    for lay in done:
        x = (lay.domain_m or [[float("nan"), float("nan")]])[0]
        groups.setdefault((lay.summary.get("cells") or 0, x[0], x[1], lay.summary.get("end_time_s")), []).append(lay)
    return groups


def _strike_table(lay) -> list[str]:
    s = lay.strikes
    if not len(s):
        return ["No strike on the column in the simulated time."]
    lines = ["| # | body | strike | time | velocity (normal) | obliquity | contact height | water at the face | "
             "yaw / pitch / roll | peak force | duration | impulse | peak base shear of the strike alone |",
             "|" + "---|" * 13]
    for i, r in enumerate(s.itertuples(), 1):
        lines.append(f"| {i} | {r.body} | {r.strike} | {figure_text(r.time_s)} s | {figure_text(r.impact_velocity_m_s, '.2f')} m/s | "
                     f"{figure_text(r.obliquity_deg, '.0f')} deg | {figure_text(r.height_m)} m | {figure_text(r.face_water_level_m)} m | "
                     f"{figure_text(r.yaw_deg, '.0f')} / {figure_text(r.pitch_deg, '.0f')} / {figure_text(r.roll_deg, '.0f')} deg | "
                     f"{figure_text(r.peak_force_N, '.0f')} N | {figure_text(1e3 * r.duration_s, '.2f')} ms | {figure_text(r.impulse_Ns)} N s | "
                     f"{figure_text(r.peak_base_shear_N, '.0f')} N |")
    return lines


def _contact_lines(lay) -> list[str]:
    bc = lay.body_contacts
    if not len(bc):
        return [f"No contact between two bodies; {_walls(lay)}."]
    approach = bc["approach_velocity_m_s"].abs()
    lines = [f"{len(bc)} contacts between two bodies, from {figure_text(bc['time_s'].min())} s to {figure_text(bc['time_s'].max())} s; "
             f"relative velocity along the contact normal {figure_text(approach.min(), '.2f')}-{figure_text(approach.max(), '.2f')} m/s "
             f"(median {figure_text(approach.median(), '.2f')} m/s); {_walls(lay)}.",
             "", "| time | bodies | approach velocity | separation velocity | restitution |", "|---|---|---|---|---|"]
    for r in bc.sort_values("time_s").head(CONTACT_ROWS).itertuples():
        lines.append(f"| {figure_text(r.time_s)} s | {r.body} - {r.other} | {figure_text(abs(r.approach_velocity_m_s), '.3f')} m/s | "
                     f"{figure_text(r.separation_velocity_m_s, '.3f')} m/s | {figure_text(r.restitution, '.2f')} |")
    if len(bc) > CONTACT_ROWS:
        lines.append(f"\nThe first {CONTACT_ROWS} of {len(bc)}; all in `body_contacts.csv`.")
    return lines


def _walls(lay) -> str:
    return f"{lay.wall_contacts} contacts with the flume's side walls, {lay.end_contacts} with the record's end walls"


def _record_end(lay) -> list[str]:
    """The bodies that reached an end of the flow record, where the transport holds them."""
    if not lay.at_record_end:
        return []
    region = (lay.record_region_m or [[None, None]])[0]
    bodies = ", ".join(f"{b} from {figure_text(t)} s (x = {figure_text(x, '.2f')} m)" for b, (t, x) in lay.at_record_end.items())
    return [f"The flow is recorded over x = {figure_text(region[0], '.2f')} to {figure_text(region[1], '.2f')} m (plan.json, "
            "`flow_record.region_m`: the bodies' starts less a margin to the modelled flume's downstream end); the "
            "transport closes the record's ends with walls, so a body that gets there stays there. Reached the end: "
            f"{bodies}; {lay.end_contacts} contacts with those walls. From then on their tracks and any strikes or "
            "contacts they have are the end wall's, not the flow's, and their spreading angles are measured no "
            "further downstream than the record's end.", ""]


def _spread_line(lay) -> str:
    sp = lay.spreading
    if sp.empty:
        return "No spreading table (results/spreading.csv)."
    parts = []
    for name, spec in SPREADING_ANGLES_DEG.items():
        key = "inside_" + name.split()[0].lower()
        if key in sp:
            inside = int(sp[key].astype(str).eq("True").sum())
            parts.append(f"{inside} of {len(sp)} bodies stayed inside {name}'s {spec['half_angle_deg']:g} deg area")
    return (f"Largest spreading angle of a track from the start line: {figure_text(sp['max_spread_deg'].max(), '.1f', ' deg')}; "
            + "; ".join(parts) + ".")


def markdown(layouts: list, table: pd.DataFrame, agreement: pd.DataFrame, figures: dict[str, str], agree) -> str:
    """The page (module notes); ``figures``: figure name -> file name in the page's folder; ``agree``: the
    flow agreement of a list of layouts (:func:`orchestrator.report.layouts.flow_agreement`)."""
    done = [lay for lay in layouts if lay.ok]
    lines = ["# The debris layouts side by side", "",
             "Generated by `make results-layouts` (`debrisfoam report layouts RUNS... -o DIR`) from the runs; never "
             "edited by hand. Tables: `layouts.csv`, `impacts.csv`, `body_contacts.csv`, `flow_agreement.csv`.", ""]
    couplings = sorted({str(lay.coupling) for lay in done})
    if couplings == ["one-way"]:
        lines += ["Every layout ran one-way: interFoam without the bodies, the flow recorded, then the bodies "
                  "carried through the record on MuJoCo; each strike on the column is resolved by the contact law in "
                  "series with the column's MDOF model, which gives its force history and base shear. Wall times: "
                  f"the solver's on {_ranks(done)} (and its master rank's CPU time, which other jobs on the machine "
                  "do not lengthen), meshing, and the transport: MuJoCo's stepping and the strikes' pulses.", ""]
    lines += ["## The runs", "", *_runs_table(layouts, table), ""]
    for lay in layouts:
        if not lay.ok:
            lines.append(f"- **{lay.name}** did not give results: {lay.status}; {lay.error or 'no error recorded'}"
                         + (f" (log: `{lay.log}`)" if lay.log else "") + f"; case `{lay.case}`.")
    lines += ["", "## The flow of every layout (cf. the study's Figs. 12-13)", ""]
    if "flow" in figures:
        lines += [f"![gauges and column force]({figures['flow']})", "",
                  "Water levels at WG1-WG4 and the hydrodynamic force on the column along the flow, the layouts "
                  "overlaid (each with its own dashes, so coinciding lines stay visible).", ""]
    lines += [*_flow_text(layouts, agreement, agree), ""]
    if "impact_summary" in figures:
        lines += ["## Impact velocities and orientations (cf. the study's Fig. 16)", "",
                  f"![impact velocities and yaw]({figures['impact_summary']})", "",
                  "Each strike on the column: the body's velocity along the contact normal and its yaw at the strike "
                  "(0: long axis along the flow), first strikes of a body and later ones apart.", ""]
    for lay in done:
        lines += [f"## {lay.name}", ""]
        if f"{lay.slug}-tracks" in figures:
            lines += [f"![{lay.name} tracks]({figures[f'{lay.slug}-tracks']})", "",
                      "Tracks of the bodies' centres of mass in plan view (cf. the study's Fig. 14), with the column, "
                      "the spreading areas from the debris's start line and the contacts between bodies; below, "
                      "each body's speed and the times of the strikes.", "", _spread_line(lay), "",
                      *_record_end(lay)]
        lines += ["Strikes on the column (orientation from the body's track at the strike; the base shear is the "
                  "strike's pulse alone on the column's MDOF model, without the hydrodynamic load, which "
                  "results/column_response.csv adds):", "", *_strike_table(lay),
                  ""]
        if f"{lay.slug}-impacts" in figures and len(lay.strikes):
            lines += [f"![{lay.name} impact forces]({figures[f'{lay.slug}-impacts']})", "",
                      "Force of each strike on the column and the base shear it causes at the load cell, from "
                      "contact (cf. the study's Fig. 15).", ""]
        lines += ["Contacts between bodies:", "", *_contact_lines(lay), ""]
    return "\n".join(lines)
