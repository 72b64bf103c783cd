"""The plots as a report carries them: size, text inside the figure and big enough, legends.

Drawn from the committed real cases under tests/data/post/ (see its README.md) and from
comparisons derived from them (four impacts, a failed fit), without OpenFOAM. What a reader
would otherwise have to see: every PNG at most about 1,600 px wide, no text cut at the
figure's edge or smaller than 9 pt, every drawn line named in a legend, the hydrodynamic
force on an axis of its own scale, and every pulse drawn whole.
"""

from __future__ import annotations

import copy
import shutil
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from PIL import Image

from orchestrator.report import plots
from orchestrator.report.figures import DPI, pyplot
from orchestrator.results.tables import tables
from orchestrator.results.compare import compare

DATA = Path(__file__).parent / "data" / "post"
MAX_WIDTH_PX, MAX_HEIGHT_PX = 1600, 2000
MIN_FONT_PT = 9.0
FIGURES = ("gauges", "column_forces", "impacts", "study_fits", "tracks")


# --------------------------------------------------------------------------- checks


def texts_outside(fig) -> list[str]:
    """Every text, axes (with its tick labels) and legend that reaches past the figure's edge."""
    from matplotlib.legend import Legend

    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    box = fig.bbox

    def out(extent) -> bool:
        return (extent.x0 < box.x0 - 1 or extent.x1 > box.x1 + 1 or extent.y0 < box.y0 - 1
                or extent.y1 > box.y1 + 1)

    bad = []
    for ax in fig.axes:
        if not ax.get_visible():
            continue
        name = ax.get_title(loc="left") or ax.get_title() or ax.get_label()
        texts = [ax.title, ax._left_title, ax._right_title, ax.xaxis.label, ax.yaxis.label, *ax.texts]
        for t in texts:
            if t.get_visible() and t.get_text().strip() and out(t.get_window_extent(renderer)):
                bad.append(f"{name!r}: text {t.get_text()!r}")
        if ax.axison and out(ax.get_tightbbox(renderer)):
            bad.append(f"axes {name!r} with its tick labels")
    for t in fig.texts:
        if t.get_visible() and t.get_text().strip() and out(t.get_window_extent(renderer)):
            bad.append(f"figure text {t.get_text()!r}")
    for legend in fig.findobj(Legend):
        if legend.get_visible() and out(legend.get_window_extent(renderer)):
            bad.append(f"legend {[t.get_text() for t in legend.get_texts()]}")
    return bad


def small_texts(fig) -> list[str]:
    from matplotlib.text import Text

    return [f"{t.get_text()!r} at {t.get_fontsize():g} pt" for t in fig.findobj(Text)
            if t.get_visible() and t.get_text().strip() and t.get_fontsize() < MIN_FONT_PT]


def unlisted(fig) -> list[str]:
    """Labels of lines (every one) and of labelled patches and collections that no legend shows."""
    from matplotlib.legend import Legend

    listed = {t.get_text() for legend in fig.findobj(Legend) for t in legend.get_texts()}
    missing = []
    for ax in fig.axes:
        for line in ax.lines:
            if line.get_label().startswith("_") or line.get_label() not in listed:
                missing.append(f"line {line.get_label()!r} in {ax.get_title(loc='left')!r}")
        for artist in [*ax.patches, *ax.collections]:
            label = artist.get_label()
            if label and not label.startswith("_") and label not in listed:
                missing.append(f"{type(artist).__name__} {label!r} in {ax.get_title(loc='left')!r}")
    return missing


def check_figure(fig, dpi: float = DPI) -> None:
    width, height = fig.get_size_inches() * dpi
    assert width <= MAX_WIDTH_PX and height <= MAX_HEIGHT_PX, f"{width:.0f} x {height:.0f} px"
    assert not texts_outside(fig), texts_outside(fig)
    assert not small_texts(fig), small_texts(fig)
    assert not unlisted(fig), unlisted(fig)


def pulse_axes(fig) -> list:
    return [ax for ax in fig.axes if ax.get_ylabel() == "impact force (N)"]


