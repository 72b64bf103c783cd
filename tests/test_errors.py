"""One errors module for orchestrator/, and each error is also the built-in it stands for."""

from __future__ import annotations

from pathlib import Path

import pytest

from analytical.errors import InputError as AnalyticalInputError
from orchestrator.case.foam import StepError
from orchestrator.core.errors import DebrisfoamError, InputError, MissingFeatureError
from orchestrator.run.errors import DivergenceError, RunError

ROOT = Path(__file__).resolve().parents[1]


def test_orchestrator_takes_its_errors_from_core_errors_only():
    wrong = [str(p.relative_to(ROOT)) for p in (ROOT / "orchestrator").rglob("*.py")
             if "from analytical.errors import" in p.read_text() and p.relative_to(ROOT).as_posix() != "orchestrator/core/errors.py"]
    assert not wrong, f"import errors from orchestrator.core.errors: {wrong}"


@pytest.mark.parametrize("error, builtin", [
    (InputError("mesh.cell_size_m", "must be > 0"), ValueError),
    (MissingFeatureError("design"), NotImplementedError),
    (StepError("blockMesh", "a reason", "log.blockMesh"), RuntimeError),
    (RunError("stopped"), RuntimeError),
    (DivergenceError("nan", "NaN in p_rgh", 0.1, "0.05", Path("log.interFoam")), RuntimeError),
])
def test_each_error_is_also_its_builtin(error, builtin):
    assert isinstance(error, DebrisfoamError) and isinstance(error, builtin)


def test_the_physics_package_raises_the_same_input_error():
    assert AnalyticalInputError is InputError
