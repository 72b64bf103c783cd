"""The comparison plots of a run, as PNG files in DIR/results/ (matplotlib, Agg; pyvista off-screen).

:func:`make_plots` draws, from :mod:`orchestrator.post`'s tables and
:mod:`orchestrator.compare`'s comparisons:

``gauges.png``          elevation at every gauge against Ritter, Stoker and Chanson, with the
                        simulated, analytical and seed arrival times marked (seed Fig. 10);
``column_forces.png``   hydrodynamic force (pressure, viscous, total), impact pulses and their
                        sum on the column; the base shear they cause at the load cell;
``impacts.png``         each column impact's force history over the band of the study's MDOF
                        pulses (Table 2: magnitude and duration within one standard deviation
                        of the mean), against the ASCE 7-22 (k_d, k_s) pulses and the
                        SDOF/MDOF fitted pulses (seed Fig. 4b), and the peak
                        force of every method at the simulated impact velocity;
``seed_fits.png``       the simulated base shear of each impact with the SDOF and MDOF fits
                        (seed Fig. 4a) and every pulse's response on the MDOF column (Fig. 5);
``tracks.png``          debris tracks in plan view with the column, the gauges and the
                        spreading areas of Naito et al. (2014) and Nistor et al. (2017b)
                        (seed Fig. 14), and the bodies' speeds;
``snapshot.png``        a 3D view at the first impact (else at the peak hydrodynamic force):
                        free surface (alpha.water = 0.5), column, debris, read from the written
                        fields (decomposed or reconstructed) with pyvista.

Every PNG is written for every run: a plot with nothing to show says so on its face (no
debris, no impacts, a run stopped before the bore arrived), so a report never links to a
missing file. Only the snapshot needs fields on disk; without them it says why.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from analytical.contact_law import SEED_TABLE2_MDOF

__all__ = ["PLOTS", "make_plots", "snapshot"]

#: The PNGs make_plots writes (name -> file).
PLOTS = {
    "gauges": "gauges.png",
    "column_forces": "column_forces.png",
    "impacts": "impacts.png",
    "seed_fits": "seed_fits.png",
    "tracks": "tracks.png",
    "snapshot": "snapshot.png",
}
_MODEL_STYLE = {"ritter": ("Ritter", "--"), "stoker": ("Stoker", "-."), "chanson": ("Chanson", ":")}
_METHOD_COLOURS = {
    "contact model (simulated)": "#d7191c",
    "ASCE 7-22, k_d": "#2c7bb6",
    "ASCE 7-22, k_s": "#abd9e9",
    "SDOF fit": "#fdae61",
    "MDOF fit": "#1a9641",
}
_DPI = 110


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _save(fig, path: Path) -> Path:
    tmp = path.with_name(f".{path.stem}.{os.getpid()}.tmp.png")
    fig.savefig(tmp, dpi=_DPI)
    _pyplot().close(fig)
    os.replace(tmp, path)
    return path


def _empty(ax, message: str) -> None:
    ax.text(0.5, 0.5, message, ha="center", va="center", transform=ax.transAxes, fontsize=11, wrap=True)
    ax.set_xticks([])
    ax.set_yticks([])


# --------------------------------------------------------------------------- gauges


def plot_gauges(results, comp, path: Path) -> Path:
    plt = _pyplot()
    summary = results.gauge_summary
    n = max(len(summary), 1)
    fig, axes = plt.subplots(n, 1, figsize=(9, 2.3 * n + 0.8), sharex=True, squeeze=False)
    axes = axes[:, 0]
    if summary.empty:
        _empty(axes[0], "no gauge output in this run")
        return _save(fig, path)
    g = results.gauges
    for ax, r in zip(axes, summary.itertuples()):
        col = f"{r.gauge}_elevation_m"
        if col in g:
            ax.plot(g["time_s"], g[col], color="k", lw=1.6, label="simulated")
        model = comp.gauge_models.get(r.gauge)
        if model is not None:
            for key, (label, style) in _MODEL_STYLE.items():
                if f"{key}_m" in model:
                    ax.plot(model["time_s"], model[f"{key}_m"], ls=style, lw=1.2, label=label)
        if np.isfinite(r.arrival_s):
            ax.axvline(r.arrival_s, color="k", lw=0.8, alpha=0.6)
        arr = comp.arrivals[comp.arrivals["gauge"] == r.gauge]
        for a in arr.itertuples():
            if a.reference.startswith("seed"):
                marker = "v" if "experiment" in a.reference else "^"
                ax.plot([a.reference_arrival_s], [0.0], marker=marker, ms=8, ls="none",
                        color="#7b3294" if "experiment" in a.reference else "#c2a5cf", label=a.reference)
        ax.set_ylabel("elevation (m)")
        ax.set_title(f"{r.gauge} at x = {r.x_m:.2f} m, y = {r.y_m:.2f} m", fontsize=10, loc="left")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, loc="upper left", ncol=3)
    axes[-1].set_xlabel("time since the gate opened (s)")
    fig.suptitle("Water surface elevation at the gauges (vertical line: simulated arrival)", fontsize=11)
    fig.tight_layout()
    return _save(fig, path)


# --------------------------------------------------------------------------- column forces


def plot_column_forces(results, path: Path) -> Path:
    plt = _pyplot()
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(9, 7), sharex=True)
    cf, cr = results.column_forces, results.column_response
    if cf.empty or "time_s" not in cf or len(cf) == 0:
        _empty(ax1, "no column forces in this run")
    else:
        t = cf["time_s"]
        for name, label, style in (("pressure_force_x_N", "pressure", ":"), ("viscous_force_x_N", "viscous", "--"),
                                   ("hydro_force_x_N", "hydrodynamic (CFD)", "-")):
            if name in cf:
                ax1.plot(t, cf[name], ls=style, lw=1.2, label=label)
        if cf["impact_force_x_N"].abs().max() > 0:
            ax1.plot(t, cf["impact_force_x_N"], color="#d7191c", lw=1.0, label="impact pulses")
            ax1.plot(t, cf["total_force_x_N"], color="k", lw=0.8, alpha=0.7, label="sum")
            ax1.set_yscale("symlog", linthresh=max(1.0, float(cf["hydro_force_x_N"].abs().max() or 1.0)))
        ax1.set_ylabel("force on the column, x (N)")
        ax1.legend(fontsize=8)
        ax1.grid(alpha=0.3)
    if cr.empty or "base_shear_x_N" not in cr:
        _empty(ax2, "no column response (no column, or no loads)")
    else:
        t = cr["time_s"]
        ax2.plot(t, cr["hydro_base_shear_x_N"], lw=1.2, label="from the hydrodynamic force")
        if cr["impact_base_shear_x_N"].abs().max() > 0:
            ax2.plot(t, cr["impact_base_shear_x_N"], lw=0.8, color="#d7191c", label="from the impacts")
        ax2.plot(t, cr["base_shear_x_N"], lw=0.8, color="k", alpha=0.7, label="total")
        heights = ", ".join(f"{k}: {v:.3f} m" for k, v in results.hydro_heights_m.items())
        ax2.set_title(f"MDOF column base shear (hydrodynamic load height {heights})", fontsize=9, loc="left")
        ax2.set_ylabel("base shear, x (N)")
        ax2.legend(fontsize=8)
        ax2.grid(alpha=0.3)
    ax2.set_xlabel("time (s)")
    fig.tight_layout()
    return _save(fig, path)


# --------------------------------------------------------------------------- impacts


def _events(comp, limit: int = 4) -> list[int]:
    return sorted(comp.fit_records)[:limit]


def _seed_pulse_band(t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The band of half-sines with the study's MDOF magnitudes and durations, each within one
    standard deviation of its Table 2 mean: the lowest and highest such pulse at each time."""
    (f_mean, f_std), (d_mean, d_std) = SEED_TABLE2_MDOF["peak_force_N"], SEED_TABLE2_MDOF["duration_s"]
    curves = [f * np.where((t >= 0) & (t <= d), np.sin(np.pi * np.clip(t, 0, None) / d), 0.0)
              for f in (f_mean - f_std, f_mean + f_std) for d in np.linspace(d_mean - d_std, d_mean + d_std, 5)]
    return np.min(curves, axis=0), np.max(curves, axis=0)


