"""What a designer signs off a design study: the demands given a strike, the fractile to design
to and why, the band the contact law's and the flow's uncertainty put about it, and the strikes
as they struck.

* **Given a strike** (:func:`given_strike`). The unconditional curves keep every realisation,
  a non-strike as a demand of 0, so their P50 and P90 mix the chance of a strike with its size.
  Given a strike, only the realisations that struck count, each case weighted by its weight
  times its share of strikes (the mixture's law given a strike).
* **The fractile** (:data:`RECOMMENDED`). The tool's convention, not a code's: design to P90
  given a strike, times the risk category's I_tsu. Why: ASCE 7-22 6.11 assumes the debris
  strikes, so the load it sets beside its own F_i is the one given a strike; a characteristic
  load is an upper fractile of its distribution, not its median; P90's interval is narrow with
  a few hundred strikes where P99's needs thousands; and the code raises its own F_i by I_tsu
  for risk categories III and IV (Table 6.8-1), which the curves, physics without a factor,
  do not carry.
* **The band** (:func:`band`). Three parts, each stated: the quantile's own interval (the
  realisations' sampling); the contact law's calibration, the standard error of the mean peak
  force it was fitted to (the study's Table 2: 62.91 N over 22 impacts about 171.07 N, 7.8 %),
  at the page's confidence (a peak force is linear in that mean); and the flow's, the ratio of
  each case's stated speed at the column to the speed its simulated flow gives there (a peak
  force is linear in the strike's speed). The band is the quantile's interval scaled by both.
  It does not hold what no figure here measures: a full-scale law's difference from the
  Froude-scaled laboratory one, or the flow model's error beyond its speed at the site.
* **The strikes** (:func:`strike_summary`): bodies carried and grounded, strikes per striking
  realisation, faces, obliquity, eccentricity and torsion, and the strike speeds beside the
  site's u_max and the water each body came in with.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pandas as pd
from scipy.stats import norm

from analytical.contact_law import STUDY_TABLE2_MDOF
from analytical.exceedance import exceedance
from analytical.study_comparison import STUDY_IMPACT_COUNT
from orchestrator.studies.design_strikes import FACES
from orchestrator.studies.design_table import DEMANDS

__all__ = ["FASTER_THAN_WATER", "LAW_FORCE_SE", "OBLIQUE_DEG", "RECOMMENDED", "STATED_LAW_UNKNOWN", "advice", "advice_lines", "band", "conditional_exceedance",
           "demand_lines", "fmt_demand", "given_strike", "recommendation", "strike_summary"]

#: The fractile the page recommends, given a strike (module notes: the tool's convention).
RECOMMENDED = ("P90", 0.90)

#: The contact law's calibration: the relative standard error of the mean peak force it was
#: fitted to (the study's Table 2 MDOF row over its 22 impacts).
LAW_FORCE_SE = STUDY_TABLE2_MDOF["peak_force_N"][1] / math.sqrt(STUDY_IMPACT_COUNT) / STUDY_TABLE2_MDOF["peak_force_N"][0]

#: A strike faster than this times the fastest water its body came in with is one the water does
#: not explain (counted on the page).
FASTER_THAN_WATER = 1.05

#: A strike this far off the face's normal (deg) is counted as oblique on the page.
OBLIQUE_DEG = 30.0


def conditional_exceedance(per: pd.DataFrame, cases, key: str, confidence: float):
    """``key``'s exceedance given a strike (module notes), or None when nothing struck."""
    groups, weights = [], []
    for c in cases:
        mine = per[(per["case"] == c.name) & per["struck"].astype(bool)]
        n = int((per["case"] == c.name).sum())
        if len(mine) and n:
            weights.append(c.weight * len(mine) / n)
            groups.append(mine[key].to_numpy(float))
    return exceedance(groups, weights, confidence) if weights else None


