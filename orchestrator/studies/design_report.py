"""A design study's page: design.json, exceedance.png and design.md (docs/design.md).

* **Exceedance.** For each demand (:data:`~orchestrator.studies.design.DEMANDS`), the
  realisations' demands (their largest strike; 0 without one) grouped by inundation case
  and weighted by it (:func:`analytical.exceedance.exceedance`): the curve ``P(X >= x)`` with
  its pointwise Clopper-Pearson band, the DKW half-width of the simultaneous band, and P50, P90,
  P99 with their intervals (``upper`` None: more realisations needed for that quantile).
* **ASCE 7-22 beside it** (:func:`asce_values`): ``F_i = I_tsu C_o u_max sqrt(k m_d)`` with
  the column's lateral stiffness ``k_s`` and with the debris stiffness ``k_d`` (6.11.2: the
  lesser governs), bounded at full scale by the simplified static load
  (:class:`analytical.asce7.AsceDesign`); the page names what binds. Its inputs are the scene's,
  read as the analytical verbs read them (:mod:`orchestrator.studies.design_asce`): ``u_max`` of
  the case whose flow is fastest at the site (the envelope of the cases; each case's own is in
  design.json), the heaviest mass the study draws, ``I_tsu`` of the risk category. For base shear, base moment
  and the member's largest displacement the code's load is its own rectangular pulse (``F_i`` over
  ``t_d = 2 m_d u_max / F_ni``) on the same MDOF column (:func:`analytical.column_demand.column_demands`)
  at the highest contact height any realisation struck at (the code loads the most critical
  point up to the inundation depth; the highest strike stands for it), with the code's dynamic
  response ratio ``R_max`` at ``t_d / T1`` (:func:`code_pulse_demands`). Each code value gets
  ``P(X > value)`` with its interval, unless the scene is at full scale and its contact law is
  not within 30 % of a published full-scale test's peak force at its speed
  (:func:`analytical.fullscale_check.agreeing_test`; no complete test was found, so a full-scale
  page gives none and says why, :data:`NO_EXCEEDANCE`).
* **What a designer signs** (:mod:`orchestrator.studies.design_advice`): the quantiles given a
  strike, the recommended design value with its band, and the strikes as they struck.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np

from analytical.asce7 import dynamic_response_ratio
from analytical.column_demand import column_demands
from analytical.column_fem import column_model
from analytical.exceedance import exceedance
from analytical.fullscale_check import agreeing_test, calibration_possible
from analytical.pulses import Rectangular
from orchestrator.contact.resolution import body_contact_law
from orchestrator.core.files import write_json_atomic, write_text_atomic
from orchestrator.report.figures import WIDTH_IN, empty, pyplot, save_figure
from orchestrator.scene.schema import Design, column_for_analysis
from orchestrator.scene.scenefile import load_scene
from orchestrator.studies.design_advice import advice, advice_lines, conditional_exceedance, demand_lines, \
    fmt_demand
from orchestrator.studies.design_asce import scene_asce_inputs
from orchestrator.studies.design_table import DEMANDS, realisation_demands

__all__ = ["CONDITIONAL", "NO_EXCEEDANCE", "QUANTILES", "asce_values", "figure_exceedance", "markdown", "summarise", "write_report"]

QUANTILES = {"P50": 0.50, "P90": 0.90, "P99": 0.99}

NO_EXCEEDANCE = ("No probability of exceeding the code's values is given: at full scale the pulses come from the "
                 "scene's stated contact law, and no published full-scale test (a speed, a mass and a peak force "
                 "together, docs/fullscale-sources.md) shows that law within 30 % of its peak force.")

CONDITIONAL = ("Conditional on the scene's inundation: every probability here is given the inundation cases of "
               "the scene's design section, weighted as it says. This is not a probabilistic tsunami hazard "
               "analysis: how likely that inundation is at the site is not in it.")


def code_pulse_demands(force_N: float, duration_s: float, column, height_m: float) -> dict[str, float]:
    """The code's load, a rectangular pulse of ``force_N`` over ``duration_s``, on the MDOF column
    at ``height_m``: peak base shear, base moment and the member's largest displacement, read through the pulse and
    after it (:func:`analytical.column_demand.column_demands`), and the code's dynamic response
    ratio for it: ``t_d / T1`` and ``R_max``, the largest response of the column's first mode (an
    SDOF of its period and damping) over the static one (:func:`analytical.asce7.dynamic_response_ratio`)."""
    d = column_demands(Rectangular(force_N, duration_s), column, height_m)
    period = 1.0 / float(column_model(column).frequencies_Hz[0])
    return {"peak_force_N": force_N, "base_shear_N": d.peak_base_shear_N, "base_moment_Nm": d.peak_base_moment_Nm,
            "displacement_m": d.peak_displacement_m, "duration_s": duration_s,
            "first_period_s": period, "td_over_T1": duration_s / period,
            "R_max": dynamic_response_ratio(duration_s, period, "rectangular", column.damping_ratio)}


def asce_values(result, spec: Design, heights_m: np.ndarray, scene=None) -> dict[str, Any]:
    """ASCE 7-22 6.11's values for the study's inputs (module notes): the inputs are the scene's
    (``scene``, without the cases' overrides; None: the first case's), read by
    :func:`~orchestrator.studies.design_asce.scene_asce_inputs` as `analytical asce7 --scene` and
    `analytical impact --scene` read them; u_max the scene's stated ``inundation.speed_m_s``, else the
    fastest case's at the site; the code's pulse at the strike point k_s is taken at."""
    cases = result.cases
    scene = cases[0].scene if scene is None else scene
    column = column_for_analysis(scene)
    inputs = scene_asce_inputs(scene, spec=spec)
    per_case, best = [], None
    for case in cases:
        u, basis = (case.site.u_max_m_s, "u_max of the flow at the site") if case.site is not None else (None, None)
        if u is None:
            struck = result.table[(result.table["case"] == case.name) & result.table["struck"]]
            speeds = struck["impact_speed_m_s"].dropna()
            u, basis = (float(speeds.max()), "the largest impact speed (no flow velocity recorded at the site)") \
                if len(speeds) else (None, None)
        per_case.append({"case": case.name, "u_max_m_s": u, "basis": basis,
                         "site": case.site.describe() if case.site is not None else None})
        if u is not None and (best is None or u > best["u_max_m_s"]):
            best = per_case[-1]
    checked = [agreeing_test(body_contact_law(b.contact)) for b in scene.debris]
    shown = not inputs.prototype or (calibration_possible() and all(c is not None for c in checked))
    out: dict[str, Any] = {"cases": per_case, "mass_kg": inputs.mass_kg, "debris_stiffness_N_m": inputs.debris_stiffness_N_m,
                           "structure_stiffness_N_m": inputs.structure_stiffness_N_m,
                           "importance_I_tsu": inputs.importance, "risk_category": inputs.risk_category,
                           "orientation_C_o": inputs.orientation, "prototype": inputs.prototype,
                           "scale": inputs.scale_reason, "sources": inputs.sources, "values": None,
                           "exceedance_shown": shown, "exceedance_note": None if shown else NO_EXCEEDANCE,
                           "law_checked_by": [c.outcome() for c in checked if c is not None]}
    simulated = best
    if inputs.stated_speed_m_s is not None:
        best = {"case": None, "u_max_m_s": inputs.stated_speed_m_s,
                "basis": "the designer's stated speed at the site, inundation.speed_m_s"}
    if best is None:
        return out
    design = inputs.design(best["u_max_m_s"], best["basis"])
    heights = heights_m[np.isfinite(heights_m) & (heights_m > 0)]
    height = float(min(heights.max(), column.height_m)) if heights.size else 0.5 * column.height_m
    if inputs.strike_height_m is not None:
        height, heights = inputs.strike_height_m, None
    values = {}
    for label, impact in (("k_s", design.design if design.governing == "k_s" else design.other),
                          ("k_d", design.design if design.governing == "k_d" else design.other)):
        capped = bool(design.prototype and impact.force_N > design.cap_N)
        force = design.cap_N if capped else impact.force_N
        values[label] = {"stiffness_N_m": impact.stiffness_N_m, "uncapped_force_N": impact.force_N,
                         **code_pulse_demands(force, impact.duration_s, column, height), "capped": capped}
    out.update(values=values, governing=design.governing, binding=design.binding, force_N=design.force_N,
               u_max_m_s=best["u_max_m_s"], u_basis=best["basis"],
               u_case=best["case"], load_height_m=height, cap_N=design.cap_N, cap_note=design.cap_note(),
               u_simulated_m_s=None if simulated is None else simulated["u_max_m_s"],
               u_simulated_case=None if simulated is None else simulated["case"],
               height_basis="the strike point of k_s" if heights is None
               else "the highest contact height any realisation struck at" if heights.size
               else "half the column's height (no realisation struck)")
    return out


def input_sources(scene, spec: Design, typed: list) -> dict[str, str]:
    """Where each of F_i's inputs comes from, for the page (u_max's is the case's own basis)."""
    return scene_asce_inputs(scene, spec=spec).sources


