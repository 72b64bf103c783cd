"""The flume as built: every member of a sweep over the gate's sill, opening and opening time, the
wet bed's depth and the column's position (``cases/sweeps/flume-as-built.yaml``), its arrivals at WG2 and WG3 and
at the column's face against the measured ones and against the first member (the scene as
shipped), with the front's speed between the gauges; and, from the gauges' records
(:mod:`orchestrator.studies.face_reach`), the water at the column's face against the study's load
points and the front's speed over successive reaches of the centreline. The same page serves any
sweep of the flume (``cases/sweeps/face-splash.yaml``: finer cells at the face).

Arrivals are the post-processor's (``results/gauge_summary.csv``: the first rise of the level above
its start by the gauge's threshold); the measured ones are the study's (``STUDY_ARRIVALS``).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np
import pandas as pd
from orchestrator.case.folder import CaseFolder
from orchestrator.core.errors import InputError
from orchestrator.report.figures import pyplot
from orchestrator.studies.face_reach import AFTER_ARRIVAL_S, WET_ALPHA, MemberFlow, member_flow, reach_verdict
from orchestrator.studies.gauge_reading import RISES_M, SHELF_BAND_M, RiseReading, rise_reading
from orchestrator.scene.flume import Bed
from orchestrator.scene.schema import Mesh
from orchestrator.studies.sweep.store import member_dirs
from analytical.dambreak import stoker_state
from analytical.study import STUDY_ARRIVALS, STUDY_IMPACT_HEIGHTS_M

__all__ = ["FlumeMember", "flume_members", "write_flume_report"]

#: The study's gauges this page reads, by name: (x m, measured arrival s).
MEASURED = {name: (x, measured) for x, (name, measured, _model) in STUDY_ARRIVALS.items()}
#: The gauge at the column's upstream face in the shipped scenes.
FACE_GAUGE = "WG4"
#: The study's gauges by name: left out of the centreline reaches (their arrivals have their own columns).
MEASURED_NAMES = (*(name for name, _, _ in STUDY_ARRIVALS.values()), FACE_GAUGE)


@dataclass(frozen=True)
class FlumeMember:
    """One member: what it changes and when the front reached each gauge (s; nan: never)."""

    member: str
    sill_height_m: float
    depth_m: float
    opening_width_m: float | None
    wet_depth_m: float
    column_x_m: float  # nan: a flume without a column (its WG4 a plain gauge)
    face_x_m: float
    wg2_s: float
    wg3_s: float
    face_s: float
    solver_wall_s: float
    opening_time_s: float = 0.0
    turbulence: str = "laminar"
    wet_bed_cells: int = 1
    refine: str = ""  # the refinement box, in words ("": none)
    cell_size_m: float = math.nan  # mesh.cell_size_m
    friction_calibration: float = Bed.model_fields["friction_calibration"].default  # bed.friction_calibration

    @property
    def speed_wg2_wg3_m_s(self) -> float:
        return _speed(MEASURED["WG3"][0] - MEASURED["WG2"][0], self.wg3_s - self.wg2_s)

    @property
    def speed_wg3_face_m_s(self) -> float:
        return _speed(self.face_x_m - MEASURED["WG3"][0], self.face_s - self.wg3_s)


def _speed(distance_m: float, time_s: float) -> float:
    return distance_m / time_s if math.isfinite(time_s) and time_s > 0 else math.nan


def _member(case: Path) -> FlumeMember:
    summary = case / "results" / "gauge_summary.csv"
    if not summary.is_file():
        raise InputError(str(summary), "missing: run `debrisfoam post` on the member first")
    scene = CaseFolder(case).scene()
    table = pd.read_csv(summary).set_index("gauge")
    for name in ("WG2", "WG3", FACE_GAUGE):
        if name not in table.index:
            raise InputError(str(summary), f"has no gauge {name}: the page reads WG2, WG3 and {FACE_GAUGE}")
    arrival = {name: float(table.loc[name, "arrival_s"]) for name in ("WG2", "WG3", FACE_GAUGE)}
    res, summary_json = scene.reservoir, case / "results" / "summary.json"
    wall, mesh = math.nan, scene.mesh
    if summary_json.is_file():
        import json

        wall = float((json.loads(summary_json.read_text()).get("wall_time_s") or {}).get("solver_s") or math.nan)
    return FlumeMember(
        member=case.name, sill_height_m=float(res.sill_height_m), depth_m=float(res.depth_m),
        opening_width_m=None if res.opening_width_m is None else float(res.opening_width_m),
        wet_depth_m=float(scene.bed.wet_depth_m),
        column_x_m=float(scene.column.x_m) if scene.column is not None else math.nan,
        face_x_m=float(table.loc[FACE_GAUGE, "x_m"]), wg2_s=arrival["WG2"], wg3_s=arrival["WG3"],
        face_s=arrival[FACE_GAUGE], solver_wall_s=wall, opening_time_s=float(res.opening_time_s),
        turbulence=str(scene.fluids.turbulence), wet_bed_cells=int(mesh.wet_bed_cells), refine=_refine_text(mesh),
        cell_size_m=float(mesh.cell_size_m),
        friction_calibration=float(scene.bed.friction_calibration))


def _refine_text(mesh: Mesh) -> str:
    box, size = mesh.refine_box_m, mesh.refine_cell_size_m
    if box is None or size is None:
        return ""
    x0, x1, y0, y1, z0, z1 = (float(v) for v in box)
    return f"{float(size) * 100:g} cm cells in x {x0:g}-{x1:g}, y {y0:g}..{y1:g}, z {z0:g}-{z1:g} m"


def flume_members(sweep_dir: str | Path) -> list[FlumeMember]:
    """The sweep's post-processed members, in the sweep file's order (:func:`member_dirs`)."""
    cases = member_dirs(sweep_dir, "results/gauge_summary.csv")
    if not cases:
        raise InputError(str(sweep_dir), "holds no post-processed member (no */results/gauge_summary.csv)")
    return [_member(c) for c in cases]


def _change(m: FlumeMember, base: FlumeMember) -> str:
    parts = []
    if m.sill_height_m != base.sill_height_m or m.depth_m != base.depth_m:
        parts.append(f"sill {m.sill_height_m * 100:g} cm, level {m.depth_m:g} m above the bed "
                     f"({m.depth_m + m.sill_height_m:g} m deep)")
    if m.opening_width_m != base.opening_width_m:
        parts.append(f"opening {m.opening_width_m:g} m")
    if m.opening_time_s != base.opening_time_s:
        parts.append(f"gate opening over {m.opening_time_s:g} s")
    if m.wet_depth_m != base.wet_depth_m:
        parts.append(f"wet bed {m.wet_depth_m * 1000:g} mm")
    if m.column_x_m != base.column_x_m and not (math.isnan(m.column_x_m) and math.isnan(base.column_x_m)):
        parts.append(f"column at x = {m.column_x_m:g} m")
    if m.refine != base.refine:
        parts.append(m.refine or "no refinement box")
    if m.turbulence != base.turbulence:
        parts.append(f"{m.turbulence} (RANS)" if m.turbulence != "laminar" else "laminar")
    if m.wet_bed_cells != base.wet_bed_cells:
        parts.append(f"{m.wet_bed_cells} cells across the wet bed")
    if m.cell_size_m != base.cell_size_m and math.isfinite(m.cell_size_m):
        parts.append(f"{m.cell_size_m * 100:g} cm cells")
    if m.friction_calibration != base.friction_calibration:
        parts.append(f"bed drag calibration {m.friction_calibration:g}")
    return "; ".join(parts) or "the scene as shipped"


def _fmt(value: float, spec: str = ".3f", signed: bool = False) -> str:
    if not math.isfinite(value):
        return "-"
    return format(value, ("+" if signed else "") + spec)


def _plot(members: list[FlumeMember], out: Path) -> str:
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(7.5, 4.2))
    base = members[0]
    for m in members:
        ax.plot([MEASURED["WG2"][0], MEASURED["WG3"][0], m.face_x_m], [m.wg2_s, m.wg3_s, m.face_s], "o-", lw=1,
                ms=3, label=_change(m, base))
    ax.plot([v[0] for v in MEASURED.values()], [v[1] for v in MEASURED.values()], "ks", ms=8, label="measured")
    ax.set_xlabel("x past the gate (m)")
    ax.set_ylabel("front arrival (s)")
    return _finish(fig, ax, out / "arrivals.png")


def _gauge_plot(members: list[FlumeMember], sweep_dir: Path, out: Path) -> str | None:
    """WG2's and WG3's levels over time, one colour a member, the measured arrivals marked: the step in
    a front shows as a shelf. None when no member has ``results/gauges.csv``."""
    plt = pyplot()
    fig, axes = plt.subplots(1, 2, figsize=(10, 5.6), sharey=True)
    for ax in axes:
        ax.set_prop_cycle(color=plt.cm.tab20(np.linspace(0, 1, 20)))
    drawn = False
    for m in members:
        table = sweep_dir / m.member / "results" / "gauges.csv"
        if not table.is_file():
            continue
        data = pd.read_csv(table)
        for ax, name in zip(axes, ("WG2", "WG3")):
            if f"{name}_elevation_m" in data:
                ax.plot(data["time_s"], data[f"{name}_elevation_m"] * 1000, lw=1, label=_change(m, members[0]))
                drawn = True
    if not drawn:
        plt.close(fig)
        return None
    for ax, name in zip(axes, ("WG2", "WG3")):
        ax.axvline(MEASURED[name][1], color="k", ls="--", lw=1, label="measured arrival" if name == "WG2" else None)
        ax.set_xlim(MEASURED["WG2"][1] - 0.3, None)
        ax.set_xlabel("time (s)")
        ax.set_title(f"{name} (x = {MEASURED[name][0]:g} m)", fontsize=9)
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("level above the bed (mm)")
    fig.legend(*axes[0].get_legend_handles_labels(), loc="lower center", ncol=3, fontsize=6.5)
    fig.tight_layout(rect=(0, 0.17, 1, 1))
    fig.savefig(out / "gauges.png", dpi=100)
    plt.close(fig)
    return "gauges.png"


def _finish(fig, ax, path: Path) -> str:
    """Legend and grid on ``ax``; ``fig`` written to ``path`` (100 dpi) and closed; the file's name."""
    ax.legend(fontsize=6.5, loc="upper left")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    pyplot().close(fig)
    return path.name


