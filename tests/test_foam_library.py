"""One OpenFOAM dictionary library: foamlib, through orchestrator.case.dictionary.

PyFoam may be imported by one module at most, and only where foamlib cannot do the job (named in
a comment there). The edits the runner makes keep every digit, every entry left alone, and never
leave half a file.
"""

from __future__ import annotations

import ast
import os
from pathlib import Path

import pytest

from orchestrator.case.dictionary import DictionaryError, edit_dictionary, read_dictionary

ROOT = Path(__file__).resolve().parents[1]
SOURCES = ("orchestrator", "analytical", "benchmarks", "tests")

CONTROL = """FoamFile
{
    version     2.0;
    format      ascii;
    class       dictionary;
    object      controlDict;
}
// the runner edits stopAt while the solver runs
application     interFoam;
stopAt          endTime;
endTime         0.6;
gauge           (0.12345678901234 1e-17 3);
"""


def _imports_pyfoam(source: str) -> bool:
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Import) and any(a.name.split(".")[0] == "PyFoam" for a in node.names):
            return True
        if isinstance(node, ast.ImportFrom) and node.module and node.module.split(".")[0] == "PyFoam":
            return True
    return False


def _pyfoam_modules() -> list[str]:
    return sorted(str(p.relative_to(ROOT)) for top in SOURCES for p in (ROOT / top).rglob("*.py")
                  if _imports_pyfoam(p.read_text()))


def test_the_import_count_sees_every_way_of_importing_pyfoam():
    assert _imports_pyfoam("def f():\n    from PyFoam.RunDictionary.ParsedParameterFile import X\n")
    assert _imports_pyfoam("import PyFoam.Basics.DataStructures as ds\n")
    assert not _imports_pyfoam("import foamlib\n# PyFoam is not imported here\n")


def test_pyfoam_is_imported_by_one_module_at_most():
    assert len(_pyfoam_modules()) <= 1, _pyfoam_modules()


def test_an_edit_writes_every_digit_and_keeps_the_rest_as_written(tmp_path):
    path = tmp_path / "controlDict"
    path.write_text(CONTROL)
    with edit_dictionary(path) as control:
        control["endTime"] = 0.1 + 0.2
        control["stopAt"] = "writeNow"
        control["velocity"] = [1 / 3, -2e-12, 0.0]
    text = path.read_text()
    assert "endTime 0.30000000000000004;" in text and "velocity (0.3333333333333333 -2e-12 0.0);" in text
    assert "gauge           (0.12345678901234 1e-17 3);" in text  # not touched: as written
    assert "// the runner edits stopAt while the solver runs" in text
    read = read_dictionary(path)
    assert read["endTime"] == 0.1 + 0.2 and read["stopAt"] == "writeNow"
    assert list(read["velocity"]) == [1 / 3, -2e-12, 0.0]
    assert "\n\n\n" not in text and not any(line.strip() == "" and line for line in text.splitlines())


def test_an_edit_that_changes_nothing_or_fails_leaves_the_file(tmp_path):
    path = tmp_path / "controlDict"
    path.write_text(CONTROL)
    os.utime(path, (1.0e9, 1.0e9))
    with edit_dictionary(path) as control:
        assert control["endTime"] == 0.6  # read, nothing set
    assert path.stat().st_mtime == 1.0e9
    with pytest.raises(KeyError), edit_dictionary(path) as control:
        control["endTime"] = 0.2
        raise KeyError("a failure half way")
    assert path.read_text() == CONTROL and path.stat().st_mtime == 1.0e9
    assert sorted(p.name for p in tmp_path.iterdir()) == ["controlDict"]  # no copy left behind


def test_adding_and_removing_an_entry_again_and_again_does_not_grow_the_file(tmp_path):
    path = tmp_path / "dynamicMeshDict"
    path.write_text(CONTROL.replace("controlDict", "dynamicMeshDict") + "constraints\n{\n    keep { axis (0 0 1); }\n}\n")
    sizes = []
    for _ in range(3):
        with edit_dictionary(path) as d:
            d["constraints"]["stickPoint"] = {"sixDoFRigidBodyMotionConstraint": "point"}
        with edit_dictionary(path) as d:
            del d["constraints"]["stickPoint"]
        sizes.append(len(path.read_text()))
    assert sizes[0] == sizes[1] == sizes[2]
    assert read_dictionary(path)["constraints"].as_dict() == {"keep": {"axis": [0, 0, 1]}}


def test_a_file_that_is_not_a_dictionary_raises_the_dictionary_error(tmp_path):
    path = tmp_path / "controlDict"
    path.write_text("endTime 0.6\nstopAt {{ ;\n")
    with pytest.raises(DictionaryError):
        read_dictionary(path)["endTime"]
