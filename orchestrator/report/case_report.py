"""`debrisfoam report case RUN -o DIR`: one run's answers beside the study's figures, to a results page.

Reads a post-processed run (``RUN/results/summary.json``, ``impacts.csv``) and writes into DIR:
  report.md      the table: arrivals, the first impact (time, speed, contact height, water level
                 at the column's face, afloat or not, the law's pulse, base shear), water balance,
                 wall time, each beside the study's figure and the target where there is one; then
                 each body's first column strike beside the study's 22, like for like (speeds, and
                 the base shear fitted as the study fitted its records: :mod:`orchestrator.report.
                 study_table`), with Welch's test, or a single strike's z; and the ASCE 7-22
                 6.11 design force of each strike with the governing stiffness, at the flow's
                 u_max beside the body's impact speed (:mod:`orchestrator.report.asce_section`)
  summary.json   the run's summary, copied
  *.png          the run's gauges, column forces, impacts and tracks plots, copied
``make results-1debris`` runs it on ``make case-1debris``'s folder; the README's table comes from it.
"""

from __future__ import annotations

import math
import shutil
from pathlib import Path

import pandas as pd

from analytical.study import STUDY_ARRIVALS, STUDY_IMPACT_HEIGHTS_M
from orchestrator.core.errors import InputError
from orchestrator.case.folder import SUMMARY_JSON, CaseFolder
from orchestrator.core.files import read_json_object, write_text_atomic
from orchestrator.report.asce_section import asce_markdown
from orchestrator.report.study_table import comparison_markdown, comparison_note
from orchestrator.results.asce_design import asce_design_table, site_flow_speed
from orchestrator.results.readers import load_case
from orchestrator.results.study_fit import compare_strikes

__all__ = ["write_case_report"]

PLOTS = ("preview.png", "gauges.png", "column_forces.png", "impacts.png", "tracks.png")
#: Wall-time target of the default run (min).
WALL_TARGET_MIN = 30.0


def _fmt(value, spec: str, unit: str = "") -> str:
    if value is None or value != value:
        return "-"
    return f"{value:{spec}}{unit}"


def _within(value, low: float, high: float) -> str:
    if value is None or value != value:
        return "-"
    return "met" if low <= value <= high else "missed"


def _rows(head: dict, first_impact: dict | None) -> list[tuple[str, str, str, str]]:
    rows = []
    arrivals = head.get("comparisons", {}).get("arrival_errors_s", {})
    for gauge, experiment, model in STUDY_ARRIVALS.values():
        g = head.get("gauges", {}).get(gauge, {})
        errors = arrivals.get(gauge, {})
        rows.append((f"bore arrival at {gauge}", _fmt(g.get("arrival_s"), ".3f", " s"),
                     f"experiment {experiment} s, the study's model {model} s; Chanson {_fmt(errors.get('Chanson'), '+.3f', ' s')} off",
                     "-"))
    if first_impact is None:
        rows.append(("first impact on the column", "none", "the study: 22 single-container impacts", "missed"))
        return rows
    speed = first_impact.get("impact_speed_m_s")
    if speed is None:  # impacts.csv without the centre's speed: the normal part over the obliquity's cosine
        normal, oblique = first_impact.get("normal_velocity_in_m_s"), first_impact.get("obliquity_deg")
        speed = normal / math.cos(math.radians(oblique)) if normal is not None and oblique is not None \
            and oblique < 89 else None
    low_h, high_h, mean_h = STUDY_IMPACT_HEIGHTS_M
    afloat = first_impact.get("afloat")
    rows += [
        ("first impact: time", _fmt(first_impact.get("time_s"), ".3f", " s"), "-", "-"),
        ("impact speed (along the contact normal, obliquity)",
         f"{_fmt(speed, '.2f', ' m/s')} ({_fmt(first_impact.get('impact_velocity_m_s'), '.2f', ' m/s')}, "
         f"{_fmt(first_impact.get('obliquity_deg'), '.0f', ' degrees')})", "1.6 +- 0.13 m/s", "below"),
        ("afloat at the impact", {True: "yes", False: "no"}.get(afloat, "-") +
         f" (lowest point {_fmt(first_impact.get('body_clearance_m'), '.3f', ' m')} above the bed)",
         "carried afloat", {True: "met", False: "missed"}.get(afloat, "-")),
        ("contact point above the bed", _fmt(first_impact.get("height_m"), ".3f", " m"), ">= 0.05 m",
         _within(first_impact.get("height_m"), 0.05, float("inf"))),
        ("water level at the column's face (the study's impact height)",
         _fmt(first_impact.get("face_water_level_m"), ".3f", " m"), f"{low_h}-{high_h} m, mean {mean_h} m", "-"),
        ("time since the front reached the face (negative: ahead of it)",
         _fmt(first_impact.get("time_since_front_s"), ".3f", " s"), "not stated", "-"),
    ]
    for name, label, scale, unit, spec in (("peak_force_N", "the contact law's pulse: magnitude", 1.0, " N", ".0f"),
                                           ("duration_s", "the contact law's pulse: duration", 1e3, " ms", ".2f"),
                                           ("impulse_Ns", "the contact law's pulse: impulse", 1.0, " N s", ".3f")):
        value = first_impact.get(name)
        rows.append((label, _fmt(value * scale if value is not None else None, spec, unit),
                     "not tabulated (Table 2 holds fits of the base shear)", "-"))
    fit = first_impact.get("study_fit_peak_N")
    rows.append(("the study's fit of its base shear (half-sine on the MDOF column)",
                 f"{_fmt(fit, '.0f', ' N')}, {_fmt((first_impact.get('study_fit_duration_s') or math.nan) * 1e3, '.2f', ' ms')}, "
                 f"{_fmt(first_impact.get('study_fit_impulse_Ns'), '.3f', ' N s')} at "
                 f"{_fmt(first_impact.get('study_fit_height_m'), '.3f', ' m')} "
                 f"({first_impact.get('study_fit_height_source') or 'no fit'})",
                 "171 +- 63 N, 4.7 +- 0.5 ms, 0.52 +- 0.22 N s (Table 2, MDOF)", "below"))
    shear = head.get("column_response", {}).get("peak_base_shear_N")
    rows.append(("peak base shear at the load cell", _fmt(shear, ".0f", " N"), "not tabulated by the study", "-"))
    return rows


