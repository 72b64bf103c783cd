"""Prototype scenes: the planner at 40:1 (Froude similarity) and scenes that state their bore.

The study's 1-debris scene and its 40:1 twin (cases/prototype-1debris.yaml) must plan the same
mesh cell for cell, with every length x 40 and every time x sqrt(40); the dam break sized for a
requested bore must give that bore back through Stoker's solution; a request no dam break on the
scene's wet bed can make is exit 2 naming the field.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import yaml

from analytical.bore_sizing import (
    froude_on_wet_bed,
    plateau_froude,
    reflection_arrival_s,
    reservoir_length_for,
    size_dam_break,
)
from analytical.dambreak import StokerSolution, stoker_state
from orchestrator.plan.planner import plan_case
from orchestrator.plan.scale import REFERENCE_DEPTH_M, froude_factor
from orchestrator.plan.timestep import max_delta_t_s
from orchestrator.scene.scenefile import dump_scene_yaml, load_scene
from orchestrator.transport.case_transport import FROUDE_SCALED_SETTINGS, scene_settings
from orchestrator.transport.engine import TransportSettings
from tests.conftest import ROOT, run_cli

SCALE = 40.0
LAB = ROOT / "cases" / "1debris.yaml"
PROTOTYPE = ROOT / "cases" / "prototype-1debris.yaml"


@pytest.fixture(scope="module")
def scenes():
    return load_scene(LAB), load_scene(PROTOTYPE)


@pytest.fixture(scope="module")
def plans(scenes):
    return plan_case(scenes[0]), plan_case(scenes[1])


def test_prototype_scene_is_the_lab_scene_froude_scaled(scenes):
    lab, proto = scenes
    r = math.sqrt(SCALE)
    assert proto.reservoir.depth_m == pytest.approx(SCALE * lab.reservoir.depth_m)
    assert proto.bed.wet_depth_m == pytest.approx(SCALE * lab.bed.wet_depth_m)
    assert proto.column.x_m == pytest.approx(SCALE * lab.column.x_m)
    assert proto.debris[0].mass_kg == pytest.approx(SCALE ** 3 * lab.debris[0].mass_kg)
    assert np.allclose(proto.debris[0].centre_m, SCALE * np.asarray(lab.debris[0].centre_m))
    assert proto.run.end_time_s == pytest.approx(r * lab.run.end_time_s, rel=1e-4)
    assert proto.outputs.probe_interval_s == pytest.approx(r * lab.outputs.probe_interval_s, rel=1e-4)
    assert proto.column.stiffness_N_m == pytest.approx(SCALE ** 2 * lab.column.stiffness_N_m)
    assert proto.column.natural_frequency_Hz == pytest.approx(lab.column.natural_frequency_Hz / r, rel=1e-4)
    assert proto.mesh.cell_size_m == pytest.approx(SCALE * lab.mesh.cell_size_m)


def test_planner_at_40_scale_same_cells_times_by_sqrt_40(plans):
    lab, proto = plans
    r = math.sqrt(SCALE)
    assert proto.cell_count == lab.cell_count
    assert proto.time_step_estimate_s == pytest.approx(r * lab.time_step_estimate_s, rel=1e-9)
    assert proto.max_delta_t_s == pytest.approx(r * lab.max_delta_t_s, rel=1e-4)
    assert proto.first_delta_t_s == pytest.approx(r * lab.first_delta_t_s, rel=0.02)  # two significant digits
    assert proto.flow_record.interval_s == pytest.approx(r * lab.flow_record.interval_s, rel=1e-4)
    assert np.allclose(np.asarray(proto.domain_m), SCALE * np.asarray(lab.domain_m), rtol=1e-5, atol=1e-9)  # end time 22.136 s, rounded
    assert proto.bed_cell_m == pytest.approx(SCALE * lab.bed_cell_m)
    assert proto.friction_layer_m == pytest.approx(SCALE * lab.friction_layer_m)
    # the bed's drag per metre, rho F |U| U with F = f / (4 dz): 1 / 40 of the lab's
    assert proto.bed_friction_per_m == pytest.approx(lab.bed_friction_per_m / SCALE)
    assert proto.estimated_wall_time_s == pytest.approx(lab.estimated_wall_time_s, rel=1e-6)


def test_laboratory_scenes_keep_their_constants():
    assert froude_factor(REFERENCE_DEPTH_M) == 1.0
    assert froude_factor(0.16) == 1.0
    assert froude_factor(16.0) == pytest.approx(40.0)
    assert max_delta_t_s(None, 0.1, 0.40) == 0.01
    assert max_delta_t_s(None, 0.1, 0.20) == 0.01
    assert max_delta_t_s(None, 1.0, 16.0) == pytest.approx(0.01 * math.sqrt(40.0))
    assert max_delta_t_s(0.002, 1.0, 16.0) == 0.002  # a stated cap is kept


def test_transport_settings_scale_with_the_scene(scenes):
    lab, proto = scenes
    defaults = TransportSettings()
    assert scene_settings(lab).hydro_interval_s == defaults.hydro_interval_s
    scaled = scene_settings(proto)
    for name in FROUDE_SCALED_SETTINGS:
        assert getattr(scaled, name) == pytest.approx(math.sqrt(SCALE) * getattr(defaults, name)), name
    kept = scene_settings(proto, TransportSettings(hydro_interval_s=2e-3))
    assert kept.hydro_interval_s == 2e-3  # a value the caller chose is not scaled


# ------------------------------------------------------------------ the bore a scene asks for


@pytest.mark.parametrize("depth, speed", [(4.0, 6.0), (6.0, 8.0), (0.1, 0.3), (2.0, 12.0), (0.2, 1.5)])
def test_sized_dam_break_gives_the_requested_bore(depth, speed):
    s = size_dam_break(depth, speed)
    st = stoker_state(s.reservoir_depth_m, s.wet_bed_depth_m)
    assert st.h2_m == pytest.approx(depth, rel=1e-9)
    assert st.u2_m_s == pytest.approx(speed, rel=1e-9)
    assert s.bore_speed_m_s == pytest.approx(st.shock_speed_m_s, rel=1e-9)
    # the Riemann invariant in closed form: h0 = h2 (1 + Fr/2)^2
    fr = speed / math.sqrt(9.81 * depth)
    assert s.reservoir_depth_m == pytest.approx(depth * (1 + fr / 2) ** 2, rel=1e-12)
    assert froude_on_wet_bed(depth, s.wet_bed_depth_m) == pytest.approx(fr, rel=1e-9)


def test_plateau_froude_closed_form_and_monotone():
    r = np.linspace(0.01, 0.99, 99)
    fr = np.array([plateau_froude(v) for v in r])
    assert np.all(np.diff(fr) < 0)
    # r = 1/3: (2/3) sqrt(2) = 0.9428
    assert plateau_froude(1 / 3) == pytest.approx(2 / 3 * math.sqrt(2))


def test_the_study_dam_break_sized_back():
    """The study's flume: 0.40 m on a 15 mm bed; its Stoker plateau asked for gives 0.40 and 15 mm."""
    st = stoker_state(0.40, 0.015)
    s = size_dam_break(st.h2_m, st.u2_m_s)
    assert s.reservoir_depth_m == pytest.approx(0.40, rel=1e-9)
    assert s.wet_bed_depth_m == pytest.approx(0.015, rel=1e-9)


