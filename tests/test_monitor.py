"""Log parsing, health checks and progress, on small real OpenFOAM v1912 logs.

The logs under tests/data/logs/ were written by the runner on tiny cases (2 ranks):

- interFoam-finished.log: 28 steps to the end time (0.2 s), `End`.
- interFoam-writeNow.log: stopped by `stopAt writeNow` (Ctrl-C) at 0.18 s: the solver
  re-read controlDict, ran one more step, wrote and ended.
- interFoam-courant.log: a fixed deltaT of 0.04 s (adjustTimeStep no): max Co about 60-80.
- interFoam-fpe.log: a fixed deltaT of 0.3 s: floating point exception (exit 136).
- interFoam-nan.log: the same with FOAM_SIGFPE=false: NaN in the residuals, then an abort.
- overInterDyMFoam-2bodies-contact.log: two six-DoF bodies, stopped by writeNow for a
  contact of debris1 with the column.
- overInterDyMFoam-pcorr.log: the first 200 lines of a restart whose pcorr solve diverged
  (a body mesh ending on a side wall, cases/hard/small/near-side-wall.yaml): the Courant
  number then jumped to 1e7 and deltaT collapsed.
"""

from __future__ import annotations

import io
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from orchestrator.run.monitor import (
    STALL_S,
    DivergenceLimits,
    HealthWatch,
    LogParser,
    LogTail,
    Progress,
    foam_build,
    parse_log,
    water_balance_diagnosis,
)

LOGS = Path(__file__).parent / "data" / "logs"


def test_finished_interfoam_log():
    steps, parser = parse_log(LOGS / "interFoam-finished.log")
    assert len(steps) == 28 and parser.steps_seen == 28
    assert steps[0].index == 1 and steps[-1].index == 28
    assert steps[-1].time_s == pytest.approx(0.2) and steps[-1].time_name == "0.2"
    assert parser.finished and not parser.fatal and not parser.fpe  # the header's "trapFpe" is not an FPE
    assert parser.nonfinite_line is None
    assert parser.build == "1912 patch=200626"
    assert all(s.bodies == () for s in steps)
    # deltaT and Courant belong to the step they precede; the first step starts at the controlDict deltaT
    assert steps[0].delta_t_s == pytest.approx(0.00119047619) and steps[0].max_courant == 0.0
    assert steps[-1].delta_t_s == pytest.approx(0.01)
    assert all(0 <= s.max_courant < 0.9 + 1e-6 for s in steps)
    times = [s.time_s for s in steps]
    assert times == sorted(times)
    cpu = [s.execution_time_s for s in steps]
    assert None not in cpu and cpu == sorted(cpu)


def test_write_now_log_shows_the_reread_and_a_clean_end():
    steps, parser = parse_log(LOGS / "interFoam-writeNow.log")
    assert parser.rereads == 1 and parser.finished
    assert steps[-1].time_name == "0.18"
    assert HealthWatch(DivergenceLimits(min_delta_t_s=1e-6), 0.9).check_parser(parser) is None


def test_courant_runaway_is_diagnosed():
    steps, parser = parse_log(LOGS / "interFoam-courant.log")
    watch = HealthWatch(DivergenceLimits(courant_factor=10, courant_steps=5), max_courant=0.9)
    diag = None
    for s in steps:
        diag = diag or watch.check_step(s)
    assert diag is not None and diag.kind == "courant"
    assert "Courant number runaway" in diag.cause and "0.9" in diag.cause
    assert diag.since_s < diag.time_s  # the streak's first step: later writes are not trusted
    # a milder limit is not triggered by a calm run
    calm, _ = parse_log(LOGS / "interFoam-finished.log")
    watch = HealthWatch(DivergenceLimits(), max_courant=0.9)
    assert all(watch.check_step(s) is None for s in calm)


def test_floating_point_exception_is_seen():
    steps, parser = parse_log(LOGS / "interFoam-fpe.log")
    assert parser.fpe and not parser.finished
    assert steps[-1].time_s == pytest.approx(1.2)  # the last step completed
    assert parser.current_time_s == pytest.approx(1.5)  # the step it died in


def test_nan_is_seen_with_its_time():
    _, parser = parse_log(LOGS / "interFoam-nan.log")
    assert parser.nonfinite_line is not None and "nan" in parser.nonfinite_line.lower()
    assert parser.nonfinite_time_s == pytest.approx(1.5)
    diag = HealthWatch(DivergenceLimits(), 0.9).check_parser(parser)
    assert diag.kind == "nan" and diag.time_s == pytest.approx(1.5)