def _face_plot(members: list[FlumeMember], flows: list[MemberFlow], out: Path) -> str:
    """WG4's elevation (solid) and highest wet point (dashed) against the time since the front reached the
    face, one colour a member, over the study's load points."""
    plt = pyplot()
    lo, hi, mean = STUDY_IMPACT_HEIGHTS_M
    fig, ax = plt.subplots(figsize=(7.5, 4.2))
    ax.axhspan(lo, hi, color="0.85", label=f"the study's load points {lo:g}-{hi:g} m")
    ax.axhline(mean, color="0.4", lw=1, label=f"their mean {mean:g} m")
    base = members[0]
    for m, f in zip(members, flows):
        t_e, v_e, t_w, v_w = f.series
        (line,) = ax.plot(t_e - m.face_s, v_e, lw=1.2, label=_change(m, base))
        ax.plot(t_w - m.face_s, v_w, "--", lw=0.9, color=line.get_color())
    ax.set_xlim(-0.2, None)
    ax.set_ylim(0, None)
    ax.set_xlabel(f"time since the front reached the face ({FACE_GAUGE}'s arrival, s)")
    ax.set_ylabel(f"{FACE_GAUGE} above the bed (m)")
    ax.set_title(f"{FACE_GAUGE}: elevation (solid), highest wet point (dashed)", fontsize=9)
    return _finish(fig, ax, out / "face.png")


