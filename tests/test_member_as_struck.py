"""The member as struck (issue 48, item 3), through the scene: ASCE 7-22's k_s is the member's
stiffness at the strike point with its end conditions (column.ends, column.strike_height_m), turned
to the flow (column.heading_deg); the design's code pulse loads that same member there; u_max is the
designer's stated speed, the simulated one beside it."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pandas as pd
import pytest

from analytical.column_demand import column_demands
from analytical.column_fem import lateral_stiffness
from analytical.pulses import Rectangular
from orchestrator.cli import main
from orchestrator.results.asce_design import SiteFlow
from orchestrator.scene.scenefile import load_scene
from orchestrator.scene.schema import column_for_analysis
from orchestrator.studies.design import DESIGN_COLUMNS, DesignCase, DesignResult
from orchestrator.studies.design_asce import face_obliquity_deg, scene_asce_inputs, strike_point
from orchestrator.studies.design_report import asce_values
from tests.conftest import ROOT

STREET = ROOT / "cases" / "design-street.yaml"
LIGHT = ["column.elements=20"]  # a coarse model keeps the tests fast; the strike points below are its nodes


def test_k_s_is_the_members_at_the_flow_depth():
    """The street strikes at its stated 3.0 m flow depth: k_s is the model's point stiffness there,
    for each end condition, and a restrained top stiffens the member (Timoshenko, 0.70 E I_g)."""
    ks = {}
    for ends in ("cantilever", "fixed-fixed", "pinned"):
        scene = load_scene(STREET, [*LIGHT, f"column.ends={ends}"])
        inputs = scene_asce_inputs(scene)
        assert inputs.strike_height_m == 3.0
        assert inputs.structure_stiffness_N_m == pytest.approx(lateral_stiffness(column_for_analysis(scene), 3.0),
                                                              rel=1e-12)
        assert ends in inputs.sources["k_s"] and "3 m" in inputs.sources["k_s"]
        ks[ends] = inputs.structure_stiffness_N_m
    assert ks["cantilever"] < ks["pinned"] < ks["fixed-fixed"]
    assert ks["cantilever"] == pytest.approx(1.528e8, rel=1e-3)
    assert ks["fixed-fixed"] == pytest.approx(1.868e9, rel=1e-3)


def test_strike_point_defaults():
    scene = load_scene(STREET, LIGHT)
    assert strike_point(scene)[0] == 3.0
    over = load_scene(STREET, [*LIGHT, "column.ends=fixed-fixed", "column.height_m=2.5"])
    assert strike_point(over)[0] == 1.25  # the flow reaches the floor: mid-height
    top = load_scene(STREET, [*LIGHT, "column.ends=cantilever", "column.height_m=2.5"])
    assert strike_point(top)[0] == 2.5  # a cantilever the flow overtops: its top
    stated = load_scene(STREET, [*LIGHT, "column.strike_height_m=1.0"])
    assert scene_asce_inputs(stated).structure_stiffness_N_m == pytest.approx(
        lateral_stiffness(column_for_analysis(stated), 1.0), rel=1e-12)


def test_a_turned_rectangular_column_bends_about_both_axes():
    """A 1.0 x 0.5 m RC column (1.0 m along the flow at heading 0): turned 90 degrees it is the
    0.5 x 1.0 m column; turned 30 degrees, 1/k = cos^2/k_x + sin^2/k_y; a square one does not care."""
    fine = [*LIGHT, "mesh.cell_size_m=0.25"]  # two cells across the 0.5 m side
    base = [*fine, "column.section={kind: rc-rectangular, size_m: [1.0, 0.5]}"]
    k0 = scene_asce_inputs(load_scene(STREET, base)).structure_stiffness_N_m
    k90 = scene_asce_inputs(load_scene(STREET, [*base, "column.heading_deg=90"])).structure_stiffness_N_m
    swapped = load_scene(STREET, [*fine, "column.section={kind: rc-rectangular, size_m: [0.5, 1.0]}"])
    assert k90 == pytest.approx(scene_asce_inputs(swapped).structure_stiffness_N_m, rel=1e-9)
    assert k90 < 0.5 * k0  # the weak axis (I 4 times smaller, shear the same)
    inputs = scene_asce_inputs(load_scene(STREET, [*base, "column.heading_deg=30"]))
    h = math.radians(30)
    assert inputs.structure_stiffness_N_m == pytest.approx(1 / (math.cos(h) ** 2 / k0 + math.sin(h) ** 2 / k90),
                                                           rel=1e-9)
    assert "30 deg" in inputs.sources["k_s"]
    square = scene_asce_inputs(load_scene(STREET, [*LIGHT, "column.heading_deg=30"])).structure_stiffness_N_m
    assert square == pytest.approx(scene_asce_inputs(load_scene(STREET, LIGHT)).structure_stiffness_N_m, rel=1e-9)
    assert [face_obliquity_deg(a) for a in (0, 30, -30, 60, 90)] == [0, 30, 30, 30, 0]


def test_the_designs_code_pulse_loads_the_same_member_at_the_stated_speed():
    """design's ASCE line for a fixed-fixed street column: u_max is the scene's stated 4.0 m/s (the
    simulated 3.53 m/s beside it), k_s the member's at 3.0 m, and the code's pulse loads that member
    at 3.0 m (its base shear the fixed-fixed model's, not the cantilever's)."""
    scene = load_scene(STREET, [*LIGHT, "column.ends=fixed-fixed", "design.prototype=false"])
    site = SiteFlow(3.53, 8.0, 3.0, 45.0, 2.0, "test")
    result = DesignResult(pd.DataFrame(columns=DESIGN_COLUMNS), [DesignCase("nominal", [], 1.0, 10, scene, site=site)],
                          {})
    asce = asce_values(result, scene.design, np.array([1.7]), scene)
    assert asce["u_max_m_s"] == 4.0 and asce["u_simulated_m_s"] == 3.53
    assert asce["load_height_m"] == 3.0 and asce["height_basis"] == "the strike point of k_s"
    column = column_for_analysis(scene)
    assert column.ends == "fixed-fixed"
    inputs = scene_asce_inputs(scene)
    assert asce["force_N"] == pytest.approx(inputs.design(4.0).force_N, rel=1e-12)
    ks = asce["values"]["k_s"]
    assert ks["stiffness_N_m"] == pytest.approx(lateral_stiffness(column, 3.0), rel=1e-12)
    member = column_demands(Rectangular(ks["peak_force_N"], ks["duration_s"]), column, 3.0)
    cantilever = column_demands(Rectangular(ks["peak_force_N"], ks["duration_s"]),
                                dataclasses.replace(column, ends="cantilever"), 3.0)
    assert ks["base_shear_N"] == pytest.approx(member.peak_base_shear_N, rel=1e-12)
    assert ks["base_moment_Nm"] == pytest.approx(member.peak_base_moment_Nm, rel=1e-12)
    # the floor above takes a share: the base moment is well under the cantilever's
    assert ks["base_moment_Nm"] < 0.6 * cantilever.peak_base_moment_Nm
    assert "inundation.speed_m_s" in asce["u_basis"] and asce["u_simulated_case"] == "nominal"


@pytest.mark.parametrize("setting, field", [
    ("column.ends=hinged", "column.ends"),
    ("column.strike_height_m=5.0", "column.strike_height_m"),
    ("column.heading_deg=120", "column.heading_deg"),
])
def test_bad_member_keys_are_exit_2_naming_the_field(capfd, setting, field):
    code = main(["analytical", "asce7", "--scene", str(STREET), "--velocity", "4", "--set", "column.ends=fixed-fixed",
                 "--set", setting])
    err = capfd.readouterr().err
    assert code == 2 and field in err, err


def test_a_stated_stiffness_on_a_restrained_member_is_named(capfd):
    lab = ROOT / "cases" / "1debris.yaml"
    code = main(["analytical", "asce7", "--scene", str(lab), "--velocity", "1.5", "--set", "column.ends=pinned"])
    err = capfd.readouterr().err
    assert code == 2 and "column.stiffness_N_m" in err, err


def test_a_turned_column_is_refused_for_an_openfoam_case(capfd, tmp_path):
    out = tmp_path / "case"
    code = main(["render", str(STREET), "-o", str(out), "--set", "column.heading_deg=15"])
    err = capfd.readouterr().err
    assert code == 2 and "column.heading_deg" in err, err
    assert not out.exists() or not any(out.iterdir())
