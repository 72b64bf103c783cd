"""The CLI contract: verbs, JSON keys, and exit codes (0 ok, 2 bad input, 1 failure)."""


import json

import numpy as np
import pandas as pd
import pytest

from tests.conftest import ROOT, cli_json, run_cli


def test_asce7_json_keys_and_values():
    out = cli_json("analytical", "asce7", "--velocity", "1.5", "--mass", "0.236", "--stiffness", "4.685e5")
    assert {"force_N", "nominal_force_N", "duration_s", "impulse_Ns", "orientation_C_o", "importance_I_tsu"} <= set(out)
    assert "design force" in out["note"]
    assert out["nominal_force_N"] == pytest.approx(1.5 * np.sqrt(4.685e5 * 0.236), rel=1e-12)
    assert out["force_N"] == pytest.approx(0.65 * out["nominal_force_N"], rel=1e-12)
    assert out["impulse_Ns"] == pytest.approx(2 * 0.65 * 0.236 * 1.5, rel=1e-12)


@pytest.mark.parametrize(
    "args, field",
    [
        (["--velocity", "1.5", "--mass", "-1", "--stiffness", "4e5"], "mass"),
        (["--velocity", "1.5", "--mass", "0.2", "--stiffness", "0"], "stiffness"),
        (["--velocity", "1.5", "--mass", "0.2", "--structure-stiffness", "-1"], "--structure-stiffness"),
        (["--mass", "0.2"], "--velocity"),
    ],
)
def test_asce7_bad_input_exits_2_naming_the_field(args, field):
    proc = run_cli("analytical", "asce7", *args)
    assert proc.returncode == 2
    assert field in proc.stderr
    assert "Traceback" not in proc.stderr


def test_modes_rigid_and_calibrated():
    rigid = cli_json("analytical", "modes")["frequencies_Hz"]
    cal = cli_json("analytical", "modes", "--set", "column.base=calibrated")
    assert len(rigid) >= 3 and rigid == sorted(rigid)
    assert 80 < rigid[0] < 95  # the study's rigid-base column: about 88 Hz
    assert cal["frequencies_Hz"][0] == pytest.approx(70.0, rel=1e-6)
    assert cal["base_spring_Nm_per_rad"] > 0
    other = cli_json("analytical", "modes", "--set", "column.base=calibrated", "--set", "column.natural_frequency_Hz=60")
    assert other["frequencies_Hz"][0] == pytest.approx(60.0, rel=1e-6)


def test_unknown_set_key_exits_2():
    proc = run_cli("analytical", "modes", "--set", "column.colour=red")
    assert proc.returncode == 2 and "column.colour" in proc.stderr
    proc = run_cli("analytical", "modes", "--set", "column.base=wobbly")
    assert proc.returncode == 2 and "column.base" in proc.stderr


@pytest.mark.parametrize("model", ["sdof", "mdof"])
def test_response_json_and_csv(model, tmp_path):
    csv = tmp_path / "r.csv"
    out = cli_json("analytical", "response", "--model", model, "--pulse", "half-sine", "--magnitude", "237",
                   "--duration", "0.0047", "--height", "0.4", "--out", str(csv))
    assert set(out) == {"peak_N", "time_of_peak_s"}
    frame = pd.read_csv(csv)
    assert list(frame.columns) == ["time_s", "response_N"]
    assert frame["response_N"].max() == pytest.approx(out["peak_N"], rel=1e-9)
    assert 0 < out["time_of_peak_s"] < 0.05


def test_response_bad_duration_exits_2():
    proc = run_cli("analytical", "response", "--model", "sdof", "--magnitude", "100", "--duration", "-1")
    assert proc.returncode == 2 and "--duration" in proc.stderr


def test_dambreak_arrival_and_profile(tmp_path):
    out = cli_json("analytical", "dambreak", "--model", "ritter", "--h0", "0.4", "--arrival", "2.4")
    assert out["arrival_s"] == pytest.approx(2.4 / (2 * np.sqrt(9.81 * 0.4)), rel=1e-9)
    csv = tmp_path / "p.csv"
    cli_json("analytical", "dambreak", "--model", "stoker", "--h0", "0.4", "--hr", "0.015",
             "--profile", "1.0", "--out", str(csv))
    frame = pd.read_csv(csv)
    assert list(frame.columns) == ["x_m", "depth_m", "velocity_m_s"]
    assert frame["depth_m"].max() == pytest.approx(0.4, rel=1e-9)
    proc = run_cli("analytical", "dambreak", "--model", "chanson", "--h0", "0.4", "--arrival", "2.4")
    assert proc.returncode == 2 and "friction" in proc.stderr


