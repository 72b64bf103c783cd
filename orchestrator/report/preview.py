"""Scene preview: one PNG that shows what a scene and its plan will model, before any run.

:func:`preview_scene` draws a :class:`~orchestrator.scene.schema.Scene` and its
:class:`~orchestrator.plan.planner.ModelPlan` off-screen with pyvista into a 1600 x 900 px PNG with
three views, from the whole to the detail:

* top: an isometric view of the simulated domain (``plan.domain_m``) inside the flume;
* middle: a plan view from above of the region of interest (the plan's fine region, the
  column, the debris and the gauges), with names and x and y scales (bodies side by side,
  whose full names would overlap, are numbered by what follows their common prefix);
* bottom: a strip with the whole flume from above, the simulated part against the full
  reservoir and the full downstream length.

Drawn: the flume walls and floor (translucent), the simulated domain (black outline), the
water the case starts with (blue: the reservoir and the wet bed; the water outside the
simulated domain paler), the column (solid grey), each debris body (red, rotated by its
orientation) with the outline of its overset mesh, the gauges (green vertical lines), the
fine-mesh region (orange outline), and a text block with the plan's headline (solver, 2D or
3D, cell count, estimated wall time). :func:`preview_scene_file` loads, plans and draws.

Coordinates as everywhere (docs/scene.md): x along the flume, 0 at the gate; y across,
0 on the centreline; z up from the floor; metres.
"""

from __future__ import annotations

import contextlib
import io
import math
import os
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from orchestrator.core.errors import DebrisfoamError
from orchestrator.core.files import write_bytes_atomic
from orchestrator.plan.planner import ModelPlan, estimated_steps, load_and_plan
from orchestrator.plan.resources import Demand, check_resources
from orchestrator.scene.geometry import body_rotation, flume_extent
from orchestrator.scene.schema import Scene

__all__ = ["COLOURS", "WINDOW_SIZE_PX", "preview_scene", "preview_scene_file"]

#: Size of the PNG (width, height) in pixels.
WINDOW_SIZE_PX = (1600, 900)

#: Colours of the drawing (hex RGB); tests look for the debris colour in the image.
COLOURS = {
    "background": "#ffffff",
    "text": "#1a1a1a",
    "flume": "#8c8c8c",
    "floor": "#e6e2da",
    "domain": "#111111",
    "fine": "#f08c00",
    "water": "#1f6fd1",
    "column": "#5f6b73",
    "debris": "#d7191c",
    "body_mesh": "#d7191c",
    "gauge": "#1a9641",
}

#: Text sizes (VTK font size, pixels): names of gauges, bodies and the column, and the scale
#: marks, at least 16 px, so that their letters (small in VTK's font) read at 100 % in a report;
#: the corner texts (headline, view titles) use pyvista's scale, which grows with the window.
_LABEL_PX = 18
_BODY_LABEL_PX = 16
_LEGIBLE_BODY_LABEL_PX = 12
_MIN_BODY_LABEL_PX = 9
_TICK_PX = 18
_CORNER_SIZE = 10
#: Height of the three views as fractions of the image (isometric, plan, whole flume).
_ROW_WEIGHTS = (0.50, 0.37, 0.13)
#: Opacities: water in the simulated domain, water outside it, flume walls.
_WATER_OPACITY = 0.35
_WATER_OUTSIDE_OPACITY = 0.12
_WALL_OPACITY = 0.06
#: Bodies closer than this (m) share one label in the isometric view.
_CROWDED_M = 0.5
#: Where the isometric view looks from (towards the camera): upstream, the -y side, above.
_ISO_DIRECTION = np.array([-0.22, -1.0, 0.75])


# ------------------------------------------------------------------------- public API


def preview_scene_file(path: str | Path, out_png: str | Path, overrides: Sequence[str] = (),
                       warnings: bool = False):
    """Load the scene in ``path`` (with ``key.path=value`` overrides), plan it, draw it to ``out_png``.

    An :class:`~orchestrator.core.errors.InputError` from loading the scene passes through unchanged, as
    does one from the resource guard's hard limits (:mod:`orchestrator.plan.resources`), before
    anything is written. Returns the path of the PNG written, or with ``warnings`` the planner's
    warnings and the guard's soft ones (a picture runs nothing: they are not asked about).
    """
    scene, plan = load_and_plan(path, overrides)
    large = check_resources(Demand.of_plan(plan), str(path), confirmed=True)
    written = preview_scene(scene, plan, out_png)
    return list(plan.warnings) + large if warnings else written


