"""The case folder: one owner of its file names, time folders and JSON records.

A debrisfoam case is an OpenFOAM case (foamlib's :class:`~foamlib.FoamCase` reads its
dictionaries) plus the records the tool keeps beside it::

    scene.yaml      the resolved scene it was rendered from (overrides applied)
    plan.json       the planner's decisions (mesh, bodies, time-step caps, warnings)
    run.json        the runner's record: status, segments, wall times, diagnosis
    bodies/<name>/  each body's own mesh before it is merged (overset cases)
    results/        what post-processing writes: tables, plots, summary.json, report.md

Every module that reads or writes one of these goes through :class:`CaseFolder`, so a
name is spelled once and every write is atomic (a temporary file and a rename).
"""
from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

from foamlib import FoamCase

from orchestrator.core.errors import InputError
from orchestrator.core.files import read_json, read_json_object, write_json_atomic, write_text_atomic
from orchestrator.case.run_state import RunState
from orchestrator.plan.model import ModelPlan
from orchestrator.scene.scenefile import dump_scene_yaml, load_scene
from orchestrator.scene.schema import Scene

SCENE_YAML = "scene.yaml"
PLAN_JSON = "plan.json"
RUN_JSON = "run.json"
RESULTS_DIR = "results"
SUMMARY_JSON = "summary.json"
BODIES_DIR = "bodies"
#: The cell zone of the bed's friction layer (topoSet writes it, fvOptions uses it).
BED_LAYER_ZONE = "bedLayer"
#: Two times closer than this (s) are the same written time.
EPS_T = 1e-9


def time_names(base: str | Path) -> list[tuple[float, str]]:
    """The time folders directly under ``base`` as (time, folder name), earliest first."""
    base = Path(base)
    out = []
    if not base.is_dir():
        return out
    for p in base.iterdir():
        if p.is_dir():
            try:
                out.append((float(p.name), p.name))
            except ValueError:
                continue
    return sorted(out)


def processor_dirs(case: str | Path) -> list[Path]:
    """The case's processorN folders, by rank."""
    procs = [p for p in Path(case).glob("processor*") if p.is_dir() and p.name[9:].isdigit()]
    return sorted(procs, key=lambda p: int(p.name[9:]))