def _span(values: list[float]) -> str:
    lo, hi = f"{min(values):.2f}", f"{max(values):.2f}"
    return lo if lo == hi else f"{lo}-{hi}"


def _face_lines(members: list[FlumeMember], flows: list[MemberFlow], figure: str) -> list[str]:
    lo, hi, mean = STUDY_IMPACT_HEIGHTS_M
    after = " and ".join(f"{d:g}" for d in AFTER_ARRIVAL_S)
    ends = [f.face.record_end_s - m.face_s for m, f in zip(members, flows) if f.face is not None]
    lines = [
        "## The water at the column's face", "",
        f"{FACE_GAUGE}, 1 cm upstream of the column's face: its elevation (the alpha.water integral along its "
        f"line) and its highest wet point (the highest sample with alpha.water above {WET_ALPHA:g}; water thrown "
        f"up the face counts there but hardly in the integral), at their peaks over the run and {after} s after "
        f"the front reached the face. The study's load points, the water surface at the face at impact read "
        f"from its WG4 (its MDOF fit): {lo:g}-{hi:g} m above the base, mean {mean:g} m."
        + (f" The records end {_span(ends)} s after the front reached the face." if ends else ""),
        "",
        "| change | front at the face (s) | elevation peak (m, s after the front) "
        + "".join(f"| at +{d:g} s " for d in AFTER_ARRIVAL_S)
        + "| highest wet point peak (m, s after) " + "".join(f"| at +{d:g} s " for d in AFTER_ARRIVAL_S)
        + "| cells | solver (s) |",
        "|---" * (6 + 2 * len(AFTER_ARRIVAL_S)) + "|",
    ]
    for m, f in zip(members, flows):
        r = f.face
        if r is None:
            cells = ["-"] * (2 + 2 * len(AFTER_ARRIVAL_S))
        else:
            cells = ([f"{_fmt(r.elevation_peak_m)} ({_fmt(r.elevation_peak_s - m.face_s, '.2f', True)})"]
                     + [_fmt(v) for v in r.elevation_after_m]
                     + [f"{_fmt(r.wet_peak_m)} ({_fmt(r.wet_peak_s - m.face_s, '.2f', True)})"]
                     + [_fmt(v) for v in r.wet_after_m])
        lines.append(f"| {_change(m, members[0])} | {_fmt(m.face_s)} | " + " | ".join(cells)
                     + f" | {f.cells or '-'} | {_fmt(m.solver_wall_s, '.0f')} |")
    return lines + ["", f"![{FACE_GAUGE}]({figure})", ""]