def preview_scene(scene: Scene, plan: ModelPlan, out_png: str | Path) -> Path:
    """Draw ``scene`` as ``plan`` models it into the PNG ``out_png`` (folders made as needed).

    The image is :data:`WINDOW_SIZE_PX` pixels; see the module docstring for what is drawn.
    The file is written whole or not at all (a temporary file renamed into place).
    Returns ``out_png`` as a Path.
    """
    pv = _pyvista()
    out = Path(out_png)
    geo = _geometry(pv, scene, plan)
    with quiet_vtk():
        plotter = pv.Plotter(
            off_screen=True,
            shape=(3, 1),
            row_weights=list(_ROW_WEIGHTS),
            window_size=list(WINDOW_SIZE_PX),
            border=False,
        )
        try:
            plotter.set_background(COLOURS["background"])
            plotter.subplot(0, 0)
            _draw_isometric(plotter, geo, scene, plan)
            plotter.subplot(1, 0)
            _draw_plan_view(plotter, geo)
            plotter.subplot(2, 0)
            _draw_whole_flume(plotter, geo, scene, plan)
            image = plotter.screenshot(return_img=True)
        finally:
            plotter.close()
    write_png(np.asarray(image), out)
    return out


# ------------------------------------------------------------------------- geometry


@dataclass
class _Geometry:
    """Everything to draw, as pyvista meshes in scene coordinates (m)."""

    flume: Any
    floor: Any
    domain: Any
    fine: Any
    water: list
    water_outside: list
    column: Any | None
    column_top: tuple[float, float, float] | None
    debris: list
    debris_names: list[str]
    debris_tops: np.ndarray
    body_meshes: list
    gauges: list
    gauge_names: list[str]
    gauge_tops: np.ndarray
    flume_bounds: tuple[float, ...]
    domain_bounds: tuple[float, ...]
    detail_bounds: tuple[float, ...]


def _bounds(extent: Sequence[Sequence[float]]) -> tuple[float, ...]:
    """((x0, x1), (y0, y1), (z0, z1)) -> (x0, x1, y0, y1, z0, z1)."""
    return tuple(float(v) for pair in extent for v in pair)


def _box(pv, lo: Sequence[float], hi: Sequence[float]):
    return pv.Box(bounds=(lo[0], hi[0], lo[1], hi[1], lo[2], hi[2]))


def _oriented_box(pv, centre: Sequence[float], rotation: Any, size: Sequence[float]):
    """A box of ``size`` (body axes) turned by ``rotation`` (columns = body axes) about its centre."""
    cube = pv.Cube(center=(0.0, 0.0, 0.0), x_length=size[0], y_length=size[1], z_length=size[2])
    matrix = np.eye(4)
    matrix[:3, :3] = np.asarray(rotation, dtype=float)
    matrix[:3, 3] = np.asarray(centre, dtype=float)
    return cube.transform(matrix, inplace=False)