@pytest.mark.parametrize("line, bad", [
    ("GAMG:  Solving for p_rgh, Initial residual = nan, Final residual = nan, No Iterations 1000", True),
    ("Phase-1 volume fraction = -nan  Min(alpha.water) = 1", True),
    ("Courant Number mean: inf max: inf", True),
    ("Selecting incompressible transport model Newtonian", False),
    ("    Not including porosity effects", False),
    ("Reading/calculating face flux field phi", False),
    ("trapFpe: Floating point exception trapping enabled (FOAM_SIGFPE).", False),
    ("Info: infinity is a word here, so is nano", False),
])
def test_nonfinite_detection_on_single_lines(line, bad):
    parser = LogParser()
    parser.feed([line])
    assert (parser.nonfinite_line is not None) == bad
    assert not parser.fpe


def test_two_body_reports_are_assigned_in_solvers_order():
    steps, parser = parse_log(LOGS / "overInterDyMFoam-2bodies-contact.log", ["debris1", "debris2"])
    assert len(steps) == 10 and parser.rereads == 1 and parser.finished
    for s in steps:
        assert [b.name for b in s.bodies] == ["debris1", "debris2"]
        assert all(b.time_s == s.time_s for b in s.bodies)
    first, last = steps[0].bodies, steps[-1].bodies
    assert first[0].centre_of_mass_m[0] == pytest.approx(1.05, abs=2e-3)  # started at x = 1.05 m, 0.6 m/s
    assert first[1].centre_of_mass_m[:2] == pytest.approx((0.70, 0.10), abs=2e-3)
    assert first[0].velocity_m_s[0] == pytest.approx(0.6, abs=0.01)
    assert first[1].velocity_m_s[:2] == pytest.approx((0.2, 0.05), abs=0.01)
    assert last[0].centre_of_mass_m[0] > first[0].centre_of_mass_m[0]
    assert len(last[0].orientation) == 9 and last[0].centre_of_rotation_m == last[0].centre_of_mass_m
    assert last[1].speed_m_s == pytest.approx(sum(v * v for v in last[1].velocity_m_s) ** 0.5)


def test_log_tail_reads_appended_bytes_only(tmp_path):
    """Feeding the log as it grows, in odd-sized chunks, gives the same steps as a whole parse."""
    source = (LOGS / "overInterDyMFoam-2bodies-contact.log").read_bytes()
    log = tmp_path / "log.overInterDyMFoam"
    log.write_bytes(b"")
    tail = LogTail(log)
    parser = LogParser(["debris1", "debris2"])
    steps = []
    for start in range(0, len(source), 777):
        with open(log, "ab") as fh:
            fh.write(source[start:start + 777])
        steps += parser.feed(tail.read_lines())
    steps += parser.feed(tail.flush())
    whole, _ = parse_log(LOGS / "overInterDyMFoam-2bodies-contact.log", ["debris1", "debris2"])
    assert steps == whole
    assert tail.offset == len(source)
    assert tail.read_lines() == []


def test_log_tail_of_a_missing_file(tmp_path):
    assert LogTail(tmp_path / "nothing").read_lines() == []


def test_body_speed_and_domain_checks():
    steps, _ = parse_log(LOGS / "overInterDyMFoam-2bodies-contact.log", ["debris1", "debris2"])
    step = steps[-1]
    domain = ((-0.32, 1.87), (-0.2, 0.2), (0.0, 0.24))
    watch = HealthWatch(DivergenceLimits(max_body_speed_m_s=7.5), 0.9, domain)
    assert watch.check_step(step) is None
    fast = replace(step.bodies[1], velocity_m_s=(8.0, 0.0, 0.0))
    diag = watch.check_step(replace(step, bodies=(step.bodies[0], fast)))
    assert diag.kind == "body_speed" and "debris2" in diag.cause
    assert diag.body == "debris2" and diag.velocity_m_s == (8.0, 0.0, 0.0)  # for the resume (ContactBook)
    gone = replace(step.bodies[0], centre_of_mass_m=(2.0, 0.0, 0.1))
    diag = HealthWatch(DivergenceLimits(), 0.9, domain).check_step(replace(step, bodies=(gone,)))
    assert diag.kind == "left_domain" and "x = 2 m > 1.87 m" in diag.cause