def _reach_lines(members: list[FlumeMember], flows: list[MemberFlow]) -> list[str]:
    spans = sorted({(r.x0_m, r.x1_m) for f in flows for r in f.reaches})
    if not spans:
        return []
    intervals = sorted({f.probe_interval_s for f in flows if f.probe_interval_s is not None})
    dt = ", ".join(f"{v:g}" for v in intervals) or "one time step"
    lines = [
        "## The front along the centreline", "",
        "The front's speed over each reach between successive centreline gauges (y = 0) past the gate, its "
        "length over the difference of the arrivals, the study's gauges left out (their arrivals are above). "
        f"The gauges are sampled {dt} s apart (outputs.probe_interval_s), so an arrival is taken as uncertain "
        "by half that and a reach's speed v over a time T by v dt / T (the figure after the +-). A reach speeds "
        "up when it is faster than the one before by more than both uncertainties together; otherwise the "
        "front falls or holds.", "",
        "| change " + "".join(f"| {a:g}-{b:g} m (m/s) " for a, b in spans) + "| verdict |",
        "|---" * (len(spans) + 2) + "|",
    ]
    for m, f in zip(members, flows):
        by_span = {(r.x0_m, r.x1_m): r for r in f.reaches}
        cells = [f"{_fmt(by_span[s].speed_m_s, '.2f')} +- {_fmt(by_span[s].uncertainty_m_s, '.2f')}"
                 if s in by_span else "-" for s in spans]
        lines.append(f"| {_change(m, members[0])} | " + " | ".join(cells) + f" | {reach_verdict(list(f.reaches))} |")
    return lines + [""]


def _rise_lines(members: list[FlumeMember], readings: list[RiseReading | None]) -> list[str]:
    (x2, t2), (x3, t3) = MEASURED["WG2"], MEASURED["WG3"]
    if not any(readings):
        return []
    lines = [
        "## The front between WG2 and WG3 read at other rises", "",
        "The study gives its arrivals without the rise of the level it read them at. Here each member's front "
        "between WG2 and WG3, read at rises of the level above its start from "
        f"{RISES_M[0] * 1000:g} to {RISES_M[-1] * 1000:g} mm, and at the one rise that puts WG2 on its measured "
        f"{t2:g} s, with WG3's arrival then: one coefficient taken from one gauge and checked on the other "
        f"(measured {t3:g} s, the front {(x3 - x2) / (t3 - t2):.2f} m/s; \"-\": the front's tip reaches WG2 "
        f"after {t2:g} s, so no rise does). Levels: the gauges' alpha.water integrals (rises.csv). WG2's "
        "step, which the study puts down to the gate's support columns: the time its level takes from the "
        "arrival to half Stoker's bore depth, and the longest span in between that it holds within "
        f"{SHELF_BAND_M * 1000:g} mm, at its mean level.", "",
        "| change " + "".join(f"| {r * 1000:g} mm (m/s) " for r in RISES_M)
        + f"| rise for WG2 at {t2:g} s (mm) | WG3 then (s) | against measured (s) | front then (m/s) "
        "| WG2 to half the bore (s) | WG2 held (s, at m) |",
        "|---" * (len(RISES_M) + 7) + "|",
    ]
    for m, r in zip(members, readings):
        if r is None:
            continue
        speeds = " | ".join(_fmt(v, ".2f") for v in r.speeds_m_s())
        sh = r.wg2_shelf
        step = (f"| {_fmt(sh.rise_s, '.2f')} | {_fmt(sh.held_s, '.2f')} at {_fmt(sh.level_m)} |" if sh is not None
                else "| - | - |")
        lines.append(f"| {_change(m, members[0])} | {speeds} | {_fmt(r.fitted_rise_m * 1000, '.1f')} "
                     f"| {_fmt(r.wg3_at_fitted_s)} | {_fmt(r.wg3_at_fitted_s - t3, '.3f', True)} "
                     f"| {_fmt(r.speed_at_fitted_m_s, '.2f')} {step}")
    return lines + [""]