def check_pulses_whole(fig) -> None:
    """Every pulse starts and ends at zero force inside its panel: none is cut at an edge."""
    for ax in pulse_axes(fig):
        lo, hi = ax.get_xlim()
        for line in ax.lines:
            x, y = np.asarray(line.get_xdata(), float), np.asarray(line.get_ydata(), float)
            assert lo <= x.min() + 1e-9 and x.max() <= hi + 1e-9
            assert abs(y[0]) < 1e-6 * max(1.0, np.abs(y).max()), f"{line.get_label()} cut at the left edge"
            assert abs(y[-1]) < 1e-6 * max(1.0, np.abs(y).max()), f"{line.get_label()} cut at the right edge"


# --------------------------------------------------------------------------- data


@pytest.fixture(scope="module")
def real() -> dict[str, tuple]:
    """(results, comparison) of each committed case, and of a bare case with no outputs."""
    out = {name: tables(DATA / name) for name in ("tiny-1debris", "tiny-nodebris", "tiny-nodebris-stopped")}
    return {name: (res, compare(res)) for name, res in out.items()}


@pytest.fixture(scope="module")
def bare(tmp_path_factory):
    case = tmp_path_factory.mktemp("bare")
    shutil.copy(DATA / "tiny-1debris/plan.json", case)
    res = tables(case)
    return res, compare(res)


def _four_impacts(comp):
    """The one real impact as four events, the third with its MDOF fit failed."""
    comp = copy.deepcopy(comp)
    (event, rec), = comp.fit_records.items()
    rows = comp.impact_formulas[comp.impact_formulas["event"] == event]
    formulas = []
    for k in range(4):
        comp.fit_records[event + k] = copy.deepcopy(rec)
        formulas.append(rows.assign(event=event + k, impact_velocity_m_s=rows["impact_velocity_m_s"] * (1 + 0.1 * k)))
    comp.impact_formulas = pd.concat(formulas, ignore_index=True)
    del comp.fit_records[event + 2]["pulses"]["MDOF fit"]
    comp.fit_records[event + 2]["mdof_N"] = None
    comp.notes.append(f"impact event {event + 2}: the MDOF fit failed (no convergence in 200 iterations)")
    return comp


# --------------------------------------------------------------------------- every figure


@pytest.mark.parametrize("case", ["tiny-1debris", "tiny-nodebris", "tiny-nodebris-stopped"])
@pytest.mark.parametrize("name", FIGURES)
def test_every_figure_fits_a_report(real, case, name):
    _check_built(name, *real[case])


@pytest.mark.parametrize("name", FIGURES)
def test_a_case_without_outputs_still_gets_readable_figures(bare, name):
    _check_built(name, *bare)


def _check_built(name, results, comp):
    """Build figure ``name`` of the case and check it fits a report."""
    builder = getattr(plots, f"figure_{name}")
    fig = builder(results) if name == "column_forces" else builder(results, comp)
    try:
        check_figure(fig)
    finally:
        pyplot().close(fig)


def test_the_written_pngs_are_report_sized(real, tmp_path):
    results, comp = real["tiny-1debris"]
    written, _ = plots.make_plots(results, comp, tmp_path, snapshot_3d=False)
    for name, path in written.items():
        with Image.open(path) as img:
            width, height = img.size
        assert 800 <= width <= MAX_WIDTH_PX and 400 <= height <= MAX_HEIGHT_PX, f"{name}: {img.size}"


# --------------------------------------------------------------------------- column forces


def _water_load(results, low_N: float = 25.0, high_N: float = 50.0):
    """The run with a hydrodynamic force of a full-size flume's bore (25-50 N, rising)."""
    results = copy.copy(results)
    cf = results.column_forces.copy()
    ramp = np.linspace(0.0, 1.0, len(cf))
    cf["pressure_force_x_N"] = low_N + (high_N - low_N) * ramp
    cf["viscous_force_x_N"] = 0.01 * cf["pressure_force_x_N"]
    cf["hydro_force_x_N"] = cf["pressure_force_x_N"] + cf["viscous_force_x_N"]
    cf["total_force_x_N"] = cf["hydro_force_x_N"] + cf["impact_force_x_N"]
    results.column_forces = cf
    return results


