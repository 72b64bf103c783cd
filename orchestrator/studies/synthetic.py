"""`debrisfoam analytical study`: the study's section 3.3 on synthetic records, to files.

Writes into the output folder:
  records.csv      one row per record and method: pulse, peak response, ratio
  table2.csv/.md   the study's Table 2 regenerated, beside the study's figures
  figure7.png      peak modelled vs peak measured base shear, 1:1 line
  figure4.png      one record with its SDOF and MDOF fits and every method's pulse
  summary.json     headline numbers, the agreement with the study, timings
  study.md         the same in words (generated, never hand-edited)
"""

from __future__ import annotations

import os
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import replace
from pathlib import Path

import numpy as np

from analytical.column import Column
from analytical.column_fem import column_model
from analytical.mdof import mdof_response
from analytical.synthetic import (
    METHODS,
    STUDY_EQUIVALENT,
    RecordAnalysis,
    analyse_record,
    make_records,
    pulse_statistics,
    ratio_statistics,
    sdof_start_rules,
    table1_sdof_check,
)
from analytical.study import STUDY_FIG7_RATIOS, STUDY_TABLE1, STUDY_TABLE2
from orchestrator.core.files import write_json_atomic

LABELS = {
    "asce_kd": "ASCE 7-22, k_d",
    "asce_ks": "ASCE 7-22, k_s",
    "sdof": "SDOF fit",
    "sdof_column_mass": "SDOF fit, m_s = column mass",
    "mdof": "MDOF fit",
    "true": "true pulse",
}
#: The three column set-ups the study compares: (records made with, fits use).
VARIANTS = {
    "rigid": ("rigid", "rigid"),  # the study's model throughout
    "calibrated": ("calibrated", "calibrated"),  # base spring: f1 = 70 Hz as measured
    "calibrated-fit-rigid": ("calibrated", "rigid"),  # a 70 Hz column analysed with the study's 88 Hz model
}


def _analyse(args) -> RecordAnalysis:
    record, column, fit_column = args
    return analyse_record(record, column=column, fit_column=fit_column)


def variant_columns(variant: str) -> tuple[Column, Column]:
    """(column that makes the records, column the fits use) for a variant.

    Both carry as `natural_frequency_Hz` the first frequency of the record-making
    column: what an experimenter would have measured, and the centre of the SDOF
    fit's frequency bounds.
    """
    make_base, fit_base = VARIANTS[variant]
    column = replace(Column(), base=make_base)
    measured_f1 = float(column_model(column).frequencies_Hz[0])
    column = replace(column, natural_frequency_Hz=measured_f1)
    return column, replace(column, base=fit_base)


def run_variant(variant: str, n_records: int = 22, seed: int = 2019, workers: int | None = None):
    """Make and analyse the records of one variant; returns (analyses, seconds)."""
    column, fit_column = variant_columns(variant)
    t0 = time.perf_counter()
    records = make_records(n_records, seed=seed, column=column)
    workers = workers or min(2, os.cpu_count() or 1)
    jobs = [(r, column, fit_column) for r in records]
    if workers > 1:
        with ProcessPoolExecutor(workers) as pool:
            analyses = list(pool.map(_analyse, jobs))
    else:
        analyses = [_analyse(j) for j in jobs]
    return analyses, time.perf_counter() - t0


def _agreement(ratios: dict) -> dict[str, str]:
    """Plain statements comparing our ratio ranges with the study's Fig. 7 ranges."""
    out = {}
    for method in METHODS:
        lo, hi, mean = ratios[method]
        s_lo, s_hi, s_mean = STUDY_FIG7_RATIOS[STUDY_EQUIVALENT.get(method, method)]
        overlap = min(hi, s_hi) - max(lo, s_lo)
        if lo >= s_lo - 0.05 and hi <= s_hi + 0.05:
            verdict = "agrees (inside the study's range)"
        elif overlap > 0:
            verdict = "partly agrees (ranges overlap)"
        else:
            verdict = "disagrees (ranges do not overlap)"
        study_mean = f", mean {s_mean}" if s_mean is not None else ""
        out[method] = (f"{LABELS[method]}: ratio {lo:.2f}-{hi:.2f} (mean {mean:.2f}); the study {s_lo}-{s_hi}"
                       f"{study_mean}: {verdict}")
    return out