def plot_impacts(results, comp, path: Path) -> Path:
    plt = _pyplot()
    events = _events(comp)
    ncol = max(len(events), 1)
    fig, axes = plt.subplots(2, ncol, figsize=(5.2 * ncol + 1, 8), squeeze=False)
    if not events:
        why = "no debris in this scene" if results.data.scene is not None and not results.data.scene.debris \
            else "no impact on the column in this run"
        _empty(axes[0, 0], f"{why}:\nno impact pulses to compare")
        _empty(axes[1, 0], "no impact formulas to evaluate")
        return _save(fig, path)
    for j, event in enumerate(events):
        rec = comp.fit_records[event]
        ax = axes[0, j]
        contact = rec["pulses"]["contact model (simulated)"]
        t0 = contact.start_s
        span = max(p.end_s for p in rec["pulses"].values() if np.isfinite(p.end_s)) - t0
        span = max(span, 1.1 * (SEED_TABLE2_MDOF["duration_s"][0] + SEED_TABLE2_MDOF["duration_s"][1]))
        tt = np.linspace(t0 - 0.1 * span, t0 + 1.15 * span, 2000)
        low, high = _seed_pulse_band(tt - t0)
        ax.fill_between((tt - t0) * 1e3, low, high, color="0.85", lw=0,
                        label="study's MDOF pulses (Table 2: mean +- std)")
        for method, pulse in rec["pulses"].items():
            ax.plot((tt - t0) * 1e3, pulse.force(tt), lw=2.0 if "contact" in method else 1.2,
                    color=_METHOD_COLOURS.get(method), label=method)
        ax.set_xlabel("time from impact (ms)")
        ax.set_ylabel("impact force (N)")
        ax.set_title(f"event {event}: impact pulses (cf. seed Fig. 4b)", fontsize=10, loc="left")
        ax.legend(fontsize=7)
        ax.grid(alpha=0.3)
        ax = axes[1, j]
        rows = comp.impact_formulas[comp.impact_formulas["event"] == event]
        if rows.empty:
            _empty(ax, "no formula comparison")
            continue
        y = np.arange(len(rows))
        ax.barh(y, rows["peak_force_N"], color=["#d7191c" if "contact" in m else "#7f7f7f" for m in rows["method"]])
        ax.set_yticks(y, rows["method"], fontsize=7)
        ax.invert_yaxis()
        u = float(rows["impact_velocity_m_s"].iloc[0])
        ax.set_xlabel("peak impact force (N)")
        ax.set_title(f"peak force at the simulated u = {u:.2f} m/s", fontsize=10, loc="left")
        ax.grid(alpha=0.3, axis="x")
    fig.tight_layout()
    return _save(fig, path)


