"""One errors module for orchestrator/, and each error is also the built-in it stands for; no plain
built-in exception a user can cause reaches the CLI (it would be exit 1 'unexpected error'), and the
CLI answers a representative set of bad files, folders and values with exit 2 naming the file and
the field."""

from __future__ import annotations

import ast
import builtins
from pathlib import Path

import pytest

from analytical.errors import InputError as AnalyticalInputError
from orchestrator.run.openfoam import StepError
from orchestrator.core.errors import DebrisfoamError, InputError, MissingFeatureError
from orchestrator.run.errors import DivergenceError, RunError

ROOT = Path(__file__).resolve().parents[1]


def test_orchestrator_takes_its_errors_from_core_errors_only():
    wrong = [str(p.relative_to(ROOT)) for p in (ROOT / "orchestrator").rglob("*.py")
             if "from analytical.errors import" in p.read_text() and p.relative_to(ROOT).as_posix() != "orchestrator/core/errors.py"]
    assert not wrong, f"import errors from orchestrator.core.errors: {wrong}"


@pytest.mark.parametrize("error, builtin", [
    (InputError("mesh.cell_size_m", "must be > 0"), ValueError),
    (MissingFeatureError("design"), NotImplementedError),
    (StepError("blockMesh", "a reason", "log.blockMesh"), RuntimeError),
    (RunError("stopped"), RuntimeError),
    (DivergenceError("nan", "NaN in p_rgh", 0.1, "0.05", Path("log.interFoam")), RuntimeError),
])
def test_each_error_is_also_its_builtin(error, builtin):
    assert isinstance(error, DebrisfoamError) and isinstance(error, builtin)


def test_the_physics_package_raises_the_same_input_error():
    assert AnalyticalInputError is InputError


# --------------------------------------------------------------------------- no plain raises a user can reach

#: A raise of a built-in exception outside the scene's validators carries this comment, saying why no
#: user input can reach it (e.g. ``# internal: json's protocol for default=``).
INTERNAL = "# internal:"
#: pydantic's validators must raise ValueError (pydantic names the field and the file).
VALIDATORS = {"field_validator", "model_validator"}
BUILTIN_ERRORS = {name for name, v in vars(builtins).items() if isinstance(v, type) and issubclass(v, Exception)}


def _name(node: ast.expr) -> str | None:
    node = node.func if isinstance(node, ast.Call) else node
    return node.id if isinstance(node, ast.Name) else node.attr if isinstance(node, ast.Attribute) else None


def plain_raises(rel: str, text: str) -> list[str]:
    """``rel:line`` of each raise of a built-in exception (ValueError, KeyError, TypeError, RuntimeError,
    SystemExit...) in ``text`` (the module at ``rel``) that is neither marked internal nor in a pydantic
    validator of orchestrator/scene/."""
    lines = text.splitlines()
    scene = rel.startswith("orchestrator/scene/")
    found = []

    def visit(node: ast.AST, in_validator: bool) -> None:
        for child in ast.iter_child_nodes(node):
            inside = in_validator
            if isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef)):
                inside = scene and any(_name(d) in VALIDATORS for d in child.decorator_list)
            if isinstance(child, ast.Raise) and child.exc is not None:
                name = _name(child.exc)
                marked = any(INTERNAL in line for line in lines[child.lineno - 1:child.end_lineno])
                if (name in BUILTIN_ERRORS or name == "SystemExit") and not inside and not marked:
                    found.append(f"{rel}:{child.lineno}: {lines[child.lineno - 1].strip()}")
            visit(child, inside)

    visit(ast.parse(text), False)
    return found


def test_no_plain_raise_of_a_builtin_reaches_the_cli():
    """A user's mistake raises a DebrisfoamError (InputError: exit 2, naming the file and the field);
    a built-in exception would reach the CLI as exit 1 'unexpected error'."""
    wrong = [line for path in sorted((ROOT / "orchestrator").rglob("*.py"))
             for line in plain_raises(path.relative_to(ROOT).as_posix(), path.read_text())]
    assert not wrong, ("raise an orchestrator.core.errors class (InputError names the field and the file), or "
                       f"mark a raise no input can reach with '{INTERNAL} why':\n" + "\n".join(wrong))


def test_the_walk_finds_plain_raises_and_honours_the_marker_and_the_scene_validators():
    text = ("from pydantic import field_validator\n\n\n"
            "class A:\n"
            "    @field_validator('x')\n"
            "    def check(cls, x):\n"
            "        if x:\n"
            "            raise ValueError('pydantic names the field')\n"
            "        raise SystemExit('no')\n\n\n"
            "def f(x):\n"
            "    if x:\n"
            "        raise KeyError(x)  # internal: the caller checked it\n"
            "    raise TypeError(\n"
            "        'spread over lines')\n")
    assert plain_raises("orchestrator/scene/probe.py", text) == ["orchestrator/scene/probe.py:15: raise TypeError("]
    assert plain_raises("orchestrator/plan/probe.py", text) == [
        "orchestrator/plan/probe.py:8: raise ValueError('pydantic names the field')",
        "orchestrator/plan/probe.py:9: raise SystemExit('no')",
        "orchestrator/plan/probe.py:15: raise TypeError("]


