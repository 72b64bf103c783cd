"""A design study's page: design.json, exceedance.png and design.md (docs/design.md).

* **Exceedance.** For each demand (:data:`~orchestrator.studies.design.DEMANDS`), the
  realisations' demands (largest over the bodies; 0 without a strike) grouped by inundation case
  and weighted by it (:func:`analytical.exceedance.exceedance`): the curve ``P(X >= x)`` with
  its pointwise Clopper-Pearson band, the DKW half-width of the simultaneous band, and P50, P90,
  P99 with their intervals (``upper`` None: more realisations needed for that quantile).
* **ASCE 7-22 beside it** (:func:`asce_values`): ``F_i = I_tsu C_o u_max sqrt(k m_d)`` with
  the column's lateral stiffness ``k_s`` and with the debris stiffness ``k_d`` (6.11.2: the
  lesser governs), capped at prototype scale by the simplified static load
  (:class:`analytical.asce7.AsceDesign`). Its inputs: ``u_max`` of the case whose flow is
  fastest at the site (the envelope of the cases; each case's own is in design.json), the
  heaviest mass the study draws, ``I_tsu`` of the risk category. For base shear, base moment
  and top displacement the code's load is its own rectangular pulse (``F_i`` over
  ``t_d = 2 m_d u_max / F_ni``) on the same MDOF column (:func:`analytical.column_demand.column_demands`)
  at the highest contact height any realisation struck at (the code loads the most critical
  point up to the inundation depth; the highest strike stands for it). Each code value gets
  ``P(X > value)`` with its interval.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np

from analytical.asce7 import SEED_DEBRIS_STIFFNESS_N_M, asce7_design, importance_factor
from analytical.column_demand import column_demands
from analytical.exceedance import exceedance
from analytical.pulses import Rectangular
from analytical import catalogue
from orchestrator.core.files import write_json_atomic, write_text_atomic
from orchestrator.report.figures import WIDTH_IN, empty, pyplot, save_figure
from orchestrator.scene.schema import Design, column_for_analysis
from orchestrator.studies.design_table import DEMANDS, debris_types, mass_range, realisation_demands
from orchestrator.transport.case_transport import scene_bodies

__all__ = ["CONDITIONAL", "QUANTILES", "asce_values", "figure_exceedance", "markdown", "summarise", "write_report"]

QUANTILES = {"P50": 0.50, "P90": 0.90, "P99": 0.99}

CONDITIONAL = ("Conditional on the scene's inundation: every probability here is given the inundation cases of "
               "the scene's design section, weighted as it says. This is not a probabilistic tsunami hazard "
               "analysis: how likely that inundation is at the site is not in it.")


def asce_values(result, spec: Design, heights_m: np.ndarray) -> dict[str, Any]:
    """ASCE 7-22 6.11's values for the study's inputs (module notes)."""
    cases = result.cases
    scene = cases[0].scene
    column = column_for_analysis(scene)
    types = debris_types(scene)
    mass = max(mass_range(b, spec, types.get(b.name))[1] for b in scene_bodies(scene))
    typed = [catalogue.debris_type(t) for t in types.values() if t is not None]
    # the code's k_d: the design section's; else the catalogued debris's (the study's k_d Froude-scaled,
    # docs/catalogue.md: ASCE 7-22's Table 6.11-2 values are not in the tool); else the study's
    k_d = float(spec.debris_stiffness_N_m or max((e.kd_N_m for e in typed), default=SEED_DEBRIS_STIFFNESS_N_M))
    k_s = float(column.stiffness_N_m)
    sources = input_sources(scene, spec, typed)
    importance = importance_factor(spec.risk_category)
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
    out: dict[str, Any] = {"cases": per_case, "mass_kg": mass, "debris_stiffness_N_m": k_d,
                           "structure_stiffness_N_m": k_s, "importance_I_tsu": importance,
                           "risk_category": spec.risk_category, "orientation_C_o": float(spec.orientation_coefficient),
                           "prototype": bool(spec.prototype), "sources": sources, "values": None}
    if best is None:
        return out
    design = asce7_design(best["u_max_m_s"], mass, k_d, k_s, importance, float(spec.orientation_coefficient),
                          prototype=bool(spec.prototype), velocity_basis=best["basis"])
    heights = heights_m[np.isfinite(heights_m) & (heights_m > 0)]
    height = float(min(heights.max(), column.height_m)) if heights.size else 0.5 * column.height_m
    values = {}
    for label, impact in (("k_s", design.design if design.governing == "k_s" else design.other),
                          ("k_d", design.design if design.governing == "k_d" else design.other)):
        force = min(impact.force_N, design.cap_N) if spec.prototype else impact.force_N
        d = column_demands(Rectangular(force, impact.duration_s), column, height)
        values[label] = {"stiffness_N_m": impact.stiffness_N_m, "duration_s": impact.duration_s,
                         "peak_force_N": force, "base_shear_N": d.peak_base_shear_N,
                         "base_moment_Nm": d.peak_base_moment_Nm, "top_displacement_m": d.peak_top_displacement_m,
                         "capped": bool(spec.prototype and impact.force_N > design.cap_N)}
    out.update(values=values, governing=design.governing, u_max_m_s=best["u_max_m_s"], u_basis=best["basis"],
               u_case=best["case"], load_height_m=height, cap_N=design.cap_N, cap_note=design.cap_note(),
               height_basis="the highest contact height any realisation struck at" if heights.size
               else "half the column's height (no realisation struck)")
    return out


def input_sources(scene, spec: Design, typed: list) -> dict[str, str]:
    """Where each of F_i's inputs comes from, for the page (u_max's is the case's own basis)."""
    if spec.debris_stiffness_N_m is not None:
        k_d = "the scene's design.debris_stiffness_N_m"
    elif typed:
        e = max(typed, key=lambda t: t.kd_N_m)
        k_d = (f"the debris catalogue's for {e.name}: the study's 1:{e.scale:g} container's k_d "
               f"({SEED_DEBRIS_STIFFNESS_N_M:.3g} N/m) Froude-scaled by {e.scale:g}^2; ASCE 7-22 Table 6.11-2's "
               "value is not in the tool (docs/catalogue.md)")
    else:
        k_d = f"the study's 1:40 container's k_d, {SEED_DEBRIS_STIFFNESS_N_M:.3g} N/m (analytical/asce7.py)"
    if spec.mass_kg is not None:
        m_d = "the upper end of the scene's design.mass_kg"
    elif any(t.family is not None for t in typed):
        m_d = "the loaded mass of the debris catalogue's " + ", ".join(sorted({t.family for t in typed if t.family}))
    else:
        m_d = "the heaviest body's own mass"
    section = getattr(scene.column, "section", None)
    k_s = ("the column's MDOF model's lateral stiffness at its top, from its catalogued section "
           f"({section.kind} {'x'.join(f'{v:g}' for v in section.size_m)} m, docs/catalogue.md)" if section is not None
           else "the scene's column.stiffness_N_m")
    c_o = "design.orientation_coefficient (0.65: ASCE 7-22 6.11's value for containers, logs and poles, the default)"
    return {"k_d": k_d, "m_d": m_d, "k_s": k_s, "C_o": c_o,
            "I_tsu": f"ASCE 7-22 Table 6.8-1 for the scene's design.risk_category ({spec.risk_category})"}


