"""The sweep file: read, its members expanded and every one validated before anything runs.

A sweep file (YAML; the format is documented in docs/sweeps.md)::

    name: mesh-study                 # optional; default: the file's stem
    base: ../nodebris.yaml           # the scene, relative to this file (or `scenes:`, a list)
    set: {run.end_time_s: 2.0}       # optional overrides applied to every member
    mode: grid                       # grid (cartesian product, default) or zip (parallel lists)
    axes:
      mesh.cell_size_m: [0.08, 0.06, 0.04]
    executor: {kind: local, workers: 1}   # optional defaults; the CLI's options win
    cores_per_member: 2              # optional: MPI ranks of every member (default: its run.cores)

:func:`load_sweep` loads each member's scene with the overrides of
:mod:`orchestrator.scene.scenefile` and plans it with :func:`orchestrator.plan.planner.plan_case`,
so a bad member is an :class:`InputError` naming the sweep file, the member and the field
before a single case is rendered. A member's id is a short hash of its resolved scene
(:func:`member_id`): the same scene always lands in the same folder, whatever axes produced it.
"""

from __future__ import annotations

import itertools
import json
import os
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from orchestrator.core.errors import DebrisfoamError, InputError
from orchestrator.core.jsonio import json_default
from orchestrator.plan.identity import ID_LENGTH, case_key
from orchestrator.plan.planner import ModelPlan, estimate_wall_time_s, plan_case
from orchestrator.scene.scenefile import load_scene, read_yaml, scene_to_dict
from orchestrator.scene.schema import Scene

#: The executors a sweep runs on.
EXECUTORS = ("local", "dask")

_SWEEP_KEYS = ("name", "description", "base", "scenes", "set", "mode", "axes", "executor", "cores_per_member")
_EXECUTOR_KEYS = ("kind", "workers", "scheduler")
_MODES = ("grid", "zip")
_NAME_RE = re.compile(r"^[A-Za-z0-9][A-Za-z0-9._-]*$")

class SweepMemberError(InputError):
    """A member of a sweep is bad input: names the sweep file, the member and the field."""

    def __init__(self, sweep_file: str, index: int, total: int, label: str, err: InputError):
        self.member = index
        self.label = label
        self.scene_source = err.source
        self.member_text = f"member {index} of {total} ({label or 'the base scene'})"
        scene = f" [scene {err.source}]" if err.source and err.source != sweep_file else ""
        super().__init__(err.field, f"{err.rule}{scene}", sweep_file)

    def _text(self) -> str:
        return f"{self.source}: {self.member_text}: {self.field}: {self.rule}"


@dataclass(frozen=True)
class Member:
    """One member of a sweep: its scene (validated), its plan and where it came from."""

    index: int  # 1-based, in expansion order
    id: str
    base: Path
    overrides: tuple[str, ...]  # every override applied to the base: `set` first, then the axes
    axis_overrides: tuple[str, ...]  # the overrides that differ between members
    params: dict[str, Any]  # axis key -> value (plus "scene" -> file stem with `scenes:`)
    scene: Scene
    plan: ModelPlan

    @property
    def label(self) -> str:
        parts = ([f"scene={self.params['scene']}"] if "scene" in self.params else []) + list(self.axis_overrides)
        return ", ".join(parts)

    @property
    def estimated_wall_time_s(self) -> float:
        return float(self.plan.estimated_wall_time_s or estimate_wall_time_s(self.plan))


@dataclass(frozen=True)
class Sweep:
    """An expanded, validated sweep file."""

    name: str
    description: str
    path: Path
    mode: str
    bases: tuple[Path, ...]
    set: tuple[str, ...]
    axes: dict[str, list]
    members: tuple[Member, ...]
    executor: str | None = None
    workers: int | None = None
    scheduler: str | None = None
    cores_per_member: int | None = None

    @property
    def parameters(self) -> list[str]:
        """The store's parameter columns: "scene" (with `scenes:`) and one per axis key."""
        return (["scene"] if len(self.bases) > 1 else []) + list(self.axes)

    def member_cores(self, member: Member) -> int:
        return int(self.cores_per_member or member.plan.cores)


def default_sweep_dir(sweep: Sweep | str | Path) -> Path:
    """runs/sweeps/<sweep name>, relative to the current directory."""
    name = sweep.name if isinstance(sweep, Sweep) else Path(sweep).stem
    return Path("runs") / "sweeps" / name


def member_id(scene: Scene, coupling: str | None = None) -> str:
    """The member's id: the first :data:`ID_LENGTH` hex digits of its case key
    (:func:`orchestrator.plan.identity.case_key`, the one answer to "is this the same case?"),
    for a case of ``coupling`` (None: as the scene plans)."""
    if coupling is None:
        coupling = plan_case(scene, scene.name).debris_coupling
    return case_key(scene, coupling)[:ID_LENGTH]


