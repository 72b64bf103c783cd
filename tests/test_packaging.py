"""A plain (non-editable) wheel carries the templates and the example scenes and renders a case
from another folder; installed into a fresh environment, its `debrisfoam` lists the shipped scenes,
renders one by name and dry-runs a shipped sweep from an empty folder; `debrisfoam --version`
reports the package's version."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import sysconfig
import tomllib
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent


@pytest.fixture(scope="module")
def wheel(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("wheel")
    proc = subprocess.run([sys.executable, "-m", "pip", "wheel", str(ROOT), "--no-deps", "-q", "-w", str(out)],
                          capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    (path,) = out.glob("debrisfoam-*.whl")
    return path


@pytest.mark.slow
def test_the_wheel_carries_every_template_and_scene(wheel):
    names = set(zipfile.ZipFile(wheel).namelist())
    for folder, package in (("templates", "orchestrator/templates"), ("cases", "orchestrator/scenes")):
        files = [p for p in (ROOT / folder).rglob("*") if p.is_file() and "__pycache__" not in p.parts]
        assert files
        for f in files:
            assert f"{package}/{f.relative_to(ROOT / folder).as_posix()}" in names, f


@pytest.mark.slow
def test_the_wheel_carries_every_code_package(wheel):
    names = set(zipfile.ZipFile(wheel).namelist())
    packages = [p.parent.relative_to(ROOT).as_posix() for top in ("orchestrator", "analytical")
                for p in (ROOT / top).rglob("__init__.py")]
    assert len(packages) >= 10
    missing = [p for p in packages if f"{p}/__init__.py" not in names]
    assert not missing, f"packages not in the wheel (pyproject.toml [tool.setuptools] packages): {missing}"


@pytest.mark.slow
def test_an_installed_wheel_renders_a_scene_from_another_folder(wheel, tmp_path):
    target = tmp_path / "site"
    proc = subprocess.run([sys.executable, "-m", "pip", "install", "-q", "--no-deps", "--target", str(target),
                           str(wheel)], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    work = tmp_path / "elsewhere"
    work.mkdir()
    (work / "1debris.yaml").write_text((ROOT / "cases" / "1debris.yaml").read_text())
    env = {"PYTHONPATH": str(target), "PATH": "/usr/bin:/bin"}
    run = subprocess.run([sys.executable, "-m", "orchestrator.cli", "render", "1debris.yaml", "-o", "case"],
                         cwd=work, env=env, capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    assert (work / "case" / "system" / "blockMeshDict").is_file()
    assert (work / "case" / "system" / "controlDict").is_file()
    where = subprocess.run([sys.executable, "-c", "import orchestrator.case.render as r; print(r.TEMPLATE_DIR)"],
                           cwd=work, env=env, capture_output=True, text=True)
    assert where.stdout.strip().startswith(str(target))  # the wheel's templates, not the repository's


def test_version_is_the_packages():
    version = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["version"]
    proc = subprocess.run([sys.executable, "-m", "orchestrator.cli", "--version"], capture_output=True, text=True)
    assert proc.returncode == 0
    assert proc.stdout.strip() == f"debrisfoam {version}"


@pytest.mark.slow
def test_the_installed_wheel_names_its_scenes_and_sweeps_from_any_folder(wheel, tmp_path):
    """A fresh venv (no pip, no packages) gets the wheel alone (pip --python, so that the
    `debrisfoam` script runs the venv's interpreter); the dependencies come from this environment's
    site-packages on PYTHONPATH, which holds no copy of the package (an editable install's .pth is
    not read from PYTHONPATH), so everything below runs the wheel's code and data, offline."""
    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", "--without-pip", str(venv)], check=True)
    python = venv / "bin" / "python"
    clean = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}  # a source tree there reads as installed
    proc = subprocess.run([sys.executable, "-m", "pip", "--python", str(python), "install", "-q", "--no-deps",
                           "--no-index", str(wheel)], capture_output=True, text=True, env=clean)
    assert proc.returncode == 0, proc.stderr
    deps = {sysconfig.get_paths()["purelib"], sysconfig.get_paths()["platlib"]}
    env = {"PYTHONPATH": ":".join(sorted(deps)), "PATH": f"{venv / 'bin'}:/usr/bin:/bin", "HOME": str(tmp_path)}
    work = tmp_path / "elsewhere"
    work.mkdir()

    def debrisfoam(*args):
        return subprocess.run([str(venv / "bin" / "debrisfoam"), *args], cwd=work, env=env, capture_output=True,
                              text=True)

    where = subprocess.run([str(python), "-c", "import orchestrator; print(orchestrator.__file__)"], cwd=work,
                           env=env, capture_output=True, text=True)
    assert where.stdout.strip().startswith(str(venv)), where  # the wheel's package, not the repository's

    listed = debrisfoam("scenes", "--json")
    assert listed.returncode == 0, listed.stderr
    listed = json.loads(listed.stdout)
    assert listed["folder"].startswith(str(venv))
    names = {s["name"] for s in listed["scenes"]}
    assert {"1debris", "nodebris", "tiny-nodebris", "hard/glancing"} <= names
    assert {"tiny-mesh-study", "debris-layouts", "mesh-study"} <= {s["name"] for s in listed["sweeps"]}

    render = debrisfoam("render", "1debris", "-o", "case", "--json")
    assert render.returncode == 0, render.stderr
    assert json.loads(render.stdout)["planned_cells"] == 181500
    assert (work / "case" / "system" / "controlDict").is_file()
    assert "name: 1debris" in (work / "case" / "scene.yaml").read_text()

    for sweep in ("tiny-mesh-study", "debris-layouts"):  # a base scene, and a list of scenes, inside the package
        dry = debrisfoam("sweep", sweep, "--dry-run", "--json")
        assert dry.returncode == 0, dry.stderr
        assert len(json.loads(dry.stdout)["members"]) >= 2
    assert sorted(p.name for p in work.iterdir()) == ["case"]  # a dry run writes nothing

    missing = debrisfoam("render", "no-such-scene", "-o", "x")
    assert missing.returncode == 2 and "debrisfoam scenes" in missing.stderr
