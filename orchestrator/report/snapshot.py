"""The 3D snapshot of a run (``snapshot.png``): the free surface (alpha.water = 0.5), the
column and the debris at the first impact (else at the peak hydrodynamic force, else at the
latest written time), read from the written fields (decomposed or reconstructed) with pyvista
off-screen. Without fields on disk, a placeholder says why.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from orchestrator.report.figures import empty, pyplot, save_figure
from orchestrator.report.preview import quiet_vtk, write_png

__all__ = ["snapshot"]


def _snapshot_time(results) -> tuple[float | None, str]:
    """The time to draw and what happens then: the first impact, else the peak hydrodynamic force."""
    imp = results.impacts
    if len(imp):
        first = imp.sort_values("time_s").iloc[0]
        return float(first["time_s"]), f"first impact ({first['body']} on {first['other']})"
    cf = results.column_forces
    if "hydro_force_x_N" in cf and cf["hydro_force_x_N"].notna().any():
        i = int(cf["hydro_force_x_N"].abs().idxmax())
        return float(cf.loc[i, "time_s"]), "peak hydrodynamic force on the column (no impact in this run)"
    return None, "latest written time"


def _placeholder(path: Path, message: str) -> Path:
    """A PNG that says why there is no snapshot."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(9, 5.5))
    empty(ax, message)
    return save_figure(fig, path)


def snapshot(results, path: Path) -> tuple[Path, str | None]:
    """3D view at the first impact (else the peak hydrodynamic force, else the latest time).

    Returns (png, note): the note says why a placeholder was drawn instead, or which
    written time stands in for the wanted one.
    """
    case = results.data.case
    wanted, what = _snapshot_time(results)
    try:
        import pyvista as pv
    except ImportError as exc:  # a declared dependency
        note = f"snapshot: pyvista is not installed ({exc})"
        return _placeholder(path, note), note
    if not (case / "system" / "controlDict").is_file():
        note = "snapshot: the case has no system/controlDict, so its fields cannot be read"
        return _placeholder(path, note), note
    with quiet_vtk():
        try:
            reader, times = _open_reader(pv, case, wanted)
        except Exception as exc:  # VTK raises plain errors for unreadable cases
            note = f"snapshot: the case's fields could not be read ({exc})"
            return _placeholder(path, note), note
        if not times:
            note = "snapshot: no written time directory with fields in the case"
            return _placeholder(path, note), note
        t = min(times, key=lambda v: abs(v - wanted)) if wanted is not None else max(times)
        note = None
        if wanted is not None and abs(t - wanted) > 1e-6:
            note = f"snapshot: no fields written at t = {wanted:.6g} s ({what}); drawn at the nearest written time"
        image = _render(pv, results, reader, t, what)
    return write_png(image, path), note


def _open_reader(pv, case: Path, wanted: float | None):
    """(the OpenFOAM reader, its written times after 0): the decomposed case when it has the
    wanted time, else the reconstructed one."""
    decomposed = any(p.is_dir() for p in case.glob("processor*"))
    reader = pv.POpenFOAMReader(str(case / "system" / "controlDict"))
    times: list[float] = []
    for kind in (("decomposed", "reconstructed") if decomposed else ("reconstructed",)):
        reader.case_type = kind
        reader.reader.UpdateInformation()
        times = [t for t in reader.time_values if t > 0] or list(reader.time_values)
        if times and (wanted is None or min(abs(t - wanted) for t in times) < 1e-6 or kind == "reconstructed"):
            break
    return reader, times


def _render(pv, results, reader, t: float, what: str) -> np.ndarray:
    """The image of the fields at time t: free surface, bed, column, bodies and gauges."""
    reader.set_active_time_value(t)
    reader.cell_to_point_creation = True
    reader.enable_all_patch_arrays()
    mesh = reader.read()
    internal = mesh["internalMesh"]
    if "cellTypes" in internal.cell_data:  # overset: leave out the hole cells (type 2)
        internal = internal.threshold(value=(-0.5, 1.5), scalars="cellTypes", preference="cell")
    surface = internal.contour([0.5], scalars="alpha.water") if "alpha.water" in internal.point_data else None
    boundary = mesh["boundary"] if "boundary" in mesh.keys() else None
    plotter = pv.Plotter(off_screen=True, window_size=(1400, 900))
    plotter.set_background("white")
    if surface is not None and surface.n_points:
        plotter.add_mesh(surface, color="#1f6fd1", opacity=0.75, smooth_shading=True)
    patches = set(boundary.keys()) if boundary is not None else set()
    if "bed" in patches:
        plotter.add_mesh(boundary["bed"], color="#e6e2da", opacity=0.6)
    if "column" in patches:
        plotter.add_mesh(boundary["column"], color="#5f6b73")
    for name in results.data.body_names:
        if name in patches:
            plotter.add_mesh(boundary[name], color="#d7191c")
    for r in results.gauge_summary.itertuples():
        if np.isfinite(r.x_m):
            top = internal.bounds[5]
            plotter.add_mesh(pv.Line((r.x_m, r.y_m, 0.0), (r.x_m, r.y_m, top)), color="#1a9641", line_width=3)
    _aim(plotter, results, internal.bounds)
    plotter.add_text(f"t = {t:.4g} s: {what}", font_size=11, color="black")
    image = plotter.screenshot(return_img=True)
    plotter.close()
    return np.asarray(image)


def _aim(plotter, results, bounds) -> None:
    """The camera: from upstream and to the side, above, at the point of interest."""
    focus = _focus(results, bounds)
    scene = results.data.scene
    size = 2.5 * scene.column.height_m if scene is not None and scene.column is not None else \
        0.5 * (bounds[3] - bounds[2])
    plotter.camera.focal_point = focus
    plotter.camera.position = (focus[0] - 0.9 * size, focus[1] - 1.3 * size, focus[2] + 0.8 * size)
    plotter.camera.up = (0.0, 0.0, 1.0)


def _focus(results, bounds) -> tuple[float, float, float]:
    """The first impact's point, else the foot of the column, else the middle of the bed."""
    scene = results.data.scene
    if results.impacts is not None and len(results.impacts):
        first = results.impacts.sort_values("time_s").iloc[0]
        return float(first["point_x_m"]), float(first["point_y_m"]), float(first["point_z_m"])
    if scene is not None and scene.column is not None:
        return float(scene.column.x_m), float(scene.column.y_m), 0.1 * float(scene.column.height_m)
    return (0.5 * (bounds[0] + bounds[1]), 0.5 * (bounds[2] + bounds[3]), bounds[4])