def given_strike(per: pd.DataFrame, cases, confidence: float, quantiles: dict[str, float]) -> dict[str, Any]:
    """Each demand's quantiles given a strike (module notes): ``per`` is one row per realisation
    (:func:`~orchestrator.studies.design_table.realisation_demands`); None where nothing struck."""
    out: dict[str, Any] = {"strikes": int(per["struck"].astype(bool).sum())}
    for k in DEMANDS:
        exc = conditional_exceedance(per, cases, k, confidence)
        out[k] = None if exc is None else {name: exc.quantile(p).to_dict() for name, p in quantiles.items()}
    return out


def band(quantile: dict[str, Any], stated_over_site: list[float], confidence: float) -> dict[str, Any]:
    """The band about a quantile given a strike (module notes): its interval, scaled by the
    law's calibration (± z x :data:`LAW_FORCE_SE`) and by the flow's speed (the cases' stated
    over simulated speeds, when they state one)."""
    z = float(norm.ppf(0.5 + confidence / 2.0))
    law = z * LAW_FORCE_SE
    ratios = [r for r in stated_over_site if r is not None and math.isfinite(r) and r > 0]
    low_flow, high_flow = (min(min(ratios), 1.0), max(max(ratios), 1.0)) if ratios else (1.0, 1.0)
    upper = quantile["upper"]
    return {"law_relative": law, "flow_low": low_flow, "flow_high": high_flow, "flow_stated": bool(ratios),
            "lower": quantile["lower"] * (1.0 - law) * low_flow,
            "upper": upper * (1.0 + law) * high_flow if upper is not None else None}


def recommendation(conditional: dict[str, Any], importance: float, stated_over_site: list[float],
                   confidence: float) -> dict[str, Any] | None:
    """The recommended design value of each demand: :data:`RECOMMENDED` given a strike times
    I_tsu, with its band (None: nothing struck)."""
    name, p = RECOMMENDED
    out = {"fractile": name, "p": p, "given": "a strike", "importance_I_tsu": importance,
           "convention": "the tool's convention (not a code's): design to P90 given a strike, times I_tsu",
           "demands": {}}
    if conditional.get("peak_force_N") is None:
        return None
    for key in DEMANDS:
        q = conditional[key][name]
        b = band(q, stated_over_site, confidence)
        out["demands"][key] = {"unit": DEMANDS[key][1], "quantile": q["value"], "value": q["value"] * importance,
                               "lower": b["lower"] * importance,
                               "upper": b["upper"] * importance if b["upper"] is not None else None,
                               "band": b}
    return out


def _stats(values) -> dict[str, float | None]:
    v = pd.to_numeric(pd.Series(values), errors="coerce").dropna().to_numpy(float)
    if not v.size:
        return {"median": None, "max": None, "count": 0}
    return {"median": float(np.median(v)), "max": float(v.max()), "count": int(v.size)}


def strike_summary(table: pd.DataFrame, per: pd.DataFrame, u_max: dict[str, float | None]) -> dict[str, Any]:
    """The strikes as they struck (module notes): ``table`` is design.csv's, ``per`` one row per
    realisation, ``u_max`` each case's site speed."""
    bodies = table.drop_duplicates(["case", "realisation", "body"])
    grounded = bodies[~bodies["carried"].astype(bool)]
    strikes = table[pd.to_numeric(table["strike"], errors="coerce").fillna(0) > 0]
    striking = per[per["struck"].astype(bool)]
    out: dict[str, Any] = {
        "bodies": int(len(bodies)), "grounded": int(len(grounded)),
        "grounded_realisations": int(grounded[["case", "realisation"]].drop_duplicates().shape[0]),
        "grounded_largest_draft_m": float(grounded["draft_m"].max()) if len(grounded) else None,
        "strikes": int(len(strikes)), "striking_realisations": int(len(striking)),
        "strikes_per_striking_realisation": {**_stats(striking["strikes"]),
                                             "mean": float(striking["strikes"].mean()) if len(striking) else None},
        "more_than_one": float((striking["strikes"] > 1).mean()) if len(striking) else None,
        "faces": {f: int((strikes["face"] == f).sum()) for f in FACES},
        "obliquity_deg": _stats(strikes["obliquity_deg"]),
        "oblique_share": float((strikes["obliquity_deg"] > OBLIQUE_DEG).mean()) if len(strikes) else None,
        "eccentricity_m": _stats(strikes["eccentricity_m"].abs()),
        "torsion_Nm": _stats(strikes["torsion_Nm"].abs()),
    }
    largest = strikes.sort_values("peak_force_N", ascending=False, kind="stable").drop_duplicates(
        ["case", "realisation"])
    out["largest_not_first"] = float((largest["strike"] > 1).mean()) if len(largest) else None
    site = strikes["case"].map(u_max).astype(float)
    speed = strikes["impact_speed_m_s"].astype(float)
    mean, fastest = strikes["flow_speed_m_s"].astype(float), strikes["flow_speed_max_m_s"].astype(float)
    out["speed_over_u_max"] = _stats(speed / site)
    out["speed_over_flow"] = _stats((speed / mean).replace(np.inf, np.nan))
    out["speed_over_fastest_water"] = _stats((speed / fastest).replace(np.inf, np.nan))
    out["fastest_water_over_u_max"] = _stats(fastest / site)
    # faster than any water the body came in with (0: it ran ahead of the front into still water)
    faster = speed > FASTER_THAN_WATER * fastest
    out["faster_than_the_water"] = int(faster.sum())
    out["faster_mass_kg"] = _stats(strikes.loc[faster, "mass_kg"])["median"]
    out["other_mass_kg"] = _stats(strikes.loc[~faster, "mass_kg"])["median"]
    out["largest_faster_than_the_water"] = (float(largest.index.isin(strikes.index[faster]).mean())
                                            if len(largest) else None)
    return out