def write_records_csv(analyses: list[RecordAnalysis], path: Path) -> None:
    import pandas as pd

    rows = []
    for a in analyses:
        for method in METHODS + ("true",):
            p = a.pulses[method]
            rows.append({
                "record": a.index,
                "method": method,
                "height_m": a.height_m,
                "velocity_m_s": a.velocity_m_s,
                "magnitude_N": p.peak_N,
                "duration_s": p.duration_s,
                "impulse_Ns": p.impulse_Ns,
                "peak_measured_N": a.peak_measured_N,
                "peak_model_N": a.peak_model_N[method],
                "ratio": a.ratio(method),
                "fit_rmse_N": a.fits[method].rmse_N if method in a.fits else np.nan,
            })
    pd.DataFrame(rows).to_csv(path, index=False)


def table2_markdown(stats: dict) -> str:
    lines = [
        "| method | magnitude mean (N) | std | duration mean (ms) | std | impulse mean (N s) | std | study magnitude | study duration (ms) | study impulse |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for method in METHODS + ("true",):
        s = stats[method]
        study = STUDY_TABLE2.get(STUDY_EQUIVALENT.get(method, method))
        study_cols = (
            f"{study['magnitude_N'][0]:.1f} +- {study['magnitude_N'][1]:.1f} | "
            f"{1e3 * study['duration_s'][0]:.1f} +- {1e3 * study['duration_s'][1]:.1f} | "
            f"{study['impulse_Ns'][0]:.2f} +- {study['impulse_Ns'][1]:.2f}"
            if study else "- | - | -"
        )
        lines.append(
            f"| {LABELS[method]} | {s['magnitude_N'][0]:.1f} | {s['magnitude_N'][1]:.1f} | "
            f"{1e3 * s['duration_s'][0]:.2f} | {1e3 * s['duration_s'][1]:.2f} | "
            f"{s['impulse_Ns'][0]:.3f} | {s['impulse_Ns'][1]:.3f} | {study_cols} |"
        )
    return "\n".join(lines) + "\n"


#: The study's figures at _DPI from figures _WIDTH_IN wide: 1,575 px, a report page at 100 %,
#: no text under 9 pt (legends and ticks included).
_DPI = 150
_WIDTH_IN = 10.5
_SMALL = 9
#: One colour per method in every panel and figure (as in orchestrator.report.plots).
_COLOURS = {"asce_kd": "#2c7bb6", "asce_ks": "#74add1", "sdof": "#e66101", "sdof_column_mass": "#7b3294",
            "mdof": "#1a9641", "true": "0.55"}


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _save(fig, path: Path) -> None:
    fig.savefig(path, dpi=_DPI)
    _pyplot().close(fig)


def figure7(results: dict[str, list[RecordAnalysis]]):
    """Peak modelled vs peak synthetic-record base shear (the records stand in for the measured ones), a
    panel per variant on shared scales, one legend."""
    plt = _pyplot()
    markers = {"asce_kd": "s", "asce_ks": "D", "sdof": "^", "sdof_column_mass": "v", "mdof": "o"}
    fig, axes = plt.subplots(1, len(results), figsize=(_WIDTH_IN, 4.9), squeeze=False, sharex=True, sharey=True,
                             layout="constrained")
    top = max(max(a.peak_measured_N, *a.peak_model_N.values()) for analyses in results.values() for a in analyses)
    for ax, (variant, analyses) in zip(axes[0], results.items()):
        measured = np.array([a.peak_measured_N for a in analyses])
        for method in METHODS:
            model = np.array([a.peak_model_N[method] for a in analyses])
            ax.scatter(measured, model, marker=markers[method], s=22, color=_COLOURS[method], label=LABELS[method],
                       alpha=0.8)
        ax.plot([0, 1.05 * top], [0, 1.05 * top], "k--", lw=1, label="1:1")
        ax.set_xlim(0, 1.05 * top)
        ax.set_ylim(0, 1.05 * top)
        ax.set_xlabel("max base shear of the synthetic record (N)")
        make_base, fit_base = VARIANTS[variant]
        ax.set_title(f"records: {make_base} base\nfits: {fit_base} base", fontsize=10)
        ax.grid(alpha=0.3)
    axes[0, 0].set_ylabel("max modelled base shear, MDOF column (N)")
    handles, labels = axes[0, 0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="outside lower center", ncol=len(labels), fontsize=_SMALL)
    n = len(next(iter(results.values())))
    fig.suptitle(f"Synthetic Fig. 7: peak modelled vs peak synthetic-record response ({n} synthetic records)",
                 fontsize=11)
    return fig


def plot_figure7(results: dict[str, list[RecordAnalysis]], path: Path) -> None:
    _save(figure7(results), path)


def figure4(analysis: RecordAnalysis, record_t: np.ndarray, column: Column):
    """One record with its fits (left) and every method's pulse against the true one (right).

    The right panel spans every pulse whole: a fitted SDOF pulse starts where the record
    leaves its baseline, after the true impact, and is shorter than the true pulse. The fits are dashed over the true pulse (solid,
    grey): on a synthetic record the truth is known, so a fit on it is a check of the fit.
    """
    plt = _pyplot()
    fig = plt.figure(figsize=(_WIDTH_IN, 5.2), layout="constrained")
    grid = fig.add_gridspec(2, 2, height_ratios=[3.8, 1.0])
    ax1, ax2 = fig.add_subplot(grid[0, 0]), fig.add_subplot(grid[0, 1])
    mdof_fit, sdof_fit = analysis.fits["mdof"], analysis.fits["sdof"]
    ax1.plot(mdof_fit.time_s * 1e3, mdof_fit.measured_N, color="0.6", lw=1, label="synthetic record (offset removed)")
    ax1.plot(sdof_fit.time_s * 1e3, sdof_fit.model_N, ls="--", color=_COLOURS["sdof"],
             label=f"SDOF fit (rmse {sdof_fit.rmse_N:.1f} N)")
    ax1.plot(mdof_fit.time_s * 1e3, mdof_fit.model_N, ls="--", color=_COLOURS["mdof"],
             label=f"MDOF fit (rmse {mdof_fit.rmse_N:.1f} N)")
    t = np.arange(record_t[0], record_t[-1], 2e-5)
    for method in ("asce_ks",):
        r = mdof_response(analysis.pulses[method], column, analysis.height_m, t)
        ax1.plot(t * 1e3, r.response_N, lw=0.9, ls=":", color=_COLOURS[method], label=f"{LABELS[method]} pulse on the MDOF column")
    ax1.set_xlabel("time (ms)")
    ax1.set_ylabel("base shear (N)")
    ax1.set_title(f"synthetic record {analysis.index}: fits (cf. the study's Fig. 4a / 5)", fontsize=10)
    ax1.grid(alpha=0.3)
    t0 = analysis.true_pulse.start_s
    pulses = {method: analysis.pulses[method] for method in METHODS + ("true",)}
    lo = min([t0] + [p.start_s for p in pulses.values() if np.isfinite(p.start_s)])
    hi = max([t0] + [p.end_s for p in pulses.values() if np.isfinite(p.end_s)])
    pad = 0.05 * (hi - lo)
    tt = np.linspace(lo - pad, hi + pad, 3000)
    for method, p in pulses.items():
        true = method == "true"
        fitted = method in ("sdof", "sdof_column_mass", "mdof")
        ax2.plot((tt - t0) * 1e3, p.force(tt), label=LABELS[method], lw=3.0 if true else 1.4, color=_COLOURS[method], ls="--" if fitted else "-",
                 zorder=1 if true else 2)
    ax2.set_xlim((lo - pad - t0) * 1e3, (hi + pad - t0) * 1e3)
    ax2.set_xlabel("time from impact (ms)")
    ax2.set_ylabel("impact force (N)")
    ax2.set_title("impact forces (cf. the study's Fig. 4b); dashed: fitted to the record", fontsize=10)
    ax2.grid(alpha=0.3)
    for j, (ax, ncol) in enumerate(((ax1, 1), (ax2, 2))):  # each legend under its panel
        below = fig.add_subplot(grid[1, j])
        below.axis("off")
        below.legend(*ax.get_legend_handles_labels(), loc="upper center", ncol=ncol, fontsize=_SMALL,
                     frameon=False)
    return fig


def plot_figure4(analysis: RecordAnalysis, record_t: np.ndarray, column: Column, path: Path) -> None:
    _save(figure4(analysis, record_t, column), path)


def run_synthetic_study(out_dir: Path, seed: int = 2019, n_records: int = 22, column_base: str = "rigid",
                        compare: bool = True) -> dict:
    """Run the study (the `column_base` variant, plus the others when `compare`) and write its files."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    variants = list(VARIANTS) if compare else [column_base]
    if column_base in variants:
        variants.remove(column_base)
    variants.insert(0, column_base)
    results, timings = {}, {}
    for variant in variants:
        results[variant], timings[variant] = run_variant(variant, n_records=n_records, seed=seed)
    primary = results[column_base]
    stats = pulse_statistics(primary)
    ratios = {v: ratio_statistics(a) for v, a in results.items()}
    write_records_csv(primary, out_dir / "records.csv")
    import pandas as pd

    pd.DataFrame([
        {"method": m, **{f"{k}_mean": v[0] for k, v in stats[m].items()},
         **{f"{k}_std": v[1] for k, v in stats[m].items()}}
        for m in stats
    ]).to_csv(out_dir / "table2.csv", index=False)
    (out_dir / "table2.md").write_text(table2_markdown(stats))
    plot_figure7(results, out_dir / "figure7.png")
    plot_figure4(primary[0], primary[0].fits["mdof"].time_s, variant_columns(column_base)[0],
                 out_dir / "figure4.png")
    agreement = {v: _agreement(r) for v, r in ratios.items()}
    explained = [v for v in (column_base, "calibrated") if v in results]
    explained = list(dict.fromkeys(explained))
    rules, table1 = {}, {}
    for v in explained:
        column, fit_column = variant_columns(v)
        rules[v] = sdof_start_rules(make_records(n_records, seed=seed, column=column), column, fit_column)
        table1[v] = table1_sdof_check(column, fit_column)
    idents = [a.fits["sdof"].duration_identifiability for a in primary]
    ident_summary = {
        "identifiable": sum(i.identifiable for i in idents),
        "records": len(idents),
        "median_interval_width_ms": float(np.median([1e3 * (i.interval_s[1] - i.interval_s[0]) for i in idents])),
        "median_condition_number": float(np.median([i.condition_number for i in idents])),
        "median_magnitude_duration_correlation": float(np.median([i.magnitude_duration_correlation for i in idents])),
    }
    summary = {
        "records": n_records,
        "seed": seed,
        "primary_variant": column_base,
        "ratios_min_max_mean": {v: {m: list(r[m]) for m in r} for v, r in ratios.items()},
        "agreement": agreement,
        "wall_time_s": {v: round(t, 2) for v, t in timings.items()},
        "sdof_start_rules": {v: [r.__dict__ for r in rows] for v, rows in rules.items()},
        "table1_sdof_fit": table1,
        "sdof_duration_identifiability": ident_summary,
    }
    write_json_atomic(out_dir / "summary.json", summary)
    lines = ["# Synthetic reproduction of the study's section 3.3", "",
             f"{n_records} records, random seed {seed}. Generated by `debrisfoam analytical study`.", "",
             f"## Table 2 ({column_base} base)", "", table2_markdown(stats), "## Fig. 7 ratios", ""]
    for v in results:
        lines.append(f"### records: {VARIANTS[v][0]} base, fits: {VARIANTS[v][1]} base "
                     f"({timings[v]:.1f} s)")
        lines.append("")
        lines.extend(f"- {s}" for s in agreement[v].values())
        lo, hi, mean = ratios[v]["true"]
        lines.append(f"- true pulse on the same column: ratio {lo:.2f}-{hi:.2f} (mean {mean:.2f}; 1 up to noise)")
        lines.append("")
    lines += sdof_explanation(rules, table1, ident_summary, column_base)
    (out_dir / "study.md").write_text("\n".join(lines))
    return {"out_dir": str(out_dir), "wall_time_s": summary["wall_time_s"], "agreement": agreement[column_base]}


def sdof_explanation(rules: dict, table1: dict, ident: dict, primary: str) -> list[str]:
    """The page's section on why the SDOF row differs from the study's, in numbers."""
    study_mag, study_dur, study_imp = (STUDY_TABLE2["sdof"][k] for k in ("magnitude_N", "duration_s", "impulse_Ns"))
    lines = ["## Why the SDOF row differs from the study's", "",
             "The records here are synthetic: the MDOF column's base shear (all its modes, sampled at 10 kHz) to a "
             "known half-sine, with 2.5 % white noise and an offset; the study's were measured. An SDOF has no "
             "higher modes and no shear-wave transit from the load point to the base, so what it fits is the "
             "first mode's ringing: that fixes the pulse's Fourier amplitude at the natural frequency (about its "
             "impulse) and its phase (about start + duration / 2), not the split into magnitude and duration. "
             "The split then follows from where the pulse may start (docs/fitting.md):", "",
             "| column (records and fits) | SDOF start rule, gain | magnitude (N) | duration (ms) | impulse (N s) "
             "| Fig. 7 ratio min-max (mean) | start - true start, mean (min) (ms) | rmse (N) |",
             "|---|---|---|---|---|---|---|---|"]
    for v, rows in rules.items():
        for r in rows:
            lines.append(f"| {VARIANTS[v][0]} | {r.rule} | {r.magnitude_N[0]:.0f} +- {r.magnitude_N[1]:.0f} | "
                         f"{1e3 * r.duration_s[0]:.2f} +- {1e3 * r.duration_s[1]:.2f} | "
                         f"{r.impulse_Ns[0]:.3f} +- {r.impulse_Ns[1]:.3f} | {r.ratio[0]:.2f}-{r.ratio[1]:.2f} "
                         f"({r.ratio[2]:.2f}) | {1e3 * r.start_minus_true_s[0]:+.2f} ({1e3 * r.start_minus_true_s[1]:+.2f}) | "
                         f"{r.rmse_N:.1f} |")
    lines.append(f"| the study (measured) | - | {study_mag[0]:.0f} +- {study_mag[1]:.0f} | {1e3 * study_dur[0]:.1f} +- "
                 f"{1e3 * study_dur[1]:.1f} | {study_imp[0]:.2f} +- {study_imp[1]:.2f} | "
                 f"{STUDY_FIG7_RATIOS['sdof'][0]}-{STUDY_FIG7_RATIOS['sdof'][1]} ({STUDY_FIG7_RATIOS['sdof'][2]}) | - | - |")
    lines += ["", "- Free to start up to 10 ms before the onset, the SDOF puts a long, weak pulse milliseconds before "
              "the impact (its slow rise hides in the quiet stretch): twice the true duration, a third of the "
              "magnitude, a Fig. 7 ratio below 1. That is not the study's fit, whose pulses were short.",
              "- Held to start where the record leaves its baseline (the default), the pulse starts late by the "
              "time the base shear takes to rise out of the noise (the shear wave's transit from the load to the "
              "base, then the rise), and keeps the ringing's phase with a shorter pulse: about 2.4-2.6 ms, the "
              "study's duration. Its short, strong pulse excites the column's higher modes, so on the MDOF column "
              "it over-predicts the peak (ratio above 1), as the study found.",
              "- The impulse follows the gain: with m = k / omega^2 the SDOF sees only the first mode's share of "
              "the base shear and its impulse is below the true one; with m_s = the column's mass (the study's "
              "eq. [6] read with k, m_s and omega as separate inputs) the same fit scales up by m_s omega^2 / k. "
              "On the 70 Hz column that reading with the departure rule gives magnitude, duration and impulse "
              "within the study's SDOF row (above), and a Fig. 7 ratio whose range overlaps the study's.", ""]
    mdof, sdof = STUDY_TABLE1["MDOF fit"], STUDY_TABLE1["SDOF fit"]
    lines += ["### The SDOF fit of the MDOF response to Table 1's MDOF pulse", "",
              f"Table 1's MDOF pulse ({mdof[0]:.2f} N, {mdof[1] * 1e3:.1f} ms) on the MDOF column 0.40 m up, a "
              "noise-free record starting at the impact (t = 0), fitted by the SDOF with its frequency bounds "
              "centred on the column's first "
              f"frequency (the study: SDOF {sdof[0]:.2f} N, {sdof[1] * 1e3:.1f} ms, {sdof[2]:.2f} N s):", "",
              "| column | gain | magnitude (N) | duration (ms) | impulse (N s) | start (ms) | f (Hz) | rmse (N) | "
              "Fig. 7 ratio | duration 95 % interval (ms) | Jacobian condition | corr(magnitude, duration) |",
              "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for v, c in table1.items():
        for name, gain in (("sdof", "m = k / omega^2"), ("sdof_column_mass", "m_s = column mass")):
            f = c[name]
            lo, hi = f["duration_interval_s"]
            lines.append(f"| {VARIANTS[v][0]} | {gain} | {f['magnitude_N']:.1f} | {1e3 * f['duration_s']:.2f} | "
                         f"{f['impulse_Ns']:.3f} | {1e3 * f['start_s']:.2f} | {f['natural_frequency_Hz']:.1f} | "
                         f"{f['rmse_N']:.1f} | {f['fig7_ratio']:.2f} | {1e3 * lo:.2f}-{1e3 * hi:.2f} | "
                         f"{f['jacobian_condition_number']:.0f} | {f['magnitude_duration_correlation']:.3f} |")
    first = next(iter(table1.values()))["sdof"]
    prof = first["profile"]
    half = min(range(len(prof["duration_s"])), key=lambda i: abs(prof["duration_s"][i] - first["duration_s"] / 4))
    lines += ["", "Every fit starts at or after the record's first sample (the start is bounded by the last sample "
              "at the baseline: the base shear stays at zero while the shear wave travels from 0.40 m to the base). "
              "The duration is fixed within the interval above only because the start is bounded: profiled over "
              f"duration, a pulse of {1e3 * prof['duration_s'][half]:.2f} ms fits with impulse "
              f"{prof['impulse_Ns'][half]:.3f} N s (the fit's {first['impulse_Ns']:.3f}) and an excess misfit of "
              f"{prof['excess_cost'][half]:.0f} (threshold {prof['threshold']:.2f}, in units of the residual "
              "variance, which here is model error, not noise); magnitude and duration correlate at "
              f"{first['magnitude_duration_correlation']:.3f}.", "",
              f"On the {ident['records']} synthetic records ({primary} base) the SDOF duration's 95 % profile "
              f"interval is closed and within +-25 % for {ident['identifiable']} of them; median width "
              f"{ident['median_interval_width_ms']:.2f} ms, median Jacobian condition "
              f"{ident['median_condition_number']:.0f}, median magnitude-duration correlation "
              f"{ident['median_magnitude_duration_correlation']:.3f}.", ""]
    return lines
