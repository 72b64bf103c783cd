"""`debrisfoam report scale LAB PROTOTYPE -o DIR`: a scene and its Froude-scaled twin, side by side.

LAB and PROTOTYPE are post-processed run folders of the same scene at two scales (``make
prototype-1debris``: cases/1debris.yaml and cases/prototype-1debris.yaml, 40:1). The scale
lambda is the ratio of their impoundments; the column's position, the flume's width and the mesh's
finest cell must be in the same ratio (else InputError). Each figure of the lab run is scaled by
Froude similarity (lengths x lambda, times and speeds x sqrt(lambda), forces x lambda^3, impulses
x lambda^3.5) and set beside the prototype's: a flow that obeys Froude similarity gives the same
numbers. DIR receives ``report.md`` (the page), ``comparison.csv`` (its table) and ``gauges.png``
(the gauges' elevations, the lab's Froude-scaled over the prototype's).

Arrival times and the first strike's speed carry the issue's target (within :data:`TARGET`);
the other rows say how far the rest follows.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import pandas as pd

from orchestrator.case.folder import CaseFolder
from orchestrator.core.errors import InputError
from orchestrator.core.files import write_text_atomic
from orchestrator.report.figures import pyplot, save_figure
from orchestrator.results.tables import write_table
from orchestrator.studies.speed_error import solver_cpu_s

__all__ = ["TARGET", "ScaleComparison", "compare_scales", "write_scale_report"]

#: Largest relative difference allowed on bore arrivals and the first strike's speed.
TARGET = 0.05
#: Columns of comparison.csv.
COLUMNS = ("quantity", "unit", "exponent", "lab", "lab_scaled", "prototype", "difference_percent", "target_percent")


@dataclass
class ScaleComparison:
    """The two runs, the scale, and the table of figures."""

    lab: Path
    prototype: Path
    scale: float
    table: pd.DataFrame
    lab_gauges: pd.DataFrame | None
    prototype_gauges: pd.DataFrame | None
    notes: list[str]
    name: str = "the scene"

    def within_target(self) -> bool:
        rows = self.table[self.table["target_percent"].notna()]
        return bool(len(rows)) and bool((rows["difference_percent"].abs() <= rows["target_percent"]).all())


def _csv(path: Path, *columns: str) -> pd.DataFrame | None:
    """The table at ``path`` (None if there is none), with at least ``columns``."""
    try:
        table = pd.read_csv(path) if path.is_file() else None
    except (ValueError, pd.errors.ParserError) as exc:  # EmptyDataError is a ValueError
        raise InputError(path.name, f"not a table ({exc}): post-process the run again", str(path.parent)) from None
    missing = [c for c in columns if table is not None and c not in table.columns]
    if missing:
        raise InputError(path.name, f"no column {', '.join(map(repr, missing))} (it has {', '.join(table.columns)}): "
                         "not the table `debrisfoam post` writes; post-process the run again", str(path.parent))
    return table


def _scale(lab_dir: Path, proto_dir: Path) -> float:
    lab, proto = (CaseFolder(d).scene() for d in (lab_dir, proto_dir))
    scale = proto.reservoir.depth_m / lab.reservoir.depth_m
    pairs = {"flume.width_m": (lab.flume.width_m, proto.flume.width_m),
             "mesh.cell_size_m": (lab.mesh.cell_size_m, proto.mesh.cell_size_m)}
    if lab.column is not None and proto.column is not None:
        pairs["column.x_m"] = (lab.column.x_m, proto.column.x_m)
    for field, (a, b) in pairs.items():
        if not math.isclose(b / a, scale, rel_tol=1e-3):
            raise InputError(field, f"{b:g} is {b / a:.4g} x the lab's {a:g}, not the impoundments' ratio {scale:.4g}: "
                             "the two runs are not one scene at two scales", str(proto_dir))
    return scale


def _row(quantity: str, unit: str, exponent: float, lab: float | None, proto: float | None, scale: float,
         target: bool = False) -> dict:
    scaled = None if lab is None or not math.isfinite(lab) else lab * scale ** exponent
    diff = None
    if scaled is not None and proto is not None and math.isfinite(proto) and scaled != 0:
        diff = 100.0 * (proto - scaled) / abs(scaled)
    return {"quantity": quantity, "unit": unit, "exponent": exponent, "lab": lab, "lab_scaled": scaled,
            "prototype": proto, "difference_percent": diff, "target_percent": 100 * TARGET if target else None}


def _first_strike(impacts: pd.DataFrame | None) -> dict:
    if impacts is None or impacts.empty:
        return {}
    column = impacts[impacts["kind"] == "column"].sort_values("time_s")
    return column.iloc[0].to_dict() if len(column) else {}


def _value(record: dict | pd.Series, key: str) -> float | None:
    v = record.get(key) if record is not None else None
    return None if v is None or (isinstance(v, float) and math.isnan(v)) else float(v)


def compare_scales(lab_dir: str | Path, proto_dir: str | Path) -> ScaleComparison:
    """Read both post-processed runs and build the table (module notes)."""
    lab_dir, proto_dir = Path(lab_dir), Path(proto_dir)
    for d, name in ((lab_dir, "lab"), (proto_dir, "prototype")):
        if not (CaseFolder(d).results_dir / "gauge_summary.csv").is_file():
            raise InputError(name, f"no results/gauge_summary.csv: run `debrisfoam post {d}` first", str(d))
    scale = _scale(lab_dir, proto_dir)
    res = {k: CaseFolder(d).results_dir for k, d in (("lab", lab_dir), ("proto", proto_dir))}
    summary = {k: _csv(r / "gauge_summary.csv", "gauge").set_index("gauge") for k, r in res.items()}
    rows = []
    for gauge in summary["lab"].index:
        lab_g, proto_g = summary["lab"].loc[gauge], summary["proto"].loc[gauge] if gauge in summary["proto"].index else {}
        if _value(lab_g, "arrival_s") is not None:
            rows.append(_row(f"{gauge} bore arrival", "s", 0.5, _value(lab_g, "arrival_s"),
                             _value(proto_g, "arrival_s"), scale, target=True))
        rows.append(_row(f"{gauge} peak elevation", "m", 1.0, _value(lab_g, "peak_elevation_m"),
                         _value(proto_g, "peak_elevation_m"), scale))
    strikes = {k: _first_strike(_csv(r / "impacts.csv", "kind", "time_s")) for k, r in res.items()}
    a, b = strikes["lab"], strikes["proto"]
    rows += [
        _row("first strike time", "s", 0.5, _value(a, "time_s"), _value(b, "time_s"), scale),
        _row("first-strike speed (centre of mass)", "m/s", 0.5, _value(a, "impact_speed_m_s"),
             _value(b, "impact_speed_m_s"), scale, target=True),
        _row("first-strike speed along the normal", "m/s", 0.5, _value(a, "impact_velocity_m_s"),
             _value(b, "impact_velocity_m_s"), scale),
        _row("first strike height", "m", 1.0, _value(a, "height_m"), _value(b, "height_m"), scale),
        _row("first strike peak force", "N", 3.0, _value(a, "peak_force_N"), _value(b, "peak_force_N"), scale),
        _row("first strike duration", "s", 0.5, _value(a, "duration_s"), _value(b, "duration_s"), scale),
        _row("first strike impulse", "N s", 3.5, _value(a, "impulse_Ns"), _value(b, "impulse_Ns"), scale),
    ]
    forces = {k: _csv(r / "column_forces.csv", "hydro_force_x_N") for k, r in res.items()}
    peak = {k: (float(f["hydro_force_x_N"].max()) if f is not None and len(f) else None) for k, f in forces.items()}
    rows.append(_row("peak hydrodynamic force on the column", "N", 3.0, peak["lab"], peak["proto"], scale))
    impacts = {k: _csv(r / "impacts.csv", "kind") for k, r in res.items()}
    n = {k: (0 if f is None else int((f["kind"] == "column").sum())) for k, f in impacts.items()}
    rows.append(_row("column strikes", "-", 0.0, float(n["lab"]), float(n["proto"]), scale))
    runs = {k: CaseFolder(d).run_state() for k, d in (("lab", lab_dir), ("proto", proto_dir))}
    steps = {k: r.time_steps for k, r in runs.items()}
    rows.append(_row("solver time steps", "-", 0.0, steps["lab"], steps["proto"], scale))
    cpu = {k: solver_cpu_s(d) for k, d in (("lab", lab_dir), ("proto", proto_dir))}
    rows.append(_row("solver CPU time (master rank; cost, not physics)", "s", 0.0, cpu["lab"], cpu["proto"], scale))
    table = pd.DataFrame(rows, columns=list(COLUMNS))
    notes = _notes(lab_dir, scale)
    name = CaseFolder(lab_dir).scene().name
    return ScaleComparison(lab_dir, proto_dir, scale, table, _csv(res["lab"] / "gauges.csv", "time_s"),
                           _csv(res["proto"] / "gauges.csv", "time_s"), notes, name)


def _notes(lab_dir: Path, scale: float) -> list[str]:
    """What Froude similarity leaves out, with its numbers."""
    scene = CaseFolder(lab_dir).scene()
    g, h0, nu = scene.fluids.gravity_m_s2, scene.reservoir.depth_m, scene.fluids.water_viscosity_m2_s
    re_lab = math.sqrt(g * h0) * h0 / nu
    re_proto = re_lab * scale ** 1.5
    blasius = scale ** -0.375  # f ~ Re^-1/4 (Blasius), Re ~ lambda^1.5
    we_lab = scene.fluids.water_density_kg_m3 * g * h0 * h0 / max(scene.fluids.surface_tension_N_m, 1e-300)
    return [
        f"Reynolds number sqrt(g h0) h0 / nu: {re_lab:.3g} in the lab, {re_proto:.3g} at prototype scale "
        f"(x {scale ** 1.5:.0f}). The bed's Darcy f is kept at {scene.bed.friction_factor:g}: the assumption is a bed "
        "rough enough that f does not depend on the Reynolds number (fully rough turbulent flow). On a smooth bed "
        f"f would fall as Re^-1/4 (Blasius), to {blasius:.2f} of the lab's, {scene.bed.friction_factor * blasius:.4f}.",
        "The solver is laminar: the viscous stress at the bed and the column, a small part of the drag in the lab, "
        f"is {scale ** 1.5:.0f} times smaller relative to inertia at prototype scale; the rows above measure what "
        "that and the bed drag together change.",
        f"Weber number rho g h0^2 / sigma: {we_lab:.3g} in the lab, {we_lab * scale ** 2:.3g} at prototype scale: "
        "surface tension matters at neither.",
        "The contact law scales when its stiffness does (x lambda^2, the prototype scene's contact.stiffness_N_m) "
        "with the damping ratio kept; forces then scale as lambda^3 and durations as sqrt(lambda).",
    ]


def _plot(cmp: ScaleComparison, path: Path) -> Path:
    plt = pyplot()
    names = [c[: -len("_elevation_m")] for c in (cmp.lab_gauges.columns if cmp.lab_gauges is not None else [])
             if c.endswith("_elevation_m")]
    fig, axes = plt.subplots(len(names) or 1, 1, figsize=(7.5, 1.9 * max(len(names), 1)), sharex=True, squeeze=False)
    r = math.sqrt(cmp.scale)
    for ax, name in zip(axes[:, 0], names):
        col = f"{name}_elevation_m"
        ax.plot(cmp.lab_gauges["time_s"] * r, cmp.lab_gauges[col] * cmp.scale, lw=2.2, color="0.65",
                label=f"lab x {cmp.scale:g} (time x {r:.3g})")
        if cmp.prototype_gauges is not None and col in cmp.prototype_gauges:
            ax.plot(cmp.prototype_gauges["time_s"], cmp.prototype_gauges[col], lw=1.0, color="C0", label="prototype")
        ax.set_ylabel(f"{name} (m)")
        ax.grid(alpha=0.3)
    axes[0, 0].legend(loc="upper left", fontsize=8)
    axes[-1, 0].set_xlabel("time from the gate's release, prototype scale (s)")
    fig.suptitle("water surface elevation at the gauges: the lab run Froude-scaled and the prototype run", fontsize=10)
    fig.tight_layout()
    return save_figure(fig, path)


def _fmt(v) -> str:
    if v is None or (isinstance(v, float) and not math.isfinite(v)):
        return "-"
    return f"{v:.4g}"


def markdown(cmp: ScaleComparison) -> str:
    t = cmp.table
    lines = [
        f"# {cmp.name} at {cmp.scale:g}:1 against the lab run, Froude-scaled", "",
        "Written by `debrisfoam report scale` (`make prototype-1debris`), never by hand. Lab run: "
        f"`{cmp.lab}`; prototype run: `{cmp.prototype}`. Each lab figure is multiplied by lambda^exponent "
        f"(lambda = {cmp.scale:g}: lengths 1, times and speeds 1/2, forces 3, impulses 3.5) and set beside "
        f"the prototype's. Target: bore arrivals and the first strike's speed within {100 * TARGET:g} %.", "",
        f"**Within the target: {'yes' if cmp.within_target() else 'no'}.**", "",
        "| quantity | unit | exponent | lab | lab scaled | prototype | difference (%) | target (%) |",
        "|---|---|---:|---:|---:|---:|---:|---:|",
    ]
    for row in t.to_dict("records"):
        lines.append(f"| {row['quantity']} | {row['unit']} | {row['exponent']:g} | {_fmt(row['lab'])} | "
                     f"{_fmt(row['lab_scaled'])} | {_fmt(row['prototype'])} | {_fmt(row['difference_percent'])} | "
                     f"{_fmt(row['target_percent'])} |")
    lines += ["", "![gauges](gauges.png)", "", "## What does not scale", ""]
    lines += [f"- {n}" for n in cmp.notes]
    return "\n".join(lines) + "\n"


def write_scale_report(cmp: ScaleComparison, out: str | Path) -> dict[str, Path]:
    """report.md, comparison.csv and gauges.png in ``out``."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    files = {"table": write_table(cmp.table, out / "comparison.csv"), "figure": _plot(cmp, out / "gauges.png")}
    files["report"] = write_text_atomic(out / "report.md", markdown(cmp))
    return files