def summarise(result, scene_path, sets: list[str], spec: Design, wall: dict[str, Any]) -> dict[str, Any]:
    """design.json's content (module notes)."""
    per = realisation_demands(result.table)
    cases = result.cases
    weights = [c.weight for c in cases]
    groups = {k: [per.loc[per["case"] == c.name, k].to_numpy(float) for c in cases] for k in DEMANDS}
    strike = exceedance([per.loc[per["case"] == c.name, "struck"].to_numpy(float) for c in cases], weights,
                        spec.confidence).exceeds(0.5)
    heights = result.table.loc[result.table["struck"], "impact_height_m"].to_numpy(float)
    asce = asce_values(result, spec, heights)
    demands = {}
    for key, (label, unit) in DEMANDS.items():
        exc = exceedance(groups[key], weights, spec.confidence)
        entry = {"label": label, "unit": unit, "dkw_halfwidth": exc.dkw(),
                 "quantiles": {name: exc.quantile(p).to_dict() for name, p in QUANTILES.items()},
                 "max": float(exc.values[-1])}
        if asce["values"] is not None:
            entry["asce"] = {k: exc.exceeds(v[key]) for k, v in asce["values"].items()}
        demands[key] = entry
    return {"scene": str(scene_path), "overrides": sets, "conditional": CONDITIONAL,
            "realisations": int(len(per)), "confidence": spec.confidence, "seed": int(spec.seed),
            "effective_samples": exc.n_eff,
            "strike_probability": {k: strike[k] for k in ("probability", "lower", "upper")},
            "cases": [{"name": c.name, "overrides": c.sets[len(sets):], "weight": c.weight,
                       "realisations": c.realisations, "flow_case": str(c.flow_case),
                       "strike_probability": float(per.loc[per["case"] == c.name, "struck"].mean()),
                       "flow_phase_wall_s": round(c.flow_wall_s, 2)} for c in cases],
            "draws": {"mass_kg": list(spec.mass_kg) if spec.mass_kg else _masses_drawn(result.table),
                      "heading_deg": list(spec.heading_deg) if spec.heading_deg else "placement tolerance",
                      "start_x_m": list(spec.start_x_m) if spec.start_x_m else None,
                      "start_y_m": list(spec.start_y_m) if spec.start_y_m else None},
            "intervals": {"exceedance": "Clopper-Pearson (pointwise) on effective counts",
                          "curve": "DKW simultaneous band, half-width dkw_halfwidth",
                          "quantiles": "the pointwise band inverted; upper null: more realisations needed"},
            "demands": demands, "asce": asce, **wall}


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
        floor = max(float(curve["probability"].min()) / 3.0, 1e-5)
        for name, q in summary["demands"][key]["quantiles"].items():
            ax.plot([q["value"]], [1.0 - QUANTILES[name]], "k.", ms=5)
            if q["upper"] is not None:
                ax.plot([q["lower"], q["upper"]], [1.0 - QUANTILES[name]] * 2, "k-", lw=1)
        for k, style in (("k_s", "-"), ("k_d", "--")):
            if asce["values"] is None:
                continue
            value = asce["values"][k][key]
            p = summary["demands"][key]["asce"][k]
            governs = " (governs)" if asce["governing"] == k else ""
            ax.axvline(value, color="C3", ls=style, lw=1.2,
                       label=f"ASCE 7-22 with {k}{governs}: P(exceed) = {p['probability']:.3g} "
                             f"[{p['lower']:.2g}, {p['upper']:.2g}]")
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


