"""The scene reference is generated from the schema: docs/scene.md is current, every key has a
meaning, and the scenes / validate / schema verbs keep the exit-code contract."""

from __future__ import annotations

import json
from pathlib import Path

from orchestrator.scene.reference import markdown, schema_rows
from orchestrator.scene.shipped import shipped_scenes
from orchestrator.scene.scenefile import load_scene
from tests.conftest import run_cli

ROOT = Path(__file__).resolve().parent.parent


def test_docs_scene_md_is_what_the_schema_generates():
    assert (ROOT / "docs" / "scene.md").read_text() == markdown(schema_rows()), "run `make scene-doc`"


def test_every_scene_key_is_described_with_its_default_and_range():
    rows = {r.key: r for r in schema_rows()}
    assert all(r.description for r in rows.values()), [k for k, r in rows.items() if not r.description]
    assert rows["run.max_courant"].range == "> 0, <= 5" and rows["run.max_courant"].default == "0.9"
    assert rows["debris[N].contact.restitution"].range == "> 0, <= 1"
    assert rows["debris[N].size_m"].range == "each > 0"


def test_every_shipped_scene_loads():
    scenes = shipped_scenes()
    assert len(scenes) >= 10
    for path, text in scenes:
        assert text, path
        load_scene(path)


def test_scenes_validate_and_schema_verbs(tmp_path):
    listed = json.loads(run_cli("scenes", "--json").stdout)
    assert any(s["path"].endswith("1debris.yaml") for s in listed["scenes"])
    ok = run_cli("validate", str(ROOT / "cases" / "1debris.yaml"), "--json", cwd=tmp_path)
    assert ok.returncode == 0 and json.loads(ok.stdout)["valid"] is True
    bad = run_cli("validate", str(ROOT / "cases" / "1debris.yaml"), "--set", "debris.0.contact.damping_ratio=-0.5",
                  cwd=tmp_path)
    assert bad.returncode == 2 and "debris.0.contact.damping_ratio" in bad.stderr and "1debris.yaml" in bad.stderr
    keys = json.loads(run_cli("schema", "debris.0.contact", "--json").stdout)["keys"]
    assert {k["key"] for k in keys} >= {"debris[N].contact.law", "debris[N].contact.bed_friction_coefficient"}
    unknown = run_cli("schema", "no.such.key")
    assert unknown.returncode == 2 and "no scene key" in unknown.stderr
    assert list(tmp_path.iterdir()) == []  # validate wrote nothing where it ran
