"""Guards before anything runs (issue 48, item 6): the design, ensemble and analytical verbs refuse
implausible input with exit 2 naming the field (or flag) the user set and writing nothing; the
realisations' wall time is estimated before they start and needs --yes above a limit; an unstable
rigid-body engine ends a study with exit 1 naming the realisation and no page."""

from __future__ import annotations

import subprocess
import sys

import mujoco
import pytest

from analytical.column import Column
from orchestrator.cli import main
from orchestrator.scene.schema import Design
from orchestrator.scene.scenefile import load_scene
from orchestrator.studies.design import design_batch, design_starts
from orchestrator.studies.engine_watch import UnstableEngineError
from orchestrator.transport.engine import TransportSettings
from orchestrator.transport.mujoco_model import FlumeBounds, PlacedColumn
from tests.conftest import debris
from tests.conftest import ROOT

STREET = ROOT / "cases" / "design-street.yaml"
LAB = ROOT / "cases" / "1debris.yaml"
TINY = ROOT / "tests" / "data" / "scenes" / "tiny-oneway-strike.yaml"


def _refused(capfd, argv, field: str, out=None) -> str:
    code = main(argv)
    err = capfd.readouterr().err
    assert code == 2, err
    assert "bad input: " in err and f"{field}:" in err, err
    if out is not None:
        assert not out.exists()
    return err


@pytest.mark.parametrize("sets, field, words", [
    (["column.height_m=5000"], "column.height_m", "at most 100 m"),
    (["design.debris_stiffness_N_m=42.9"], "design.debris_stiffness_N_m", "1e+05-1e+11 N/m"),
    (["column.x_m=500"], "column.x_m", "past the flume's downstream end"),
    (["column.section.size_m=[600]"], "column.section.size_m", "wider than the flume"),
    (["inundation.speed_m_s=4000"], "inundation.speed_m_s", "30 m/s"),  # named inundation.depth_m before
    (["design.heading_deg=[-3000, 3000]"], "design.heading_deg", "at most a full turn"),
])
def test_implausible_design_scene_values_name_the_field_set(capfd, tmp_path, sets, field, words):
    """Each names the field the user set (column.x_m=500 named run.end_time_s, the 600 m section
    column.x_m) and comes before anything is written."""
    out = tmp_path / "study"
    err = _refused(capfd, ["design", str(STREET), "-o", str(out), *[a for s in sets for a in ("--set", s)]], field, out)
    assert words in err and "design-street.yaml" in err


def test_a_million_realisations_are_estimated_and_need_yes(tmp_path):
    """`design S -n 1000000`: the realisations' wall time is printed before they start (about a
    day on 2 workers for the street's 13 s) and, over the limit, refused without --yes (no
    terminal to ask), naming -n; nothing is written."""
    out = tmp_path / "study"
    proc = subprocess.run([sys.executable, "-m", "orchestrator.cli", "design", str(STREET), "-n", "1000000", "-o",
                           str(out), "--workers", "2"], capture_output=True, text=True, cwd=ROOT,
                          stdin=subprocess.DEVNULL)
    assert proc.returncode == 2, proc.stderr
    assert "1,000,000 realisation(s): about" in proc.stderr and " h of wall time on 2 worker(s)" in proc.stderr
    assert "-n:" in proc.stderr and "--yes" in proc.stderr and "design-street.yaml" in proc.stderr
    assert not out.exists()


def test_the_estimate_stands_on_the_measured_cost(capfd):
    """The benchmark's 10,000 one-body realisations of the 1-debris scene took 1,092 s of CPU
    (benchmarks/ensemble.md): the estimate is within 30 % of it; confirmed (--yes), a long
    estimate is printed and goes ahead."""
    from orchestrator.cli.design import REALISATION_LIMIT_S, confirm_realisations, realisation_seconds

    cpu, how = realisation_seconds(load_scene(LAB), 10_000)
    assert cpu == pytest.approx(1092.0, rel=0.3), how
    wall = confirm_realisations([(load_scene(LAB), 1_000_000)], 2, True, LAB)
    assert wall > REALISATION_LIMIT_S and "1,000,000 realisation(s): about" in capfd.readouterr().err


def test_a_study_fit_height_above_the_column_is_refused(capfd, tmp_path):
    out = tmp_path / "ens"
    err = _refused(capfd, ["ensemble", str(LAB), "-n", "2", "-o", str(out), "--study-fit-height", "40"],
                   "--study-fit-height", out)
    assert "column.height_m = 0.8 m" in err