def _geometry(pv, scene: Scene, plan: ModelPlan) -> _Geometry:
    (fx0, fx1), (fy0, fy1), (_, fz1) = flume_extent(scene)
    # one-way: the bodies are the scene's, carried through the recorded flow (no body meshes)
    scene_bodies = [(body, body_rotation(body.yaw_deg, body.pitch_deg, body.roll_deg))
                    for body in ([] if plan.bodies else scene.debris)]
    (dx0, dx1), _, _ = plan.domain_m
    flume_bounds = (fx0, fx1, fy0, fy1, 0.0, fz1)

    # water the scene holds that the case leaves out: the reservoir upstream of the domain
    # and the wet bed downstream of it (the water inside the domain comes from the plan)
    outside = []
    h0, wet = scene.reservoir.depth_m, scene.bed.wet_depth_m
    for x_a, x_b, depth in ((fx0, min(dx0, 0.0), h0), (max(dx1, 0.0), fx1, wet)):
        if depth > 0 and x_b - x_a > 1e-9:
            outside.append(_box(pv, (x_a, fy0, 0.0), (x_b, fy1, depth)))

    column = column_top = None
    if scene.column is not None:
        c = scene.column
        column = _box(
            pv,
            (c.x_m - c.size_x_m / 2, c.y_m - c.size_y_m / 2, 0.0),
            (c.x_m + c.size_x_m / 2, c.y_m + c.size_y_m / 2, c.height_m),
        )
        column_top = (c.x_m, c.y_m, c.height_m)

    debris, tops, body_meshes = [], [], []
    for body, rotation in scene_bodies:
        box = _oriented_box(pv, body.centre_m, rotation, body.size_m)
        debris.append(box)
        tops.append((body.centre_m[0], body.centre_m[1], box.bounds[5]))
    for body in plan.bodies:
        box = _oriented_box(pv, body.centre_of_mass_m, body.orientation, body.size_m)
        debris.append(box)
        tops.append((body.centre_of_mass_m[0], body.centre_of_mass_m[1], box.bounds[5]))
        grid = body.grid
        lo = np.array([grid.planes(a)[0] for a in "xyz"])
        hi = np.array([grid.planes(a)[-1] for a in "xyz"])
        rot = np.asarray(grid.rotation, dtype=float)
        centre = np.asarray(grid.origin, dtype=float) + rot @ ((lo + hi) / 2.0)
        body_meshes.append(_oriented_box(pv, centre, rot, hi - lo).extract_all_edges())

    gauges = [pv.Line((g.x, g.y, 0.0), (g.x, g.y, g.z_top)) for g in plan.gauges]

    # the detail view: the fine region, the column, the bodies' meshes and the gauges
    # downstream of the reservoir (a gauge far upstream would stretch the view)
    fine = _bounds(plan.fine_region_m)
    xs = [fine[0], fine[1]] + [m.bounds[0] for m in body_meshes] + [m.bounds[1] for m in body_meshes]
    if column is not None:
        xs += [column.bounds[0], column.bounds[1]]
    xs += [g.x for g in plan.gauges if g.x >= fine[0] - 1.0]
    pad = 0.04 * (max(xs) - min(xs))
    detail = (max(min(xs) - pad, dx0), min(max(xs) + pad, dx1), fy0, fy1, 0.0, plan.domain_m[2][1])

    return _Geometry(
        flume=_box(pv, (fx0, fy0, 0.0), (fx1, fy1, fz1)),
        floor=pv.Plane(
            center=((fx0 + fx1) / 2, (fy0 + fy1) / 2, -1e-4), direction=(0, 0, 1),
            i_size=fx1 - fx0, j_size=fy1 - fy0, i_resolution=1, j_resolution=1,
        ),
        domain=_box(pv, *zip(*plan.domain_m)).outline(),
        fine=_box(pv, *zip(*plan.fine_region_m)).outline(),
        water=[_box(pv, w.min_m, w.max_m) for w in plan.water],
        water_outside=outside,
        column=column,
        column_top=column_top,
        debris=debris,
        debris_names=[b.name for b in (plan.bodies or scene.debris)],
        debris_tops=np.array(tops, dtype=float).reshape(-1, 3),
        body_meshes=body_meshes,
        gauges=gauges,
        gauge_names=[g.name for g in plan.gauges],
        gauge_tops=np.array([(g.x, g.y, g.z_top) for g in plan.gauges], dtype=float).reshape(-1, 3),
        flume_bounds=flume_bounds,
        domain_bounds=_bounds(plan.domain_m),
        detail_bounds=detail,
    )


# ------------------------------------------------------------------------- drawing


