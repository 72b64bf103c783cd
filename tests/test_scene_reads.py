"""A case's scene.yaml is read as a typed Scene (``CaseFolder.scene()``, ``load_scene``): outside the
scene stage no module parses YAML. case/render.py imports the library only to write scene.yaml for
a stand-in scene given as a mapping (tests render a plan beside one); it reads none."""
from __future__ import annotations

import ast
from pathlib import Path

import pytest

from orchestrator.case.folder import CaseFolder
from orchestrator.core.errors import InputError
from tests.conftest import package_modules

ROOT = Path(__file__).resolve().parents[1]
#: the scene stage parses YAML; render writes it
OWNERS = ("orchestrator/scene/", "orchestrator/case/render.py")


def yaml_imports(source: str) -> list[int]:
    out = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Import) and any(a.name == "yaml" for a in node.names):
            out.append(node.lineno)
        elif isinstance(node, ast.ImportFrom) and node.module == "yaml":
            out.append(node.lineno)
    return out


@pytest.mark.parametrize("module", package_modules(*OWNERS))
def test_a_module_outside_the_scene_stage_parses_no_yaml(module):
    assert not yaml_imports((ROOT / module).read_text()), f"{module}: read scene.yaml with CaseFolder(case).scene()"


def case_scene_loads(source: str) -> list[int]:
    """Lines that load a case folder's own scene.yaml as it is (``load_scene(folder.scene_path)``,
    ``load_scene(case / "scene.yaml")``) instead of taking ``CaseFolder.scene()``; a load with
    overrides (a second argument) makes another scene from it and is not counted."""
    out = []
    for node in ast.walk(ast.parse(source)):
        if not (isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id == "load_scene"
                and len(node.args) == 1 and not node.keywords):
            continue
        arg = node.args[0]
        if any(isinstance(n, ast.Attribute) and n.attr == "scene_path" for n in ast.walk(arg)) or any(
                isinstance(n, ast.Constant) and n.value == "scene.yaml" for n in ast.walk(arg)):
            out.append(node.lineno)
    return out


@pytest.mark.parametrize("module", package_modules(*OWNERS, "orchestrator/case/folder.py"))
def test_a_case_folders_scene_is_read_through_the_folder(module):
    assert not case_scene_loads((ROOT / module).read_text()), f"{module}: take CaseFolder(case).scene()"


def test_the_scan_sees_a_case_scene_loaded_by_hand():
    assert case_scene_loads("s = load_scene(folder.scene_path)\nt = load_scene(case / 'scene.yaml')\n") == [1, 2]
    assert not case_scene_loads("s = load_scene(args.scene)\nt = load_scene(folder.scene_path, ['a=1'])\n")


def test_the_scan_sees_an_import_inside_a_function():
    assert yaml_imports("def f():\n    import yaml\n    return yaml.safe_load('a: 1')\n") == [2]
    assert yaml_imports("from yaml import safe_load\n") == [1]


def test_a_case_folder_reads_its_scene_typed_and_names_a_missing_one(tmp_path):
    shipped = ROOT / "cases" / "1debris.yaml"
    (tmp_path / "scene.yaml").write_text(shipped.read_text())
    scene = CaseFolder(tmp_path).scene()
    assert scene.column is not None and scene.column.x_m == pytest.approx(5.0)
    (tmp_path / "scene.yaml").unlink()
    with pytest.raises(InputError) as err:
        CaseFolder(tmp_path).scene()
    assert err.value.field == "scene.yaml" and "missing" in str(err.value)
