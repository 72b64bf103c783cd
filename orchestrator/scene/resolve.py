"""Resolving a raw scene mapping into a :class:`~orchestrator.scene.schema.Scene`.

The YAML says what the user means; the resolved scene says it explicitly: debris layouts
(``layout: RxC``) become named bodies on their grid, each body gets a full ``[x, y, z]``
centre from its placement rule (on the bed, afloat at its draft, or as given), gauges
written ``at: column_upstream_face`` get their coordinates. The result is then checked by
the cross-field rules (:func:`~orchestrator.scene.validation.validate_scene`). pydantic's
errors become :class:`~orchestrator.core.errors.InputError` naming the dotted key of the YAML.
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Sequence
from typing import Any

from pydantic import ValidationError

from orchestrator.core.errors import InputError
from orchestrator.scene.geometry import TOLERANCE_M, draft_m, half_extent_z
from orchestrator.scene.inundation import apply_inundation
from orchestrator.scene.schema import DebrisBody, DebrisLayout, Gauge, Scene, SceneSection
from orchestrator.scene.validation import validate_scene

__all__ = ["scene_from_dict"]

_LAYOUT_RE = re.compile(r"^\s*(\d+)\s*[xX]\s*(\d+)\s*$")


def scene_from_dict(data: dict, source: str | None = None) -> Scene:
    """Resolve and validate a raw scene mapping (as read from YAML) into a Scene."""
    if not isinstance(data, dict):
        raise InputError("scene", f"must be a mapping of sections, got a {type(data).__name__}", source)
    data = apply_inundation(dict(data), source)
    raw_debris = data.pop("debris", None)
    raw_gauges = data.pop("gauges", None)
    base = _validate(Scene, data, (), source)

    bodies, origins = _expand_debris(raw_debris, base, source)
    gauges = _resolve_gauges(raw_gauges, base, source)
    scene = base.model_copy(update={"debris": tuple(bodies), "gauges": tuple(gauges)})
    validate_scene(scene, source, origins)
    return scene


# ---------------------------------------------------------------------------- debris


def _expand_debris(raw: Any, base: Scene, source: str | None) -> tuple[list[DebrisBody], list[dict]]:
    """Bodies from the raw ``debris`` list; each with where it came from in the YAML."""
    if raw is None:
        return [], []
    if not isinstance(raw, list):
        raise InputError("debris", f"must be a list of bodies or layouts, got {type(raw).__name__}", source)
    bodies: list[DebrisBody] = []
    origins: list[dict] = []
    for i, item in enumerate(raw):
        if not isinstance(item, dict):
            raise InputError(f"debris.{i}", "must be a mapping (a body or a layout)", source)
        if "layout" in item:
            for body in _layout_bodies(item, i, source):
                bodies.append(_place_body(body, base, f"debris.{i}", source))
                origins.append({"path": f"debris.{i}", "layout": True})
        else:
            item = dict(item)
            if "name" not in item:
                item["name"] = f"debris{len(bodies) + 1}"
            body = _validate(DebrisBody, item, ("debris", i), source)
            bodies.append(_place_body(body, base, f"debris.{i}", source))
            origins.append({"path": f"debris.{i}", "layout": False})
    return bodies, origins


def _layout_shape(text: str, field: str, source: str | None = None) -> tuple[int, int]:
    """(rows, columns) of a layout written ``RxC`` (or ``1``); InputError on ``field`` otherwise."""
    m = _LAYOUT_RE.match(text)
    if text.strip() == "1":
        rows, cols = 1, 1
    elif m:
        rows, cols = int(m.group(1)), int(m.group(2))
    else:
        raise InputError(field, f"must look like RxC (e.g. 2x3) or 1, got {text!r}", source)
    if rows < 1 or cols < 1:
        raise InputError(field, f"needs at least one row and one column, got {text!r}", source)
    return rows, cols


def _layout_bodies(item: dict, i: int, source: str | None) -> list[DebrisBody]:
    """The unplaced bodies of the layout at ``debris.<i>``, row by row from upstream, -y to +y."""
    lay = _validate(DebrisLayout, item, ("debris", i), source)
    rows, cols = _layout_shape(str(lay.layout), f"debris.{i}.layout", source)
    if (rows > 1 and lay.spacing_m[0] <= 0) or (cols > 1 and lay.spacing_m[1] <= 0):
        raise InputError(f"debris.{i}.spacing_m", f"must be > 0, got {list(lay.spacing_m)}", source)
    bodies = []
    for r in range(rows):
        for c in range(cols):
            x = lay.centre_m[0] + (r - (rows - 1) / 2.0) * lay.spacing_m[0]
            y = lay.centre_m[1] + (c - (cols - 1) / 2.0) * lay.spacing_m[1]
            fields = lay.body.model_dump()
            fields.update(name=f"{lay.name_prefix}{len(bodies) + 1}", centre_m=(x, y))
            bodies.append(_validate(DebrisBody, fields, ("debris", i, "body"), source))
    return bodies


def _place_body(body: DebrisBody, scene: Scene, path: str, source: str | None) -> DebrisBody:
    """The body with a 3-component centre: z from its placement rule."""
    placement = body.placement or ("given" if len(body.centre_m) == 3 else "on_bed")
    x, y = body.centre_m[0], body.centre_m[1]
    if placement == "given":
        if len(body.centre_m) != 3:
            raise InputError(f"{path}.centre_m", "placement 'given' needs [x, y, z]", source)
        z = body.centre_m[2]
    else:
        half_z = half_extent_z(body)
        z = half_z
        if placement == "floating":
            if abs(body.pitch_deg) > TOLERANCE_M or abs(body.roll_deg) > TOLERANCE_M:
                raise InputError(f"{path}.placement", "floating needs pitch_deg = roll_deg = 0", source)
            water = scene.reservoir.depth_m if x < 0 else scene.bed.wet_depth_m
            draft = draft_m(body, scene.fluids.water_density_kg_m3)
            if draft < water:
                z = water - draft + body.size_m[2] / 2.0
    return body.model_copy(update={"centre_m": (float(x), float(y), float(z)), "placement": placement})


# ---------------------------------------------------------------------------- gauges


def _resolve_gauges(raw: Any, base: Scene, source: str | None) -> list[Gauge]:
    """Gauges from the raw ``gauges`` list, those written with ``at`` given their coordinates."""
    if raw is None:
        return []
    if not isinstance(raw, list):
        raise InputError("gauges", f"must be a list, got {type(raw).__name__}", source)
    out = []
    for i, item in enumerate(raw):
        g = _validate(Gauge, item, ("gauges", i), source)
        if g.at == "column_upstream_face":
            if base.column is None:
                raise InputError(f"gauges.{i}.at", "column_upstream_face needs a column", source)
            col = base.column
            g = g.model_copy(update={"x_m": col.x_m - col.size_x_m / 2.0 - g.offset_m, "y_m": col.y_m})
        elif g.x_m is None or g.y_m is None:
            missing = "x_m" if g.x_m is None else "y_m"
            raise InputError(f"gauges.{i}.{missing}", "required unless `at` places the gauge", source)
        out.append(g)
    return out


# ----------------------------------------------------------------- error translation


def _dotted(loc: Iterable[Any]) -> str:
    return ".".join(str(p) for p in loc)


def _from_validation_error(err: ValidationError, prefix: Sequence[Any], source: str | None) -> InputError:
    """The first pydantic error as an InputError with the dotted location."""
    errors = err.errors(include_url=False)
    first = errors[0]
    loc = list(first["loc"])
    kind = first["type"]
    short_list = kind == "missing" and loc and isinstance(loc[-1], int)
    if short_list:  # a list with too few items: name the list, not the missing slot
        loc = loc[:-1]
    field = _dotted([*prefix, *loc]) or "scene"
    if kind == "extra_forbidden":
        rule = "unknown key"
    elif short_list:
        rule = f"too few values: item {first['loc'][-1]} is missing"
    elif kind == "missing":
        rule = "required, but missing"
    else:
        rule = f"{first['msg']}, got {first.get('input')!r}"
    if len(errors) > 1:
        rule += f" (and {len(errors) - 1} more problem(s))"
    return InputError(field, rule, source)


def _validate(model: type[SceneSection], data: Any, prefix: Sequence[Any], source: str | None):
    """``model`` validated from ``data``; a pydantic error becomes an InputError at ``prefix``."""
    try:
        return model.model_validate(data)
    except ValidationError as err:
        raise _from_validation_error(err, prefix, source) from None