def _write_record(path, t, f):
    pd.DataFrame({"time_s": t, "force_N": f}).to_csv(path, index=False)


def test_fit_recovers_a_known_pulse(tmp_path):
    t = np.arange(0, 0.06, 1e-4)
    csv = tmp_path / "resp.csv"
    proc = run_cli("analytical", "response", "--model", "mdof", "--magnitude", "200", "--duration", "0.005",
                   "--height", "0.4", "--t-end", "0.05", "--out", str(csv))
    assert proc.returncode == 0, proc.stderr
    frame = pd.read_csv(csv)
    shifted = np.interp(t - 0.01, frame["time_s"], frame["response_N"], left=0.0)
    _write_record(tmp_path / "rec.csv", t, shifted + 3.0)
    out = cli_json("analytical", "fit", "--model", "mdof", str(tmp_path / "rec.csv"), "--height", "0.4")
    assert {"magnitude_N", "duration_s", "impulse_Ns", "rmse_N", "peak_measured_N", "peak_model_N",
            "offset_removed_N", "height_m"} <= set(out)
    assert out["magnitude_N"] == pytest.approx(200, rel=0.02)
    assert out["duration_s"] == pytest.approx(0.005, rel=0.02)
    assert out["offset_removed_N"] == pytest.approx(3.0, abs=0.5)
    # one measured peak per record whatever the model; the SDOF fit shows its fitted oscillator
    sdof = run_cli("analytical", "fit", "--model", "sdof", str(tmp_path / "rec.csv"), "--json")
    assert sdof.returncode == 0
    sdof_out = __import__("json").loads(sdof.stdout)
    assert sdof_out["peak_measured_N"] == pytest.approx(out["peak_measured_N"], rel=1e-12)
    assert {"natural_frequency_Hz", "damping_ratio", "stiffness_N_m"} <= set(sdof_out)
    if sdof_out["rmse_N"] > 0.2 * (sdof_out["peak_measured_N"] - sdof_out["offset_removed_N"]):
        assert "poor fit" in sdof.stderr
    else:
        assert "poor fit" not in sdof.stderr


@pytest.mark.parametrize(
    "kind, field",
    [("nan", "force_N"), ("short", "time_s"), ("backwards", "time_s"), ("flat", "force_N"), ("nocol", "force_N")],
)
def test_fit_bad_records_exit_2_naming_file_and_field(tmp_path, kind, field):
    t = np.arange(0, 0.05, 1e-4)
    f = np.where((t > 0.01) & (t < 0.015), 100 * np.sin(np.pi * (t - 0.01) / 0.005), 0.0)
    path = tmp_path / f"{kind}.csv"
    if kind == "nan":
        f[100] = np.nan
        _write_record(path, t, f)
    elif kind == "short":
        _write_record(path, t[:5], f[:5])
    elif kind == "backwards":
        t[50] = t[10]
        _write_record(path, t, f)
    elif kind == "flat":
        _write_record(path, t, np.random.default_rng(1).normal(0, 1, t.size))
    else:
        pd.DataFrame({"time_s": t, "F": f}).to_csv(path, index=False)
    proc = run_cli("analytical", "fit", "--model", "sdof", str(path))
    assert proc.returncode == 2, proc.stderr
    assert str(path) in proc.stderr and field in proc.stderr


def test_sweep_of_a_missing_file_exits_2_naming_it():
    proc = run_cli("sweep", "nothing.yaml")
    assert proc.returncode == 2
    assert "nothing.yaml" in proc.stderr and "Traceback" not in proc.stderr


def test_debug_reraises():
    proc = run_cli("--debug", "analytical", "asce7", "--velocity", "1", "--mass", "-1", "--stiffness", "1")
    assert proc.returncode != 0 and "Traceback" in proc.stderr


def test_run_with_a_bad_stall_limit_exits_2_and_touches_nothing(tmp_path):
    """A non-positive --stall-limit is refused before the case is even looked at."""
    proc = run_cli("run", str(tmp_path / "case"), "--stall-limit", "0")
    assert proc.returncode == 2 and "--stall-limit" in proc.stderr and "Traceback" not in proc.stderr
    assert not (tmp_path / "case").exists()