def test_reflection_head_in_the_fan_is_ritters_closed_form():
    """In Ritter's fan the reflected head reaches the gate at (3/2)^(3/2) L / c0 (Stoker 1957, 10.8)
    when the fan still covers the gate (a supercritical plateau)."""
    h0, hr, length = 16.0, 0.6, 862.0
    c0 = math.sqrt(9.81 * h0)
    assert stoker_state(h0, hr).rarefaction_tail_speed_m_s > 0
    assert reflection_arrival_s(0.0, length, h0, hr) == pytest.approx(1.5 ** 1.5 * length / c0, rel=1e-9)


def test_reflection_through_the_plateau_and_its_inverse():
    h0, hr = 8.7487, 1.3093  # a subcritical plateau (4 m at 6 m/s): its tail moves upstream
    st = stoker_state(h0, hr)
    assert st.rarefaction_tail_speed_m_s < 0
    t1 = reflection_arrival_s(150.0, 80.0, h0, hr)
    t2 = reflection_arrival_s(250.0, 80.0, h0, hr)
    # in the plateau the head runs at u2 + c2
    assert (250.0 - 150.0) / (t2 - t1) == pytest.approx(st.u2_m_s + math.sqrt(9.81 * st.h2_m), rel=1e-9)
    length = reservoir_length_for(196.0, 22.0, h0, hr)
    assert reflection_arrival_s(196.0, length, h0, hr) == pytest.approx(22.0, rel=1e-8)
    # the solution itself holds the plateau at x until then (the reflection is not in Stoker's
    # semi-infinite reservoir): behind the bore, depth and speed are h2, u2
    prof = StokerSolution(h0, hr).profile([150.0], 20.0)
    assert prof.depth_m[0] == pytest.approx(st.h2_m) and prof.velocity_m_s[0] == pytest.approx(st.u2_m_s)