def fmt_demand(value: float | None, unit: str) -> str:
    """A demand in kN or MN (N), kN m or MN m (N m), mm (m)."""
    if value is None or not math.isfinite(value):
        return "-"
    if unit == "m":
        return f"{value * 1e3:.3g} mm"
    suffix = " m" if unit == "N m" else ""
    if abs(value) >= 1e6:
        return f"{value / 1e6:.3g} MN{suffix}"
    if abs(value) >= 1e3:
        return f"{value / 1e3:.3g} kN{suffix}"
    return f"{value:.3g} N{suffix}"


# --------------------------------------------------------------------------- design.json and the page
def advice(result, per: pd.DataFrame, confidence: float, quantiles: dict[str, float], asce: dict[str, Any]) -> dict:
    """design.json's ``given_strike``, ``recommended``, ``flow_speeds`` and ``strikes``."""
    conditional = given_strike(per, result.cases, confidence, quantiles)
    speeds = []
    for c in result.cases:
        inundation = getattr(c.scene, "inundation", None) if c.scene is not None else None
        stated = getattr(inundation, "speed_m_s", None)
        site = c.site.u_max_m_s if c.site is not None else None
        front = getattr(c, "front_celerity_m_s", None)
        speeds.append({"case": c.name, "stated_m_s": stated, "simulated_m_s": site,
                       "stated_over_simulated": stated / site if stated and site else None,
                       "front_m_s": front, "front_over_simulated": front / site if front and site else None})
    importance = float(asce.get("importance_I_tsu") or 1.0)
    u_max = {c["case"]: c["u_max_m_s"] for c in asce["cases"]}
    strikes = strike_summary(result.table, per, u_max)
    rec = recommendation(conditional, importance, [s["stated_over_simulated"] for s in speeds], confidence)
    if rec is not None:  # what a designer copies, whole: the counts behind it and what binds the code's F_i
        rec.update(strikes=strikes["strikes"], striking_realisations=strikes["striking_realisations"],
                   realisations=int(len(per)), confidence=confidence,
                   asce_binds=asce.get("binding"), asce_force_N=asce.get("force_N"))
    return {"given_strike": conditional, "flow_speeds": speeds, "recommended": rec, "strikes": strikes}


def _cell(q: dict[str, Any] | None, unit: str) -> str:
    if q is None:
        return "-"
    return f"{fmt_demand(q['value'], unit)} [{fmt_demand(q['lower'], unit)}, {fmt_demand(q['upper'], unit)}]"


def _ratio(stats: dict[str, Any]) -> str:
    if stats["median"] is None:
        return "-"
    return f"median {stats['median']:.2f}, largest {stats['max']:.2f}"