def _add_common(
    plotter, geo: _Geometry, *, body_meshes: bool, gauge_dots: bool = False, line_scale: float = 1.0
) -> None:
    """The scene's solids and outlines, the same in every view."""
    plotter.add_mesh(geo.floor, color=COLOURS["floor"], opacity=0.6, lighting=False)
    plotter.add_mesh(geo.flume, color=COLOURS["flume"], opacity=_WALL_OPACITY, lighting=False)
    plotter.add_mesh(geo.flume.outline(), color=COLOURS["flume"], line_width=1.0 * line_scale)
    for box in geo.water_outside:
        plotter.add_mesh(box, color=COLOURS["water"], opacity=_WATER_OUTSIDE_OPACITY, lighting=False)
    deepest = max((box.bounds[5] - box.bounds[4] for box in geo.water), default=1.0)
    for box in geo.water:  # shallow water paler, so a wet bed reads apart from the reservoir
        depth = box.bounds[5] - box.bounds[4]
        opacity = _WATER_OPACITY * (0.45 + 0.55 * min(1.0, depth / deepest))
        plotter.add_mesh(box, color=COLOURS["water"], opacity=opacity, lighting=False)
        plotter.add_mesh(box.outline(), color=COLOURS["water"], line_width=1.0 * line_scale)
    if geo.column is not None:
        plotter.add_mesh(geo.column, color=COLOURS["column"], show_edges=True, edge_color="#2b2b2b")
    for box in geo.debris:
        plotter.add_mesh(box, color=COLOURS["debris"], show_edges=True, edge_color="#5a0000", line_width=1.0)
    if body_meshes:
        for edges in geo.body_meshes:
            plotter.add_mesh(edges, color=COLOURS["body_mesh"], opacity=0.35, line_width=1.0)
    for line in geo.gauges:
        plotter.add_mesh(line, color=COLOURS["gauge"], line_width=3.0 * line_scale)
    if gauge_dots and len(geo.gauge_tops):
        plotter.add_points(
            geo.gauge_tops, color=COLOURS["gauge"], point_size=9.0 * line_scale, render_points_as_spheres=True
        )
    plotter.add_mesh(geo.fine, color=COLOURS["fine"], line_width=2.0 * line_scale)
    plotter.add_mesh(geo.domain, color=COLOURS["domain"], line_width=2.5 * line_scale)


def _labels(plotter, points: np.ndarray, names: Sequence[str], colour: str, font_size: int, **kwargs) -> None:
    """Names at points, never hidden by geometry; the text starts at the point unless justified.

    (pyvista keeps the background box left-justified whatever the justification: pass
    ``shape=None`` with ``justification_horizontal``.)
    """
    if len(names) == 0:
        return
    options = dict(
        font_size=font_size,
        text_color=colour,
        bold=True,
        show_points=False,
        shape_color="white",
        shape_opacity=0.75,
        margin=2,
        always_visible=True,
    )
    options.update(kwargs)
    plotter.add_point_labels(np.asarray(points, dtype=float), list(names), **options)


def _draw_isometric(plotter, geo: _Geometry, scene: Scene, plan: ModelPlan) -> None:
    _add_common(plotter, geo, body_meshes=True)
    lift = 0.02 * (geo.domain_bounds[5] - geo.domain_bounds[4])
    for top, text in _debris_groups(geo.debris_tops, geo.debris_names, _CROWDED_M):
        _labels(plotter, [top + [0.0, 0.0, lift]], [text], COLOURS["debris"], _BODY_LABEL_PX)
    _labels(plotter, geo.gauge_tops, geo.gauge_names, COLOURS["gauge"], _LABEL_PX)
    if geo.column_top is not None:
        _labels(plotter, [geo.column_top], ["column"], COLOURS["column"], _LABEL_PX)
    gate = (0.0, geo.flume_bounds[3], scene.reservoir.depth_m)
    _labels(plotter, [gate], ["gate (x = 0)"], "#555555", _TICK_PX, bold=False)
    plotter.add_text(_headline(scene, plan), position="upper_left", font_size=_CORNER_SIZE, color=COLOURS["text"])
    entries = [["simulated domain", COLOURS["domain"]], ["fine-mesh region", COLOURS["fine"]]]
    entries += [["water at t = 0", COLOURS["water"]]] if geo.water else []
    entries += [["column", COLOURS["column"]]] if geo.column is not None else []
    entries += [["debris (+ overset mesh)" if geo.body_meshes else "debris (carried one-way)",
                 COLOURS["debris"]]] if geo.debris else []
    entries += [["gauge", COLOURS["gauge"]]] if geo.gauges else []
    plotter.add_legend(
        labels=entries,
        bcolor="white",
        border=True,
        size=(0.15, 0.047 * len(entries)),
        loc="lower right",
        face="rectangle",
        background_opacity=0.8,
    )
    _set_camera(plotter, _ISO_DIRECTION, (0.0, 0.0, 1.0), geo.domain_bounds, row=0)


