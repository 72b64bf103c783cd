"""The one-way forcing's variants through a recorded 1-debris flow: first strike, speed, yaw
(``debrisfoam report forcing-variants RUN -o FILE``; ``make forcing-variants``).

Needs a one-way run of cases/1debris.yaml (``make case-1debris``); carries its container through
the record from a 0 and a 20 degree start with the drag on each body axis or along the flow,
with and without the Munk moment, at three drag coefficients, and writes the table that
docs/one-way.md ("The drag coefficient") quotes (benchmarks/forcing_variants.md).
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

from orchestrator.case.folder import CaseFolder
from orchestrator.core.errors import InputError
from orchestrator.transport.case_transport import case_flow, scene_settings, transport_setup
from orchestrator.transport.mujoco_model import with_start
from orchestrator.transport.engine import run_transport

__all__ = ["VARIANTS", "YAWS_DEG", "forcing_variants"]

#: (name, the hydrodynamic settings changed, drag coefficient C_d), in the table's order.
VARIANTS = [
    ("per axis, no Munk", dict(drag_area="per_axis", munk_moment=False), 3.0),
    ("along the flow, no Munk", dict(drag_area="projected", munk_moment=False), 3.0),
    ("along the flow + Munk", dict(drag_area="projected", munk_moment=True), 3.0),
    ("along the flow + Munk", dict(drag_area="projected", munk_moment=True), 2.0),
    ("along the flow + Munk (default)", dict(drag_area="projected", munk_moment=True), 1.05),
]
#: The container's start headings (deg).
YAWS_DEG = (0.0, 20.0)


def forcing_variants(case_dir: str | Path, say: Callable[[str], None] = print) -> str:
    """The page (Markdown): the first body of the one-way run ``case_dir`` carried through its flow
    record under each variant and start heading; ``say`` gets each row as it is measured.
    InputError when the folder is not a case with a scene and a flow record."""
    folder = CaseFolder(case_dir)
    if not folder.scene_path.is_file():
        raise InputError("case_dir", "no scene.yaml: not a debrisfoam case (run `make case-1debris` first)",
                         str(case_dir))
    scene = folder.scene()
    if not scene.debris:
        raise InputError("debris", "the scene has no debris to carry through its record", str(folder.scene_path))
    flow, _ = case_flow(folder.path, say=lambda _: None)
    bodies, flume, column = transport_setup(scene, flow)
    base = scene_settings(scene)
    rows = ["| forcing | C_d | start yaw | first strike | speed (normal) | obliquity | yaw then | y then | law's peak | wall |",
            "|---|---|---|---|---|---|---|---|---|---|"]
    for name, options, cd in VARIANTS:
        for yaw in YAWS_DEG:
            body = with_start(bodies[0], yaw_deg=yaw)
            hydro = dataclasses.replace(base.hydro, drag_coefficient=cd, **options)
            start = time.perf_counter()
            run = run_transport([body], flume, float(scene.run.end_time_s), flow=flow, column=column,
                                settings=dataclasses.replace(base, hydro=hydro))
            wall = time.perf_counter() - start
            strikes = run.impacts[run.impacts["kind"] == "column"]
            if not len(strikes):
                rows.append(f"| {name} | {cd:g} | {yaw:g} | none | - | - | - | - | - | {wall:.1f} s |")
                say(rows[-1])
                continue
            hit = strikes.iloc[0]
            track = run.track(body.name)
            then = track[track["time_s"] <= hit["time_s"]].iloc[-1]
            speed = float(np.hypot(hit["normal_velocity_in_m_s"], hit["tangential_velocity_in_m_s"]))
            rows.append(f"| {name} | {cd:g} | {yaw:g} | {hit['time_s']:.3f} s | {speed:.2f} "
                        f"({hit['normal_velocity_in_m_s']:.2f}) m/s | {hit['obliquity_deg']:.0f} | "
                        f"{then['yaw_deg']:.0f} | {then['y_m']:+.3f} m | {hit['peak_force_N']:.0f} N | {wall:.1f} s |")
            say(rows[-1])
    return ("# One-way forcing variants through the 1-debris record\n\n"
            f"Written by `debrisfoam report forcing-variants {case_dir}` from that run's flow record "
            f"({scene.name}, {float(scene.run.end_time_s):g} s); the container's first column strike under each "
            "forcing. The study: 1.60 +- 0.13 m/s.\n\n" + "\n".join(rows) + "\n")