def plot_seed_fits(results, comp, path: Path) -> Path:
    from analytical.mdof import mdof_response

    plt = _pyplot()
    events = _events(comp)
    ncol = max(len(events), 1)
    fig, axes = plt.subplots(2, ncol, figsize=(5.2 * ncol + 1, 8), squeeze=False)
    if not events:
        _empty(axes[0, 0], "no impact on the column in this run:\nno response to fit (seed section 3.3)")
        _empty(axes[1, 0], "no pulses to apply to the MDOF column")
        return _save(fig, path)
    column = results.data.column
    for j, event in enumerate(events):
        rec = comp.fit_records[event]
        t, r = rec["time_s"], rec["record_N"]
        t0 = rec["pulses"]["contact model (simulated)"].start_s
        ax = axes[0, j]
        ax.plot((t - t0) * 1e3, r, color="0.4", lw=1.6, label="simulated base shear (impact part)")
        for key, label, colour in (("sdof", "SDOF fit", _METHOD_COLOURS["SDOF fit"]),
                                   ("mdof", "MDOF fit", _METHOD_COLOURS["MDOF fit"])):
            if rec.get(f"{key}_N") is not None:
                ax.plot((rec[f"{key}_time_s"] - t0) * 1e3, rec[f"{key}_N"], color=colour, lw=1.1, label=label)
        ax.set_xlabel("time from impact (ms)")
        ax.set_ylabel("base shear (N)")
        ax.set_title(f"event {event}: fits to the response (cf. seed Fig. 4a)", fontsize=10, loc="left")
        ax.legend(fontsize=7)
        ax.grid(alpha=0.3)
        ax = axes[1, j]
        tf = np.arange(t[0], t[-1], 2e-5)
        ax.plot((t - t0) * 1e3, r, color="0.4", lw=2.0, label="simulated")
        for method, pulse in rec["pulses"].items():
            if "contact" in method:
                continue
            resp = mdof_response(pulse, column, rec["height_m"], tf).response_N
            ax.plot((tf - t0) * 1e3, resp, lw=1.0, color=_METHOD_COLOURS.get(method), label=f"{method} pulse")
        ax.set_xlabel("time from impact (ms)")
        ax.set_ylabel("MDOF base shear (N)")
        ax.set_title(f"every pulse on the MDOF column at z = {rec['height_m']:.3f} m (cf. seed Fig. 5)",
                     fontsize=9, loc="left")
        ax.legend(fontsize=7)
        ax.grid(alpha=0.3)
    fig.tight_layout()
    return _save(fig, path)