def summarise(result, scene_path, sets: list[str], spec: Design, wall: dict[str, Any]) -> dict[str, Any]:
    """design.json's content (module notes)."""
    per = realisation_demands(result.table)
    cases = result.cases
    weights = [c.weight for c in cases]
    groups = {k: [per.loc[per["case"] == c.name, k].to_numpy(float) for c in cases] for k in DEMANDS}
    strike = exceedance([per.loc[per["case"] == c.name, "struck"].to_numpy(float) for c in cases], weights,
                        spec.confidence).exceeds(0.5)
    heights = result.table.loc[result.table["struck"], "impact_height_m"].to_numpy(float)
    asce = asce_values(result, spec, heights, load_scene(scene_path, list(sets)))
    demands = {}
    for key, (label, unit) in DEMANDS.items():
        exc = exceedance(groups[key], weights, spec.confidence)
        entry = {"label": label, "unit": unit, "dkw_halfwidth": exc.dkw(),
                 "quantiles": {name: exc.quantile(p).to_dict() for name, p in QUANTILES.items()},
                 "max": float(exc.values[-1])}
        if asce["values"] is not None and asce["exceedance_shown"]:
            entry["asce"] = {k: exc.exceeds(v[key]) for k, v in asce["values"].items()}
        demands[key] = entry
    return {"scene": str(scene_path), "overrides": sets, "conditional": CONDITIONAL,
            "realisations": int(len(per)), "confidence": spec.confidence, "seed": int(spec.seed),
            "effective_samples": exc.n_eff,
            "strike_probability": {k: strike[k] for k in ("probability", "lower", "upper")},
            "cases": [{"name": c.name, "overrides": c.sets[len(sets):], "weight": c.weight,
                       "realisations": c.realisations, "flow_case": str(c.flow_case),
                       "strike_probability": float(per.loc[per["case"] == c.name, "struck"].mean()),
                       "front_celerity_m_s": c.front_celerity_m_s,
                       "flow_phase_wall_s": round(c.flow_wall_s, 2)} for c in cases],
            "draws": {"mass_kg": list(spec.mass_kg) if spec.mass_kg else _masses_drawn(result.table),
                      "heading_deg": list(spec.heading_deg) if spec.heading_deg else "placement tolerance",
                      "start_x_m": list(spec.start_x_m) if spec.start_x_m else None,
                      "start_y_m": list(spec.start_y_m) if spec.start_y_m else None},
            "intervals": {"exceedance": "Clopper-Pearson (pointwise) on effective counts",
                          "curve": "DKW simultaneous band, half-width dkw_halfwidth",
                          "quantiles": "the pointwise band inverted; upper null: more realisations needed"},
            "demands": demands, "asce": asce, **advice(result, per, spec.confidence, QUANTILES, asce), **wall}