# --------------------------------------------------------------------------- bad input through the CLI: exit 2


def _cli(capsys, *argv: str) -> tuple[int, str]:
    """(exit code, stderr) of `debrisfoam ARGV`, run in this process."""
    from orchestrator.cli import main

    code = main([str(a) for a in argv])
    return code, capsys.readouterr().err


TINY = ROOT / "cases" / "tiny-nodebris.yaml"


def test_a_sweep_axis_that_is_not_a_list_names_the_file_and_the_axis(tmp_path, capsys):
    sweep = tmp_path / "sweep.yaml"
    sweep.write_text(f"name: s\nbase: {TINY}\nmode: grid\naxes:\n  mesh.cell_size_m: 0.05\n")
    code, err = _cli(capsys, "sweep", sweep, "--dry-run")
    assert code == 2 and f"{sweep}: axes.mesh.cell_size_m: must be a non-empty list" in err


def test_a_bad_set_value_names_the_file_and_the_key(capsys):
    code, err = _cli(capsys, "validate", TINY, "--set", "mesh.cell_size_m=abc")
    assert code == 2 and f"{TINY}: mesh.cell_size_m:" in err and "unexpected" not in err


def test_run_of_a_missing_folder_names_it(tmp_path, capsys):
    code, err = _cli(capsys, "run", tmp_path / "nowhere")
    assert code == 2 and f"{tmp_path / 'nowhere'}: case_dir: no such folder" in err


@pytest.mark.parametrize("plan, said", [("garbage", "could not be read"),
                                        ("{}", "has no 'scene_name'")])
def test_run_of_a_case_whose_plan_json_is_broken_names_the_file(tmp_path, capsys, plan, said):
    """plan.json is the case's record of its plan: unreadable or not a plan, it is bad input (was exit 1)."""
    (tmp_path / "plan.json").write_text(plan)
    code, err = _cli(capsys, "run", tmp_path)
    assert code == 2, err
    assert f"{tmp_path / 'plan.json'}: plan.json: {said}" in err


#: a plan.json `debrisfoam render` wrote (a tiny interFoam case on 2 ranks)
PLAN = (ROOT / "tests" / "data" / "post" / "tiny-nodebris" / "plan.json").read_text()
CONTROL = "FoamFile { version 2.0; format ascii; class dictionary; object controlDict; }\nendTime 1;\n"


@pytest.mark.parametrize("control, dynamic, said", [
    (None, None, "system/controlDict: missing"),
    ("FoamFile { version 2.0; }\nfoo { bar\n", None, "system/controlDict: not an OpenFOAM dictionary"),
    (CONTROL, "FoamFile { version 2.0; }\nsolvers { debris1 { sixDoFRigidBodyMotionCoeffs { centreOfMass (0 0 0); } } }\n",
     "constant/dynamicMeshDict: not the dictionary `debrisfoam render` writes (KeyError('mass'))"),
])
def test_run_of_a_case_whose_openfoam_dictionaries_are_broken_names_the_file(tmp_path, capsys, control, dynamic, said):
    (tmp_path / "plan.json").write_text(PLAN)
    for name, text in (("system/controlDict", control), ("constant/dynamicMeshDict", dynamic)):
        if text is not None:
            (tmp_path / name).parent.mkdir(exist_ok=True)
            (tmp_path / name).write_text(text)
    code, err = _cli(capsys, "run", tmp_path)
    assert code == 2 and f"{tmp_path}: {said}" in err, err


def test_report_case_of_an_unreadable_summary_names_the_file(tmp_path, capsys):
    (tmp_path / "results").mkdir()
    (tmp_path / "results" / "summary.json").write_text("garbage")
    code, err = _cli(capsys, "report", "case", tmp_path, "-o", tmp_path / "page")
    assert code == 2 and f"{tmp_path}: results/summary.json: not a JSON object" in err


def test_report_layouts_of_a_sweep_folder_whose_record_is_unreadable_names_it(tmp_path, capsys):
    (tmp_path / "sweep.json").write_text("garbage")
    code, err = _cli(capsys, "report", "layouts", tmp_path, "-o", tmp_path / "page")
    assert code == 2 and f"{tmp_path}: RUNS: sweep.json is not a JSON object" in err


BROKEN_CSV = 'a,b\n1,2,3,4\n"x'


