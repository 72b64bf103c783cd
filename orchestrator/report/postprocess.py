"""Post-processing a run: what the solver and the runner wrote -> tidy tables in DIR/results/,
then the comparisons, the plots and report.md beside them.

:func:`post_case` reads whatever a case holds (a run stopped early, a run without debris or
without contacts is post-processed up to where it got; what is missing is listed in
``summary.json`` and the report, never crashed on) and writes, in ``DIR/results/``:

``gauges.csv``
    ``time_s`` and one ``<gauge>_elevation_m`` column per gauge: the water height on the
    gauge's vertical ``sets`` line, ``integral of alpha.water dz`` from the bed to the top of
    the line (see :func:`orchestrator.results.metrics.gauge_elevation`). Empty (NaN) where the
    line was obstructed.
``gauge_summary.csv``
    One row per gauge: position, initial level, arrival threshold, bore arrival time, peak
    elevation and its time, samples and obstructed samples.
``column_forces.csv``
    ``time_s``; the hydrodynamic force on the column from the ``forces`` function object,
    ``hydro_force_{x,y,z}_N`` (= ``pressure_force_*`` + ``viscous_force_*``) and its moment
    about the column's base ``hydro_moment_{x,y,z}_Nm``; the impact pulses of the contact
    events on the column ``impact_force_{x,y,z}_N``; their sum ``total_force_{x,y,z}_N``.
    One time axis: the solver's steps plus every sample of every impact pulse.
``bodies.csv``
    One row per body per solver step: ``time_s, body``, centre of mass ``x_m y_m z_m``,
    velocity ``u_m_s v_m_s w_m_s``, ``speed_m_s``, angular velocity ``omega_{x,y,z}_rad_s``,
    orientation as ``yaw_deg pitch_deg roll_deg`` (intrinsic z-y'-x'', as scenes give it) and
    as the rotation matrix ``q_xx .. q_zz`` (body axes -> scene axes, row-major).
``impacts.csv``
    One row per contact event that was an impact (see :data:`orchestrator.results.impact_table.IMPACT_COLUMNS`): where
    (``height_m``, the contact point's height on the column), the water level at the column's
    face at that moment (``face_water_level_m``, the study's definition of impact height),
    the body's lowest point above the bed and whether it was ``afloat``, the contact law's pulse;
    then the centre's speed (``impact_speed_m_s``) and, for a column strike, its base shear fitted
    as the study fitted its records (``study_fit_*``: a half-sine on the MDOF column loaded at
    the water level at the face, :mod:`orchestrator.results.study_fit`).
``column_response.csv``
    The total load on the column's MDOF model and the base shear at the load cell it causes
    (the quantity the study's experiments measured), split into its hydrodynamic and impact
    parts (see :func:`orchestrator.results.metrics.column_response`).
``water_balance.csv``
    Per solver step, the water volume in the fluid mesh, the water leaving through the open
    boundaries (in all and through each: the outlet's, and the atmosphere's over the top of
    the air space) and the balance error (:func:`orchestrator.case.outputs.read_water_balance`): the conservation
    check. Water leaving over the top passing
    :data:`orchestrator.case.outputs.ATMOSPHERE_LOSS_WARNING` of the initial
    water is a warning (stderr, summary.json's ``missing``, the report).
``fringe_flux.csv``
    Overset runs: per reconstructed time and overset zone (0: the background), the cell
    counts and the net water and volume flux into the fringe cells
    (:mod:`orchestrator.results.fringe`): where the overset loses or makes water.
``summary.json``
    The headline figures, the run's status, wall time and cell count, what is missing.

With ``comparisons=True`` (the default) :func:`post_case` then writes the comparisons with
the analytical models and the study (:mod:`orchestrator.results.compare`), the plots
(:mod:`orchestrator.report.plots`) and ``report.md`` (:mod:`orchestrator.report.markdown`) beside them.

The tables are built in memory by :func:`orchestrator.results.tables.tables` and the headline
figures by :func:`orchestrator.results.headline.headline`; this module writes them, and sits
in the report stage because it then draws the plots and writes the report.
"""

from __future__ import annotations

import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from orchestrator.core.errors import InputError
from orchestrator.case.folder import CaseFolder
from orchestrator.report import markdown, plots
from orchestrator.results import compare
from orchestrator.results.headline import headline
from orchestrator.results.tables import Results, atmosphere_warning, tables, write_table

__all__ = ["PostSummary", "TABLE_FILES", "post_case"]