@pytest.mark.parametrize("load", ["as run", "25-50 N"])
def test_the_hydrodynamic_force_has_an_axis_of_its_own_scale(real, load):
    """The CFD force (well under 1 N in this run, or 25-50 N as in a full-size flume) beside an
    impact of 520 N: its panel's y range is linear and set by the hydrodynamic force alone, so
    the force fills at least a quarter of it."""
    results, _ = real["tiny-1debris"]
    if load != "as run":
        results = _water_load(results)
    hydro = results.column_forces["hydro_force_x_N"].dropna()
    assert results.column_forces["impact_force_x_N"].max() > 10 * hydro.abs().max()
    fig = plots.figure_column_forces(results)
    try:
        ax, = [a for a in fig.axes if a.get_label() == "hydrodynamic force"]
        lo, hi = ax.get_ylim()
        assert ax.get_yscale() == "linear"
        assert lo <= hydro.min() and hydro.max() <= hi
        assert (hydro.max() - hydro.min()) / (hi - lo) > 0.25, (lo, hi)
        pulses = [a for a in fig.axes if any("impact pulses" in line.get_label() for line in a.lines)]
        assert pulses and pulses[0] is not ax and pulses[0].get_ylim()[1] >= results.column_forces[
            "impact_force_x_N"].max()
    finally:
        pyplot().close(fig)


# --------------------------------------------------------------------------- impacts


def test_impact_pulses_are_whole_and_the_fits_stand_apart(real):
    results, comp = real["tiny-1debris"]
    fig = plots.figure_impacts(results, comp)
    try:
        check_figure(fig)
        check_pulses_whole(fig)
        axes = pulse_axes(fig)
        assert len(axes) == 2
        predicted, fitted = axes
        labels = {line.get_label(): line for line in fitted.lines}
        for name in ("SDOF fit", "MDOF fit"):
            line = labels[f"{name} (fitted to this run's base shear)"]
            assert line.get_linestyle() == "--"
            assert not any(name in line.get_label() for line in predicted.lines)
        assert {"ASCE 7-22, k_d", "ASCE 7-22, k_s", "contact model (simulated)"} <= {
            line.get_label() for line in predicted.lines}
        # the study's band of MDOF pulses stays under the predicted pulses
        assert any("Table 2" in c.get_label() for c in predicted.collections)
    finally:
        pyplot().close(fig)


def test_four_impacts_fit_the_width_and_a_failed_fit_says_why(real):
    results, comp = real["tiny-1debris"]
    comp = _four_impacts(comp)
    for builder in (plots.figure_impacts, plots.figure_study_fits):
        fig = builder(results, comp)
        try:
            check_figure(fig)
            texts = [t.get_text() for ax in fig.axes for t in ax.texts]
            assert any("no MDOF fit: the fit failed (no convergence in 200 iterations)" in " ".join(t.split())
                       for t in texts), texts
        finally:
            pyplot().close(fig)
    fig = plots.figure_impacts(results, comp)
    try:
        check_pulses_whole(fig)
        assert len(pulse_axes(fig)) == 8
    finally:
        pyplot().close(fig)


# --------------------------------------------------------------------------- tracks


def test_tracks_have_no_empty_band_and_the_areas_stay_inside(real):
    """The plan view's axes fill their share of the figure's height (equal scales, no blank band
    above or below), and the spreading areas end at the walls and at the axes."""
    results, comp = real["tiny-1debris"]
    fig = plots.figure_tracks(results, comp)
    try:
        check_figure(fig)
        fig.canvas.draw()
        plan, speeds = fig.axes[:2]
        plan_box, speed_box = plan.get_position(), speeds.get_position()
        # the plan view reaches down to the speed panel's title and up to the figure's top
        gap = plan_box.y0 - speed_box.y1
        assert gap < 0.2, f"{gap:.2f} of the figure's height between the plan and the speeds"
        assert plan_box.y1 > 0.8
        patches = [p for p in plan.patches if "deg" in p.get_label()]
        assert len(patches) == 2
        walls = results.data.plan.domain_m[1]
        for p in patches:
            assert p.get_clip_path() is None and p.get_clip_box() is not None  # the axes clip them
            y = p.get_path().vertices[:, 1]
            assert walls[0] - 1e-9 <= y.min() and y.max() <= walls[1] + 1e-9
    finally:
        pyplot().close(fig)