def _bore_scene(tmp_path, **inundation) -> str:
    data = {"extends": str(PROTOTYPE), "name": "bore", "reservoir": {"length_m": None, "depth_m": None},
            "bed": {"wet_depth_m": None}, "inundation": inundation or {"depth_m": 6.0, "speed_m_s": 8.0}}
    path = tmp_path / "bore.yaml"
    path.write_text(yaml.safe_dump(data))
    return str(path)


def test_inundation_scene_sizes_its_reservoir(tmp_path):
    scene = load_scene(_bore_scene(tmp_path))
    st = stoker_state(scene.reservoir.depth_m, scene.bed.wet_depth_m)
    assert st.h2_m == pytest.approx(6.0, rel=1e-9) and st.u2_m_s == pytest.approx(8.0, rel=1e-9)
    face = scene.column.x_m - scene.column.size_x_m / 2
    # the sized reservoir holds the state at the column's face to the end of the run
    t = reflection_arrival_s(face, scene.reservoir.length_m, scene.reservoir.depth_m, scene.bed.wet_depth_m)
    assert t == pytest.approx(scene.run.end_time_s, rel=1e-5)
    plan = plan_case(scene)
    assert "sized for inundation 6 m at 8 m/s" in plan.reasons["water"]
    # the resolved scene written back loads to the same scene
    again = tmp_path / "resolved.yaml"
    again.write_text(dump_scene_yaml(scene))
    assert load_scene(again) == scene
    # --set reaches the request (a design sweep over inundation levels)
    deeper = load_scene(_bore_scene(tmp_path), ["inundation.depth_m=8.0"])
    assert stoker_state(deeper.reservoir.depth_m, deeper.bed.wet_depth_m).h2_m == pytest.approx(8.0, rel=1e-9)


@pytest.mark.parametrize("override, field", [
    ("bed.wet_depth_m=0.6", "inundation.speed_m_s"),     # that wet bed makes another Froude number
    ("bed.wet_depth_m=0.0", "inundation.speed_m_s"),     # a dry bed has no plateau
    ("inundation.depth_m=30", "inundation.depth_m"),     # the reservoir would top the walls
    ("inundation.speed_m_s=0", "inundation.speed_m_s"),
    ("reservoir.depth_m=10", "reservoir.depth_m"),       # a reservoir and a bore that disagree
    ("run.end_time_s=5", "run.end_time_s"),              # the bore would not reach the column
    ("flume.length_m=250", "flume.length_m"),            # no room for the sized reservoir
])
def test_bad_inundation_exits_2_naming_the_field(tmp_path, override, field):
    proc = run_cli("validate", _bore_scene(tmp_path), "--set", override)
    assert proc.returncode == 2, proc.stderr
    assert field in proc.stderr and "bore.yaml" in proc.stderr


