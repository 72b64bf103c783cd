"""Scene overrides: ``key.path=value`` changes laid over a raw scene mapping.

``debrisfoam render --set mesh.cell_size_m=0.02``, the sweeps' parameters and the studies
all change a scene the same way: a dotted key (list items by index, ``debris.0.mass_kg``)
and a YAML value. Overrides apply to the raw mapping before it is resolved, so a layout,
a placement or a gauge written ``at:`` follows the changed values. A key the schema does
not know is an :class:`~orchestrator.core.errors.InputError` naming it, not a silent no-op.
"""

from __future__ import annotations

import copy
from collections.abc import Iterable, Sequence
from typing import Any

from orchestrator.core.errors import InputError
from orchestrator.scene.schema import (
    Bed,
    ColumnSection,
    DebrisBody,
    DebrisLayout,
    DebrisTemplate,
    Flume,
    Fluids,
    Gauge,
    Mesh,
    Outputs,
    Reservoir,
    Run,
    Scene,
    SceneSection,
)
from orchestrator.scene.yamltext import load_yaml

__all__ = ["apply_overrides", "parse_override"]

#: The model of each top-level section that is a single mapping.
_SECTIONS: dict[str, type[SceneSection]] = {
    "flume": Flume,
    "reservoir": Reservoir,
    "bed": Bed,
    "column": ColumnSection,
    "fluids": Fluids,
    "mesh": Mesh,
    "run": Run,
    "outputs": Outputs,
}


def parse_override(text: str) -> tuple[list[str], Any]:
    """``"a.b.c=value"`` -> (["a", "b", "c"], value parsed as a YAML scalar/list)."""
    if "=" not in text:
        raise InputError(text, "an override must look like key.path=value")
    key, _, raw = text.partition("=")
    key = key.strip()
    if not key or any(not part for part in key.split(".")):
        raise InputError(key or text, "an override key must be a dotted path such as mesh.cell_size_m")
    try:
        value = load_yaml(raw, key) if raw.strip() else None
    except InputError as err:
        raise InputError(key, f"value {raw!r} is not a YAML value: {err.rule}") from None
    return key.split("."), value


def _section_model(path: Sequence[str], container: Any) -> type[SceneSection] | None:
    """The model that a dict reached by ``path`` is validated with (for unknown-key checks)."""
    if len(path) == 0:
        return Scene
    if len(path) == 1 and path[0] in _SECTIONS:
        return _SECTIONS[path[0]]
    if len(path) == 2 and path[0] == "debris":
        return DebrisLayout if isinstance(container, dict) and "layout" in container else DebrisBody
    if len(path) == 3 and path[0] == "debris" and path[2] == "body":
        return DebrisTemplate
    if len(path) == 2 and path[0] == "gauges":
        return Gauge
    return None


def apply_overrides(data: dict, overrides: Iterable[str], source: str | None = None) -> dict:
    """A copy of the raw scene mapping with each ``key.path=value`` applied in order.

    Missing sections are created; list items are addressed by index (``debris.0.mass_kg``).
    A key the schema does not know raises InputError naming the key.
    """
    data = copy.deepcopy(data)
    for text in overrides:
        try:
            path, value = parse_override(text)
        except InputError as err:
            raise err.with_source(source) if source else err from None
        _apply_one(data, path, value, text, source)
    return data


def _apply_one(data: dict, path: list[str], value: Any, text: str, source: str | None) -> None:
    """Set ``value`` at ``path`` in ``data`` (in place); ``text`` is the override, for the errors."""
    key = ".".join(path)
    node: Any = data
    for depth, part in enumerate(path):
        last = depth == len(path) - 1
        if isinstance(node, list):
            if not (part.isascii() and part.isdigit()) or int(part) >= len(node):
                held = f"an item is named by its index, 0 to {len(node) - 1}" if node else "the list is empty"
                raise InputError(key, f"no item {part!r} in a list of {len(node)}: {held} (override {text!r})", source)
            idx = int(part)
            if last:
                node[idx] = value
            else:
                if node[idx] is None:
                    node[idx] = {}
                node = node[idx]
            continue
        if not isinstance(node, dict):
            raise InputError(key, f"{'.'.join(path[:depth]) or 'scene'} is not a mapping (override {text!r})", source)
        model = _section_model(path[:depth], node)
        if model is not None and part not in model.model_fields:
            raise InputError(key, f"unknown key {part!r} (override {text!r})", source)
        if last:
            node[part] = value
        else:
            if node.get(part) is None:
                node[part] = {}
            node = node[part]