def figure_exceedance(result, summary: dict[str, Any]):
    """One log-scale exceedance panel per demand, its band, the ASCE 7-22 values as vertical lines."""
    plt = pyplot()
    fig, axes = plt.subplots(2, 2, figsize=(WIDTH_IN, 8.0))
    per = realisation_demands(result.table)
    weights = [c.weight for c in result.cases]
    asce = summary["asce"]
    for ax, (key, (label, unit)) in zip(axes.ravel(), DEMANDS.items()):
        exc = exceedance([per.loc[per["case"] == c.name, key].to_numpy(float) for c in result.cases], weights,
                         summary["confidence"])
        curve = exc.curve()
        if curve["level"].size == 0:
            empty(ax, f"{label}: no realisation struck the column")
            continue
        conf = f"{summary['confidence'] * 100:.0f} %"
        ax.fill_between(curve["level"], np.maximum(curve["lower"], 1e-12), curve["upper"], step="pre", alpha=0.25,
                        color="C0", lw=0, label=f"{conf} interval of each probability (Clopper-Pearson)")
        ax.step(curve["level"], curve["probability"], where="pre", color="C0", label="this tool's realisations")
        given = conditional_exceedance(per, result.cases, key, summary["confidence"])
        if given is not None:
            g = given.curve()
            ax.step(g["level"], g["probability"], where="pre", color="C2", ls="--", label="given a strike")
        rec = summary.get("recommended")
        if rec is not None:
            ax.axvline(rec["demands"][key]["value"], color="C2", ls=":", lw=1.2,
                       label=f"recommended: {rec['fractile']} given a strike x I_tsu")
        floor = max(float(curve["probability"].min()) / 3.0, 1e-5)
        for name, q in summary["demands"][key]["quantiles"].items():
            ax.plot([q["value"]], [1.0 - QUANTILES[name]], "k.", ms=5)
            if q["upper"] is not None:
                ax.plot([q["lower"], q["upper"]], [1.0 - QUANTILES[name]] * 2, "k-", lw=1)
        for k, style in (("k_s", "-"), ("k_d", "--")):
            if asce["values"] is None:
                continue
            value = asce["values"][k][key]
            p = summary["demands"][key].get("asce", {}).get(k)
            governs = " (governs)" if asce["governing"] == k else ""
            ax.axvline(value, color="C3", ls=style, lw=1.2,
                       label=f"ASCE 7-22 with {k}{governs}" + (f": P(exceed) = {p['probability']:.3g} "
                                                                f"[{p['lower']:.2g}, {p['upper']:.2g}]" if p else ""))
        if asce["values"] is not None and asce["prototype"] and key == "peak_force_N":
            ax.axvline(asce["cap_N"], color="C3", ls=":", lw=1, label="simplified static load (cap)")
        ax.set_yscale("log")
        ax.set_ylim(floor, 1.05)
        ax.set_xlabel(f"{label} ({unit})")
        ax.set_ylabel("exceedance probability")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7, loc="upper right")
    p = summary["strike_probability"]
    fig.suptitle(f"{summary['realisations']} realisations; P(strike) = {p['probability']:.3f} "
                 f"[{p['lower']:.3f}, {p['upper']:.3f}]; conditional on the scene's inundation "
                 "(not a probabilistic tsunami hazard analysis)", fontsize=9)
    fig.tight_layout(rect=(0, 0, 1, 0.96))
    return fig