def write_case_report(case_dir: str | Path, out_dir: str | Path) -> Path:
    """Write the results page of a post-processed run (see the module notes); returns report.md."""
    case, out = Path(case_dir), Path(out_dir)
    folder = CaseFolder(case)
    summary_path = folder.summary_path
    if not summary_path.is_file():
        raise InputError("case_dir", f"no results/summary.json: run `debrisfoam post {case}` first", str(case))
    head = read_json_object(summary_path)
    if head is None:
        raise InputError("results/summary.json", f"not a JSON object: run `debrisfoam post {case}` again", str(case))
    impacts_path = folder.results_dir / "impacts.csv"
    first, firsts, impacts = None, pd.DataFrame(), pd.DataFrame()
    if impacts_path.is_file():
        impacts = pd.read_csv(impacts_path)
        column = impacts[impacts["kind"] == "column"].sort_values("time_s", kind="stable")
        firsts = column.drop_duplicates("body", keep="first")
        if len(column):
            row = column.iloc[0]
            first = {k: (None if pd.isna(v) else v) for k, v in row.to_dict().items()}
            if isinstance(first.get("afloat"), str):
                first["afloat"] = first["afloat"] == "True"
    out.mkdir(parents=True, exist_ok=True)
    for name in PLOTS:  # the scene's preview lies in the case, the rest in its results
        for where in (folder.results_dir / name, case / name):
            if where.is_file():
                shutil.copy2(where, out / name)
                break
    shutil.copy2(summary_path, out / SUMMARY_JSON)
    rows = _rows(head, first)
    balance = head.get("water_balance") or {}
    wall = (head.get("wall_time_s") or {}).get("total_s")
    rows.append(("water balance at the end", _fmt(100 * balance["final_error"], "+.2f", " %") if balance else "-",
                 "conserved to 1 %", _within(abs(balance.get("final_error", float("nan"))), 0.0, 0.01)))
    finished = head.get("status") == "finished"
    reached = head.get("reached_time_s")
    rows.append(("time steps / wall time", f"{head.get('time_steps', '-')} / {_fmt(wall / 60 if wall else None, '.1f', ' min')}"
                 + ("" if finished else f" to t = {_fmt(reached, '.2f', ' s')}"),
                 f"at most {WALL_TARGET_MIN:g} min on 2 cores",
                 _within(wall / 60 if wall else None, 0.0, WALL_TARGET_MIN) if finished
                 else ("missed" if wall and wall / 60 > WALL_TARGET_MIN else "not finished")))
    lines = [f"# `{head.get('scene', case.name)}`: the run beside the study", "",
             "Generated by `make results-1debris` (`debrisfoam report case RUN -o DIR`) from a run; never edited by "
             "hand.", "",
             f"{head.get('cells', '-')} cells; simulated to {_fmt(head.get('reached_time_s'), '.3g', ' s')} of "
             f"{head.get('end_time_s', '-')} s, status {head.get('status', '-')}; "
             f"{head.get('impacts', {}).get('on_column', 0)} impacts on the column. The speed and the pulse are set "
             "against the study's 22 impacts like for like below the table (\"below\").", "",
             "| figure | this run | the study | target |", "|---|---|---|---|"]
    lines += [f"| {a} | {b} | {c} | {d} |" for a, b, c, d in rows]
    lines += ["", f"## Each body's first column strike beside the study's 22, like for like ({len(firsts)} "
              f"strike{'' if len(firsts) == 1 else 's'})", "",
              *comparison_markdown(compare_strikes(firsts)), "", comparison_note(), ""]
    data = load_case(case)
    site = site_flow_speed(case, data.scene)
    asce = asce_design_table(impacts, data.body_masses_kg, float(data.column.stiffness_N_m), site) \
        if data.column is not None and not impacts.empty else pd.DataFrame()
    lines += asce_markdown(asce, site, heading="##")
    lines += ["", *(f"![{p[:-4]}]({p})" for p in PLOTS if (out / p).is_file()), ""]
    if head.get("missing"):
        lines += ["What the post-processing could not give:", "", *(f"- {m}" for m in head["missing"]), ""]
    return write_text_atomic(out / "report.md", "\n".join(lines))