def _masses_drawn(table) -> str:
    """The mass draw without `design.mass_kg`: a catalogued body's empty-to-loaded range, as drawn."""
    masses = table["mass_kg"].to_numpy(float)
    if not len(masses) or masses.min() == masses.max():
        return "each body's own"
    return f"each catalogued body's empty-to-loaded range (drawn {masses.min():,.0f} to {masses.max():,.0f} kg)"


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
             "of 0 and stays in every curve. Intervals: " + "; ".join(f"{k}: {v}" for k, v in
                                                                       summary["intervals"].items()) + ".", "",
             "## Inundation cases", "", "| case | overrides | weight | realisations | P(strike) | u_max (m/s) |",
             "|---|---|---|---|---|---|"]
    asce = summary["asce"]
    u = {c["case"]: c["u_max_m_s"] for c in asce["cases"]}
    for c in summary["cases"]:
        lines.append(f"| {c['name']} | {', '.join(c['overrides']) or 'the scene as it is'} | {c['weight']:.3g} | "
                     f"{c['realisations']} | {c['strike_probability']:.3g} | {_num(u.get(c['name']), 3)} |")
    draws = summary["draws"]
    lines += ["", f"Draws (uniform where a range is given): mass {_range(draws['mass_kg'], 'kg')}, heading "
                  f"{_range(draws['heading_deg'], 'deg')}, start x {_range(draws['start_x_m'], 'm')}, start y "
                  f"{_range(draws['start_y_m'], 'm')}.", "",
              "## Demands", "", f"Quantiles with their {conf} intervals ('-': more realisations needed).", "",
              "| demand | P50 | P90 | P99 | largest |", "|---|---|---|---|---|"]
    for d in summary["demands"].values():
        cells = [f"{_num(q['value'])} [{_num(q['lower'])}, {_num(q['upper'])}]" for q in d["quantiles"].values()]
        lines.append(f"| {d['label']} ({d['unit']}) | {' | '.join(cells)} | {_num(d['max'])} |")
    lines += ["", "## ASCE 7-22 Section 6.11 for the same inputs", ""]
    if asce["values"] is None:
        lines.append("No site speed and no strike: no ASCE value to set beside the curves.")
    else:
        lines += [f"F_i = I_tsu C_o u_max sqrt(k m_d) with u_max = {asce['u_max_m_s']:.3g} m/s ({asce['u_basis']}, "
                  f"case {asce['u_case']}), m_d = {asce['mass_kg']:.4g} kg (the heaviest drawn), I_tsu = "
                  f"{asce['importance_I_tsu']:g} (risk category {asce['risk_category']}), C_o = "
                  f"{asce['orientation_C_o']:g}, k_s = {asce['structure_stiffness_N_m']:.4g} N/m, k_d = "
                  f"{asce['debris_stiffness_N_m']:.4g} N/m; {asce['governing']} governs (the lesser); "
                  f"{asce['cap_note']}. Base shear, base moment and top displacement: the code's rectangular pulse "
                  f"on the same MDOF column at {asce['load_height_m']:.3g} m ({asce['height_basis']}).", "",
                  "Where each input comes from:", "",
                  f"- u_max: {asce['u_basis']} (two column widths upstream of the face, "
                  "orchestrator/results/asce_design.py), in the fastest case",
                  *[f"- {k}: {v}" for k, v in asce["sources"].items()], "",
                  "| demand | with k_s | P(exceed k_s value) | with k_d | P(exceed k_d value) |",
                  "|---|---|---|---|---|"]
        for key, d in summary["demands"].items():
            cells = []
            for k in ("k_s", "k_d"):
                e = d["asce"][k]
                cells += [_num(asce["values"][k][key]), f"{e['probability']:.3g} [{e['lower']:.3g}, {e['upper']:.3g}]"]
            lines.append(f"| {d['label']} ({d['unit']}) | {' | '.join(cells)} |")
    lines += ["", "![exceedance](exceedance.png)", "",
              "Files: design.csv (one row per realisation and body), design.json (these figures), exceedance.png.",
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