def _author(case) -> str:
    """u_max's origin: the scene author's statement (no case) or the simulated flow."""
    return " (the scene author's statement)" if case is None else ""


def _masses_drawn(table) -> str:
    """The mass draw without `design.mass_kg`: a catalogued body's empty-to-loaded range, as drawn."""
    masses = table["mass_kg"].to_numpy(float)
    if not len(masses) or masses.min() == masses.max():
        return "each body's own"
    return f"each catalogued body's empty-to-loaded range (drawn {masses.min():,.0f} to {masses.max():,.0f} kg)"


def _force(value: float) -> str:
    """A force in kN or MN."""
    return f"{value / 1e6:.3g} MN" if abs(value) >= 1e6 else f"{value / 1e3:.3g} kN" if abs(value) >= 1e3 \
        else f"{value:.4g} N"


def _binding(binding: str) -> str:
    return {"k_s": "the k_s line (the column's stiffness, the lesser)",
            "k_d": "the k_d line (the debris' stiffness, the lesser)"}.get(binding, f"the {binding} (full scale)")


def _num(value: float | None, digits: int = 4) -> str:
    if value is None or (isinstance(value, float) and not math.isfinite(value)):
        return "-"
    return f"{value:.{digits}g}"


def _range(value, unit: str) -> str:
    if isinstance(value, list):
        return f"{value[0]:g} to {value[1]:g} {unit}"
    return "each body's own" if value == "each body's own" else f"{value or 'the placement tolerance'}"


