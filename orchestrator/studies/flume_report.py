"""The flume as built: every member of a sweep over the gate's sill, opening and opening time, the
wet bed's depth and the column's position (``cases/sweeps/flume-as-built.yaml``), its arrivals at WG2 and WG3 and
at the column's face against the measured ones and against the first member (the scene as
shipped), with the front's speed between the gauges.

Arrivals are the post-processor's (``results/gauge_summary.csv``: the first rise of the level above
its start by the gauge's threshold); the measured ones are the study's (``SEED_ARRIVALS``).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from pathlib import Path

import pandas as pd
import yaml

from orchestrator.core.errors import InputError
from analytical.study import SEED_ARRIVALS

__all__ = ["FlumeMember", "flume_members", "write_flume_report"]

#: The study's gauges this page reads, by name: (x m, measured arrival s).
MEASURED = {name: (x, measured) for x, (name, measured, _model) in SEED_ARRIVALS.items()}
#: The gauge at the column's upstream face in the shipped scenes.
FACE_GAUGE = "WG4"


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
    scene = yaml.safe_load((case / "scene.yaml").read_text())
    table = pd.read_csv(summary).set_index("gauge")
    for name in ("WG2", "WG3", FACE_GAUGE):
        if name not in table.index:
            raise InputError(str(summary), f"has no gauge {name}: the page reads WG2, WG3 and {FACE_GAUGE}")
    arrival = {name: float(table.loc[name, "arrival_s"]) for name in ("WG2", "WG3", FACE_GAUGE)}
    res, summary_json = scene["reservoir"], case / "results" / "summary.json"
    wall = math.nan
    if summary_json.is_file():
        import json

        wall = float((json.loads(summary_json.read_text()).get("wall_time_s") or {}).get("solver_s") or math.nan)
    return FlumeMember(
        member=case.name, sill_height_m=float(res.get("sill_height_m") or 0.0), depth_m=float(res["depth_m"]),
        opening_width_m=None if res.get("opening_width_m") is None else float(res["opening_width_m"]),
        wet_depth_m=float(scene["bed"]["wet_depth_m"]),
        column_x_m=float(scene["column"]["x_m"]) if scene.get("column") else math.nan,
        face_x_m=float(table.loc[FACE_GAUGE, "x_m"]), wg2_s=arrival["WG2"], wg3_s=arrival["WG3"],
        face_s=arrival[FACE_GAUGE], solver_wall_s=wall, opening_time_s=float(res.get("opening_time_s") or 0.0))


def flume_members(sweep_dir: str | Path) -> list[FlumeMember]:
    """The post-processed members of the sweep, in the sweep file's order when its store lists it."""
    sweep = Path(sweep_dir)
    cases = [p.parent.parent for p in sweep.glob("*/results/gauge_summary.csv")]
    if not cases:
        raise InputError(str(sweep), "holds no post-processed member (no */results/gauge_summary.csv)")
    order = _sweep_order(sweep)
    cases.sort(key=lambda c: (order.get(c.name, len(order)), c.name))
    return [_member(c) for c in cases]


def _sweep_order(sweep: Path) -> dict[str, int]:
    """Member id -> its index in the sweep (results.sqlite's members table), when the store is there."""
    store = sweep / "results.sqlite"
    if not store.is_file():
        return {}
    import sqlite3

    with sqlite3.connect(store) as db:
        cols = {row[1] for row in db.execute("PRAGMA table_info(members)")}
        rows = db.execute("SELECT member_id, member FROM members").fetchall() if {"member", "member_id"} <= cols else []
    return {str(i): int(k) for i, k in rows}


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
    return "; ".join(parts) or "the scene as shipped"


def _fmt(value: float, spec: str = ".3f", signed: bool = False) -> str:
    if not math.isfinite(value):
        return "-"
    return format(value, ("+" if signed else "") + spec)


def _plot(members: list[FlumeMember], out: Path) -> str:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7.5, 4.2))
    base = members[0]
    for m in members:
        ax.plot([MEASURED["WG2"][0], MEASURED["WG3"][0], m.face_x_m], [m.wg2_s, m.wg3_s, m.face_s], "o-", lw=1,
                ms=3, label=_change(m, base))
    ax.plot([v[0] for v in MEASURED.values()], [v[1] for v in MEASURED.values()], "ks", ms=8, label="measured")
    ax.set_xlabel("x past the gate (m)")
    ax.set_ylabel("front arrival (s)")
    ax.legend(fontsize=6.5, loc="upper left")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    name = "arrivals.png"
    fig.savefig(out / name, dpi=100)
    plt.close(fig)
    return name


#: The make target that writes each shipped sweep's page.
_MAKE_TARGETS = {"flume-as-built": "flume-as-built", "flume-centreline-2d": "flume-2d"}


def _setting(case: Path) -> str:
    """What every member shares, from the first member's scene: its name, closure, cells and end time."""
    scene = yaml.safe_load((case / "scene.yaml").read_text())
    closure = (scene.get("fluids") or {}).get("turbulence", "laminar")
    width = float(scene.get("flume", {}).get("width_m", math.nan))
    column = "no column" if not scene.get("column") else "the column"
    return (f"the scene `{scene.get('name')}` ({closure}, {float(scene['mesh']['cell_size_m']) * 100:g} cm cells, "
            f"a {width:g} m wide flume, {column}, {float(scene['run']['end_time_s']):g} s)")


def write_flume_report(sweep_dir: str | Path, out_dir: str | Path) -> dict[str, Path]:
    """report.md, flume.csv and arrivals.png in ``out_dir``."""
    members = flume_members(sweep_dir)
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    rows = [{**asdict(m), "speed_wg2_wg3_m_s": m.speed_wg2_wg3_m_s, "speed_wg3_face_m_s": m.speed_wg3_face_m_s}
            for m in members]
    pd.DataFrame(rows).to_csv(out / "flume.csv", index=False)
    figure = _plot(members, out)
    base = members[0]
    (x2, t2), (x3, t3) = MEASURED["WG2"], MEASURED["WG3"]
    sweep = Path(sweep_dir).resolve()
    lines = [
        "# The flume as built: the gate's sill, opening and opening time, the wet bed, the column's position",
        "",
        f"Generated by `debrisfoam sweep cases/sweeps/{sweep.name}.yaml`, then `debrisfoam report flume` "
        f"(`make {_MAKE_TARGETS.get(sweep.name, 'sweep')}`): {_setting(Path(sweep_dir) / base.member)}, "
        "one change at a time from the sweep's first member (the first row). The sizes are assumed: the study "
        "names the false floor acting as a sill and the gate's support columns but gives neither's size "
        "(the sweep file says what each value stands for). Arrivals: the first rise of each gauge's level by "
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
    (out / "report.md").write_text("\n".join(lines))
    return {"report": out / "report.md", "table": out / "flume.csv", "figure": out / figure}