#: The tables post_case writes (name -> file), in order; water_balance and fringe_flux only
#: when the run has them.
TABLE_FILES = {
    "gauges": "gauges.csv",
    "gauge_summary": "gauge_summary.csv",
    "column_forces": "column_forces.csv",
    "bodies": "bodies.csv",
    "impacts": "impacts.csv",
    "column_response": "column_response.csv",
    "water_balance": "water_balance.csv",
    "fringe_flux": "fringe_flux.csv",
}


@dataclass(frozen=True)
class PostSummary:
    """What :func:`post_case` wrote. Times in s; ``headline`` holds the figures of summary.json."""

    case: Path
    results_dir: Path
    status: str
    reached_time_s: float | None
    end_time_s: float | None
    tables: dict[str, Path]
    plots: dict[str, Path]
    report: Path | None
    missing: tuple[str, ...]
    headline: dict[str, Any]

    def to_dict(self) -> dict[str, Any]:
        return {
            "case": str(self.case),
            "results_dir": str(self.results_dir),
            "status": self.status,
            "reached_time_s": self.reached_time_s,
            "end_time_s": self.end_time_s,
            "tables": {k: str(v) for k, v in self.tables.items()},
            "plots": {k: str(v) for k, v in self.plots.items()},
            "report": str(self.report) if self.report else None,
            "missing": list(self.missing),
            "headline": self.headline,
        }


def post_case(case_dir: str | Path, *, comparisons: bool = True, snapshot: bool = True,
              arrival_threshold_m: float | None = None) -> PostSummary:
    """Post-process a case into ``DIR/results/`` (see the module docstring); returns what was written.

    comparisons: also the comparisons with the analytical models and the study, the plots
    and report.md. snapshot: include the pyvista 3D snapshot (needs fields on disk).
    arrival_threshold_m: rise above the initial level that marks the bore's arrival
    (default :data:`orchestrator.results.metrics.ARRIVAL_FRACTION` of the impoundment depth).

    Raises InputError when ``case_dir`` is not a case, or is one that has never run (nothing to
    post-process: a report of it would be hollow).
    """
    rendered = CaseFolder(case_dir)
    if rendered.path.is_dir() and rendered.is_case() and not rendered.has_run():
        raise InputError("case_dir", f"this case has not run: run `debrisfoam run {case_dir}` first", str(case_dir))
    results = tables(case_dir, arrival_threshold_m)
    data = results.data
    warning = atmosphere_warning(data, results.water_balance)
    if warning:
        print(f"debrisfoam: warning: {data.case}: {warning}", file=sys.stderr)
    folder = CaseFolder(data.case)
    out_dir = folder.results_dir
    out_dir.mkdir(exist_ok=True)
    written = _write_tables(results, out_dir)
    figures = headline(results)
    drawn: dict[str, Path] = {}
    report_path = None
    if comparisons:
        drawn, report_path = _compare_and_report(results, figures, written, out_dir, snapshot)
    figures["missing"] = list(dict.fromkeys(results.missing))
    figures["tables"] = {k: p.name for k, p in written.items()}
    figures["plots"] = {k: p.name for k, p in drawn.items()}
    written["summary"] = folder.write_summary(figures)
    return PostSummary(data.case, out_dir, figures["status"], figures["reached_time_s"], figures["end_time_s"],
                       written, drawn, report_path, tuple(figures["missing"]), figures)


def _write_tables(results: Results, out_dir: Path) -> dict[str, Path]:
    """Every table of :data:`TABLE_FILES` the run has, as CSV in out_dir."""
    frames = {
        "gauges": results.gauges,
        "gauge_summary": results.gauge_summary,
        "column_forces": results.column_forces,
        "bodies": results.bodies,
        "impacts": results.impacts,
        "column_response": results.column_response,
        "water_balance": results.water_balance,
        "fringe_flux": results.fringe_flux,
    }
    return {name: write_table(frame, out_dir / TABLE_FILES[name]) for name, frame in frames.items()
            if frame is not None}


def _compare_and_report(results: Results, figures: dict[str, Any], written: dict[str, Path], out_dir: Path,
                        snapshot: bool) -> tuple[dict[str, Path], Path]:
    """The comparisons' tables (added to ``written``) and headline (to ``figures``), the plots
    and report.md; returns (plots, report.md)."""
    comp = compare.compare(results)
    written.update(compare.write_tables(comp, out_dir))
    figures["comparisons"] = comp.headline()
    drawn, plot_notes = plots.make_plots(results, comp, out_dir, snapshot_3d=snapshot)
    results.missing.extend(comp.notes)
    results.missing.extend(plot_notes)
    report_path = markdown.write_report(results, comp, figures, written, drawn, out_dir / "report.md")
    return drawn, report_path
