"""plan.json is read as a ModelPlan: no module of orchestrator/ outside plan/ and case/folder.py reads it as a mapping.

``CaseFolder.model_plan()`` / ``require_plan()`` (orchestrator/case/folder.py) read the file into
:class:`orchestrator.plan.model.ModelPlan` through ``ModelPlan.from_dict``; every other module takes
the plan's attributes. The scan (an AST walk of each module) counts as a mapping read of plan.json:

- a call of a method named ``plan`` (``CaseFolder.plan()``, the raw mapping);
- ``ModelPlan.from_dict`` / ``from_json`` (the typed reading belongs to the case folder);
- a JSON load (``json.load(s)``, ``read_json``, ``read_json_object``) or a text read (``open``,
  ``.read_text()``) whose expression names the file: the string ``"plan.json"``, ``PLAN_JSON`` or
  ``.plan_path``.

What it does not catch: a path to plan.json built without naming it (a variable holding the file
name from elsewhere) and read as JSON there. Writing the file (``case/render.py``) is not a read.
"""
from __future__ import annotations

import ast
from pathlib import Path

import pytest
from tests.conftest import package_modules

ROOT = Path(__file__).resolve().parents[1]
#: Where plan.json may be read as a mapping: the plan's own reader and the case folder that owns the file.
OWNERS = ("orchestrator/plan/", "orchestrator/case/folder.py")
#: Modules that still read plan.json as a mapping, each with why (none: every reader takes the typed plan).
ALLOWED: set[str] = set()
JSON_LOADS = {"load", "loads", "read_json", "read_json_object"}
TEXT_READS = {"open", "read_text"}


def _names_plan_json(node: ast.AST) -> bool:
    for sub in ast.walk(node):
        if isinstance(sub, ast.Constant) and sub.value == "plan.json":
            return True
        if isinstance(sub, ast.Name) and sub.id == "PLAN_JSON":
            return True
        if isinstance(sub, ast.Attribute) and sub.attr in ("PLAN_JSON", "plan_path"):
            return True
    return False


def _callee(call: ast.Call) -> str | None:
    if isinstance(call.func, ast.Attribute):
        return call.func.attr
    if isinstance(call.func, ast.Name):
        return call.func.id
    return None


def plan_json_reads(source: str) -> list[tuple[int, str]]:
    """(line, what) of every mapping read of plan.json in the module's source (see the module notes)."""
    out = []
    for node in ast.walk(ast.parse(source)):
        if not isinstance(node, ast.Call):
            continue
        name = _callee(node)
        if name == "plan" and isinstance(node.func, ast.Attribute):
            out.append((node.lineno, "CaseFolder.plan(), the raw mapping"))
        elif name in ("from_dict", "from_json") and isinstance(node.func, ast.Attribute) \
                and isinstance(node.func.value, ast.Name) and node.func.value.id == "ModelPlan":
            out.append((node.lineno, f"ModelPlan.{name}"))
        elif name in JSON_LOADS | TEXT_READS and _names_plan_json(node):
            out.append((node.lineno, f"{name}() of plan.json"))
    return out


@pytest.mark.parametrize("module", package_modules(*OWNERS))
def test_plan_json_is_read_as_a_model_plan(module):
    reads = plan_json_reads((ROOT / module).read_text())
    if module in ALLOWED:
        assert reads, f"{module} reads plan.json as a ModelPlan: take it off ALLOWED"
    else:
        assert not reads, f"{module} reads plan.json as a mapping: {reads} (take CaseFolder.model_plan())"


def test_the_scan_sees_the_owners_reads():
    """The case folder reads plan.json as a mapping (plan(), ModelPlan.from_dict): the scan finds both
    in real code, so a module it passes reads none."""
    whats = {what for _, what in plan_json_reads((ROOT / "orchestrator/case/folder.py").read_text())}
    assert whats >= {"CaseFolder.plan(), the raw mapping", "ModelPlan.from_dict"}, whats


def test_the_allowed_modules_exist():
    assert all((ROOT / m).is_file() for m in ALLOWED), sorted(m for m in ALLOWED if not (ROOT / m).is_file())


@pytest.mark.parametrize("source", [
    "plan = folder.plan()\nx = plan['solver']\n",
    "coupling = (CaseFolder(case).plan() or {}).get('debris_coupling')\n",
    "data = json.loads((case / 'plan.json').read_text())\n",
    "data = read_json(folder.plan_path)\n",
    "with open(case / PLAN_JSON) as fh:\n    data = json.load(fh)\n",
    "plan = ModelPlan.from_dict(raw)\n",
])
def test_the_scan_sees_a_mapping_read(source):
    assert plan_json_reads(source)


@pytest.mark.parametrize("source", [
    "plan = folder.model_plan()\nx = plan.solver\n",
    "plan = CaseFolder(case).require_plan()\n",
    "files[PLAN_JSON] = plan.to_json()\n",
    "cells = lay.plan.background.cell_count()\n",
])
def test_the_scan_passes_a_typed_read(source):
    assert not plan_json_reads(source)