def test_report_layouts_of_a_run_whose_results_table_is_broken_names_the_table(tmp_path, capsys):
    (tmp_path / "results").mkdir()
    (tmp_path / "plan.json").write_text(PLAN)
    (tmp_path / "results" / "summary.json").write_text('{"status": "finished"}')
    (tmp_path / "results" / "gauges.csv").write_text(BROKEN_CSV)
    code, err = _cli(capsys, "report", "layouts", tmp_path, "-o", tmp_path / "page")
    assert code == 2 and f"{tmp_path / 'results'}: gauges.csv: not a table" in err


def test_report_scale_of_a_run_whose_gauge_summary_is_broken_names_it(tmp_path, capsys):
    (tmp_path / "results").mkdir()
    (tmp_path / "scene.yaml").write_text(TINY.read_text())
    (tmp_path / "results" / "gauge_summary.csv").write_text(BROKEN_CSV)
    code, err = _cli(capsys, "report", "scale", tmp_path, tmp_path, "-o", tmp_path / "page")
    assert code == 2 and f"{tmp_path / 'results'}: gauge_summary.csv: not a table" in err


@pytest.mark.parametrize("verb", ["stability", "speed-error"])
def test_a_sweep_report_of_a_results_store_that_is_no_database_names_it(tmp_path, capsys, verb):
    (tmp_path / "results.sqlite").write_text("garbage")
    code, err = _cli(capsys, "report", verb, tmp_path)
    assert code == 2 and f"{tmp_path}: sweep_dir: results.sqlite is not a sweep's results store" in err


@pytest.mark.parametrize("verb", ["approach", "forcing-variants"])
def test_the_approach_pages_of_a_folder_that_is_no_one_way_run_name_it(tmp_path, capsys, verb):
    out = tmp_path / ("page" if verb == "approach" else "page.md")
    code, err = _cli(capsys, "report", verb, tmp_path / "run", "-o", out)
    assert code == 2 and f"{tmp_path / 'run'}: case_dir: no " in err
    assert not out.exists()


def _tiny_with(tmp_path: Path, old: str, new: str) -> Path:
    """TINY written to tmp_path/scene.yaml with its one ``old`` replaced by ``new``."""
    text = TINY.read_text()
    assert text.count(old) == 1, old
    scene = tmp_path / "scene.yaml"
    scene.write_text(text.replace(old, new))
    return scene


@pytest.mark.parametrize("old, new, field", [
    ("write_interval_s: 0.25", "write_interval_s: .inf", "run.write_interval_s"),
    ("probe_interval_s: 0.025", "probe_interval_s: .nan", "outputs.probe_interval_s"),
    ("friction_factor: 0.0293", "friction_factor: .inf", "bed.friction_factor"),
    ("width_m: 0.3", "width_m: .inf", "flume.width_m"),
])
def test_a_scene_number_that_is_not_finite_names_the_file_and_the_field(tmp_path, capsys, old, new, field):
    """Infinity and NaN are refused by the scene, before the planner's arithmetic or the renderer's
    number filter (which raises a plain ValueError, marked internal) could meet them."""
    scene = _tiny_with(tmp_path, old, new)
    code, err = _cli(capsys, "render", scene, "-o", tmp_path / "case")
    assert code == 2 and f"{scene}: {field}: Input should be a finite number" in err, err
    assert not (tmp_path / "case").exists()


@pytest.mark.parametrize("key", ["gauges.-1.x_m", "gauges.3.x_m", "gauges.\u00b2.x_m", "debris.-1.x_m"])
def test_a_set_list_index_outside_0_to_n_names_the_file_and_the_key(tmp_path, capsys, key):
    code, err = _cli(capsys, "render", TINY, "--set", f"{key}=0.3", "-o", tmp_path / "case")
    assert code == 2 and f"{TINY}: {key}: no item" in err, err
    assert not (tmp_path / "case").exists()


def test_a_sweep_axis_with_a_negative_list_index_names_the_sweep_and_the_key(tmp_path, capsys):
    sweep = tmp_path / "sweep.yaml"
    sweep.write_text(f"name: s\nbase: {TINY}\nmode: grid\naxes:\n  gauges.-1.x_m: [0.3, 0.4]\n")
    code, err = _cli(capsys, "sweep", sweep, "--dry-run")
    assert code == 2 and f"{sweep}: " in err and "gauges.-1.x_m: no item '-1' in a list of 3" in err, err


def test_a_set_list_index_inside_the_list_sets_that_item():
    from orchestrator.scene.scenefile import load_scene

    assert [g.x_m for g in load_scene(TINY, ["gauges.1.x_m=0.35"]).gauges[:2]] == [-0.05, 0.35]


GAUGE_SUMMARY = "gauge,arrival_s,peak_elevation_m\nWG1,0.5,0.1\n"


