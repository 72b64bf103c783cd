"""What a user meets on the way in: impossible work refused before it starts, and every bad input
an exit 2 naming the file and the field (or the flag) with nothing written.

One test per class of input: the resource guard (cells against OpenFOAM's labels and this
machine's memory, the estimated time, the analytical verbs' sizes), unwritable outputs, scene
encodings, folders that are not cases (or never ran), a closed pipe, and implausible scenes
(density, a column in the reservoir, a key given twice, a boolean for a number, counts < 1).
Each runs the real command line: in-process through :func:`orchestrator.cli.main` where time or
output is measured, as a separate process where the terminal or the pipe matters.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

import pytest

from analytical.errors import InputError
from orchestrator.cli import main
from orchestrator.plan.resources import (
    BYTES_PER_CELL,
    MAX_CELLS_LABELS,
    Demand,
    LargeRunError,
    Machine,
    check_resources,
)
from tests.conftest import ROOT, run_cli

SCENE = ROOT / "cases" / "1debris.yaml"
TINY = ROOT / "cases" / "tiny-nodebris.yaml"
TINY_CASE = ROOT / "tests" / "data" / "post" / "tiny-nodebris"
ABSURD = "mesh.cell_size_m=1e-6"


def _files(folder: Path) -> list[Path]:
    return sorted(p for p in folder.rglob("*")) if folder.exists() else []


def _cli(capsys, *argv: str) -> tuple[int, str, float]:
    """(exit code, stderr, wall seconds) of `debrisfoam ARGV` run in this process."""
    t0 = time.perf_counter()
    code = main(list(argv))
    seconds = time.perf_counter() - t0
    return code, capsys.readouterr().err, seconds


@pytest.fixture
def read_only(tmp_path):
    """An empty folder nobody can write in, root included (root: chattr +i; others: mode 555)."""
    folder = tmp_path / "read-only"
    folder.mkdir()
    if os.geteuid() == 0:
        proc = subprocess.run(["chattr", "+i", str(folder)], capture_output=True, text=True)
        if proc.returncode:
            pytest.fail(f"as root a read-only folder needs `chattr +i` (e2fsprogs, ext4): {proc.stderr}")
        yield folder
        subprocess.run(["chattr", "-i", str(folder)], check=True)
    else:
        folder.chmod(0o555)
        yield folder
        folder.chmod(0o755)


# --------------------------------------------------------------------------- the resource guard


def _sweep_file(tmp_path: Path, sizes: str, base: Path = SCENE) -> Path:
    path = tmp_path / "sweep.yaml"
    path.write_text(f"name: guard\nbase: {base}\nmode: grid\naxes:\n  mesh.cell_size_m: {sizes}\n")
    return path


@pytest.mark.parametrize("verb", ["validate", "render", "ensemble", "sweep"])
def test_an_absurd_cell_size_is_refused_at_once_naming_the_cells_and_the_limit(tmp_path, capsys, verb):
    out = tmp_path / "out"
    argv = {
        "validate": ["validate", str(SCENE), "--set", ABSURD],
        "render": ["render", str(SCENE), "-o", str(out), "--set", ABSURD],
        "ensemble": ["ensemble", str(SCENE), "-n", "2", "-o", str(out), "--set", ABSURD],
        "sweep": ["sweep", str(_sweep_file(tmp_path, "[0.04, 1.0e-6]")), "-o", str(out), "--dry-run"],
    }[verb]
    code, err, seconds = _cli(capsys, *argv)
    assert code == 2, err
    assert "mesh.cell_size_m" in err and "planned cells" in err and f"{MAX_CELLS_LABELS:,}" in err
    assert str(SCENE) in err or "sweep.yaml" in err
    assert seconds < 2.0, f"{verb} took {seconds:.2f} s to refuse"
    assert not out.exists()


def test_memory_over_the_machine_is_refused_and_over_half_of_it_needs_a_yes():
    machine = Machine(cores=2, total_memory_B=8_000_000_000, available_memory_B=6_000_000_000)
    # 5 M interFoam cells: 10 GB at the measured 2,000 bytes a cell, more than the machine has
    with pytest.raises(InputError) as err:
        check_resources(Demand(5_000_000, "interFoam", 2, 3600.0), "s.yaml", machine=machine)
    assert err.value.field == "mesh.cell_size_m" and err.value.source == "s.yaml"
    assert "5,000,000 planned cells" in err.value.rule and "10.2 GB" in err.value.rule
    fit = (8_000_000_000 - 2 * 120_000_000) // BYTES_PER_CELL["interFoam"]
    assert f"{fit:,} cells" in err.value.rule
    # 2 M cells: 4.2 GB, over half of the 6 GB available: asked, allowed when confirmed
    with pytest.raises(LargeRunError) as soft:
        check_resources(Demand(2_000_000, "interFoam", 2, 3600.0), "s.yaml", machine=machine)
    assert "50% of the 6 GB available now" in soft.value.messages[0] and "--yes" in str(soft.value)
    assert check_resources(Demand(2_000_000, "interFoam", 2, 3600.0), machine=machine, confirmed=True)
    # 100 k cells for 1 h: nothing to say
    assert check_resources(Demand(100_000, "interFoam", 2, 3600.0), machine=machine) == []


def test_a_long_run_warns_in_validate_and_is_refused_without_yes(tmp_path):
    long_run = "run.end_time_s=5000"  # 10,032 cells, about 8 h of solver time (over 6 h)
    proc = run_cli("validate", str(TINY), "--set", long_run)
    assert proc.returncode == 0 and "estimated solver time" in proc.stderr and "over 6 h" in proc.stderr
    out = tmp_path / "case"
    proc = subprocess.run([sys.executable, "-m", "orchestrator.cli", "render", str(TINY), "-o", str(out), "--set",
                           long_run], capture_output=True, text=True, cwd=ROOT, stdin=subprocess.DEVNULL)
    assert proc.returncode == 2 and "--yes" in proc.stderr and str(TINY) in proc.stderr
    assert "mesh.cell_size_m" in proc.stderr and not out.exists()
    proc = subprocess.run([sys.executable, "-m", "orchestrator.cli", "render", str(TINY), "-o", str(out), "--set",
                           long_run, "--yes"], capture_output=True, text=True, cwd=ROOT, stdin=subprocess.DEVNULL)
    assert proc.returncode == 0, proc.stderr
    assert (out / "plan.json").is_file() and "over 6 h" in proc.stderr


def test_a_sweep_over_a_soft_limit_warns_in_its_dry_run_and_needs_yes_to_run(tmp_path):
    sweep = tmp_path / "long.yaml"
    sweep.write_text(f"name: long\nbase: {TINY}\nset:\n  run.end_time_s: 5000\nmode: grid\naxes:\n"
                     "  mesh.cell_size_m: [0.025]\n")
    out = tmp_path / "out"
    proc = run_cli("sweep", str(sweep), "-o", str(out), "--dry-run")
    assert proc.returncode == 0 and "member 1 (mesh.cell_size_m=0.025): 10,032 planned cells" in proc.stderr
    proc = subprocess.run([sys.executable, "-m", "orchestrator.cli", "sweep", str(sweep), "-o", str(out)],
                          capture_output=True, text=True, cwd=ROOT, stdin=subprocess.DEVNULL)
    assert proc.returncode == 2 and str(sweep) in proc.stderr and "--yes" in proc.stderr and "over 6 h" in proc.stderr
    assert not out.exists()


def test_run_of_a_case_planned_over_a_soft_limit_needs_yes(tmp_path):
    plan = json.loads((TINY_CASE / "plan.json").read_text())
    plan["estimated_wall_time_s"] = 7 * 3600.0  # as a case rendered with --yes records it
    (tmp_path / "plan.json").write_text(json.dumps(plan))
    proc = subprocess.run([sys.executable, "-m", "orchestrator.cli", "run", str(tmp_path)], capture_output=True,
                          text=True, cwd=ROOT, stdin=subprocess.DEVNULL)
    assert proc.returncode == 2 and "estimated solver time about" in proc.stderr and "--yes" in proc.stderr
    assert str(tmp_path / "plan.json") in proc.stderr
    assert [p.name for p in tmp_path.iterdir()] == ["plan.json"]


@pytest.mark.parametrize("argv, field, size", [
    (["analytical", "response", "--model", "sdof", "--magnitude", "100", "--duration", "0.005", "--t-end", "1e6"],
     "--t-end", "100,000,000,001 samples"),
    (["analytical", "modes", "--set", "column.elements=100000"], "column.elements", "100,000 elements"),
])
def test_analytical_sizes_beyond_memory_are_bad_input(capsys, argv, field, size):
    code, err, seconds = _cli(capsys, *argv)
    assert code == 2 and field in err and size in err and "MemoryError" not in err
    assert seconds < 2.0


# --------------------------------------------------------------------------- unwritable outputs


@pytest.mark.parametrize("verb", ["preview", "case", "ensemble", "sweep", "dambreak", "response"])
def test_an_unwritable_output_is_bad_input_naming_it(capsys, read_only, verb):
    target = read_only / "out"
    argv = {
        "preview": ["preview", str(TINY), "-o", str(read_only / "x.png")],
        "case": ["case", str(TINY), "-o", str(target)],
        "ensemble": ["ensemble", str(SCENE), "-n", "2", "-o", str(target)],
        "sweep": ["sweep", str(ROOT / "cases" / "sweeps" / "tiny-mesh-study.yaml"), "-o", str(target)],
        "dambreak": ["analytical", "dambreak", "--model", "ritter", "--h0", "0.4", "--profile", "0.5", "--out",
                     str(read_only / "x.csv")],
        "response": ["analytical", "response", "--model", "sdof", "--magnitude", "100", "--duration", "0.005",
                     "--out", str(read_only / "x.csv")],
    }[verb]
    code, err, _ = _cli(capsys, *argv)
    assert code == 2, err
    assert "--out" in err and str(read_only) in err and "cannot write" in err
    assert _files(read_only) == []


def test_post_into_a_read_only_results_folder_is_bad_input_and_keeps_what_is_there(tmp_path, capsys):
    case = tmp_path / "case"
    shutil.copytree(TINY_CASE, case)
    results = case / "results"
    results.mkdir()
    (results / "summary.json").write_text('{"kept": true}')
    if os.geteuid() == 0:
        subprocess.run(["chattr", "+i", str(results)], check=True)
    else:
        results.chmod(0o555)
    try:
        code, err, _ = _cli(capsys, "post", str(case), "--tables-only")
    finally:
        if os.geteuid() == 0:
            subprocess.run(["chattr", "-i", str(results)], check=True)
        else:
            results.chmod(0o755)
    assert code == 2 and "case_dir" in err and str(results) in err
    assert [p.name for p in results.iterdir()] == ["summary.json"]
    assert (results / "summary.json").read_text() == '{"kept": true}'


def test_a_refused_preview_makes_no_folders(tmp_path, capsys):
    out = tmp_path / "new" / "sub" / "x.png"
    code, err, _ = _cli(capsys, "preview", str(SCENE), "-o", str(out), "--set", ABSURD)
    assert code == 2 and "mesh.cell_size_m" in err
    assert not (tmp_path / "new").exists()


# --------------------------------------------------------------------------- encodings


@pytest.mark.parametrize("encoding", ["utf-8-sig", "utf-16", "utf-16-be-bom"])
def test_scenes_with_a_byte_order_mark_are_read_by_every_verb(tmp_path, capsys, encoding):
    def write(path: Path, text: str) -> Path:
        raw = (b"\xfe\xff" + text.encode("utf-16-be")) if encoding == "utf-16-be-bom" else text.encode(encoding)
        path.write_bytes(raw)
        return path

    scene = write(tmp_path / "tiny.yaml", TINY.read_text())
    sweep = write(tmp_path / "sweep.yaml", "name: enc\nbase: tiny.yaml\nmode: grid\naxes:\n  mesh.cell_size_m: [0.05]\n")
    for argv in (["validate", str(scene)], ["analytical", "modes", "--scene", str(scene)],
                 ["sweep", str(sweep), "-o", str(tmp_path / "sw"), "--dry-run"],
                 ["render", str(scene), "-o", str(tmp_path / "case")]):
        code, err, _ = _cli(capsys, *argv)
        assert code == 0, (argv, err)
    assert "name: tiny-nodebris" in (tmp_path / "case" / "scene.yaml").read_text()


def test_a_scene_in_another_encoding_is_bad_input_naming_the_file(tmp_path, capsys):
    scene = tmp_path / "latin1.yaml"
    scene.write_bytes(TINY.read_text().replace("Tiny dam break", "Tiny dam break \u00e0 Ottawa").encode("latin-1"))
    code, err, _ = _cli(capsys, "validate", str(scene))
    assert code == 2 and str(scene) in err and "UTF-8" in err


# --------------------------------------------------------------------------- folders, pipes


def test_run_on_a_folder_that_is_not_a_case_is_bad_input(tmp_path, capsys):
    (tmp_path / "notes.txt").write_text("not a case")
    code, err, _ = _cli(capsys, "run", str(tmp_path))
    assert code == 2 and "case_dir" in err and "not a debrisfoam case" in err and str(tmp_path) in err
    assert [p.name for p in tmp_path.iterdir()] == ["notes.txt"]


def test_post_on_a_case_that_never_ran_is_bad_input_and_writes_nothing(tmp_path, capsys):
    shutil.copy(TINY_CASE / "plan.json", tmp_path)
    shutil.copy(TINY_CASE / "scene.yaml", tmp_path)
    code, err, _ = _cli(capsys, "post", str(tmp_path))
    assert code == 2 and "this case has not run" in err and f"debrisfoam run {tmp_path}" in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["plan.json", "scene.yaml"]


def test_a_closed_pipe_ends_quietly():
    proc = subprocess.Popen([sys.executable, "-m", "orchestrator.cli", "scenes", "--json"], cwd=ROOT,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    proc.stdout.close()  # the reader is gone before the command writes a byte (as `| head` after its line)
    err = proc.stderr.read().decode()
    proc.stderr.close()
    assert proc.wait(timeout=60) == 1
    assert "Traceback" not in err and "BrokenPipe" not in err and "Exception ignored" not in err


# --------------------------------------------------------------------------- implausible scenes


@pytest.mark.parametrize("mass, rule", [("1000", "denser than any material"), ("1e-9", "lighter than air")])
def test_an_impossible_body_density_is_bad_input(capsys, mass, rule):
    code, err, _ = _cli(capsys, "validate", str(SCENE), "--set", f"debris.0.mass_kg={mass}")
    assert code == 2 and "debris.0.mass_kg" in err and rule in err and str(SCENE) in err


def test_an_unlikely_body_density_is_a_warning(capsys):
    code, err, _ = _cli(capsys, "validate", str(SCENE), "--set", "debris.0.mass_kg=2.7")  # 5,000 kg/m3
    assert code == 0 and "warning: debris 'debris1': bulk density 5000 kg/m3" in err


def test_a_column_in_the_reservoir_is_bad_input(capsys):
    code, err, _ = _cli(capsys, "validate", str(SCENE), "--set", "column.x_m=-1.0")
    assert code == 2 and "column.x_m" in err and "downstream of the gate" in err


@pytest.mark.parametrize("change, field, rule", [
    (("end_time_s: 0.5,", "end_time_s: 0.5, end_time_s: 0.7,"), "run.end_time_s", "given twice (lines"),
    (("end_time_s: 0.5,", "end_time_s: true,"), "run.end_time_s", "not a boolean"),
    (("cell_size_m: 0.025,", "cell_size_m: 0.025, coarsening_ratio: false,"), "mesh.coarsening_ratio",
     "given twice"),
])
def test_duplicate_keys_and_booleans_for_numbers_are_bad_input(tmp_path, capsys, change, field, rule):
    scene = tmp_path / "scene.yaml"
    text = TINY.read_text()
    assert change[0] in text
    scene.write_text(text.replace(change[0], change[1]))
    code, err, _ = _cli(capsys, "validate", str(scene))
    assert code == 2 and field in err and rule in err and str(scene) in err


@pytest.mark.parametrize("argv, flag", [
    (["analytical", "modes", "--count", "-3"], "--count"),
    (["analytical", "dambreak", "--model", "ritter", "--h0", "0.4", "--profile", "0.5", "--points", "0", "--out"],
     "--points"),
])
def test_counts_below_one_are_bad_input(tmp_path, capsys, argv, flag):
    if argv[-1] == "--out":
        argv = [*argv, str(tmp_path / "x.csv")]
    code, err, _ = _cli(capsys, *argv)
    assert code == 2 and flag in err
    assert _files(tmp_path) == []


STREET = ROOT / "cases" / "design-street.yaml"


@pytest.mark.parametrize("setting, words", [
    ("design.mass_kg=[2.3,30.48]", "masses in kg, not tonnes"),  # tonnes for kg: lighter than air
    ("design.mass_kg=[2300,30480000]", "bulk density of 7.965e+05"),
    ("design.start_x_m=[52,62]", "a body must start upstream of it"),  # past the column
    ("design.start_x_m=[-80,35]", "upstream of the flume's upstream end"),
    ("design.start_y_m=[-40,40]", "beyond the walls"),  # outside the 20 m street
    ("design.start_y_m=[-8,8]", "beyond the walls"),  # a turned container reaches through the wall
])
def test_a_design_draw_that_cannot_be_is_refused_before_anything_runs(capsys, tmp_path, setting, words):
    out = tmp_path / "design"
    code, err, _ = _cli(capsys, "design", str(STREET), "-o", str(out), "--yes", "--set", setting)
    assert code == 2
    assert f"design-street.yaml: design.{setting.split('=')[0].split('.')[1]}:" in err and words in err
    assert _files(out) == []


def test_the_shipped_design_draws_are_accepted():
    from orchestrator.scene.scenefile import load_scene

    design = load_scene(STREET).design
    assert design.start_x_m == (25.0, 35.0) and design.start_y_m == (-4.0, 4.0)


@pytest.mark.parametrize("argv, flag", [
    (["--stiffness", "0"], "--stiffness"),  # the one k the user gave, not --debris-stiffness
    (["--importance", "12.5"], "--importance"),  # Table 6.8-1 has 1.0 and 1.25 only
])
def test_the_code_verb_names_the_flag_the_user_gave(capsys, argv, flag):
    code, err, _ = _cli(capsys, "analytical", "asce7", "--velocity", "4", "--mass", "2300", *argv)
    assert code == 2 and f"bad input: {flag}:" in err


def test_the_code_verb_takes_each_importance_factor_of_table_6_8_1(capsys):
    for value in ("1.0", "1.25"):
        code, _, _ = _cli(capsys, "analytical", "asce7", "--velocity", "1.6", "--mass", "0.236", "--importance", value)
        assert code == 0