def _draw_plan_view(plotter, geo: _Geometry) -> None:
    _add_common(plotter, geo, body_meshes=True, gauge_dots=True)
    b = geo.detail_bounds
    _set_camera(plotter, (0.0, 0.0, 1.0), (0.0, 1.0, 0.0), b, row=1, margin=1.22)
    px_per_m = WINDOW_SIZE_PX[0] / (2.0 * plotter.camera.parallel_scale * _view_aspect(row=1))
    # each name just above its body's upstream corner, so rows and columns of bodies stay legible
    corners = np.array([(box.bounds[0], box.bounds[3], box.bounds[5]) for box in geo.debris]).reshape(-1, 3)
    names, size = list(geo.debris_names), _body_label_px(corners, geo.debris_names, px_per_m)
    prefix = os.path.commonprefix(names) if len(names) > 1 else ""
    short = [n[len(prefix):] for n in names]
    if size < _LEGIBLE_BODY_LABEL_PX and prefix and all(short):
        # bodies side by side: each numbered by what follows the common prefix, the prefix said once
        short_size = _body_label_px(corners, short, px_per_m)
        if short_size > size:
            names, size = short, short_size
            top = (corners[:, 0].min(), corners[:, 1].max() + 1.6 * size / px_per_m, corners[:, 2].max())
            _labels(plotter, [top], [f"{prefix}N = body N"], COLOURS["debris"], _BODY_LABEL_PX)
    _labels(plotter, corners, names, COLOURS["debris"], size)
    inside = (geo.gauge_tops[:, 0] >= b[0]) & (geo.gauge_tops[:, 0] <= b[1])
    names = [f"{n} " for n, ok in zip(geo.gauge_names, inside) if ok]  # each name ends at its gauge
    _labels(
        plotter, geo.gauge_tops[inside], names, COLOURS["gauge"], _LABEL_PX, justification_horizontal="right",
        shape=None,
    )
    if geo.column_top is not None:
        x_face = geo.column.bounds[1]
        _labels(plotter, [(x_face, geo.column_top[1], geo.column_top[2])], [" column"], COLOURS["column"], _LABEL_PX)
    _scale_marks(plotter, b[0], b[1], geo.flume_bounds[2], _nice_step((b[1] - b[0]) / 10.0), _TICK_PX)
    # y marks just inside the view's left edge
    x_left = plotter.camera.focal_point[0] - plotter.camera.parallel_scale * _view_aspect(row=1)
    y0, y1 = geo.flume_bounds[2], geo.flume_bounds[3]
    _y_marks(plotter, x_left + 6.0 / px_per_m, y0, y1, _nice_step((y1 - y0) / 4.0), _TICK_PX)
    plotter.add_text("plan view (from above): region of interest", position="upper_left", font_size=_CORNER_SIZE,
                     color=COLOURS["text"])


def _body_label_px(corners: np.ndarray, names: Sequence[str], px_per_m: float) -> int:
    """The largest size up to _BODY_LABEL_PX at which no two names overlap in the plan view.

    VTK drops a label that would overlap another, so names of bodies side by side (the 2x3
    layout) must shrink rather than vanish; the letters are about 0.6 of the size wide.
    """
    size = float(_BODY_LABEL_PX)
    for i in range(len(corners)):
        for j in range(i + 1, len(corners)):
            dx, dy = np.abs(corners[i, :2] - corners[j, :2]) * px_per_m
            if dy >= 1.3 * size:
                continue
            width = 0.62 * max(len(names[i]), len(names[j])) + 1.0
            size = min(size, max(dy / 1.3, dx / width))
    return int(max(_MIN_BODY_LABEL_PX, size))


def _draw_whole_flume(plotter, geo: _Geometry, scene: Scene, plan: ModelPlan) -> None:
    _add_common(plotter, geo, body_meshes=False, gauge_dots=True, line_scale=0.6)
    f = geo.flume_bounds
    step = _nice_step((f[1] - f[0]) / 8.0)
    _scale_marks(plotter, f[0], f[1], f[2], step, _TICK_PX)
    (dx0, dx1), _, _ = plan.domain_m
    text = (
        f"whole flume, x = {f[0]:.2f} .. {f[1]:.2f} m: simulated x = {dx0:.2f} .. {dx1:.2f} m "
        f"({-dx0:.2f} of {scene.reservoir.length_m:.2f} m of reservoir)"
    )
    plotter.add_text(text, position="upper_left", font_size=_CORNER_SIZE, color=COLOURS["text"])
    if dx0 - f[0] > 0.1 * (f[1] - f[0]):
        _labels(
            plotter, [(f[0] + 0.03 * (dx0 - f[0]), 0.0, scene.reservoir.depth_m)],
            ["reservoir not simulated"], "#555555", _TICK_PX, bold=False, shape=None,
        )
    _set_camera(plotter, (0.0, 0.0, 1.0), (0.0, 1.0, 0.0), f, row=2, margin=1.25)


