"""The approach study written out: docs/results/approach/ (``make approach``).

``debrisfoam report approach RUN [--runs runs] [--coupled RUN ...] -o DIR`` (RUN: runs/1debris)

Reads the one-way flow records it finds (the default case, and the study's own runs under
``--runs``: ``1debris-4cm``, ``approach-4cm-200hz``, ``approach-3cm-box``, ``approach-2cm-box``; a
missing one is named in the page), carries the container through each
(:mod:`orchestrator.studies.approach`), sets the bodies of two-way runs of the same scene beside
them (``--coupled``, those with results; each is compared with the one-way carry on its own cell
size near the column) and writes ``report.md`` (the table), ``approach.csv``, ``speed_vs_gap.png`` (speed against the
nose's distance to the face, one line a carry) and ``budget.png`` / ``budget.csv`` (the default
run's forces along the flume over the last 0.3 m).
"""

from __future__ import annotations

import io
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pandas as pd

from analytical.study import STUDY_IMPACT_VELOCITY_M_S
from orchestrator.case.folder import CaseFolder
from orchestrator.core.errors import InputError
from orchestrator.core.files import write_bytes_atomic, write_text_atomic
from orchestrator.studies.approach import APPROACH_REACH_M, ApproachFlow, ApproachRun, carry, coupled_run, thinned
from orchestrator.transport.flow import FlowField

__all__ = ["COUPLED_RUNS", "STUDY_RUNS", "markdown", "write_approach_report"]

#: The study's own flow runs (folder under --runs: finest cell near the column, record rate, how made).
STUDY_RUNS = {
    "1debris-4cm": (0.04, 50.0, "--set mesh.column_approach_cell_size_m=null"),
    "approach-4cm-200hz": (0.04, 200.0, "--set outputs.flow_record_hz=200 --set run.end_time_s=2.6 "
                                        "--set run.max_delta_t_s=0.005"),
    "approach-3cm-box": (0.03, 100.0, "--set 'mesh.refine_box_m=[4.3,5.05,-0.16,0.16,0,0.24]' "
                                      "--set mesh.refine_cell_size_m=0.03 --set outputs.flow_record_hz=100 "
                                      "--set run.end_time_s=2.6"),
    "approach-2cm-box": (0.02, 100.0, "--set 'mesh.refine_box_m=[4.3,5.05,-0.16,0.16,0,0.24]' "
                                      "--set mesh.refine_cell_size_m=0.02 --set outputs.flow_record_hz=100 "
                                      "--set run.end_time_s=2.6"),
}
#: Reaches (m) of the approach flow frozen upstream of the face (ApproachFlow).
FROZEN_REACHES_M = (0.1, 0.2)
TERMS_PLOTTED = ("froude_krylov", "added_mass_flow", "drag", "contact", "inertia")


#: Two cell sizes near the column whose mean strike speeds differ by at most this fraction: converged.
CONVERGED = 0.05


#: Two-way runs of the 1-debris scene set beside the carries when they have results: the coupled
#: reference on the 4 cm background, on the default's (3 cm near the column) and with 2 cm there.
COUPLED_RUNS = (Path("runs/1debris-two-way"), Path("runs/coupling-1debris-3cm/two-way"),
                Path("runs/coupling-1debris-2cm/two-way"))


def near_column_cell_m(scene) -> float:
    """The finest cell where the body closes on the column (a loaded scene): the refinement box's, or
    the mesh's."""
    from orchestrator.plan.refine import refinement
    refined = refinement(scene)
    return refined[1] if refined is not None else scene.mesh.cell_size_m


def _record(case: Path) -> FlowField | None:
    npz = case / "results" / "flow_record.npz"
    return FlowField.load(npz) if npz.is_file() else None


def _row(run: ApproachRun) -> dict:
    s = run.strike
    base = {"carry": run.label, "cell_near_column_m": run.cell_m, "record_hz": run.rate_hz, "forcing": run.forcing}
    if s is None:
        return {**base, "strike_time_s": np.nan}
    return {**base, "strike_time_s": s.time_s, "speed_m_s": s.speed_m_s, "normal_m_s": s.normal_m_s,
            "yaw_deg": s.yaw_deg, "obliquity_deg": s.obliquity_deg, "speed_at_0.1m_m_s": s.speed_at_0p1_m_s,
            "speed_at_0.3m_m_s": s.speed_at_0p3_m_s, "slowed_at_gap_m": s.slowed_at_gap_m}