def test_two_way_contact_settings_scale_with_the_scene():
    from orchestrator.contact.settings import ContactSettings

    lab = ContactSettings()
    assert lab.froude_scaled(1.0) == lab
    proto = lab.froude_scaled(SCALE)
    assert proto.gap_m == pytest.approx(SCALE * lab.gap_m)
    assert proto.float_margin_m == pytest.approx(SCALE * lab.float_margin_m)
    assert proto.window_s == pytest.approx(math.sqrt(SCALE) * lab.window_s)
    assert proto.min_impact_speed_m_s == pytest.approx(math.sqrt(SCALE) * lab.min_impact_speed_m_s)
    assert ContactSettings(gap_m=0.1).froude_scaled(SCALE).gap_m == 0.1  # a chosen gap is kept


# ------------------------------------------------------------------ the scale report


def _fake_run(folder, scene_path, scale, arrival_factor=1.0):
    """A post-processed run folder: the resolved scene and results tables of a made-up flow,
    every figure the lab's times lambda^exponent."""
    import json

    import pandas as pd

    r = math.sqrt(scale)
    (folder / "results").mkdir(parents=True)
    (folder / "scene.yaml").write_text(dump_scene_yaml(load_scene(scene_path)))
    (folder / "run.json").write_text(json.dumps({"time_steps": 450}))
    pd.DataFrame({"gauge": ["WG2", "WG3"], "arrival_s": [0.88 * r * arrival_factor, 1.19 * r],
                  "peak_elevation_m": [0.147 * scale, 0.133 * scale]}).to_csv(folder / "results" / "gauge_summary.csv")
    t = np.linspace(0, 3.5, 36)
    pd.DataFrame({"time_s": t * r, "WG2_elevation_m": 0.1 * scale * (t > 0.88)}).to_csv(
        folder / "results" / "gauges.csv", index=False)
    pd.DataFrame({"kind": ["column"], "time_s": [2.37 * r], "impact_speed_m_s": [1.30 * r],
                  "impact_velocity_m_s": [1.25 * r], "height_m": [0.093 * scale], "peak_force_N": [206 * scale ** 3],
                  "duration_s": [0.0047 * r], "impulse_Ns": [0.46 * scale ** 3.5]}).to_csv(
        folder / "results" / "impacts.csv", index=False)
    pd.DataFrame({"time_s": t * r, "hydro_force_x_N": 52 * scale ** 3 * (t > 1.7)}).to_csv(
        folder / "results" / "column_forces.csv", index=False)
    return folder


def test_scale_report_on_an_exactly_scaled_flow(tmp_path):
    from orchestrator.studies.froude_scale import compare_scales, write_scale_report

    lab = _fake_run(tmp_path / "lab", LAB, 1.0)
    proto = _fake_run(tmp_path / "proto", PROTOTYPE, SCALE)
    cmp = compare_scales(lab, proto)
    assert cmp.scale == pytest.approx(SCALE)
    diffs = cmp.table["difference_percent"].dropna()
    assert len(diffs) >= 10 and np.allclose(diffs, 0.0, atol=1e-9)
    assert cmp.within_target()
    files = write_scale_report(cmp, tmp_path / "page")
    assert "| WG2 bore arrival | s | 0.5 |" in files["report"].read_text()
    assert files["figure"].stat().st_size > 1000
    late = _fake_run(tmp_path / "late", PROTOTYPE, SCALE, arrival_factor=1.06)
    cmp = compare_scales(lab, late)
    assert not cmp.within_target()
    row = cmp.table.set_index("quantity").loc["WG2 bore arrival"]
    assert row["difference_percent"] == pytest.approx(6.0)


def test_scale_report_refuses_runs_of_different_scenes(tmp_path):
    from orchestrator.core.errors import InputError
    from orchestrator.studies.froude_scale import compare_scales

    lab = _fake_run(tmp_path / "lab", LAB, 1.0)
    coarse = tmp_path / "coarse.yaml"
    coarse.write_text(yaml.safe_dump({"extends": str(PROTOTYPE), "mesh": {"cell_size_m": 1.2}}))
    other = _fake_run(tmp_path / "other", coarse, SCALE)
    with pytest.raises(InputError, match="mesh.cell_size_m"):
        compare_scales(lab, other)
