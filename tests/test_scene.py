"""Scenes: loading, overrides, resolution (layouts, placement, gauges) and validation.

Every file in tests/data/bad_scenes/ (except _valid_base.yaml, the valid scene they are
made from) breaks one rule; its `# expect-field:` line names the dotted field the
InputError must carry.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import yaml
from hypothesis import given, settings
from hypothesis import strategies as st

from analytical.errors import InputError
from orchestrator.scene.geometry import body_rotation, boxes_overlap, flume_extent
from orchestrator.scene.overrides import apply_overrides, parse_override
from orchestrator.scene.resolve import scene_from_dict
from orchestrator.scene.scenefile import dump_scene_yaml, load_scene, scene_to_dict
from orchestrator.scene.schema import Scene, column_for_analysis, default_column
from orchestrator.scene.validation import MIN_CELLS_ACROSS_DEBRIS

from tests.conftest import CASES, ROOT, input_error

BAD = ROOT / "tests" / "data" / "bad_scenes"
VALID = BAD / "_valid_base.yaml"
CASE_NAMES = ["nodebris", "1debris", "3debris-3x1", "3debris-1x3", "6debris-2x3"]
BAD_FILES = sorted(p for p in BAD.glob("*.yaml") if not p.name.startswith("_"))


def expected_field(path: Path) -> str:
    for line in path.read_text().splitlines():
        if line.startswith("# expect-field:"):
            return line.split(":", 1)[1].strip()
    raise AssertionError(f"{path} has no '# expect-field:' line")


def raw(path: Path) -> dict:
    return yaml.safe_load(path.read_text())


# ------------------------------------------------------------------------ the cases


@pytest.mark.parametrize("name", CASE_NAMES)
def test_every_case_loads_and_reproduces_the_study(name):
    s = load_scene(CASES / f"{name}.yaml")
    assert s.name == name
    assert s.reservoir.depth_m == 0.40
    assert s.flume.width_m == 1.5
    assert s.bed.friction_factor == 0.0293
    assert s.bed.wet_depth_m == 0.015
    gauges = {g.name: g for g in s.gauges}
    assert gauges["WG1"].x_m == pytest.approx(-0.10)
    assert gauges["WG2"].x_m == pytest.approx(2.40)
    assert gauges["WG3"].x_m == pytest.approx(3.20)
    assert abs(gauges["WG3"].y_m) > 0.3  # off to one side
    face = s.column.x_m - s.column.size_x_m / 2
    assert 0 < face - gauges["WG4"].x_m <= 0.02  # at the column's upstream face
    assert s.column == default_column(s.column.x_m)
    for body in s.debris:
        assert body.size_m == (0.15, 0.06, 0.06)  # long axis along the flow
        assert body.mass_kg == 0.236 and body.wall_thickness_m == 0.005
        assert body.centre_m[2] == pytest.approx(0.03)  # resting on the bed
    if s.debris:
        xs = [b.centre_m[0] for b in s.debris]
        assert np.mean(xs) == pytest.approx(3.20)


@pytest.mark.parametrize(
    "name, rows, cols",
    [("1debris", 1, 1), ("3debris-3x1", 3, 1), ("3debris-1x3", 1, 3), ("6debris-2x3", 2, 3)],
)
def test_layouts_expand_rows_along_the_flow_and_columns_across(name, rows, cols):
    s = load_scene(CASES / f"{name}.yaml")
    assert len(s.debris) == rows * cols
    assert len({round(b.centre_m[0], 9) for b in s.debris}) == rows
    assert len({round(b.centre_m[1], 9) for b in s.debris}) == cols
    assert [b.name for b in s.debris] == [f"debris{i + 1}" for i in range(rows * cols)]


def test_layout_one_and_case_insensitive_rxc():
    assert len(load_scene(CASES / "6debris-2x3.yaml", ["debris.0.layout=1"]).debris) == 1
    s = load_scene(CASES / "6debris-2x3.yaml", ["debris.0.layout=3X1"])
    assert [b.centre_m[0] for b in s.debris] == pytest.approx([2.95, 3.20, 3.45])


def test_nodebris_has_an_empty_debris_list():
    assert load_scene(CASES / "nodebris.yaml").debris == ()


@pytest.mark.parametrize(
    "key, value",
    [
        ("reservoir.depth_m", 0.3),
        ("mesh.cell_size_m", 0.03),
        ("run.end_time_s", 2.0),
        ("run.cores", 4),
        ("column.natural_frequency_Hz", 72.2),
        ("column.base", "calibrated"),
        ("column.damping_ratio", 0.05),
        ("column.elements", 80),
    ],
)
def test_required_dotted_keys_exist_and_take_overrides(key, value):
    s = load_scene(CASES / "1debris.yaml", [f"{key}={value}"])
    section, name = key.split(".")
    assert getattr(getattr(s, section), name) == value


def test_column_defaults_are_the_measured_values():
    c = default_column()
    assert (c.natural_frequency_Hz, c.stiffness_N_m, c.damping_ratio, c.base, c.elements) == (
        70.0, 4.685e5, 0.045, "rigid", 160,
    )
    assert load_scene(VALID).run.cores == 2


# ------------------------------------------------------------------------ overrides


@pytest.mark.parametrize(
    "text, path, value",
    [
        ("a.b=1", ["a", "b"], 1),
        ("a.b=0.02", ["a", "b"], 0.02),
        ("a=null", ["a"], None),
        ("a.b=[1, 2.5]", ["a", "b"], [1, 2.5]),
        ("a.b=calibrated", ["a", "b"], "calibrated"),
        ("a.b=x=y", ["a", "b"], "x=y"),
        ("debris.0.mass_kg=0.3", ["debris", "0", "mass_kg"], 0.3),
    ],
)
def test_override_values_are_yaml_scalars(text, path, value):
    assert parse_override(text) == (path, value)


def test_override_debris_empty_and_column_null():
    s = load_scene(CASES / "1debris.yaml", ["debris=[]", "column=null", "gauges=[]"])
    assert s.debris == () and s.column is None


def test_override_into_a_layout_and_a_list_item():
    s = load_scene(CASES / "6debris-2x3.yaml", ["debris.0.layout=1x2", "debris.0.body.mass_kg=0.3"])
    assert len(s.debris) == 2 and all(b.mass_kg == 0.3 for b in s.debris)
    s = load_scene(CASES / "1debris.yaml", ["debris.0.yaw_deg=90"])
    assert s.debris[0].yaw_deg == 90


@pytest.mark.parametrize(
    "override, field",
    [
        ("mesh.cell_sise_m=0.02", "mesh.cell_sise_m"),
        ("nosuchsection.x=1", "nosuchsection.x"),
        ("debris.0.rows=2", "debris.0.rows"),
        ("debris.4.mass_kg=1", "debris.4.mass_kg"),
        ("run.cores.x=1", "run.cores.x"),
        ("run.cores", "run.cores"),
    ],
)
def test_bad_override_names_the_key_and_the_file(override, field):
    assert input_error(field, load_scene, CASES / "1debris.yaml", [override]).source == str(CASES / "1debris.yaml")


@pytest.mark.parametrize(
    "override, field",
    [
        ("run.end_time_s=soon", "run.end_time_s"),
        ("debris.0.size_m=[0.1, 0.1]", "debris.0.size_m"),
        ("debris.0.centre_m=[1, 2, 3, 4]", "debris.0.centre_m"),
        ("gauges.0=7", "gauges.0"),
        ("column.elements=2.5", "column.elements"),
    ],
)
def test_pydantic_errors_become_input_errors_with_the_dotted_location(override, field):
    input_error(field, load_scene, CASES / "1debris.yaml", [override])


def test_override_value_errors_say_an_override_set_them():
    with pytest.raises(InputError) as info:
        load_scene(CASES / "1debris.yaml", ["run.cores=0"])
    assert info.value.field == "run.cores"
    assert "override" in info.value.rule


def test_apply_overrides_does_not_touch_its_input():
    data = raw(VALID)
    before = yaml.safe_dump(data)
    apply_overrides(data, ["mesh.cell_size_m=0.02", "outputs.preview=false"])
    assert yaml.safe_dump(data) == before


# ------------------------------------------------------------------ resolution


def test_dump_reloads_to_the_same_scene(tmp_path):
    for name in CASE_NAMES:
        s = load_scene(CASES / f"{name}.yaml", ["mesh.cell_size_m=0.03"])
        path = tmp_path / f"{name}.yaml"
        path.write_text(dump_scene_yaml(s, ["mesh.cell_size_m=0.03"]))
        assert load_scene(path) == s
        assert scene_from_dict(scene_to_dict(s)) == s


def test_scene_is_frozen():
    s = load_scene(VALID)
    with pytest.raises(Exception):
        s.run.cores = 4  # type: ignore[misc]


def test_on_bed_placement_of_a_rotated_body():
    s = load_scene(VALID, ["debris.0.pitch_deg=30"])
    b = s.debris[0]
    rot = body_rotation(b.yaw_deg, b.pitch_deg, b.roll_deg)
    half = np.asarray(b.size_m) / 2
    signs = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)])
    corners = np.asarray(b.centre_m) + (signs * half) @ rot.T
    assert corners[:, 2].min() == pytest.approx(0.0, abs=1e-12)
    expected = 0.5 * (0.15 * math.sin(math.radians(30)) + 0.06 * math.cos(math.radians(30)))
    assert b.centre_m[2] == pytest.approx(expected)


def test_floating_placement_uses_the_draft_when_the_water_is_deep_enough():
    # a light body in the reservoir floats: draft = m / (rho l w)
    s = load_scene(VALID, ["debris.0.centre_m=[-2.0, 0.0]", "debris.0.placement=floating", "debris.0.mass_kg=0.2"])
    b = s.debris[0]
    draft = 0.2 / (998.2 * 0.15 * 0.06)
    assert b.centre_m[2] == pytest.approx(0.30 - draft + 0.03)
    # downstream the 10 mm wet bed is too shallow: it rests on the floor
    s = load_scene(VALID, ["debris.0.placement=floating"])
    assert s.debris[0].centre_m[2] == pytest.approx(0.03)


def test_given_placement_keeps_z():
    s = load_scene(VALID, ["debris.0.centre_m=[2.0, 0.0, 0.2]"])
    assert s.debris[0].centre_m == (2.0, 0.0, 0.2) and s.debris[0].placement == "given"


def test_gauge_at_the_column_follows_the_column():
    s = load_scene(CASES / "1debris.yaml", ["column.x_m=6.0", "column.y_m=0.2"])
    wg4 = next(g for g in s.gauges if g.name == "WG4")
    assert (wg4.x_m, wg4.y_m) == pytest.approx((6.0 - 0.1 - 0.01, 0.2))


def test_flume_extent_puts_the_gate_at_zero():
    s = load_scene(CASES / "1debris.yaml")
    (x0, x1), (y0, y1), (z0, z1) = flume_extent(s)
    assert (x0, x1) == pytest.approx((-21.55, 30.0 - 21.55))
    assert (y0, y1) == (-0.75, 0.75) and (z0, z1) == (0.0, 0.8)


def test_column_for_analysis_builds_the_analytical_column():
    s = load_scene(CASES / "1debris.yaml", ["column.base=calibrated", "column.elements=40"])
    col = column_for_analysis(s)
    assert type(col).__module__ == "analytical.column"
    assert (col.size_x_m, col.height_m, col.youngs_modulus_Pa, col.base, col.elements) == (
        0.20, 0.80, 2.50e9, "calibrated", 40,
    )
    with pytest.raises(InputError) as info:
        column_for_analysis(load_scene(VALID, ["column=null"]))
    assert info.value.field == "column"


# ------------------------------------------------------------------ validation


def test_the_valid_base_is_valid():
    assert isinstance(load_scene(VALID), Scene)


@pytest.mark.parametrize("path", BAD_FILES, ids=lambda p: p.stem)
def test_each_bad_scene_names_its_field_and_file(path):
    with pytest.raises(InputError) as info:
        load_scene(path)
    assert info.value.field == expected_field(path)
    assert info.value.source == str(path)
    assert str(path) in str(info.value) and info.value.field in str(info.value)


def test_there_is_a_bad_scene_for_every_listed_rule():
    names = {p.stem for p in BAD_FILES}
    for rule in (
        "unknown_key", "debris_overlaps_column", "debris_overlaps_debris", "debris_outside_flume",
        "impoundment_above_flume", "gauge_outside_domain", "cell_too_coarse_for_debris",
        "debris_nonpositive_mass", "debris_zero_size", "column_outside_flume", "end_time_not_positive",
        "cores_below_one",
    ):
        assert rule in names


def test_debris_resolution_rule_is_at_the_stated_ratio():
    limit = 0.06 / MIN_CELLS_ACROSS_DEBRIS
    load_scene(VALID, [f"mesh.cell_size_m={limit}"])
    with pytest.raises(InputError) as info:
        load_scene(VALID, [f"mesh.cell_size_m={limit * 1.01}"])
    assert info.value.field == "mesh.cell_size_m" and "1.5 cells across" in info.value.rule


def test_missing_file_and_non_mapping(tmp_path):
    with pytest.raises(InputError) as info:
        load_scene(tmp_path / "nope.yaml")
    assert info.value.field == "scene"
    p = tmp_path / "list.yaml"
    p.write_text("- 1\n- 2\n")
    with pytest.raises(InputError) as info:
        load_scene(p)
    assert info.value.source == str(p)


def test_body_on_the_column_face_touching_is_allowed_overlap_is_not():
    # the body's downstream end exactly on the column's upstream face (2.9 m)
    load_scene(VALID, ["debris.0.centre_m=[2.825, 0.0]"])
    with pytest.raises(InputError):
        load_scene(VALID, ["debris.0.centre_m=[2.83, 0.0]"])


# ------------------------------------------------------------ the overlap test


def test_boxes_overlap_axis_aligned_and_rotated():
    eye = np.eye(3)
    assert boxes_overlap((0, 0, 0), eye, (1, 1, 1), (0.9, 0, 0), eye, (1, 1, 1))
    assert not boxes_overlap((0, 0, 0), eye, (1, 1, 1), (1.0, 0, 0), eye, (1, 1, 1))  # touching
    rot45 = body_rotation(45, 0, 0)
    # a unit cube turned 45 deg reaches sqrt(2)/2 = 0.707 along x
    assert boxes_overlap((0, 0, 0), rot45, (1, 1, 1), (1.2, 0, 0), eye, (1, 1, 1))
    assert not boxes_overlap((0, 0, 0), rot45, (1, 1, 1), (1.25, 0, 0), eye, (1, 1, 1))
    # near the corner of an unrotated box, but outside its edge (an edge-edge separating axis)
    r = body_rotation(45, 45, 0)
    assert not boxes_overlap((0, 0, 0), eye, (1, 1, 1), (1.3, 1.3, 0), r, (1, 1, 1))


@settings(max_examples=200, deadline=None)
@given(
    st.tuples(*[st.floats(-1, 1)] * 3),
    st.tuples(*[st.floats(0, 360)] * 3),
    st.tuples(*[st.floats(0.1, 1)] * 3),
    st.tuples(*[st.floats(0.1, 1)] * 3),
)
def test_boxes_overlap_agrees_with_sampling(offset, angles, s1, s2):
    """If a sample point lies inside both boxes they overlap; the test must say so."""
    r2 = body_rotation(*angles)
    rng = np.random.default_rng(0)
    pts = (rng.random((4000, 3)) - 0.5) * np.asarray(s1)
    local = (pts - np.asarray(offset)) @ r2  # into box 2's axes
    inside2 = np.all(np.abs(local) < np.asarray(s2) / 2 - 1e-6, axis=1)
    result = boxes_overlap((0, 0, 0), np.eye(3), s1, offset, r2, s2)
    if inside2.any():
        assert result
    # and symmetric
    assert result == boxes_overlap(offset, r2, s2, (0, 0, 0), np.eye(3), s1)


# --------------------------------------------------------------------------- extends


def test_hard_cases_extend_their_base_and_change_only_what_they_say():
    base = load_scene(CASES / "1debris.yaml")
    short = load_scene(CASES / "hard" / "short-flume.yaml")
    assert short.name == "hard-short-flume" and short.column.x_m == 3.0
    assert short.column.stiffness_N_m == base.column.stiffness_N_m  # merged key by key
    assert short.reservoir == base.reservoir
    assert short.mesh == base.mesh.model_copy(update={"column_approach_cell_size_m": None})  # 4 cm at its column
    assert short.run.end_time_s == 1.4 and short.run.max_courant == base.run.max_courant
    deep = load_scene(CASES / "hard" / "max-impoundment.yaml")  # extends short-flume, which extends 1debris
    assert deep.reservoir.depth_m == 0.70 and deep.reservoir.length_m == base.reservoir.length_m
    assert deep.column.x_m == 3.0 and deep.debris == short.debris
    six = load_scene(CASES / "hard" / "six-debris.yaml")
    assert len(six.debris) == 6 and len(six.gauges) == len(short.gauges)  # lists are replaced whole


def test_every_hard_case_loads():
    names = {load_scene(p).name for p in (CASES / "hard").glob("*.yaml")}
    assert len(names) == len(list((CASES / "hard").glob("*.yaml"))) >= 8


@pytest.mark.parametrize("text, rule", [
    ("extends: missing.yaml\n", "no such scene file"),
    ("extends: [a, b]\n", "must be the path of another scene file"),
    ("extends: self.yaml\n", "a cycle"),
])
def test_bad_extends_names_the_field_and_the_file(tmp_path, text, rule):
    path = tmp_path / "self.yaml"
    path.write_text(text)
    with pytest.raises(InputError) as info:
        load_scene(path)
    assert info.value.field == "extends" and rule in str(info.value) and str(path) in str(info.value)


def test_extends_cycle_through_another_file(tmp_path):
    (tmp_path / "a.yaml").write_text("extends: b.yaml\n")
    (tmp_path / "b.yaml").write_text("extends: a.yaml\n")
    with pytest.raises(InputError, match="cycle"):
        load_scene(tmp_path / "a.yaml")