def _debris_groups(tops: np.ndarray, names: Sequence[str], gap_m: float) -> list[tuple[np.ndarray, str]]:
    """One label per cluster of bodies closer than ``gap_m`` (single linkage), placed over it.

    A lone body is labelled with its name; a cluster with its first and last names and
    its size (the plan view names every body).
    """
    groups: list[list[int]] = []
    for i, top in enumerate(tops):
        near = [g for g in groups if any(np.linalg.norm(tops[j][:2] - top[:2]) < gap_m for j in g)]
        merged = [i] + [j for g in near for j in g]
        groups = [g for g in groups if g not in near] + [sorted(merged)]
    out = []
    for g in sorted(groups):
        pts = tops[g]
        top = np.array([pts[:, 0].mean(), pts[:, 1].mean(), pts[:, 2].max()])
        if len(g) == 1:
            text = names[g[0]]
        elif len(g) == 2:
            text = f"{names[g[0]]}, {names[g[1]]}"
        else:
            text = f"{names[g[0]]} .. {names[g[-1]]} ({len(g)} bodies)"
        out.append((top, text))
    return out


def _scale_marks(plotter, x0: float, x1: float, y: float, step: float, font_size: int) -> None:
    """x labels along the y = ``y`` wall every ``step`` metres, so positions can be read."""
    first = math.ceil(x0 / step - 1e-9) * step
    marks = np.arange(first, x1 + 1e-9, step)
    if marks.size == 0:
        return
    points = np.column_stack([marks, np.full(marks.size, y), np.zeros(marks.size)])
    _scale_labels(plotter, points, [f"x = {m:g} m" if abs(m) < 1e-9 else f"{m:g}" for m in marks], font_size, "top")


def _scale_labels(plotter, points, labels, font_size: int, vertical: str) -> None:
    """Grey scale marks with their labels (one style for both axes)."""
    plotter.add_point_labels(
        points,
        labels,
        font_size=font_size,
        text_color="#555555",
        bold=False,
        show_points=True,
        point_color="#555555",
        point_size=4,
        shape=None,
        always_visible=True,
        justification_vertical=vertical,
    )


def _y_marks(plotter, x: float, y0: float, y1: float, step: float, font_size: int) -> None:
    """y labels at x = ``x`` every ``step`` metres between the walls, each right of its mark, each
    with its unit (the marks are few: the width of a flume)."""
    first = math.ceil(y0 / step - 1e-9) * step
    marks = np.arange(first, y1 + 1e-9, step)
    if marks.size == 0:
        return
    points = np.column_stack([np.full(marks.size, x), marks, np.zeros(marks.size)])
    _scale_labels(plotter, points, [f" y = {0.0 if abs(m) < 1e-9 else m:g} m" for m in marks], font_size, "center")


def _view_aspect(row: int) -> float:
    """Width over height of view ``row`` in pixels."""
    return WINDOW_SIZE_PX[0] / (WINDOW_SIZE_PX[1] * _ROW_WEIGHTS[row] / sum(_ROW_WEIGHTS))


def _nice_step(raw: float) -> float:
    """1, 2 or 5 times a power of ten, at least ``raw``."""
    power = 10.0 ** math.floor(math.log10(raw))
    for k in (1.0, 2.0, 5.0, 10.0):
        if k * power >= raw:
            return k * power
    return 10.0 * power