def _half_bore(m: FlumeMember) -> tuple[float, float] | None:
    """(WG2's arrival s, half Stoker's bore depth m) for a wet bed below the impoundment; None otherwise."""
    if not 0.0 < m.wet_depth_m < m.depth_m or not math.isfinite(m.wg2_s):
        return None
    return m.wg2_s, 0.5 * stoker_state(m.depth_m, m.wet_depth_m).h2_m


def _rise_table(members: list[FlumeMember], readings: list[RiseReading | None]) -> pd.DataFrame:
    rows = []
    for m, r in zip(members, readings):
        if r is None:
            continue
        row: dict = {"member": m.member, "change": _change(m, members[0])}
        for rise, a, b, v in zip(r.rises_m, r.wg2_s, r.wg3_s, r.speeds_m_s()):
            row |= {f"wg2_at_{rise * 1000:g}mm_s": a, f"wg3_at_{rise * 1000:g}mm_s": b,
                    f"speed_at_{rise * 1000:g}mm_m_s": v}
        row |= {"fitted_rise_m": r.fitted_rise_m, "wg2_at_fitted_s": r.wg2_at_fitted_s,
                "wg3_at_fitted_s": r.wg3_at_fitted_s, "speed_at_fitted_m_s": r.speed_at_fitted_m_s}
        if r.wg2_shelf is not None:
            row |= {"wg2_rise_to_half_bore_s": r.wg2_shelf.rise_s, "wg2_held_s": r.wg2_shelf.held_s,
                    "wg2_held_level_m": r.wg2_shelf.level_m}
        rows.append(row)
    return pd.DataFrame(rows)


#: The make target that writes each shipped sweep's page.
_MAKE_TARGETS = {"flume-as-built": "flume-as-built", "flume-centreline-2d": "flume-2d", "face-splash": "face-splash"}
#: A sweep's own title and first words (default: the flume as built's).
_TITLES = {"face-splash": ("# Splash-up at the column's face: 4 cm cells and finer cells at the face",
                           "What each member is and why is in the sweep file's header"),
           "flume-centreline-2d": ("# The study's flume as a 2D centreline strip: RANS at 2 cm and 1 cm cells, "
                                   "with and without the sill",
                                   "The sill's size is assumed (the sweep file says why)")}


def _setting(case: Path) -> str:
    """What every member shares, from the first member's scene: its name, closure, cells and end time."""
    scene = CaseFolder(case).scene()
    column = "no column" if scene.column is None else "the column"
    return (f"the scene `{scene.name}` ({scene.fluids.turbulence}, {scene.mesh.cell_size_m * 100:g} cm cells, "
            f"a {scene.flume.width_m:g} m wide flume, {column}, {scene.run.end_time_s:g} s)")