def demand_lines(summary: dict[str, Any]) -> list[str]:
    """The page's demands: unconditional and given a strike, in kN, MN, kN m, MN m, mm."""
    conf = f"{summary['confidence'] * 100:.0f} %"
    given = summary["given_strike"]
    lines = ["## Demands", "", f"Quantiles with their {conf} intervals ('-': more realisations needed). "
             "Unconditional: every realisation, a non-strike a demand of 0. Given a strike: only the "
             f"{given['strikes']} realisations that struck, each case weighted by its weight times its share of strikes.",
             "", "| demand | | P50 | P90 | P99 | largest |", "|---|---|---|---|---|---|"]
    for key, d in summary["demands"].items():
        unit = d["unit"]
        lines.append(f"| {d['label']} | unconditional | "
                     + " | ".join(_cell(q, unit) for q in d["quantiles"].values()) + f" | {fmt_demand(d['max'], unit)} |")
        cells = [_cell(given[key][name] if given.get(key) else None, unit) for name in d["quantiles"]]
        lines.append(f"| | given a strike | {' | '.join(cells)} | |")
    return lines


#: What the band leaves out at full scale: the scene states its law, and no published full-scale test
#: gives that law's uncertainty (docs/fullscale-sources.md), so the laboratory calibration's part is
#: a lower bound on it.
STATED_LAW_UNKNOWN = ("the uncertainty of the full-scale law the scene states (no published full-scale test gives "
                      "it: the laboratory calibration's part above is a lower bound on it)")