# --------------------------------------------------------------------------- tracks


def plot_tracks(results, comp, path: Path) -> Path:
    plt = _pyplot()
    from matplotlib.patches import Polygon, Rectangle

    from orchestrator.compare import SPREADING_ANGLES_DEG

    data = results.data
    fig, (ax, axv) = plt.subplots(2, 1, figsize=(11, 8), gridspec_kw={"height_ratios": [2.2, 1]})
    scene = data.scene
    bodies = results.bodies
    x_lo, x_hi, y_lo, y_hi = None, None, None, None
    if data.plan and data.plan.get("domain_m"):
        (x_lo, x_hi), (y_lo, y_hi) = data.plan["domain_m"][0], data.plan["domain_m"][1]
    elif scene is not None:
        from orchestrator.scene import flume_extent

        (x_lo, x_hi), (y_lo, y_hi), _ = flume_extent(scene)
    walls = None
    if x_lo is not None:
        walls = Rectangle((x_lo, y_lo), x_hi - x_lo, y_hi - y_lo, fill=False, lw=1.2, color="0.3")
        ax.add_patch(walls)
    colours = ["#2b83ba", "#fdae61"]
    for (name, poly), colour in zip(comp.areas.items(), colours):
        spec = SPREADING_ANGLES_DEG[name]
        flag = "" if spec["verified"] else ", unverified"
        area = Polygon(poly, closed=True, alpha=0.18, color=colour, label=f"{name}: {spec['half_angle_deg']:g} deg{flag}")
        ax.add_patch(area)
        if walls is not None:  # the area ends at the flume walls
            area.set_clip_path(walls)
        ax.plot(poly[[0, 3], 0], poly[[0, 3], 1], color=colour, lw=2.0)
    if scene is not None and scene.column is not None:
        c = scene.column
        ax.add_patch(Rectangle((c.x_m - c.size_x_m / 2, c.y_m - c.size_y_m / 2), c.size_x_m, c.size_y_m,
                               color="#5f6b73", label="column"))
    for r in results.gauge_summary.itertuples():
        if np.isfinite(r.x_m):
            ax.plot(r.x_m, r.y_m, marker="o", ms=6, color="#1a9641", ls="none")
            ax.annotate(r.gauge, (r.x_m, r.y_m), xytext=(4, 4), textcoords="offset points", fontsize=8,
                        color="#1a9641")
    if bodies.empty:
        why = "no debris in this scene" if scene is not None and not scene.debris else "no body tracks in this run"
        ax.text(0.5, 0.92, why, transform=ax.transAxes, ha="center", fontsize=10)
        _empty(axv, why)
    else:
        for body, track in bodies.groupby("body"):
            line, = ax.plot(track["x_m"], track["y_m"], lw=1.4, label=body)
            ax.plot(track["x_m"].iloc[0], track["y_m"].iloc[0], marker="s", ms=5, color=line.get_color())
            axv.plot(track["time_s"], track["speed_m_s"], lw=1.0, color=line.get_color(), label=body)
        imp = results.impacts
        if len(imp):
            ax.plot(imp["point_x_m"], imp["point_y_m"], marker="*", ms=11, ls="none", color="#d7191c",
                    label="impacts")
            for t in imp["time_s"]:
                axv.axvline(t, color="#d7191c", lw=0.6, alpha=0.6)
        axv.set_xlabel("time (s)")
        axv.set_ylabel("speed (m/s)")
        axv.grid(alpha=0.3)
        axv.legend(fontsize=7, ncol=4)
    # frame: the debris path and the column, with the flume's width
    xs = [v for v in (bodies["x_m"].min() if not bodies.empty else None,
                      bodies["x_m"].max() if not bodies.empty else None) if v is not None]
    if scene is not None and scene.column is not None:
        xs += [scene.column.x_m - scene.column.size_x_m, scene.column.x_m + scene.column.size_x_m]
    xs += [r.x_m for r in results.gauge_summary.itertuples() if np.isfinite(r.x_m)]
    for poly in comp.areas.values():
        xs.append(float(poly[0, 0]))
    if xs:
        pad = 0.1 * (max(xs) - min(xs) + 0.5)
        ax.set_xlim(min(xs) - pad, max(xs) + pad)
    if y_lo is not None:
        ax.set_ylim(y_lo - 0.05 * (y_hi - y_lo), y_hi + 0.05 * (y_hi - y_lo))
    ax.set_aspect("equal", adjustable="box")
    ax.set_xlabel("x along the flume (m)")
    ax.set_ylabel("y across (m)")
    ax.set_title("Debris tracks (centre of mass) in plan view; spreading areas from the ASCE 7-22 6.11.5.1 "
                 "source line (cf. seed Fig. 14)", fontsize=9, loc="left")
    ax.legend(fontsize=7, loc="lower left")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    return _save(fig, path)