def write_flume_report(sweep_dir: str | Path, out_dir: str | Path) -> dict[str, Path]:
    """report.md, flume.csv, arrivals.png, face.csv, face.png and (with gauge records) rises.csv and gauges.png
    in ``out_dir``."""
    members = flume_members(sweep_dir)
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    rows = [{**asdict(m), "speed_wg2_wg3_m_s": m.speed_wg2_wg3_m_s, "speed_wg3_face_m_s": m.speed_wg3_face_m_s}
            for m in members]
    pd.DataFrame(rows).to_csv(out / "flume.csv", index=False)
    figure = _plot(members, out)
    flows = [member_flow(Path(sweep_dir) / m.member, FACE_GAUGE, m.face_x_m, m.face_s, tuple(MEASURED_NAMES))
             for m in members]
    _flow_table(members, flows).to_csv(out / "face.csv", index=False)
    face_figure = _face_plot(members, flows, out)
    base = members[0]
    (x2, t2), (x3, t3) = MEASURED["WG2"], MEASURED["WG3"]
    sweep = Path(sweep_dir).resolve()
    title, about = _TITLES.get(sweep.name, (
        "# The flume as built: the gate's sill, opening and opening time, the wet bed, the column's position",
        "The sizes are assumed: the study names the false floor acting as a sill and the gate's support columns "
        "but gives neither's size (the sweep file says what each value stands for)"))
    lines = [
        title,
        "",
        f"Generated by `debrisfoam sweep cases/sweeps/{sweep.name}.yaml`, then `debrisfoam report flume` "
        f"(`make {_MAKE_TARGETS.get(sweep.name, 'sweep')}`): {_setting(Path(sweep_dir) / base.member)}, "
        f"one change at a time from the sweep's first member (the first row). {about}. "
        "Arrivals: the first rise of each gauge's level by "
        f"its threshold. Measured: WG2 (x = {x2:g} m) {t2:g} s, WG3 ({x3:g} m) {t3:g} s, the front between "
        f"them {(x3 - x2) / (t3 - t2):.2f} m/s.",
        "",
        "| change | WG2 (s) | change (s) | WG3 (s) | change (s) | column face (s) | change (s) "
        "| front WG2-WG3 (m/s) | front WG3-face (m/s) | WG2, WG3 against measured (s) | solver (s) |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for m in members:
        lines.append(
            f"| {_change(m, base)} | {_fmt(m.wg2_s)} | {_fmt(m.wg2_s - base.wg2_s, signed=True)} "
            f"| {_fmt(m.wg3_s)} | {_fmt(m.wg3_s - base.wg3_s, signed=True)} | {_fmt(m.face_s)} "
            f"| {_fmt(m.face_s - base.face_s, signed=True)} | {_fmt(m.speed_wg2_wg3_m_s, '.2f')} "
            f"| {_fmt(m.speed_wg3_face_m_s, '.2f')} | {_fmt(m.wg2_s - t2, '.3f', True)}, "
            f"{_fmt(m.wg3_s - t3, '.3f', True)} | {_fmt(m.solver_wall_s, '.0f')} |")
    lines += ["", f"![arrivals]({figure})", ""]
    columned = any(math.isfinite(m.column_x_m) for m in members)  # a flume without one has no face to read
    lines += (_face_lines(members, flows, face_figure) if columned else []) + _reach_lines(members, flows)
    readings = [rise_reading(Path(sweep_dir) / m.member, MEASURED["WG2"], MEASURED["WG3"],
                             shelf=_half_bore(m)) for m in members]
    gauge_figure = _gauge_plot(members, Path(sweep_dir), out)
    lines += _rise_lines(members, readings) + ([f"![WG2 and WG3]({gauge_figure})", ""] if gauge_figure else [])
    files = {}
    if any(readings):
        _rise_table(members, readings).to_csv(out / "rises.csv", index=False)
        files["rise_table"] = out / "rises.csv"
    if gauge_figure:
        files["gauge_figure"] = out / gauge_figure
    (out / "report.md").write_text("\n".join(lines))
    return {"report": out / "report.md", "table": out / "flume.csv", "figure": out / figure,
            "face_table": out / "face.csv", "face_figure": out / face_figure, **files}


def _flow_table(members: list[FlumeMember], flows: list[MemberFlow]) -> pd.DataFrame:
    """face.csv: a row a member, its face readings, reach speeds and verdict."""
    rows = []
    for m, f in zip(members, flows):
        row: dict = {"member": m.member, "change": _change(m, members[0]), "face_s": m.face_s, "cells": f.cells,
                     "solver_wall_s": m.solver_wall_s, "probe_interval_s": f.probe_interval_s}
        r = f.face
        row |= {"elevation_peak_m": r.elevation_peak_m if r else math.nan,
                "elevation_peak_after_s": r.elevation_peak_s - m.face_s if r else math.nan,
                "wet_peak_m": r.wet_peak_m if r else math.nan,
                "wet_peak_after_s": r.wet_peak_s - m.face_s if r else math.nan}
        for i, d in enumerate(AFTER_ARRIVAL_S):
            row[f"elevation_at_{d:g}s_m"] = r.elevation_after_m[i] if r else math.nan
            row[f"wet_at_{d:g}s_m"] = r.wet_after_m[i] if r else math.nan
        for reach in f.reaches:
            row[f"speed_{reach.x0_m:g}_{reach.x1_m:g}_m_s"] = reach.speed_m_s
            row[f"uncertainty_{reach.x0_m:g}_{reach.x1_m:g}_m_s"] = reach.uncertainty_m_s
        row["reach_verdict"] = reach_verdict(list(f.reaches))
        rows.append(row)
    return pd.DataFrame(rows)
