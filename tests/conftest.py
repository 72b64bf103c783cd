"""Shared fixtures: run the CLI in-process or as the installed console script."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
#: The shipped scenes (1debris.yaml, ..., hard/).
CASES = ROOT / "cases"


def debris(name: str, size_m, mass_kg: float, centre_m, *, friction: float | None = None, contact: dict | None = None,
           **fields):
    """A debris body (the scene's DebrisBody) at a start, as the transport carries it: ``friction``
    its Coulomb coefficient (contact.bed_friction_coefficient), ``contact`` its contact section's
    other keys, ``fields`` its own (yaw_deg, velocity_m_s, wall_thickness_m, ...)."""
    from orchestrator.scene.schema import DebrisBody, DebrisContact

    keys = dict(contact or {})
    if friction is not None:
        keys["bed_friction_coefficient"] = friction
    return DebrisBody(name=name, size_m=size_m, mass_kg=mass_kg, centre_m=centre_m, contact=DebrisContact(**keys),
                      **fields)


def input_error(field: str, call, /, *args, **kwargs):
    """``call(*args, **kwargs)`` must raise an InputError (a ValueError too) naming ``field``: the error."""
    from analytical.errors import InputError

    with pytest.raises(InputError) as info:
        call(*args, **kwargs)
    assert info.value.field == field
    assert isinstance(info.value, ValueError)
    return info.value


def closed_tank(gauge: tuple[str, float], mesh: dict | None = None, run: dict | None = None, **sections) -> dict:
    """A 2D closed tank as a scene's data: 0.4 m reservoir 0.2 m deep, the end wall 0.8 m past the
    gate, 0.6 m walls, 2 cm cells, 1 s on one core; one gauge (name, x) on its axis. ``mesh`` and
    ``run`` add to those sections, ``sections`` add sections."""
    return {
        "name": "tank",
        "flume": {"length_m": 1.2, "width_m": 0.2, "height_m": 0.6, "downstream_end": "closed"},
        "reservoir": {"length_m": 0.4, "depth_m": 0.2, "gate": "instant"},
        "bed": {"wet_depth_m": 0.015, "friction_factor": 0.0293},
        "debris": [],
        "gauges": [{"name": gauge[0], "x_m": gauge[1], "y_m": 0.0}],
        "mesh": {"cell_size_m": 0.02, "coarsening_ratio": 1, **(mesh or {})},
        "run": {"end_time_s": 1.0, "cores": 1, **(run or {})},
        **sections,
    }


def package_modules(*owners: str) -> list[str]:
    """The modules of orchestrator/ (paths from the repository's root) outside the ``owners`` (path
    prefixes): what a scan for a format read outside its owners goes through."""
    paths = (str(p.relative_to(ROOT)) for p in sorted((ROOT / "orchestrator").rglob("*.py")))
    return [p for p in paths if not p.startswith(owners)]


def run_cli(*args: str, cwd: Path | None = None) -> subprocess.CompletedProcess:
    """Run `debrisfoam ARGS` as a user would (a separate process)."""
    return subprocess.run(
        [sys.executable, "-m", "orchestrator.cli", *args],
        capture_output=True,
        text=True,
        cwd=cwd or ROOT,
    )


def check_report_verb(verb: str, sweep: Path, out: Path) -> None:
    """`debrisfoam report VERB SWEEP` writes its page (exit 0, report.md named in --json) and an
    empty folder is bad input (exit 2) naming that it holds no post-processed member."""
    proc = run_cli("report", verb, str(sweep), "-o", str(out / "page"), "--json")
    assert proc.returncode == 0, proc.stderr
    assert json.loads(proc.stdout)["report"].endswith("report.md")
    (out / "empty").mkdir()
    bad = run_cli("report", verb, str(out / "empty"), "-o", str(out / "page2"))
    assert bad.returncode == 2 and "no post-processed member" in bad.stderr


def render_and_run(scene: Path, case: Path, *sets: str) -> dict:
    """Render ``scene`` into ``case`` (with ``--set`` overrides) and run it with the CLI, each step
    asserted to succeed; the case's plan.json."""
    overrides = [a for item in sets for a in ("--set", item)]
    for args in (("render", str(scene), "-o", str(case), *overrides), ("run", str(case))):
        proc = run_cli(*args)
        assert proc.returncode == 0, proc.stderr[-2000:]
    return json.loads((case / "plan.json").read_text())


def run_container(scene: Path, case: Path) -> tuple[dict, float, float]:
    """Render and run ``scene`` (its first body a container) into ``case``: the plan, the
    container's height and its draft in fresh water (m)."""
    plan = render_and_run(scene, case)
    body = plan["bodies"][0]
    mass, (length, width, height) = body["mass_kg"], body["size_m"]
    return plan, height, mass / (998.2 * length * width)


def solvers_kept(case: Path):
    """The runner's default contact settings for ``case``, except that the bodies' motion solvers
    run even while every body is held still (`ContactSettings.hold_still_solvers` off): for tests
    of what v1912's own six-DoF constraints do."""
    from orchestrator.contact.settings import ContactSettings
    from orchestrator.plan.scale import froude_factor
    from orchestrator.run.runner import load_case_info

    depth = load_case_info(case).water_depth_m
    return ContactSettings(hold_still_solvers=False).froude_scaled(froude_factor(depth) if depth > 0 else 1.0)


def cli_json(*args: str) -> dict:
    proc = run_cli(*args, "--json")
    assert proc.returncode == 0, proc.stderr
    return json.loads(proc.stdout)


@pytest.fixture
def openfoam():
    """Skip-free guard: tests marked openfoam need the solver; `make test` installs it."""
    if shutil.which("overInterDyMFoam") is None:
        pytest.fail("OpenFOAM is not installed: run `make openfoam` (make test does it)")


@pytest.fixture(scope="module")
def current(tmp_path_factory):
    """A 0.6 m/s current 0.1 m deep over x 0-2 m, y +-0.3 m and 0-3 s (the ensemble and design tests'
    flume, its column at x 1 m), and the path of the .npz the workers load."""
    import numpy as np

    from orchestrator.transport.flow import FlowField

    flow = FlowField.uniform_current(0.1, 0.6, x_m=np.linspace(0.0, 2.0, 21), y_m=np.linspace(-0.3, 0.3, 7),
                                     t_s=np.linspace(0.0, 3.0, 31))
    return flow, str(flow.save(tmp_path_factory.mktemp("flow") / "flow_record.npz"))


@pytest.fixture(scope="session")
def tiny_sweep(tmp_path_factory):
    """The shipped tiny mesh study (cases/sweeps/tiny-mesh-study.yaml), run once per test session
    by the CLI on the local executor: (sweep folder, CompletedProcess). Shared by the sweep tests
    and the speed-error report's."""
    out = tmp_path_factory.mktemp("sweep") / "local"
    proc = run_cli("sweep", str(ROOT / "cases" / "sweeps" / "tiny-mesh-study.yaml"), "-o", str(out))
    return out, proc


#: Longest a single test may take (s): OpenFOAM tests (a hang in v1912's overset addressing is
#: documented) and the rest. pytest-timeout ends the test and reports it as failed.
OPENFOAM_TEST_TIMEOUT_S = 900
TEST_TIMEOUT_S = 300
#: A test that first uses a shared fixture running a whole sweep pays for the sweep (pytest-timeout
#: counts the setup): those get this much.
SWEEP_TEST_TIMEOUT_S = 1800
SWEEP_FIXTURES = {"small_hard", "quick_hard", "tiny_sweep", "local_sweep"}


def pytest_collection_modifyitems(config, items):
    for item in items:
        if item.get_closest_marker("timeout") is None:
            if SWEEP_FIXTURES & set(getattr(item, "fixturenames", ())):
                limit = SWEEP_TEST_TIMEOUT_S
            elif item.get_closest_marker("openfoam"):
                limit = OPENFOAM_TEST_TIMEOUT_S
            else:
                limit = TEST_TIMEOUT_S
            item.add_marker(pytest.mark.timeout(limit))