class CaseFolder:
    """A case folder on disk: where each record lives, and reading and writing them.

    >>> folder = CaseFolder("runs/1debris")          # doctest: +SKIP
    >>> folder.model_plan().cell_count               # doctest: +SKIP
    """

    def __init__(self, path: str | Path):
        self.path = Path(path)

    def __repr__(self) -> str:
        return f"CaseFolder({str(self.path)!r})"

    # ------------------------------------------------------------------ where things are
    @property
    def scene_path(self) -> Path:
        return self.path / SCENE_YAML

    @property
    def plan_path(self) -> Path:
        return self.path / PLAN_JSON

    @property
    def run_path(self) -> Path:
        return self.path / RUN_JSON

    @property
    def results_dir(self) -> Path:
        return self.path / RESULTS_DIR

    @property
    def summary_path(self) -> Path:
        return self.results_dir / SUMMARY_JSON

    def body_dir(self, name: str) -> Path:
        return self.path / BODIES_DIR / name

    @property
    def foam(self) -> FoamCase:
        """The OpenFOAM case, read with foamlib (controlDict, fvSolution, ...)."""
        return FoamCase(self.path)

    def is_case(self) -> bool:
        """A folder the tool rendered, or at least an OpenFOAM case."""
        return self.plan_path.is_file() or (self.path / "system" / "controlDict").is_file()

    def has_run(self) -> bool:
        """Whether a solver has run here at all: run.json, postProcessing/, or a time written
        after 0 (in the case or in a processor folder)."""
        if self.run_path.is_file() or (self.path / "postProcessing").is_dir():
            return True
        return any(t > EPS_T for base in (self.path, *self.processor_dirs()) for t, _ in time_names(base))

    # ------------------------------------------------------------------ time folders
    def times(self) -> list[tuple[float, str]]:
        """The case's own (reconstructed) time folders, earliest first."""
        return time_names(self.path)

    def processor_dirs(self) -> list[Path]:
        return processor_dirs(self.path)

    # ------------------------------------------------------------------ records
    def plan(self, notes: list[str] | None = None) -> dict | None:
        """plan.json as a raw mapping, or None when missing or unreadable (a line added to ``notes``).
        Read only by the modules tests/test_layers.py allows; every other reader takes
        :meth:`model_plan`."""
        data = read_json(self.plan_path, notes)
        return data if isinstance(data, dict) else None

    def model_plan(self, notes: list[str] | None = None) -> ModelPlan | None:
        """plan.json as the planner's :class:`ModelPlan`, or None when missing, unreadable or not
        the plan `debrisfoam render` writes (a line added to ``notes`` says why)."""
        data = self.plan(notes)
        if data is None:
            return None
        try:
            return self._typed_plan(data)
        except InputError as exc:
            if notes is not None:
                notes.append(f"{self.plan_path.name} is not a plan this debrisfoam reads ({exc.field}: {exc.rule}); "
                             "ignored")
            return None

    def debris_coupling(self) -> str:
        """The case's debris coupling: the typed plan's, else the ``debris_coupling`` a plan.json from
        an older debrisfoam records (its other fields may no longer read as a ModelPlan), else "none".
        What decides whether a one-way case's transport section belongs to its identity."""
        plan = self.model_plan()
        if plan is not None:
            return plan.debris_coupling
        coupling = (self.plan() or {}).get("debris_coupling")
        return coupling if isinstance(coupling, str) else "none"

    def require_plan(self) -> ModelPlan:
        """plan.json as the planner's :class:`ModelPlan`; InputError naming the file when it is
        missing, unreadable or not the plan `debrisfoam render` writes."""
        path = self.plan_path
        if not path.is_file():
            raise InputError("plan.json", f"missing: render the case first (debrisfoam render SCENE -o {self.path})",
                             str(path))
        notes: list[str] = []
        data = self.plan(notes)
        if data is None:
            why = notes[0].removeprefix(f"{path.name} ").removesuffix("; ignored") if notes else "not a JSON object"
            raise InputError("plan.json", why, str(path))
        return self._typed_plan(data)

    def _typed_plan(self, data: dict) -> ModelPlan:
        try:
            return ModelPlan.from_dict(data)
        except InputError as exc:
            raise exc.with_source(str(self.plan_path)) from None
        except (KeyError, TypeError, ValueError, AttributeError, IndexError) as exc:
            raise InputError("plan.json", f"not the plan `debrisfoam render` writes ({exc!r})",
                             str(self.plan_path)) from None

    def run_record(self, notes: list[str] | None = None) -> dict | None:
        """run.json as a raw mapping, or None when missing or unreadable: for its writers (the
        runner, the transport); readers take :meth:`run_state`."""
        data = read_json(self.run_path, notes)
        return data if isinstance(data, dict) else None

    def run_state(self, notes: list[str] | None = None) -> RunState:
        """run.json as a :class:`RunState` (empty when the case has not run or it is unreadable: a
        line added to ``notes`` says why)."""
        return RunState.from_dict(self.run_record(notes))

    def summary(self) -> dict | None:
        """results/summary.json, or None."""
        return read_json_object(self.summary_path)

    def scene(self) -> Scene:
        """scene.yaml as the resolved :class:`Scene` the case was rendered from; InputError naming
        the file when it is missing or today's checks refuse it."""
        if not self.scene_path.is_file():
            raise InputError("scene.yaml", "missing: not a case folder that `debrisfoam render` wrote",
                             str(self.scene_path))
        return load_scene(self.scene_path)

    def scene_text(self) -> str | None:
        """scene.yaml's text, or None."""
        return self.scene_path.read_text() if self.scene_path.is_file() else None

    def write_plan_json(self, text: str) -> Path:
        return write_text_atomic(self.plan_path, text)

    def write_scene(self, scene: Scene, overrides: Sequence[str] = ()) -> Path:
        """scene.yaml: the resolved ``scene`` with the ``overrides`` it was asked with
        (:func:`orchestrator.scene.scenefile.dump_scene_yaml`)."""
        text = dump_scene_yaml(scene, list(overrides))
        return write_text_atomic(self.scene_path, text)

    def write_run_record(self, data: dict[str, Any]) -> Path:
        return write_json_atomic(self.run_path, data)

    def write_summary(self, data: dict[str, Any]) -> Path:
        self.results_dir.mkdir(parents=True, exist_ok=True)
        return write_json_atomic(self.summary_path, data)