@pytest.mark.parametrize("argv, flag, words", [
    (["analytical", "asce7", "--velocity", "4000", "--mass", "2300"], "--velocity", "30 m/s"),
    (["analytical", "impact", "--velocity", "4000"], "--velocity", "30 m/s"),
    (["analytical", "asce7", "--velocity", "4", "--mass", "2.3", "--prototype"], "--mass", "full scale starts at 100 kg"),
    (["analytical", "asce7", "--velocity", "4", "--mass", "2300", "--structure-stiffness", "3.4e7",
      "--debris-stiffness", "42.9"], "--debris-stiffness", "1e+05-1e+11 N/m"),
    (["analytical", "asce7", "--velocity", "1", "--mass", "0.2", "--structure-stiffness", "1e20"],
     "--structure-stiffness", "1e+03-1e+12 N/m"),
    (["analytical", "asce7", "--velocity", "1", "--mass", "1e12", "--stiffness", "1e7"], "--mass", "at most 1e+09 kg"),
    (["analytical", "asce7", "--velocity", "1", "--mass", "0.2", "--stiffness", "1e14"], "--stiffness",
     "1e+03-1e+12 N/m"),
])
def test_implausible_analytical_inputs_name_the_flag(capfd, argv, flag, words):
    err = _refused(capfd, argv, flag)
    assert words in err


# --------------------------------------------------------------------------- an unstable engine
FLUME = FlumeBounds((0.0, 2.0), (-0.3, 0.3), 0.0)
COLUMN = PlacedColumn(1.0, 0.0, Column(size_x_m=0.1, size_y_m=0.1, height_m=0.3, wall_thickness_m=0.005))
BODY = debris("debris1", (0.15, 0.06, 0.06), 0.236, (0.6, 0.0, 0.03), wall_thickness_m=0.005)


def test_an_unstable_engine_is_an_error_naming_its_realisation(current):
    """A body thrown at 1e12 m/s makes MuJoCo's state blow up at once (as a 1e-7 kg body in a
    0.15 m box does after 0.94 s of flow, millions of steps later: too slow for a test); MuJoCo
    warns, resets and goes on. The batch (realisations 7 and 8, the bad body in 8) raises naming
    realisation 8 instead of returning its strikes."""
    _, npz = current
    good = design_starts([BODY], FLUME, COLUMN, Design(), 0, 0)
    bad = [debris("debris1", (0.15, 0.06, 0.06), 0.236, (0.6, 0.0, 0.03), wall_thickness_m=0.005,
                  velocity_m_s=(1e12, 1e12, 0.0))]
    with pytest.raises(UnstableEngineError, match=r"realisation 8: the rigid-body engine \(MuJoCo\) became unstable"):
        design_batch([7, 8], [good, bad], FLUME, COLUMN, 0.05, npz, TransportSettings(first_pulse_only=True))
    assert mujoco.get_mju_user_warning() is None  # the process's handler is restored
    # the ensemble's batches and single realisations alike
    from orchestrator.studies.ensemble import run_realisations

    settings = TransportSettings(first_pulse_only=True)
    with pytest.raises(UnstableEngineError, match=r"realisation 4: "):
        run_realisations([3, 4], [good, bad], FLUME, COLUMN, 0.05, npz, settings, study_fit=False)
    with pytest.raises(UnstableEngineError, match=r"realisation 5: "):
        run_realisations([5], [bad], FLUME, COLUMN, 0.05, npz, settings, study_fit=False)


def test_an_unstable_realisation_ends_the_design_verb_with_exit_1_and_no_page(capfd, tmp_path, monkeypatch,
                                                                              current):
    """The verb end to end on a synthetic flow (no OpenFOAM): MuJoCo's instability warning in a
    batch is exit 1 naming the realisation, and no design.csv, design.json or design.md."""
    import orchestrator.studies.design as design_module

    flow, npz = current
    scene = load_scene(TINY)
    monkeypatch.setattr(design_module, "ensemble_flow",
                        lambda path, folder, sets, **kw: (scene, folder, flow, npz))
    monkeypatch.setattr(design_module, "site_flow_speed", lambda case, scene: None)
    real = design_module.run_batch

    def unstable(starts, *args, **kwargs):  # as MuJoCo's mj_checkAcc reports it, on the batch's 3rd body
        mujoco.get_mju_user_warning()("Nan, Inf or huge value in QACC at DOF 14. The simulation is unstable. "
                                      "Time = 0.0100.")
        return real(starts, *args, **kwargs)

    monkeypatch.setattr(design_module, "run_batch", unstable)
    out = tmp_path / "study"
    code = main(["design", str(TINY), "-n", "4", "-o", str(out), "--workers", "1", "--batch-size", "4",
                 "--set", "run.end_time_s=0.1"])
    err = capfd.readouterr().err
    assert code == 1, err
    assert "realisation 2: the rigid-body engine (MuJoCo) became unstable" in err and "no page" in err
    assert not any((out / name).exists() for name in ("design.csv", "design.json", "design.md", "exceedance.png"))