def test_a_bad_stall_limit_in_a_scene_exits_2_naming_file_and_field(tmp_path):
    from pathlib import Path

    root = Path(__file__).resolve().parent.parent
    path = tmp_path / "bad.yaml"
    path.write_text(f"extends: {root / 'cases' / 'nodebris.yaml'}\nrun:\n  stall_limit_s: -5\n")
    proc = run_cli("render", str(path), "-o", str(tmp_path / "out"))
    assert proc.returncode == 2 and str(path) in proc.stderr and "run.stall_limit_s" in proc.stderr
    assert not (tmp_path / "out").exists()


def test_analytical_impact_json_keys_and_the_strikes_momentum():
    """A head-on strike at Table 1's 1.5 m/s: the contact's impulse is the effective mass (the
    box's 0.236 kg and its added mass along the normal) times (1 + e) times the speed, and e is
    the law's rigid-wall restitution (the column is 7 times stiffer than the contact spring)."""
    from analytical.added_mass import STUDY_CONTAINER_ADDED_MASS
    from analytical.contact_law import CONTAINER

    out = cli_json("analytical", "impact", "--velocity", "1.5", "--height", "0.4")
    assert {"peak_force_N", "duration_s", "impulse_Ns", "restitution", "peak_base_shear_N"} <= set(out)
    m_eff = 0.236 + STUDY_CONTAINER_ADDED_MASS.masses_kg[0]
    assert out["impulse_Ns"] == pytest.approx(m_eff * (1.0 + out["restitution"]) * 1.5, rel=0.01)
    assert out["restitution"] == pytest.approx(CONTAINER.wall_restitution, abs=0.01)
    rigid = cli_json("analytical", "impact", "--velocity", "1.5", "--set", "contact.law=asce7_kd")
    assert rigid["peak_force_N"] > 4 * out["peak_force_N"]


def test_analytical_impact_with_a_scene_uses_its_body_and_overrides():
    lossy = cli_json("analytical", "impact", "--velocity", "1.6", "--scene", "cases/1debris.yaml",
                     "--set", "debris.0.contact.restitution=0.5")
    assert lossy["damping_ratio"] > 0.2
    assert lossy["restitution"] < 0.6


def test_analytical_impact_strikes_a_scene_at_its_strike_point_unless_told():
    """A full-scale member is struck where `design` loads it (the inundation depth, 3 m on the
    street scene), not at the study's 0.40 m; --height wins; without a scene the study's mean."""
    street = cli_json("analytical", "impact", "--velocity", "3", "--scene", "cases/design-street.yaml")
    assert street["height_m"] == pytest.approx(3.0)
    assert "inundation.depth_m" in street["height_source"]
    told = cli_json("analytical", "impact", "--velocity", "3", "--scene", "cases/design-street.yaml", "--height", "1.5")
    assert (told["height_m"], told["height_source"]) == (1.5, "--height")
    assert told["peak_base_shear_N"] != pytest.approx(street["peak_base_shear_N"], rel=1e-3)
    assert cli_json("analytical", "impact", "--velocity", "1.5")["height_m"] == pytest.approx(0.40)


@pytest.mark.parametrize(
    "args, field",
    [
        (["--velocity", "0"], "--velocity"),
        (["--velocity", "-1"], "--velocity"),
        (["--velocity", "1.5", "--height", "0.9"], "--height"),
        (["--velocity", "1.5", "--height", "0"], "--height"),
        (["--velocity", "1.5", "--set", "contact.stiffness_N_m=0"], "contact.stiffness_N_m"),
        (["--velocity", "1.5", "--set", "contact.damping_ratio=-0.1"], "contact.damping_ratio"),
        (["--velocity", "1.5", "--set", "contact.restitution=1.5"], "contact.restitution"),
        (["--velocity", "1.5", "--set", "contact.restitution=0"], "contact.restitution"),
        (["--velocity", "1.5", "--set", "contact.friction_coefficient=-1"], "contact.friction_coefficient"),
        (["--velocity", "1.5", "--scene", "cases/1debris.yaml", "--set",
          "debris.0.contact.bed_friction_coefficient=-1"], "debris.0.contact.bed_friction_coefficient"),
        (["--velocity", "1.5", "--set", "contact.spring=1"], "contact.spring"),
    ],
)
def test_analytical_impact_bad_input_exits_2_naming_the_field(args, field):
    proc = run_cli("analytical", "impact", *args)
    assert proc.returncode == 2, proc.stderr
    assert field in proc.stderr
    assert "Traceback" not in proc.stderr and proc.stdout == ""