def test_gauge_names_are_not_under_the_column(real):
    results, comp = real["tiny-1debris"]
    scene = results.data.scene
    c = scene.column
    fig = plots.figure_tracks(results, comp)
    try:
        fig.canvas.draw()
        renderer = fig.canvas.get_renderer()
        plan = fig.axes[0]
        x0, y0 = plan.transData.transform((c.x_m - c.size_x_m / 2, c.y_m - c.size_y_m / 2))
        x1, y1 = plan.transData.transform((c.x_m + c.size_x_m / 2, c.y_m + c.size_y_m / 2))
        names = [t for t in plan.texts if t.get_text().startswith("WG")]
        assert {t.get_text() for t in names} == set(results.gauge_summary["gauge"])
        for t in names:
            e = t.get_window_extent(renderer)
            overlap = max(0.0, min(e.x1, x1) - max(e.x0, x0)) * max(0.0, min(e.y1, y1) - max(e.y0, y0))
            assert overlap == 0.0, f"{t.get_text()} drawn over the column"
    finally:
        pyplot().close(fig)


# --------------------------------------------------------------------------- the synthetic study


@pytest.fixture(scope="module")
def study():
    from analytical.synthetic import analyse_record, make_records
    from orchestrator.studies.synthetic import variant_columns

    column, fit_column = variant_columns("rigid")
    records = make_records(3, seed=2019, column=column)
    return column, [analyse_record(r, column=column, fit_column=fit_column) for r in records]


def test_study_figure4_draws_every_pulse_whole(study):
    """Record 0 of seed 2019: its SDOF pulses start after the true impact (where the record
    leaves its baseline) and end before the true pulse does."""
    from orchestrator.studies import synthetic as st

    column, analyses = study
    a = analyses[0]
    assert min(a.pulses[m].start_s for m in ("sdof", "sdof_column_mass")) > a.true_pulse.start_s
    assert max(a.pulses[m].end_s for m in ("sdof", "sdof_column_mass")) < a.true_pulse.end_s
    fig = st.figure4(a, a.fits["mdof"].time_s, column)
    try:
        check_figure(fig, st._DPI)
        check_pulses_whole(fig)
        ax, = pulse_axes(fig)
        fitted = [line for line in ax.lines if line.get_label() in ("SDOF fit", "SDOF fit, m_s = column mass",
                                                                    "MDOF fit")]
        assert len(fitted) == 3 and all(line.get_linestyle() == "--" for line in fitted)
    finally:
        pyplot().close(fig)


def test_study_figure7_fits_a_report(study):
    from orchestrator.studies import synthetic as st

    _, analyses = study
    fig = st.figure7({"rigid": analyses, "calibrated": analyses, "calibrated-fit-rigid": analyses})
    try:
        check_figure(fig, st._DPI)
        assert len({ax.get_xlim() for ax in fig.axes}) == 1  # one scale for the three variants
    finally:
        pyplot().close(fig)


def test_each_impact_gets_a_zoom_with_its_peak_written_out(real):
    """A 4.7 ms pulse on a 3.5 s axis cannot be read: every column impact gets a panel of a few
    pulse lengths, in ms from the impact, with its peak force and base shear written out."""
    results, _ = real["tiny-1debris"]
    fig = plots.figure_column_forces(results)
    try:
        check_figure(fig)
        zooms = [a for a in fig.axes if a.get_xlabel() == "time from the impact (ms)"]
        column = results.impacts[results.impacts["kind"] == "column"]
        assert len(zooms) == min(len(column), plots.MAX_ZOOMS) >= 1
        ax = zooms[0]
        lo, hi = ax.get_xlim()
        duration_ms = 1e3 * float(column["duration_s"].iloc[0])
        assert hi - lo < 5 * duration_ms  # milliseconds, not the run's seconds
        text = " ".join(t.get_text() for t in ax.texts)
        peak = results.column_forces["impact_force_x_N"].abs().max()
        assert f"impact pulse: peak {peak:.0f} N" in text and "base shear from it: peak" in text
    finally:
        pyplot().close(fig)