def advice_lines(summary: dict[str, Any]) -> list[str]:
    """The page's design value, its reasoning and band, and the strikes as they struck."""
    conf = f"{summary['confidence'] * 100:.0f} %"
    rec, s = summary["recommended"], summary["strikes"]
    lines = ["## Design value", ""]
    if rec is None:
        lines += ["No realisation struck the column: no design value from the curves.", ""]
    else:
        law = next(iter(rec["demands"].values()))["band"]
        flow = (f" and times {law['flow_low']:.3g} to {law['flow_high']:.3g}, each case's stated speed at the column "
                "over its simulated flow's there (a peak force is linear in the strike's speed)" if law["flow_stated"]
                else "; the flow's part is not known: no case states its speed at the column (inundation.speed_m_s)")
        if law["flow_stated"] and law["flow_low"] == law["flow_high"] == 1.0:
            flow = "; each case's simulated speed at the column is its stated one or faster (no flow part)"
        lines += [f"**Recommended: {rec['fractile']} given a strike x I_tsu ({rec['importance_I_tsu']:g}).** "
                  "The tool's convention, not a code's: ASCE 7-22 6.11 assumes the debris strikes, so the value "
                  "set beside its F_i is the one given a strike; a characteristic load is an upper fractile of its "
                  "distribution, not its median; P90's interval is narrow with a few hundred strikes where P99's "
                  "needs thousands; and the code raises its own F_i by I_tsu (Table 6.8-1), which the curves "
                  "(physics, no factor) do not carry.", "",
                  f"| demand | {rec['fractile']} given a strike | design value (x I_tsu) | band |", "|---|---|---|---|"]
        for key, d in rec["demands"].items():
            unit = summary["demands"][key]["unit"]
            lines.append(f"| {summary['demands'][key]['label']} | {fmt_demand(d['quantile'], unit)} | "
                         f"**{fmt_demand(d['value'], unit)}** | {fmt_demand(d['lower'], unit)} to "
                         f"{fmt_demand(d['upper'], unit) if d['upper'] is not None else '(more realisations needed)'} |")
        lines += ["", f"The band: the quantile's {conf} interval (the realisations' sampling), times 1 ± "
                      f"{law['law_relative'] * 100:.1f} % (the contact law's calibration: the standard error of the "
                      f"mean peak force it was fitted to, {LAW_FORCE_SE * 100:.1f} %, at {conf}){flow}. Not in it: "
                      + (STATED_LAW_UNKNOWN if summary.get("asce", {}).get("prototype") else
                         "a full-scale law's difference from the laboratory one")
                      + " and the flow model's error beyond its speed at the site.", ""]
    per = s["strikes_per_striking_realisation"]
    faces = ", ".join(f"{k} {v}" for k, v in s["faces"].items())
    grounded = (f"{s['grounded']} of {s['bodies']} bodies (in {s['grounded_realisations']} realisations, drafts up "
                f"to {s['grounded_largest_draft_m']:.3g} m) could not float in the deepest water at their start: "
                "not carried, demand 0" if s["grounded"] else
                f"all {s['bodies']} bodies float in the deepest water at their start (draft m / (rho_w L W))")
    lines += ["## Strikes", "", f"- Carried: {grounded}.",
              f"- {s['strikes']} column strikes in {s['striking_realisations']} striking realisations; every strike "
              "counts, a realisation's demand is its largest."
              + (f" Strikes per striking realisation: median {per['median']:g}, mean {per['mean']:.3g}, largest "
                 f"{per['max']:g}; {_pct(s['more_than_one'])} strike more than once, and in "
                 f"{_pct(s['largest_not_first'])} the largest strike is not the first." if per["count"] else ""),
              f"- Faces struck: {faces}.",
              f"- Obliquity (plan, the centre velocity to the face's normal): median "
              f"{_num1(s['obliquity_deg']['median'])} deg; {_pct(s['oblique_share'])} of strikes more than "
              f"{OBLIQUE_DEG:g} deg off.",
              f"- Eccentricity (the contact point's offset from the face's centre): median "
              f"{fmt_demand(s['eccentricity_m']['median'], 'm')}, largest {fmt_demand(s['eccentricity_m']['max'], 'm')};"
              f" the torsion it gives the member (peak force x eccentricity): median "
              f"{fmt_demand(s['torsion_Nm']['median'], 'N m')}, largest {fmt_demand(s['torsion_Nm']['max'], 'N m')}.",
              f"- Strike speed over its case's simulated u_max: {_ratio(s['speed_over_u_max'])}; over the "
              f"depth-averaged water the body came in with (its last length of travel): "
              f"{_ratio(s['speed_over_flow'])}; over the fastest water over that depth: "
              f"{_ratio(s['speed_over_fastest_water'])} (that water over u_max: {_ratio(s['fastest_water_over_u_max'])}); "
              "the front's speed over u_max: " + (", ".join(f"{f['case']} {f['front_over_simulated']:.2f}" for f in
                                                         summary["flow_speeds"] if f["front_over_simulated"])
                                                  or "not measured") + ".",
              "", "Why a strike can outrun u_max: u_max is a depth average two column widths upstream of the face "
              "(ASCE 7-22's flow velocity); a floating body is carried by the water at its draft, near the surface, "
              "which in a bore runs faster than the depth average, and a body the front picks up can ride it at the "
              "front's own speed (the cases' table: front, 3 to 8 column widths upstream of the face). A strike at "
              "most as fast as the fastest water it came in with is carried by that water. One faster than that is "
              "not: the bore's front throws a light container (while the rising water covers it beyond its draft, "
              "buoyancy and the water's acceleration act on a displaced mass several times its own), and riding high "
              "with little wetted area it slows only over seconds. That is the one-way forcing at a steep front, not "
              "a measured behaviour: "
              + (f"{s['faster_than_the_water']} strike(s) ran more than {(FASTER_THAN_WATER - 1) * 100:.0f} % faster "
                 f"than any water their body came in with (median mass {_kg(s['faster_mass_kg'])}, the others' "
                 f"{_kg(s['other_mass_kg'])}), and the largest strike of {_pct(s['largest_faster_than_the_water'])} "
                 "of the striking realisations is one of them (design.csv: impact_speed_m_s beside "
                 "flow_speed_max_m_s)." if s["faster_than_the_water"]
                 else f"no strike ran more than {(FASTER_THAN_WATER - 1) * 100:.0f} % faster than that water."), ""]
    return lines


def _kg(value) -> str:
    return "-" if value is None else f"{value:,.0f} kg"


def _num1(value) -> str:
    return "-" if value is None else f"{value:.3g}"


def _pct(value) -> str:
    return "-" if value is None else f"{value * 100:.0f} %"