@pytest.mark.parametrize("model", ["sdof", "mdof"])
def test_zero_column_damping_is_accepted(model):
    out = cli_json("analytical", "response", "--model", model, "--magnitude", "236.93", "--duration", "0.0047",
                   "--set", "column.damping_ratio=0")
    damped = cli_json("analytical", "response", "--model", model, "--magnitude", "236.93", "--duration", "0.0047")
    assert out["peak_N"] >= damped["peak_N"] > 0


def test_plan_warnings_reach_the_terminal_and_the_json(tmp_path):
    """The planner's warnings on the 2x3 layout's coupled path (its body meshes reach below the bed,
    the gap's thin layers) are said on stderr by render, in render --json, and per member by sweep
    --dry-run."""
    import json

    two_way = ["--set", "run.debris_coupling=two-way"]
    proc = run_cli("render", "cases/6debris-2x3.yaml", "-o", str(tmp_path / "c"), "--set", "outputs.preview=false",
                   *two_way)
    assert proc.returncode == 0, proc.stderr
    lines = [line for line in proc.stderr.splitlines() if line.startswith("debrisfoam: warning: ")]
    assert lines and all("debris" in line or "bed layer" in line for line in lines)
    plan = json.loads((tmp_path / "c" / "plan.json").read_text())
    assert len(lines) == len(plan["warnings"]) > 0
    out = json.loads(run_cli("render", "cases/6debris-2x3.yaml", "-o", str(tmp_path / "d"), "--set",
                             "outputs.preview=false", "--json", *two_way).stdout)
    assert out["warnings"] == plan["warnings"]
    layouts = tmp_path / "layouts-two-way.yaml"
    layouts.write_text("name: layouts-two-way\nscenes:\n" + "".join(
        f"  - {ROOT / 'cases' / n}.yaml\n" for n in ("1debris", "6debris-2x3")) +
        "axes:\n  run.debris_coupling: [two-way]\n")
    dry = run_cli("sweep", str(layouts), "--dry-run", "-o", str(tmp_path / "s"))
    assert dry.returncode == 0, dry.stderr
    assert any(line.startswith("debrisfoam: warning: member ") and "debris" in line for line in dry.stderr.splitlines())
    clean = run_cli("render", "cases/nodebris.yaml", "-o", str(tmp_path / "n"), "--set", "outputs.preview=false")
    assert clean.returncode == 0 and "warning" not in clean.stderr


@pytest.mark.parametrize(
    "args, field",
    [
        (["run", "{tmp}/no-such-case"], "case_dir"),
        (["render", "cases/1debris.yaml", "-o", "/proc/forbidden/case"], "-o/--out"),
        (["preview", "cases/1debris.yaml", "-o", "{tmp}"], "-o/--out"),
        (["preview", "cases/1debris.yaml", "-o", "{tmp}/p.pdf"], "-o/--out"),
        (["preview", "cases/1debris.yaml", "-o", "{tmp}/p.jpg"], "-o/--out"),
        (["preview", "cases/1debris.yaml", "-o", "{tmp}/existing.png"], "-o/--out"),
        (["analytical", "study", "--records", "0", "-o", "{tmp}/study"], "--records"),
        (["analytical", "study", "-o", "{tmp}/full"], "-o/--out"),
        (["analytical", "dambreak", "--model", "ritter", "--h0", "0.4", "--arrival", "-1"], "--arrival"),
        (["analytical", "fit", "--model", "mdof", "{tmp}"], "record"),
        (["analytical", "asce7", "--velocity", "-1", "--mass", "0.2", "--stiffness", "1e5"], "--velocity"),
        (["analytical", "asce7", "--velocity", "1", "--mass", "0", "--stiffness", "1e5"], "--mass"),
        (["analytical", "contact-law", "-o", "{tmp}/full"], "-o/--out"),
        (["report", "case", "{tmp}", "-o", "{tmp}/page"], "case_dir"),
        (["analytical", "response", "--model", "mdof", "--magnitude", "200", "--duration", "0.005", "--out",
          "{tmp}/existing.png"], "--out"),
        (["analytical", "dambreak", "--model", "ritter", "--h0", "0.4", "--profile", "0.5", "--out",
          "{tmp}/existing.png"], "--out"),
        (["analytical", "response", "--model", "mdof", "--magnitude", "200", "--duration", "0.005", "--out",
          "{tmp}/full"], "--out"),
        (["analytical", "modes", "--set", "column.base=nope", "--debug"], None),
    ],
)
def test_every_bad_input_exits_2_naming_the_flag_and_writes_nothing(tmp_path, args, field):
    (tmp_path / "existing.png").write_bytes(b"kept")
    (tmp_path / "full").mkdir()
    (tmp_path / "full" / "kept.txt").write_text("kept")
    before = sorted(p.relative_to(tmp_path) for p in tmp_path.rglob("*"))
    proc = run_cli(*[a.replace("{tmp}", str(tmp_path)) for a in args])
    if field is None:  # --debug after the verb is accepted: the traceback is shown
        assert proc.returncode != 0 and "Traceback" in proc.stderr and "unrecognized" not in proc.stderr
        return
    assert proc.returncode == 2, proc.stderr
    assert field in proc.stderr and "Traceback" not in proc.stderr and "unexpected" not in proc.stderr
    assert sorted(p.relative_to(tmp_path) for p in tmp_path.rglob("*")) == before
    assert (tmp_path / "existing.png").read_bytes() == b"kept"


