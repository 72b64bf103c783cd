"""A case folder is reused when it holds the same case (orchestrator.pipeline.prepare_case).

"The same" is the resolved scene, less what the case's coupling does not use: a two-way case
does not depend on the one-way transport's keys, so a changed default there (or a --set of
one) does not turn a finished coupled run into another case; a one-way case takes them into
its scene.yaml and carries its bodies again through the same flow. Rendering only, no OpenFOAM.
"""

from __future__ import annotations

import pytest

from analytical.errors import InputError
from orchestrator.pipeline import prepare_case as prepare_planned
from orchestrator.plan.planner import load_and_plan
from tests.conftest import ROOT

TWO_WAY = ROOT / "cases" / "hard" / "small" / "tiny-flume.yaml"
ONE_WAY = ROOT / "tests" / "data" / "scenes" / "tiny-oneway-strike.yaml"


def prepare_case(scene_path, out, sets=()):
    """The scene file loaded and planned once, as `debrisfoam case` does, then prepared."""
    return prepare_planned(*load_and_plan(scene_path, sets), scene_path, out, sets)


def test_a_two_way_case_is_the_same_whatever_the_transport_keys(tmp_path):
    case, rendered = prepare_case(TWO_WAY, tmp_path / "two")
    assert rendered
    again, rendered = prepare_case(TWO_WAY, case, ["transport.drag_coefficient=1.5", "outputs.flow_record_hz=100"])
    assert (again, rendered) == (case, False)
    with pytest.raises(InputError, match="different case"):
        prepare_case(TWO_WAY, case, ["run.end_time_s=0.7"])


def test_a_one_way_case_takes_new_transport_keys_into_the_same_flow(tmp_path):
    """The transport keys do not change a one-way case's flow: asked for with another drag
    coefficient, the folder is resumed with the new key in its scene.yaml (the bodies are
    carried again); a flow key makes it a different case."""
    case, _ = prepare_case(ONE_WAY, tmp_path / "one")
    assert prepare_case(ONE_WAY, case) == (case, False)
    assert prepare_case(ONE_WAY, case, ["transport.drag_coefficient=1.5"]) == (case, False)
    assert "drag_coefficient: 1.5" in (case / "scene.yaml").read_text()
    with pytest.raises(InputError, match="different case"):
        prepare_case(ONE_WAY, case, ["bed.wet_depth_m=0.02"])


def test_a_one_way_case_takes_a_new_contact_law_into_the_same_flow(tmp_path):
    """A body's contact law is read by the transport alone: a stated law resumes the one-way folder
    with the law in its scene.yaml (the bodies carried again); a body's mass changes the case."""
    case, _ = prepare_case(ONE_WAY, tmp_path / "one")
    law = ["debris.0.contact.stiffness_N_m=5.5e4", "debris.0.contact.damping_ratio=0.4"]
    assert prepare_case(ONE_WAY, case, law) == (case, False)
    text = (case / "scene.yaml").read_text()
    assert "stiffness_N_m: 55000" in text and "damping_ratio: 0.4" in text
    with pytest.raises(InputError, match="different case"):
        prepare_case(ONE_WAY, case, ["debris.0.mass_kg=0.3"])


def test_a_folder_whose_scene_todays_checks_refuse_is_named_as_such(tmp_path):
    """A case folder written under older rules is not "a different case": the message says its
    scene.yaml no longer passes, and why, and the folder is left as it was."""
    case, _ = prepare_case(ONE_WAY, tmp_path / "one")
    scene_file = case / "scene.yaml"
    scene_file.write_text(scene_file.read_text().replace("mass_kg: 0.236", "mass_kg: -1.0"))
    before = scene_file.read_text()
    with pytest.raises(InputError, match="today's checks refuse .*mass_kg"):
        prepare_case(ONE_WAY, case)
    assert scene_file.read_text() == before