# --------------------------------------------------------------------------- snapshot



def _snapshot_time(results) -> tuple[float | None, str]:
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
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(9, 5.5))
    _empty(ax, message)
    return _save(fig, path)


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
    decomposed = any(p.is_dir() for p in case.glob("processor*"))
    from orchestrator.preview import _quiet_vtk

    with _quiet_vtk():
        try:
            reader = pv.POpenFOAMReader(str(case / "system" / "controlDict"))
            times: list[float] = []
            for kind in (("decomposed", "reconstructed") if decomposed else ("reconstructed",)):
                reader.case_type = kind
                reader.reader.UpdateInformation()
                times = [t for t in reader.time_values if t > 0] or list(reader.time_values)
                if times and (wanted is None or min(abs(t - wanted) for t in times) < 1e-6 or kind == "reconstructed"):
                    break
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
        focus = _focus(results, internal.bounds)
        scene = results.data.scene
        size = 2.5 * scene.column.height_m if scene is not None and scene.column is not None else \
            0.5 * (internal.bounds[3] - internal.bounds[2])
        plotter.camera.focal_point = focus
        plotter.camera.position = (focus[0] - 0.9 * size, focus[1] - 1.3 * size, focus[2] + 0.8 * size)
        plotter.camera.up = (0.0, 0.0, 1.0)
        plotter.add_text(f"t = {t:.4g} s: {what}", font_size=11, color="black")
        tmp = path.with_name(f".{path.stem}.{os.getpid()}.tmp.png")
        plotter.screenshot(str(tmp))
        plotter.close()
    os.replace(tmp, path)
    return path, note


def _focus(results, bounds) -> tuple[float, float, float]:
    scene = results.data.scene
    if results.impacts is not None and len(results.impacts):
        first = results.impacts.sort_values("time_s").iloc[0]
        return float(first["point_x_m"]), float(first["point_y_m"]), float(first["point_z_m"])
    if scene is not None and scene.column is not None:
        return float(scene.column.x_m), float(scene.column.y_m), 0.1 * float(scene.column.height_m)
    return (0.5 * (bounds[0] + bounds[1]), 0.5 * (bounds[2] + bounds[3]), bounds[4])


# --------------------------------------------------------------------------- entry point


def make_plots(results, comp, out_dir: str | Path, snapshot_3d: bool = True) -> tuple[dict[str, Path], list[str]]:
    """Every PNG of :data:`PLOTS` in out_dir; returns ({name: path}, notes)."""
    out = Path(out_dir)
    notes: list[str] = []
    written = {
        "gauges": plot_gauges(results, comp, out / PLOTS["gauges"]),
        "column_forces": plot_column_forces(results, out / PLOTS["column_forces"]),
        "impacts": plot_impacts(results, comp, out / PLOTS["impacts"]),
        "seed_fits": plot_seed_fits(results, comp, out / PLOTS["seed_fits"]),
        "tracks": plot_tracks(results, comp, out / PLOTS["tracks"]),
    }
    if snapshot_3d:
        written["snapshot"], note = snapshot(results, out / PLOTS["snapshot"])
        if note:
            notes.append(note)
    return written, notes