@pytest.mark.parametrize("table, text, column", [
    ("gauge_summary.csv", "name,arrival_s\nWG1,0.5\n", "'gauge'"),
    ("impacts.csv", "body,time_s\nd1,1.0\n", "'kind'"),
    ("column_forces.csv", "time_s,force_N\n0.0,1.0\n", "'hydro_force_x_N'"),
    ("gauges.csv", "t,WG1_elevation_m\n0.0,0.1\n", "'time_s'"),
])
def test_report_scale_of_a_table_without_its_columns_names_the_table_and_the_column(tmp_path, capsys, table, text,
                                                                                    column):
    run = tmp_path / "run"
    (run / "results").mkdir(parents=True)
    (run / "scene.yaml").write_text(TINY.read_text())
    (run / "results" / "gauge_summary.csv").write_text(GAUGE_SUMMARY)
    (run / "results" / table).write_text(text)
    out = tmp_path / "page"
    code, err = _cli(capsys, "report", "scale", run, run, "-o", out)
    assert code == 2 and f"{run / 'results'}: {table}: no column {column}" in err, err
    assert not out.exists()


@pytest.mark.parametrize("plan", ["garbage", "[1, 2]"])
def test_report_layouts_of_a_run_whose_plan_json_is_no_plan_names_the_file(tmp_path, capsys, plan):
    run = tmp_path / "run"
    (run / "results").mkdir(parents=True)
    (run / "plan.json").write_text(plan)
    (run / "results" / "summary.json").write_text('{"status": "finished"}')
    out = tmp_path / "page"
    code, err = _cli(capsys, "report", "layouts", run, "-o", out)
    assert code == 2 and f"{run}: plan.json: not the plan `debrisfoam render` writes" in err, err
    assert not any(out.iterdir())  # the folder -o names is made (and tried) before the runs are read


# --------------------------------------------------------------------------- the library's own checks name the field

def test_library_arguments_out_of_range_are_input_errors_naming_the_argument(tmp_path):
    from orchestrator.contact.settings import ContactSettings
    from orchestrator.plan.scale import froude_factor
    from orchestrator.run.monitor import DivergenceLimits
    from orchestrator.run.runner import run_case

    for make, field in [(lambda: ContactSettings(gap_m=0.0), "gap_m"),
                        (lambda: froude_factor(0.0), "depth_m"),
                        (lambda: froude_factor(float("inf")), "depth_m"),
                        (lambda: DivergenceLimits(courant_factor=0.5), "courant_factor"),
                        (lambda: DivergenceLimits(water_balance=-1.0), "water_balance"),
                        (lambda: run_case(tmp_path, reconstruct="some"), "reconstruct")]:
        with pytest.raises(InputError) as err:
            make()
        assert err.value.field == field


def test_case_files_that_are_not_what_the_run_wrote_name_the_file_and_the_entry(tmp_path):
    from orchestrator.run.bodypoints import write_points
    from orchestrator.results.fringe import fringe_flux

    points = tmp_path / "points"
    points.write_text("3\n(\n(0 0 0)\n)\n")
    with pytest.raises(InputError, match=f"{points}: FoamFile: no FoamFile header"):
        write_points(points, [[0.0, 0.0, 0.0]])
    (tmp_path / "0.5").mkdir()
    with pytest.raises(InputError, match=f"{tmp_path / '0.5'}: cellTypes, .*: missing"):
        fringe_flux(tmp_path, "0.5")


def _first_segment(axis: str, key: str, value):
    def change(grid: dict) -> None:
        grid[axis][0][key] = value
    return change


def _gap_after_first_segment(grid: dict) -> None:
    grid["x"][1]["start_m"] += 0.01


@pytest.mark.parametrize("change, field", [
    (_first_segment("x", "end_m", -1e3), "end_m"),
    (_first_segment("z", "cells", 0), "cells"),
    (_first_segment("y", "grading", 0.0), "grading"),
    (lambda grid: grid.update(z=[]), "background.z"),
    (_gap_after_first_segment, "background.x"),
    (lambda grid: grid.update(holes=[[99, 0, 0]]), "background.holes"),
])
def test_a_plan_json_grid_that_breaks_a_grid_rule_is_an_input_error_naming_the_field(change, field):
    """plan.json is read back into a plan (ModelPlan.from_json); a hand-edited grid in it is bad input."""
    import json

    from orchestrator.plan.model import ModelPlan
    from orchestrator.plan.planner import plan_case
    from orchestrator.scene.scenefile import load_scene

    data = json.loads(plan_case(load_scene(TINY)).to_json())
    assert len(data["background"]["x"]) > 1
    change(data["background"])
    with pytest.raises(InputError) as err:
        ModelPlan.from_json(json.dumps(data))
    assert err.value.field == field