def run_all(default: Path, runs: Path, say=print,
            coupled: tuple[Path, ...] = ()) -> tuple[list[ApproachRun], pd.DataFrame, list[str]]:
    """Every carry of the study, the default's budget, and notes on what was missing; with
    ``coupled`` (two-way runs of the default's scene, post-processed) their bodies beside them."""
    scene = default / "scene.yaml"
    carries, notes = [], []
    flow = _record(default)
    if flow is None:
        raise InputError("case_dir", "no results/flow_record.npz: not a one-way run (run `make case-1debris` "
                                     "first)", str(default))
    from orchestrator.scene.scenefile import load_scene
    loaded = load_scene(scene)
    cell_m, rate_hz = near_column_cell_m(loaded), loaded.outputs.flow_record_hz
    run, budget = carry(scene, flow, label=f"default ({cell_m * 100:g} cm near the column, {rate_hz:g} Hz)",
                        cell_m=cell_m, rate_hz=rate_hz, budget=True)
    carries.append(run)
    col = loaded.column
    x_face = col.x_m - col.size_x_m / 2
    for reach in FROZEN_REACHES_M:
        frozen = ApproachFlow(flow, x_face, (col.y_m - col.size_y_m / 2, col.y_m + col.size_y_m / 2), reach)
        carries.append(carry(scene, frozen, label=f"approach flow frozen {reach:g} m from the face", cell_m=cell_m,
                             rate_hz=rate_hz, forcing=f"frozen at {reach:g} m")[0])
    for name, (cell, rate, how) in STUDY_RUNS.items():
        case = runs / name
        record = _record(case)
        if record is None:
            notes.append(f"`{name}` ({cell * 100:g} cm near the column, {rate:g} Hz) has no flow record under "
                         f"{runs}: not run (`debrisfoam case cases/1debris.yaml -o runs/{name} {how}`)")
            continue
        rates = [rate] + ([r for r in (100.0, 50.0) if r < rate] if cell == 0.04 else [])
        for r in rates:
            say(f"approach: {name} at {r:g} Hz")
            f = record if r == rate else thinned(record, r)
            carries.append(carry(case / "scene.yaml", f, label=f"{name} at {r:g} Hz", cell_m=cell, rate_hz=r)[0])
    for case in coupled:
        run = None
        if (case / "scene.yaml").is_file():
            name = case.name if case.name != "two-way" else case.parent.name
            run = coupled_run(case, label=f"coupled: {name}",
                              cell_m=near_column_cell_m(CaseFolder(case).scene()))
        if run is None:
            notes.append(f"`{case}` has no scene.yaml, results/bodies.csv and impacts.csv: no coupled carry "
                         "(`make case-1debris COUPLING=two-way`, or `debrisfoam post --tables-only` of a stopped run)")
        else:
            carries.append(run)
    return carries, budget, notes


def _span(values: pd.Series) -> str:
    lo, hi = float(values.min()), float(values.max())
    return f"{lo:.2f}" if round(lo, 2) == round(hi, 2) else f"{lo:.2f}-{hi:.2f}"


