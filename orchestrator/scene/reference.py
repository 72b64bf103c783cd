"""The scene reference, generated from the scene schema itself (orchestrator.scene.schema's models).

`debrisfoam schema [KEY]` prints it; `make scene-doc` writes docs/scene.md from it, and a test
checks that the committed page is what this module writes, so the reference cannot drift
from the code. The shipped scenes are :mod:`orchestrator.scene.shipped`'s.
"""

from __future__ import annotations

import types
import typing
from dataclasses import dataclass

from pydantic import BaseModel
from pydantic_core import PydanticUndefined

from orchestrator.core.errors import InputError
from orchestrator.scene.schema import DebrisBody, DebrisLayout, Scene

__all__ = ["SchemaRow", "markdown", "schema_rows"]

_SYMBOLS = {"gt": ">", "ge": ">=", "lt": "<", "le": "<="}


@dataclass(frozen=True)
class SchemaRow:
    """One scene key: dotted path, type, default, allowed range, what it means."""

    key: str
    type: str
    default: str
    range: str
    description: str
    section_doc: str = ""


def _model_of(annotation) -> type[BaseModel] | None:
    for arg in (annotation, *typing.get_args(annotation)):
        if isinstance(arg, type) and issubclass(arg, BaseModel):
            return arg
    return None


def _type_name(annotation) -> str:
    origin = typing.get_origin(annotation)
    args = typing.get_args(annotation)
    if origin is typing.Literal:
        return " | ".join(repr(a) for a in args)
    if origin in (typing.Union, types.UnionType):
        return " | ".join("null" if a is type(None) else _type_name(a) for a in args)
    if origin is tuple:
        if len(args) == 2 and args[1] is Ellipsis:
            return f"list of {_type_name(args[0])}"
        return f"[{', '.join(_type_name(a) for a in args)}]"
    if origin is typing.Annotated:
        return _type_name(args[0])
    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        return "section"
    return getattr(annotation, "__name__", str(annotation))


def _range(field) -> str:
    parts = []
    for meta in field.metadata:
        for attr, symbol in _SYMBOLS.items():
            value = getattr(meta, attr, None)
            if value is not None:
                parts.append(f"{symbol} {value:g}")
    inner = []  # the constraint on each item of a tuple such as size_m: [Pos, Pos, Pos]
    if typing.get_origin(field.annotation) is tuple:
        for arg in typing.get_args(field.annotation):
            if typing.get_origin(arg) is typing.Annotated:
                inner += [m for extra in typing.get_args(arg)[1:] for m in getattr(extra, "metadata", [extra])]
    for meta in inner[:1]:
        for attr, symbol in _SYMBOLS.items():
            value = getattr(meta, attr, None)
            if value is not None:
                parts.append(f"each {symbol} {value:g}")
    return ", ".join(parts)


def _default(field) -> str:
    if field.is_required():
        return "required"
    value = field.default
    if value is PydanticUndefined:
        return "-"
    if isinstance(value, BaseModel):
        return "(section defaults)"
    if value is None:
        return "null"
    if isinstance(value, tuple) and value and isinstance(value[0], BaseModel):
        return f"{len(value)} x (section defaults)"
    if isinstance(value, tuple):
        return "[" + ", ".join(f"{v:g}" if isinstance(v, float) else str(v) for v in value) + "]"
    if isinstance(value, float):
        return f"{value:g}"
    return str(value)


def _first_line(doc: str | None) -> str:
    return " ".join((doc or "").strip().split("\n\n")[0].split())


def schema_rows(model: type[BaseModel] = Scene, prefix: str = "") -> list[SchemaRow]:
    """Every key of the scene schema, depth first, sections before their fields."""
    rows = []
    for name, field in model.model_fields.items():
        key = f"{prefix}{name}"
        sub = _model_of(field.annotation)
        if name == "debris" and model is Scene:
            rows.append(SchemaRow("debris", "list of bodies or layouts", "[]", "",
                                  "debris bodies (each item a body, or a layout generator with `layout:`)"))
            rows += schema_rows(DebrisBody, "debris[N].")
            rows += schema_rows(DebrisLayout, "debris[N] (layout).")
            continue
        if sub is not None:
            is_list = typing.get_origin(field.annotation) in (tuple, list)
            rows.append(SchemaRow(f"{key}[N]" if is_list else key, "list of sections" if is_list else "section",
                                  _default(field), "", field.description or _first_line(sub.__doc__),
                                  _first_line(sub.__doc__)))
            rows += schema_rows(sub, f"{key}[N]." if is_list else f"{key}.")
            continue
        rows.append(SchemaRow(key, _type_name(field.annotation), _default(field), _range(field),
                              " ".join((field.description or "").split())))
    return rows


def select(rows: list[SchemaRow], key: str | None) -> list[SchemaRow]:
    """The rows of ``key`` and below (``debris.0.mass_kg`` and ``debris[N].mass_kg`` both work)."""
    if not key:
        return rows
    import re

    wanted = re.sub(r"\.(\d+)(\.|$)", r"[N]\2", key)
    chosen = [r for r in rows if r.key == wanted or r.key.startswith(wanted + ".") or r.key.startswith(wanted + "[")]
    if not chosen:
        sections = sorted({r.key.split(".")[0] for r in rows})
        raise InputError("KEY", f"no scene key {key!r}; top-level sections: {', '.join(sections)}")
    return chosen


def markdown(rows: list[SchemaRow]) -> str:
    """The reference page (docs/scene.md)."""
    lines = ["# Scene reference", "",
             "Generated from the scene schema by `make scene-doc` (`debrisfoam schema --markdown`); never edited by",
             "hand. A scene is one YAML file; every key below can also be set from the command line with",
             "`--set dotted.key=value` (a list item by its index: `debris.0.mass_kg=0.3`). Unknown keys are",
             "errors; every error names the file and the dotted field. `debrisfoam validate SCENE` checks a",
             "scene without writing anything; `debrisfoam scenes` lists the shipped ones.", "",
             "Coordinates: x along the flume, 0 at the gate, positive downstream; y across, 0 on the centreline;",
             "z up from the floor. Lengths in m, masses in kg, times in s, angles in degrees.", "",
             "| key | type | default | allowed | meaning |", "|---|---|---|---|---|"]
    for r in rows:
        key = f"**{r.key}**" if r.type in ("section", "list of sections") else f"`{r.key}`"
        lines.append(f"| {key} | {r.type.replace('|', '/')} | {r.default.replace('|', '/')} | {r.range} | "
                     f"{r.description.replace('|', '/')} |")
    return "\n".join(lines) + "\n"
