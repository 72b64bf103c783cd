"""A plain (non-editable) wheel carries the templates and the example scenes and renders a case
from another folder; `debrisfoam --version` reports the package's version."""

from __future__ import annotations

import subprocess
import sys
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