# --------------------------------------------------------------------------- the file's fields


def _override(key: str, value: Any) -> str:
    """`key=value` with the value as JSON (which YAML reads back as the same value)."""
    return f"{key}={json.dumps(value, default=json_default)}"


def _read_mapping(path: Path) -> dict:
    data = read_yaml(path, "sweep")
    if not isinstance(data, dict):
        raise InputError("sweep", f"must be a mapping (base, axes, ...), got {type(data).__name__}", str(path))
    return data


def _positive_int(value: Any, field: str, source: str) -> int | None:
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, int) or value < 1:
        raise InputError(field, f"must be a whole number >= 1, got {value!r}", source)
    return value


def _parse_executor(raw: Any, source: str) -> tuple[str | None, int | None, str | None]:
    if raw is None:
        return None, None, None
    if isinstance(raw, str):
        raw = {"kind": raw}
    if not isinstance(raw, dict):
        raise InputError("executor", f"must be local, dask or a mapping ({', '.join(_EXECUTOR_KEYS)})", source)
    unknown = [k for k in raw if k not in _EXECUTOR_KEYS]
    if unknown:
        raise InputError(f"executor.{unknown[0]}", f"unknown key (known: {', '.join(_EXECUTOR_KEYS)})", source)
    kind = raw.get("kind")
    if kind is not None and kind not in EXECUTORS:
        raise InputError("executor.kind", f"must be one of {', '.join(EXECUTORS)}, got {kind!r}", source)
    scheduler = raw.get("scheduler")
    if scheduler is not None and not isinstance(scheduler, str):
        raise InputError("executor.scheduler", f"must be an address such as tcp://host:8786, got {scheduler!r}", source)
    return kind, _positive_int(raw.get("workers"), "executor.workers", source), scheduler


def _parse_set(raw: Any, source: str) -> tuple[str, ...]:
    if raw is None:
        return ()
    if isinstance(raw, dict):
        return tuple(_override(str(k), v) for k, v in raw.items())
    if isinstance(raw, list) and all(isinstance(x, str) for x in raw):
        return tuple(raw)
    raise InputError("set", "must be a mapping {dotted.key: value} or a list of 'dotted.key=value' strings", source)


def _parse_axes(raw: Any, mode: str, source: str) -> dict[str, list]:
    if raw is None:
        return {}
    if not isinstance(raw, dict):
        raise InputError("axes", "must be a mapping {dotted.key: [value, ...]}", source)
    axes: dict[str, list] = {}
    for key, values in raw.items():
        key = str(key)
        if not key or any(not part for part in key.split(".")):
            raise InputError(f"axes.{key}", "an axis key must be a dotted scene path such as mesh.cell_size_m", source)
        if not isinstance(values, list) or not values:
            raise InputError(f"axes.{key}", f"must be a non-empty list of values, got {values!r}", source)
        axes[key] = values
    if mode == "zip" and axes:
        lengths = {k: len(v) for k, v in axes.items()}
        if len(set(lengths.values())) > 1:
            text = ", ".join(f"{k}: {n}" for k, n in lengths.items())
            longest = max(lengths, key=lengths.get)
            raise InputError(f"axes.{longest}", f"mode zip needs lists of one length, got {text}", source)
    return axes


def _parse_name_and_mode(data: dict, path: Path) -> tuple[str, str]:
    source = str(path)
    unknown = [k for k in data if k not in _SWEEP_KEYS]
    if unknown:
        raise InputError(str(unknown[0]), f"unknown key (known: {', '.join(_SWEEP_KEYS)})", source)
    name = data.get("name", path.stem)
    if not isinstance(name, str) or not _NAME_RE.match(name):
        raise InputError("name", f"must be a folder name (letters, digits, . _ -), got {name!r}", source)
    mode = data.get("mode", "grid")
    if mode not in _MODES:
        raise InputError("mode", f"must be grid or zip, got {mode!r}", source)
    return name, mode


def _parse_bases(data: dict, path: Path) -> tuple[Path, ...]:
    """The scene files (`base:` or `scenes:`), relative to the sweep file."""
    source = str(path)
    if ("base" in data) == ("scenes" in data):
        raise InputError("base", "give exactly one of base (a scene file) and scenes (a list of scene files)", source)
    raw_bases = [data["base"]] if "base" in data else data["scenes"]
    field_name = "base" if "base" in data else "scenes"
    if not isinstance(raw_bases, list) or not raw_bases or not all(isinstance(b, str) and b for b in raw_bases):
        raise InputError(field_name, "must be a scene file path (base) or a non-empty list of them (scenes)", source)
    bases = tuple(Path(os.path.normpath(path.parent / b)) for b in raw_bases)
    stems = [b.stem for b in bases]
    if len(set(stems)) != len(stems):
        raise InputError("scenes", f"scene files need distinct names (the store's `scene` column), got {stems}", source)
    return bases