def test_delta_t_collapse_needs_consecutive_steps():
    steps, _ = parse_log(LOGS / "interFoam-finished.log")
    watch = HealthWatch(DivergenceLimits(min_delta_t_s=0.005, delta_t_steps=3), 0.9)
    small = [replace(s, delta_t_s=0.001) for s in steps[:3]]
    assert watch.check_step(small[0]) is None and watch.check_step(small[1]) is None
    diag = watch.check_step(small[2])
    assert diag.kind == "delta_t" and diag.since_s == small[0].time_s


def test_a_diverged_pcorr_is_the_diagnosis():
    steps, parser = parse_log(LOGS / "overInterDyMFoam-pcorr.log")
    assert "Final residual = 4079661323" in parser.pcorr_failure
    diag = HealthWatch(DivergenceLimits(), 2.5).check_parser(parser)
    assert diag.kind == "pcorr" and "overset flux correction (pcorr) diverged" in diag.cause
    assert diag.time_s == pytest.approx(0.1, abs=1e-6) and diag.since_s is None  # the restart's fields are good
    calm, calm_parser = parse_log(LOGS / "overInterDyMFoam-2bodies-contact.log")
    assert calm_parser.pcorr_failure is None  # converged pcorr solves are not failures
    skipped = LogParser()  # the start-up projection switched off (Numerics.restart_flux_projection)
    skipped.feed(["DICPCG:  Solving for pcorr, Initial residual = 1, Final residual = 1, No Iterations 0"])
    assert skipped.pcorr_failure is None
    stuck = LogParser()  # a solve that ran and got nowhere still is one
    stuck.feed(["DICPCG:  Solving for pcorr, Initial residual = 1, Final residual = 1, No Iterations 1000"])
    assert stuck.pcorr_failure is not None


def test_stall_limit_follows_the_slowest_step():
    lim = DivergenceLimits(stall_s=600, stall_factor=20)
    assert lim.stall_limit_s(None) == 600 and lim.stall_limit_s(2.0) == 600 and lim.stall_limit_s(60.0) == 1200
    with pytest.raises(ValueError, match="stall"):
        DivergenceLimits(stall_s=0)
    assert DivergenceLimits().stall_limit_s(None) == STALL_S == 600  # unset: the default


def test_limits_are_validated():
    with pytest.raises(ValueError, match="courant_factor"):
        DivergenceLimits(courant_factor=0.5)
    with pytest.raises(ValueError, match="min_delta_t_s"):
        DivergenceLimits(min_delta_t_s=0.0)


def test_progress_bar_shows_time_dt_courant_and_bodies():
    steps, _ = parse_log(LOGS / "overInterDyMFoam-2bodies-contact.log", ["debris1", "debris2"])
    out = io.StringIO()
    bar = Progress(0.1, 0.0, quiet=False, label="overInterDyMFoam", stream=out)
    for s in steps:
        bar.update(s)
    bar.close()
    text = out.getvalue()
    assert "overInterDyMFoam" in text and "/0.1 s" in text
    assert "dt=" in text and "Co=" in text and "debris1=(" in text and "debris2=(" in text and "m/s" in text
    quiet = Progress(0.1, quiet=True)
    quiet.update(steps[0])  # no bar, no output, no error
    quiet.close()


def test_foam_build():
    assert foam_build("Build  : OPENFOAM=1912 patch=200626\n") == "1912 patch=200626"
    assert foam_build("no header") is None


def test_the_water_balance_stop_names_the_first_time_beyond_the_limit():
    import pandas as pd

    t = np.linspace(0.0, 1.0, 11)
    error = np.array([0, 0.001, -0.002, -0.004, -0.008, -0.0105, -0.02, -0.009, 0, 0, 0])
    balance = pd.DataFrame({"time_s": t, "initial_m3": 0.05, "error": error})
    diag = water_balance_diagnosis(balance, 0.01)
    assert diag.kind == "water" and diag.time_s == pytest.approx(0.5) and diag.since_s is None
    assert "-1.05% lost by t = 0.5 s" in diag.cause and "run.water_balance_limit" in diag.cause
    assert water_balance_diagnosis(balance, 0.025) is None
    made = water_balance_diagnosis(balance.assign(error=-error), 0.01)
    assert made.time_s == pytest.approx(0.5) and "+1.05% created" in made.cause
    assert water_balance_diagnosis(None, 0.01) is None  # a case without the function objects
    with pytest.raises(ValueError, match="water_balance"):
        DivergenceLimits(water_balance=0)