def markdown(table: pd.DataFrame, notes: list[str], budget: pd.DataFrame) -> str:
    """The page: the table of strikes, then what was not run."""
    lines = ["# The approach to the column", "",
             "The 1-debris scene's container carried one-way through its flow records "
             "(`make approach`, orchestrator/studies/approach.py): its first column strike against the "
             "record's cell size near the column, its frame rate and the forcing near the face. Speeds are "
             "the body's at the strike (total, and its part along the face's normal); the study measured "
             "1.60 +- 0.13 m/s (total, Table 2's 22 impacts).", "",
             "| carry | cell near column | record | forcing near the face | strike time | speed | normal | "
             "yaw | obliquity | speed 0.1 m out | speed 0.3 m out |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in table.to_dict("records"):
        if not np.isfinite(r.get("strike_time_s", np.nan)):
            lines.append(f"| {r['carry']} | {r['cell_near_column_m'] * 100:g} cm | {r['record_hz']:g} Hz | "
                         f"{r['forcing']} | no strike | - | - | - | - | - | - |")
            continue
        lines.append(f"| {r['carry']} | {r['cell_near_column_m'] * 100:g} cm | {r['record_hz']:g} Hz | {r['forcing']} | "
                     f"{r['strike_time_s']:.3f} s | {r['speed_m_s']:.2f} m/s | {r['normal_m_s']:.2f} m/s | "
                     f"{r['yaw_deg']:.1f} deg | {r['obliquity_deg']:.1f} deg | {r['speed_at_0.1m_m_s']:.2f} m/s | "
                     f"{r['speed_at_0.3m_m_s']:.2f} m/s |")
    hit = table[np.isfinite(table["strike_time_s"])] if "speed_m_s" in table else table.iloc[:0]
    if len(hit):
        undisturbed = hit[hit["forcing"] == "undisturbed"]
        frozen = hit[hit["forcing"].str.startswith("frozen")]
        two_way = hit[hit["forcing"].str.startswith("two-way")]
        one_way = hit[~hit["forcing"].str.startswith("two-way")]
        lines += ["", "## What the spread says", "",
                  f"Every one-way carry is at {_span(one_way['speed_at_0.3m_m_s'])} m/s 0.3 m from the face and "
                  f"{_span(one_way['speed_at_0.1m_m_s'])} m/s 0.1 m from it: the strike speed is decided in the last 0.1 m, inside the column's stagnation "
                  "zone. "
                  + (f"With the undisturbed flow at the sub-volumes (the model's forcing) the records give "
                     f"{_span(undisturbed['speed_m_s'])} m/s "
                     f"({len(undisturbed)} carr{'y' if len(undisturbed) == 1 else 'ies'}); " if len(undisturbed) else "")
                  + (f"with the approach flow frozen upstream of the face, {_span(frozen['speed_m_s'])} m/s. "
                     if len(frozen) else "")
                  + "The budget shows why: over the last 0.1 m the "
                  "water the body stands in decelerates towards the face in a flow without the body, and the "
                  "Froude-Krylov force and the added mass's share of it (the body's displaced and carried water "
                  "decelerating with the stagnation flow) take the body's speed away, while drag still pushes it "
                  "forward. A floating body of its own displacement, as this one nearly is, follows a water parcel "
                  "into the stagnation point; a 0.15 m body that fills the gap it closes changes that flow, which "
                  "a one-way record cannot hold. "
                  + ("Whether it does is what the coupled body (below) shows." if len(two_way) else
                     "Until a coupled reference resolves the gap, the one-way strike speed is uncertain by the "
                     "range between the undisturbed forcing and the frozen approach flow."), ""]
        for _, c in two_way.iterrows():
            lines += _coupled_findings(c, undisturbed[undisturbed["cell_near_column_m"] == c["cell_near_column_m"]])
        lines += _resolution_findings(undisturbed)
    lines += ["", "![speed against the gap to the face](speed_vs_gap.png)", "",
              "## The force budget of the default carry", "",
              f"Along the flume, over the last {APPROACH_REACH_M:g} m before the strike (budget.csv; "
              "orchestrator/transport/budget.py): each term of the one-way forcing evaluated on the track with "
              "the engine's own force function; `contact` is what is left of (m + m_a) a, the bed's friction "
              "and normal force and the column's.", "", "![force budget](budget.png)", ""]
    if len(budget):
        last = budget.iloc[-1]
        lines += [f"At the last row before the strike ({last['gap_m'] * 1000:.0f} mm from the face): "
                  + ", ".join(f"{t.replace('_', ' ')} {last[t + '_x']:+.2f} N" for t in TERMS_PLOTTED)
                  + f"; the largest |contact| over the approach {budget['contact_x'].abs().max():.2f} N.", ""]
    if notes:
        lines += ["## Not run", ""] + [f"- {n}" for n in notes] + [""]
    return "\n".join(lines)


def _coupled_findings(c: pd.Series, one_way: pd.DataFrame) -> list[str]:
    """A coupled body beside the first undisturbed one-way carry at its cell size near the column
    (the same background mesh): where they differ."""
    if one_way.empty:
        return []
    d = one_way.iloc[0]

    def loss(r) -> float:  # the share of the speed 0.1 m out lost by the strike
        return 1.0 - r["speed_m_s"] / r["speed_at_0.1m_m_s"]

    return [f"- The coupled body ({c['carry']}, {c['cell_near_column_m'] * 100:g} cm near the column, the body "
            f"changing the flow): "
            f"{c['speed_at_0.3m_m_s']:.2f} m/s 0.3 m out, {c['speed_at_0.1m_m_s']:.2f} m/s 0.1 m out, "
            f"{c['speed_m_s']:.2f} m/s at the strike ({(c['speed_m_s'] / d['speed_m_s'] - 1) * 100:+.0f} %), "
            f"against the one-way carry {d['carry']}'s {d['speed_at_0.3m_m_s']:.2f}, "
            f"{d['speed_at_0.1m_m_s']:.2f} and {d['speed_m_s']:.2f} m/s. Over the last 0.1 m the coupled body "
            f"loses {loss(c) * 100:.0f} % of its speed and the one-way one {loss(d) * 100:.0f} %"
            + (" (a like share: the strike speeds differ by what the bodies carried into the stagnation zone)"
               if abs(loss(c) - loss(d)) < 0.05 else "")
            + f". The coupled body has lost 5 % of its speed 0.3 m out by {c['slowed_at_gap_m']:.3f} m from the "
            f"face, the one-way one by {d['slowed_at_gap_m']:.3f} m"
            + (": the water the coupled body pushes into the gap it closes slows it further out."
               if c["slowed_at_gap_m"] > d["slowed_at_gap_m"] + 0.02 else "."), ""]


def _resolution_findings(undisturbed: pd.DataFrame) -> list[str]:
    """What the frame rate and the cell size near the column change, from the undisturbed carries."""
    out = []
    run = undisturbed["carry"].str.split(" at ").str[0]
    for name, group in undisturbed.groupby(run):
        if group["record_hz"].nunique() > 1:
            out.append(f"- Frame rate: the record of {name} thinned to {', '.join(f'{h:g}' for h in sorted(group['record_hz']))} Hz "
                       f"gives strike speeds {_span(group['speed_m_s'])} m/s (the frames are not what decides it).")
    by_cell = undisturbed.groupby("cell_near_column_m")["speed_m_s"]
    if by_cell.ngroups > 1:
        parts = [f"{c * 100:g} cm: {_span(v)} m/s" for c, v in by_cell]
        means = by_cell.mean()  # finest cell first
        change = means.iloc[0] - means.iloc[-1]  # finest minus coarsest
        text = ("- Cell size near the column (undisturbed forcing): " + "; ".join(parts) + ". Rows at one "
                "cell size may differ by their solver steps (the default's maxDeltaT 10 ms; the 200 Hz run's "
                f"5 ms). The finest mesh strikes {abs(change):.2f} m/s {'faster' if change > 0 else 'slower'} "
                f"than the coarsest ({change / means.iloc[-1] * 100:+.0f} %)")
        last = means.iloc[0] - means.iloc[1]  # the two finest
        if by_cell.ngroups > 2:
            text += (f"; the two finest ({means.index[1] * 100:g} and {means.index[0] * 100:g} cm) differ by "
                     f"{last / means.iloc[1] * 100:+.1f} %")
        if abs(last) <= CONVERGED * means.iloc[1]:
            text += (f": the strike speed is converged within {CONVERGED * 100:g} % at "
                     f"{means.index[1] * 100:g} cm near the column, and "
                     f"{means.index[-1] * 100:g} cm is {(means.iloc[-1] / means.iloc[0] - 1) * 100:+.0f} % off "
                     "the finest.")
        else:
            text += ": the one-way strike speed is not converged in the cell size near the column."
        out.append(text)
    return out + ([""] if out else [])


def _plots(carries: list[ApproachRun], budget: pd.DataFrame) -> tuple[bytes, bytes]:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(8, 5))
    for run in carries:
        near = run.track[run.track["gap_m"] <= 0.6]
        coupled = run.forcing.startswith("two-way")
        ax.plot(near["gap_m"], near["speed_m_s"], label=run.label, color="k" if coupled else None,
                linestyle="--" if coupled else "-", linewidth=2 if coupled else 1.5)
    mean, std = STUDY_IMPACT_VELOCITY_M_S
    ax.axhspan(mean - std, mean + std, color="0.85", label=f"study: {mean:.2f} +- {std:.2f} m/s")
    ax.invert_xaxis()
    ax.set_xlabel("nose's distance to the column's face (m)")
    ax.set_ylabel("body speed (m/s)")
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    speed = _png(fig)
    fig, ax = plt.subplots(figsize=(8, 5))
    for term in TERMS_PLOTTED:
        ax.plot(budget["gap_m"], budget[f"{term}_x"], label=term.replace("_", " "))
    ax.invert_xaxis()
    ax.set_xlabel("nose's distance to the column's face (m)")
    ax.set_ylabel("force along the flume (N)")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    return speed, _png(fig)