# --------------------------------------------------------------------------- the members


def _combinations(axes: dict[str, list], mode: str) -> list[list[tuple[str, Any]]]:
    keys = list(axes)
    if not keys:
        return [[]]
    rows = zip(*axes.values()) if mode == "zip" else itertools.product(*axes.values())
    return [list(zip(keys, row)) for row in rows]


def _resolved_value(scene_dict: dict, key: str, raw: Any) -> Any:
    """The value at a dotted key of the resolved scene (typed as the scene holds it: YAML's
    `1.0e7` is a string, the scene's float is a float); the raw value where the key does not
    survive resolution (e.g. `debris.0.layout`, expanded into bodies)."""
    node: Any = scene_dict
    for part in key.split("."):
        if isinstance(node, dict) and part in node:
            node = node[part]
        elif isinstance(node, list) and part.lstrip("-").isdigit() and -len(node) <= int(part) < len(node):
            node = node[int(part)]
        else:
            return raw
    return node


def _scene_and_plan(source: str, base: Path, overrides: list[str], where: tuple[int, int, str]) -> tuple[Scene, ModelPlan]:
    """The member's scene and plan; a SweepMemberError (at ``where``: index, total, label) when either refuses."""
    try:
        scene = load_scene(base, overrides)
        return scene, plan_case(scene)
    except SweepMemberError:
        raise
    except InputError as err:
        raise SweepMemberError(source, *where, err) from None
    except (DebrisfoamError, ValueError) as err:  # the planner refused the scene
        raise SweepMemberError(source, *where, InputError("plan", f"the planner cannot model it: {err}",
                                                          str(base))) from None


def _expand_members(source: str, bases: tuple[Path, ...], common: tuple[str, ...], axes: dict[str, list],
                    mode: str) -> tuple[Member, ...]:
    """Every member, in expansion order (each base, then the axes' combinations), validated."""
    combos = [(base, combo) for base in bases for combo in _combinations(axes, mode)]
    members: list[Member] = []
    seen: dict[str, int] = {}
    for index, (base, combo) in enumerate(combos, start=1):
        axis_overrides = tuple(_override(k, v) for k, v in combo)
        params: dict[str, Any] = ({"scene": base.stem} if len(bases) > 1 else {}) | dict(combo)
        label = ", ".join(([f"scene={base.stem}"] if len(bases) > 1 else []) + list(axis_overrides))
        where = (index, len(combos), label)
        scene, plan = _scene_and_plan(source, base, [*common, *axis_overrides], where)
        resolved = scene_to_dict(scene)
        params = {k: (_resolved_value(resolved, k, v) if k != "scene" else v) for k, v in params.items()}
        mid = member_id(scene, plan.debris_coupling)
        if mid in seen:
            first = members[seen[mid] - 1]
            raise SweepMemberError(source, *where, InputError(
                "axes", f"resolves to the same scene as member {first.index} ({first.label or 'the base scene'}); "
                        "every member must differ"))
        seen[mid] = index
        members.append(Member(index, mid, base, (*common, *axis_overrides), axis_overrides, params, scene, plan))
    return tuple(members)


def load_sweep(path: str | Path) -> Sweep:
    """Read a sweep file, expand every member and validate it (scene and plan).

    Raises InputError naming the sweep file and the field for a bad sweep file, and
    SweepMemberError (an InputError) naming the member and the field for a bad member.
    Nothing is written.
    """
    path = Path(path)
    source = str(path)
    data = _read_mapping(path)
    name, mode = _parse_name_and_mode(data, path)
    bases = _parse_bases(data, path)
    common = _parse_set(data.get("set"), source)
    axes = _parse_axes(data.get("axes"), mode, source)
    if "scene" in axes and len(bases) > 1:
        raise InputError("axes.scene", "`scene` is the column of the scenes list; it cannot be an axis too", source)
    kind, workers, scheduler = _parse_executor(data.get("executor"), source)
    cores = _positive_int(data.get("cores_per_member"), "cores_per_member", source)
    members = _expand_members(source, bases, common, axes, mode)
    return Sweep(name=name, description=str(data.get("description", "")), path=path, mode=mode, bases=bases,
                 set=common, axes=axes, members=members, executor=kind, workers=workers,
                 scheduler=scheduler, cores_per_member=cores)
