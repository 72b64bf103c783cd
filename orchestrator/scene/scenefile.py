"""Scene files: reading a scene's YAML (``extends`` included) and writing a resolved scene back.

:func:`load_scene` is the one way in: read the file, lay its ``extends`` parent under it,
apply the ``--set`` overrides, resolve and validate. Every problem is an
:class:`~orchestrator.core.errors.InputError` naming the dotted field, the rule and the file;
nothing downstream sees an invalid scene. :func:`dump_scene_yaml` writes the resolved
scene (layouts expanded, bodies and gauges placed) as YAML that loads back to the same scene.

A scene file may start from another: ``extends: ../1debris.yaml`` takes that file's
sections as defaults and lays this file's keys over them (mappings merge key by key,
lists such as ``debris`` are replaced whole); ``cases/hard/`` is written that way.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import Any

import yaml

from orchestrator.core.errors import InputError
from orchestrator.scene.overrides import apply_overrides
from orchestrator.scene.resolve import scene_from_dict
from orchestrator.scene.schema import Scene
from orchestrator.scene.yamltext import decode_text, load_yaml

__all__ = ["dump_scene_yaml", "load_scene", "read_yaml", "scene_to_dict"]


def read_yaml(path: str | Path, field: str) -> Any:
    """The YAML document in ``path``; InputError (``field`` or the key, the file) if unreadable,
    not UTF-8 or UTF-16 with a byte-order mark, not YAML, or a key is given twice
    (:mod:`orchestrator.scene.yamltext`). Every scene and sweep file is read here."""
    try:
        raw = Path(path).read_bytes()
    except FileNotFoundError:
        raise InputError(field, "no such file, nor a shipped scene or sweep of that name (`debrisfoam scenes` "
                                "lists them)", str(path)) from None
    except OSError as err:
        raise InputError(field, f"cannot read the file: {err.strerror or err}", str(path)) from None
    return load_yaml(decode_text(raw, field, str(path)), field, str(path))


def load_scene(path: str | Path, overrides: Iterable[str] = ()) -> Scene:
    """Read, override, resolve and validate the scene in ``path``.

    Raises InputError (field = dotted key, source = the file) on any problem: unreadable
    or non-YAML file, unknown keys, out-of-range values, and the cross-field rules
    listed in :func:`~orchestrator.scene.validation.validate_scene`.
    """
    source = str(path)
    data = _scene_data(Path(path), "scene", ())
    data.setdefault("name", Path(path).stem)
    overrides = list(overrides)
    data = apply_overrides(data, overrides, source)
    try:
        return scene_from_dict(data, source)
    except InputError as err:
        if any(o.partition("=")[0].strip() and err.field.startswith(o.partition("=")[0].strip()) for o in overrides):
            raise InputError(err.field, f"{err.rule} (value set by an override)", err.source) from None
        raise


def _merged(base: dict, changes: dict) -> dict:
    """``base`` with ``changes`` laid over it: mappings merge key by key, anything else is replaced."""
    out = dict(base)
    for key, value in changes.items():
        out[key] = _merged(out[key], value) if isinstance(value, dict) and isinstance(out.get(key), dict) else value
    return out


def _scene_data(path: Path, field: str, chain: tuple[Path, ...]) -> dict:
    """The raw mapping of a scene file, with ``extends: OTHER.yaml`` resolved.

    A scene may start from another (``extends``, a path relative to its own file): the
    other's sections are the defaults and this file's keys are laid over them (mappings
    merge key by key; lists such as ``debris`` and ``gauges`` are replaced whole). The
    other's ``name`` and ``description`` are not inherited.
    """
    data = read_yaml(path, field)
    if data is None:
        data = {}
    if not isinstance(data, dict):
        raise InputError(field, f"must be a mapping of sections, got a {type(data).__name__}", str(path))
    parent = data.pop("extends", None)
    if parent is None:
        return data
    if not isinstance(parent, str) or not parent.strip():
        raise InputError("extends", "must be the path of another scene file, relative to this one", str(path))
    here = path.resolve()
    target = (here.parent / parent).resolve()
    if target in (*chain, here):
        raise InputError("extends", f"{parent} extends this file again (a cycle)", str(path))
    if not target.is_file():
        raise InputError("extends", f"no such scene file: {target}", str(path))
    base = _scene_data(target, "extends", (*chain, here))
    base.pop("name", None)
    base.pop("description", None)
    return _merged(base, data)


def scene_to_dict(scene: Scene) -> dict:
    """The resolved scene as plain data (lists, numbers, strings): reloadable as-is."""
    return scene.model_dump(mode="json")


def dump_scene_yaml(scene: Scene, overrides: Sequence[str] = ()) -> str:
    """The resolved scene as YAML, headed by the overrides that produced it."""
    head = "# Resolved scene written by debrisfoam: layouts expanded, bodies and gauges placed.\n"
    if overrides:
        head += "# Overrides applied: " + " ".join(overrides) + "\n"
    return head + yaml.safe_dump(scene_to_dict(scene), sort_keys=False, default_flow_style=None)