def markdown(summary: dict[str, Any]) -> str:
    """design.md: the page (module notes)."""
    conf = f"{summary['confidence'] * 100:.0f} %"
    p = summary["strike_probability"]
    lines = [f"# Design demands: {summary['scene']}", "", f"**{summary['conditional']}**", "",
             f"{summary['realisations']} realisations (seed {summary['seed']}); P(strike) = {p['probability']:.4g} "
             f"({conf} interval {p['lower']:.3g} to {p['upper']:.3g}). A realisation that never strikes is a demand "
             "of 0 in the unconditional curves and quantiles; given a strike, it is left out. Intervals: " + "; ".join(f"{k}: {v}" for k, v in
                                                                       summary["intervals"].items()) + ".", "",
             "## Inundation cases", "", "| case | overrides | weight | realisations | P(strike) | u_max (m/s) | "
             "front (m/s) |", "|---|---|---|---|---|---|---|"]
    asce = summary["asce"]
    u = {c["case"]: c["u_max_m_s"] for c in asce["cases"]}
    for c in summary["cases"]:
        lines.append(f"| {c['name']} | {', '.join(c['overrides']) or 'the scene as it is'} | {c['weight']:.3g} | "
                     f"{c['realisations']} | {c['strike_probability']:.3g} | {_num(u.get(c['name']), 3)} | "
                     f"{_num(c.get('front_celerity_m_s'), 3)} |")
    draws = summary["draws"]
    lines += ["", f"Draws (uniform where a range is given): mass {_range(draws['mass_kg'], 'kg')}, heading "
                  f"{_range(draws['heading_deg'], 'deg')}, start x {_range(draws['start_x_m'], 'm')}, start y "
                  f"{_range(draws['start_y_m'], 'm')}.", "",
              *advice_lines(summary), *demand_lines(summary)]
    lines += ["", "## ASCE 7-22 Section 6.11 for the same inputs", ""]
    if asce["values"] is None:
        lines.append("No site speed and no strike: no ASCE value to set beside the curves.")
    else:
        case = "" if asce["u_case"] is None else f", case {asce['u_case']}"
        lines += [f"F_i = I_tsu C_o u_max sqrt(k m_d) with u_max = {asce['u_max_m_s']:.3g} m/s ({asce['u_basis']}"
                  f"{case}), m_d = {asce['mass_kg']:.4g} kg (the heaviest drawn), I_tsu = "
                  f"{asce['importance_I_tsu']:g} (risk category {asce['risk_category']}), C_o = "
                  f"{asce['orientation_C_o']:g}, k_s = {asce['structure_stiffness_N_m']:.4g} N/m, k_d = "
                  f"{asce['debris_stiffness_N_m']:.4g} N/m; {asce['governing']} is the lesser stiffness; "
                  f"{asce['cap_note']}.", "",
                  f"**F_i = {_force(asce['force_N'])}, bound by {_binding(asce['binding'])}.** Base shear, base "
                  "moment and the member's largest displacement: the code's rectangular pulse on the same MDOF column at "
                  f"{asce['load_height_m']:.3g} m ({asce['height_basis']}), read through the pulse and after it.", "",
                  "The code's dynamic response ratio (the column's first mode, an SDOF of its period T1 and "
                  "damping, under the rectangular pulse): R_max = max response / static response.", "",
                  "| line | F | t_d (s) | T1 (s) | t_d/T1 | R_max |", "|---|---|---|---|---|---|",
                  *[f"| {k}{' (capped)' if v['capped'] else ''} | {_force(v['peak_force_N'])} | {_num(v['duration_s'])} "
                    f"| {_num(v['first_period_s'])} | {_num(v['td_over_T1'], 3)} | {_num(v['R_max'], 3)} |"
                    for k, v in asce["values"].items()], "",
                  "Where each input comes from:", "",
                  f"- u_max: {asce['u_basis']}{_author(asce['u_case'])}; the simulated flow's largest, two column widths upstream of the face "
                  f"(orchestrator/results/asce_design.py): {_num(asce.get('u_simulated_m_s'), 3)} m/s in case "
                  f"{asce.get('u_simulated_case')}",
                  *[f"- {k}: {v}" for k, v in asce["sources"].items()], ""]
        shown = asce.get("exceedance_shown", True)
        if not shown:
            lines += [asce["exceedance_note"], ""]
        lines += (["| demand | with k_s | P(exceed k_s value) | with k_d | P(exceed k_d value) |", "|---|---|---|---|---|"]
                  if shown else ["| demand | with k_s | with k_d |", "|---|---|---|"])
        for key, d in summary["demands"].items():
            cells = []
            for k in ("k_s", "k_d"):
                cells.append(fmt_demand(asce["values"][k][key], d["unit"]))
                if shown:
                    e = d["asce"][k]
                    cells.append(f"{e['probability']:.3g} [{e['lower']:.3g}, {e['upper']:.3g}]")
            lines.append(f"| {d['label']} | {' | '.join(cells)} |")
    lines += ["", "![exceedance](exceedance.png)", "",
              "Files: design.csv (one row per strike, and per body that never struck), design.json (these figures), "
              "exceedance.png.",
              f"Wall time {summary['wall_time_s']:g} s (flows {summary['flow_phase_wall_s']:g} s) on "
              f"{summary['executor']} with {summary['workers']} worker(s).", ""]
    return "\n".join(lines)


def write_report(out: Path, result, scene_path, sets: list[str], spec: Design, wall: dict[str, Any]) -> dict:
    """design.json, exceedance.png and design.md in ``out``; their paths."""
    summary = summarise(result, scene_path, sets, spec, wall)
    result.summary = summary
    files = {"summary": write_json_atomic(out / "design.json", summary),
             "figure": save_figure(figure_exceedance(result, summary), out / "exceedance.png")}
    files["report"] = write_text_atomic(out / "design.md", markdown(summary))
    return files
