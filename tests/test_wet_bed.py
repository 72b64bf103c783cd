"""The wet bed resolved (cells across its depth, graded above) and the RANS closure with a rough
bed: what the planner and the renderer make of them, and a real tiny RANS dam break."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from analytical.roughness import bore_depth_m, sand_roughness_m
from orchestrator.case.render import build_context, render_files
from orchestrator.plan.grading import cell_edges
from orchestrator.plan.planner import plan_case
from orchestrator.scene.scenefile import load_scene

ROOT = Path(__file__).resolve().parent.parent
NODEBRIS = ROOT / "cases" / "nodebris.yaml"


def _z_edges(*sets: str) -> np.ndarray:
    return cell_edges(plan_case(load_scene(NODEBRIS, list(sets))).background.z)


def test_by_default_the_wet_bed_is_one_layer():
    z = _z_edges()
    assert np.count_nonzero(z < 0.015 - 1e-9) == 1 and np.any(np.isclose(z, 0.015))


@pytest.mark.parametrize("cells", [4, 6, 10])
def test_the_wet_bed_gets_its_cells_and_the_layers_above_grow_by_at_most_the_growth_ratio(cells):
    z = _z_edges(f"mesh.wet_bed_cells={cells}")
    below = z[z <= 0.015 + 1e-9]
    assert len(below) - 1 == cells and np.allclose(np.diff(below), 0.015 / cells)
    sizes = np.diff(z[z <= 0.4 + 1e-9])  # the water column up to the impoundment level
    assert np.all(sizes[1:] / sizes[:-1] <= 1.15 * (1 + 1e-6))
    assert sizes.max() == pytest.approx(0.04, rel=0.05)  # the scene's cell size reached below h0
    assert np.any(np.isclose(z, 0.4))  # the impoundment level stays a plane


def test_a_laminar_plan_keeps_the_drag_layer_and_a_rans_plan_the_roughness_instead():
    laminar = plan_case(load_scene(NODEBRIS))
    rans = plan_case(load_scene(NODEBRIS, ["fluids.turbulence=kOmegaSST"]))
    assert laminar.turbulence == "laminar" and laminar.bed_roughness_m == 0.0 and laminar.bed_friction_per_m > 0
    assert rans.turbulence == "kOmegaSST" and rans.bed_friction_per_m == 0.0
    assert rans.bed_friction_factor == laminar.bed_friction_factor  # Chanson's comparison keeps the scene's f
    assert rans.bed_roughness_m == pytest.approx(sand_roughness_m(0.0293, bore_depth_m(0.40, 0.015)), rel=1e-12)
    assert "no drag layer" in rans.reasons["bed_friction"]
    back = type(rans).from_json(rans.to_json())
    assert (back.turbulence, back.bed_roughness_m) == (rans.turbulence, rans.bed_roughness_m)


def test_a_rans_case_has_its_fields_a_rough_bed_and_no_drag():
    scene = load_scene(NODEBRIS, ["fluids.turbulence=kOmegaSST"])
    plan = plan_case(scene)
    files = render_files(build_context(scene, plan))
    assert "system/fvOptions" not in files
    assert re.search(r"RASModel\s+kOmegaSST;", files["constant/turbulenceProperties"])
    for name in ("k", "omega", "nut"):
        assert f"0/{name}" in files
    bed = files["0/nut"].split("    bed\n    {")[1].split("}")[0]
    assert "nutkRoughWallFunction" in bed
    assert float(re.search(r"Ks\s+uniform ([0-9.eE+-]+);", bed).group(1)) == pytest.approx(plan.bed_roughness_m,
                                                                                           rel=1e-9)
    column = files["0/nut"].split("    column\n    {")[1].split("}")[0]
    assert "nutkWallFunction" in column  # the other walls smooth
    assert "div(phi,omega)" in files["system/fvSchemes"] and "(k|omega)" in files["system/fvSolution"]


def test_a_laminar_case_has_no_turbulence_fields():
    scene = load_scene(NODEBRIS)
    files = render_files(build_context(scene, plan_case(scene)))
    assert not any(name in files for name in ("0/k", "0/omega", "0/nut"))
    assert re.search(r"simulationType\s+laminar;", files["constant/turbulenceProperties"])


@pytest.mark.parametrize("turbulence", ["laminar", "kOmegaSST"])
def test_a_slip_bed_lets_the_flow_slide_and_carries_no_wall_function(turbulence):
    """bed.slip: Stoker's and Ritter's frictionless bed is a slip wall (no shear), every other wall
    keeps its no-slip or wall function; no drag layer and no roughness."""
    scene = load_scene(NODEBRIS, ["bed.friction_factor=0", "bed.slip=true", f"fluids.turbulence={turbulence}"])
    plan = plan_case(scene)
    assert plan.bed_slip and plan.bed_friction_per_m == 0.0 and plan.bed_roughness_m == 0.0
    back = type(plan).from_json(plan.to_json())
    assert back.bed_slip
    files = render_files(build_context(scene, plan))

    def entry(field: str, patch: str) -> str:
        return files[field].split(f"    {patch}\n    {{")[1].split("}")[0]

    assert "type slip;" in entry("0/U", "bed") and "noSlip" in entry("0/U", "sideWalls")
    if turbulence != "laminar":
        assert "zeroGradient" in entry("0/k", "bed") and "kqRWallFunction" in entry("0/k", "sideWalls")
        assert "calculated" in entry("0/nut", "bed") and "nutkWallFunction" in entry("0/nut", "column")
    assert "slip" in plan.reasons["bed_friction"]


def test_a_slip_bed_with_friction_is_bad_input():
    from orchestrator.core.errors import InputError

    with pytest.raises(InputError, match="bed.slip"):
        load_scene(NODEBRIS, ["bed.slip=true"])  # the scene's f = 0.0293


@pytest.mark.openfoam
def test_a_tiny_rans_dam_break_runs_and_makes_turbulence(openfoam, tmp_path):
    from foamlib import FoamCase

    from tests.conftest import render_and_run

    case = tmp_path / "rans"
    plan = render_and_run(ROOT / "cases" / "tiny-nodebris.yaml", case, "fluids.turbulence=kOmegaSST",
                          "bed.wet_depth_m=0.01", "mesh.wet_bed_cells=2", "run.end_time_s=0.4")
    assert plan["turbulence"] == "kOmegaSST"
    last = FoamCase(case)[-1]
    assert last.time == pytest.approx(0.4)
    k = np.asarray(last["k"].internal_field, dtype=float)
    # the bore running into the wet bed makes turbulence from the quiescent start (1e-6 m2/s2) ...
    assert k.max() > 1e-3
    # ... and the front has left the reservoir
    alpha = np.asarray(last["alpha.water"].internal_field, dtype=float)
    assert 0.0 < alpha.mean() < 1.0