def test_every_option_says_what_it_is():
    """Every option of every verb has help text (argparse's own --help aside)."""
    import argparse

    from orchestrator.cli import build_parser

    missing = []

    def walk(parser, path):
        for action in parser._actions:
            if isinstance(action, argparse._SubParsersAction):
                for name, sub in action.choices.items():
                    walk(sub, f"{path} {name}")
            elif not isinstance(action, argparse._HelpAction) and not action.help:
                missing.append(f"{path}: {'/'.join(action.option_strings) or action.dest}")

    walk(build_parser(), "debrisfoam")
    assert not missing, missing


def test_one_verbs_response_feeds_the_others_fit(tmp_path):
    """`analytical response --out` writes time_s,response_N; `analytical fit` reads it back and
    recovers the pulse that made it (MDOF: magnitude and duration are all it fits)."""
    csv = tmp_path / "r.csv"
    cli_json("analytical", "response", "--model", "mdof", "--magnitude", "200", "--duration", "0.0047",
             "--height", "0.4", "--out", str(csv))
    fit = cli_json("analytical", "fit", "--model", "mdof", str(csv), "--height", "0.4")
    assert fit["magnitude_N"] == pytest.approx(200, rel=0.02)
    assert fit["duration_s"] == pytest.approx(0.0047, rel=0.02)
    pd.DataFrame({"time_s": [0.0, 1.0], "other_N": [0.0, 1.0]}).to_csv(tmp_path / "bad.csv", index=False)
    bad = run_cli("analytical", "fit", "--model", "mdof", str(tmp_path / "bad.csv"))
    assert bad.returncode == 2 and "force_N" in bad.stderr and "response_N" in bad.stderr


def test_help_names_every_report_verb_and_the_case_folder():
    from orchestrator.cli import build_parser

    top = run_cli("--help").stdout
    report = build_parser()._subparsers._group_actions[0].choices["report"]
    verbs = report._subparsers._group_actions[0].choices
    assert len(verbs) >= 5
    flat = " ".join(top.split())
    assert all(v in flat for v in verbs), [v for v in verbs if v not in flat]
    case = " ".join(run_cli("case", "--help").stdout.split())
    assert "runs/<the scene file's name without .yaml>, e.g. runs/1debris" in case


def test_a_shipped_scene_by_name_from_another_folder(tmp_path):
    """`render 1debris` from a folder without that file renders the shipped scene; a file of that
    name in the folder wins over it."""
    def validate(name):
        proc = run_cli("validate", name, "--json", cwd=tmp_path)
        assert proc.returncode == 0, proc.stderr
        return json.loads(proc.stdout)

    out = validate("1debris")
    assert out["scene"].endswith("1debris.yaml") and out["planned_cells"] == 181500
    assert validate("hard/glancing")["name"] == "hard-glancing"
    (tmp_path / "1debris").write_text((ROOT / "cases" / "nodebris.yaml").read_text())
    assert validate("1debris")["name"] == "nodebris"  # the user's file
    proc = run_cli("render", "no-such-scene", "-o", str(tmp_path / "x"), cwd=tmp_path)
    assert proc.returncode == 2 and "debrisfoam scenes" in proc.stderr and not (tmp_path / "x").exists()