def _set_camera(plotter, direction: np.ndarray, up: Sequence[float], bounds: Sequence[float], row: int,
                margin: float = 1.06) -> None:
    """Parallel projection from ``direction`` (towards the camera), ``bounds`` filling view ``row``.

    VTK's own reset fits a sphere around the bounds, far too loose for a flume 20 times
    longer than it is wide; this fits the box's projected corners instead.
    """
    d = np.asarray(direction, dtype=float)
    d = d / np.linalg.norm(d)
    u = np.asarray(up, dtype=float) - np.dot(up, d) * d
    u = u / np.linalg.norm(u)
    right = np.cross(-d, u)
    x0, x1, y0, y1, z0, z1 = bounds
    corners = np.array([(x, y, z) for x in (x0, x1) for y in (y0, y1) for z in (z0, z1)], dtype=float)
    a, b, c = corners @ right, corners @ u, corners @ d
    focal = right * (a.min() + a.max()) / 2 + u * (b.min() + b.max()) / 2 + d * (c.min() + c.max()) / 2
    width_px, height_px = WINDOW_SIZE_PX[0], WINDOW_SIZE_PX[1] * _ROW_WEIGHTS[row] / sum(_ROW_WEIGHTS)
    half_height = max((b.max() - b.min()) / 2, (a.max() - a.min()) / 2 * height_px / width_px)
    reach = float(np.linalg.norm(np.ptp(corners, axis=0))) + 100.0
    plotter.enable_parallel_projection()
    plotter.camera_position = [tuple(focal + reach * d), tuple(focal), tuple(u)]
    plotter.camera.parallel_scale = margin * half_height
    plotter.renderer.ResetCameraClippingRange()


def _headline(scene: Scene, plan: ModelPlan) -> str:
    """The plan in a few lines: solver, dimensions, cells, wall time, extents."""
    n = len(scene.debris)
    bodies = f", {n} debris bod{'y' if n == 1 else 'ies'}" if n else ", no debris"
    if n and not plan.bodies:  # one-way: the flow is solved without them, the bodies are carried through it
        bodies += f" ({plan.debris_coupling}: the flow without them, then carried through it)"
    steps = estimated_steps(plan)
    (dx0, dx1), _, (_, dz1) = plan.domain_m
    lines = [
        f"{plan.scene_name}: {plan.solver}, {'2D' if plan.two_d else '3D'}{bodies}",
        f"{plan.cell_count:,} cells, about {steps:,} steps to {plan.end_time_s:g} s",
        f"estimated wall time {_duration(plan.estimated_wall_time_s)} on {plan.cores} core(s)",
        f"domain x {dx0:.2f} .. {dx1:.2f} m, top {dz1:.2f} m; finest cell {scene.mesh.cell_size_m:g} m",
    ]
    if plan.warnings:
        lines.append(f"{len(plan.warnings)} plan warning(s): printed by `debrisfoam validate` and `render` "
                     "(a rendered case keeps them in plan.json)")
    return "\n".join(lines)


def _duration(seconds: float) -> str:
    if seconds < 90:
        return f"~{seconds:.0f} s"
    if seconds < 90 * 60:
        return f"~{seconds / 60:.0f} min"
    return f"~{seconds / 3600:.1f} h"


# ------------------------------------------------------------------------- plumbing


def _pyvista():
    try:
        import pyvista
    except ImportError as err:  # a declared dependency; say what is missing rather than fail obscurely
        raise DebrisfoamError(f"the preview needs pyvista (pip install pyvista): {err}") from err
    return pyvista


@contextlib.contextmanager
def quiet_vtk() -> Iterator[None]:
    """Silence VTK's warnings while drawing (off-screen, VTK first tries X and says so)."""
    from vtkmodules.vtkCommonCore import vtkLogger, vtkObject

    cutoff = vtkLogger.GetCurrentVerbosityCutoff()
    shown = vtkObject.GetGlobalWarningDisplay()
    vtkLogger.SetStderrVerbosity(vtkLogger.VERBOSITY_ERROR)
    vtkObject.GlobalWarningDisplayOff()
    try:
        yield
    finally:
        vtkLogger.SetStderrVerbosity(cutoff)
        vtkObject.SetGlobalWarningDisplay(shown)


def write_png(image: np.ndarray, out: Path) -> Path:
    """An RGB(A) image array as a PNG, written atomically (the folder made if needed)."""
    from PIL import Image

    out.parent.mkdir(parents=True, exist_ok=True)
    buffer = io.BytesIO()
    Image.fromarray(image).save(buffer, format="PNG")
    return write_bytes_atomic(out, buffer.getvalue())