def _png(fig) -> bytes:
    """A figure as PNG bytes, closed."""
    import matplotlib.pyplot as plt

    out = io.BytesIO()
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    plt.close(fig)
    return out.getvalue()


def write_approach_report(default: str | Path, runs: str | Path, out: str | Path,
                          coupled: tuple[Path, ...] = COUPLED_RUNS,
                          say: Callable[[str], None] = print) -> dict[str, Path]:
    """Every carry of the study (:func:`run_all`: ``default``, the one-way run; ``runs``, the folder
    of the study's own runs; ``coupled``, two-way runs beside them) written into ``out``; each file
    by kind (report, approach, budget, speed_vs_gap, budget_plot)."""
    carries, budget, notes = run_all(Path(default), Path(runs), say=say, coupled=tuple(Path(c) for c in coupled))
    table = pd.DataFrame([_row(r) for r in carries])
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    files = {"report": out / "report.md", "approach": out / "approach.csv", "budget": out / "budget.csv",
             "speed_vs_gap": out / "speed_vs_gap.png", "budget_plot": out / "budget.png"}
    write_text_atomic(files["approach"], table.to_csv(index=False, float_format="%.6g"))
    write_text_atomic(files["budget"], budget.to_csv(index=False, float_format="%.6g"))
    speed_png, budget_png = _plots(carries, budget)
    write_bytes_atomic(files["speed_vs_gap"], speed_png)
    write_bytes_atomic(files["budget_plot"], budget_png)
    write_text_atomic(files["report"], markdown(table, notes, budget))
    return files
