"""What the planner takes from the layers below it, gathered once before it plans.

The scene's own geometry and checks (:mod:`orchestrator.scene`) and the analytical dam-break
flow (:mod:`analytical`) give the planner a few figures that depend on the scene alone: each
body's rotation and whether it rests on the bed, the flume's extent, the scene's plausibility
warnings, Stoker's wet-bed state behind the bore, the dam-break solution that times the holds
of resting bodies, and the bed's sand roughness for a RANS flow. :func:`scene_facts` works them
out in one place; the plan's sections (:mod:`orchestrator.plan.bodies`,
:mod:`orchestrator.plan.domain`, :mod:`orchestrator.plan.planner`) take them as plain values.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from analytical.dambreak import StokerState, dam_break, stoker_state
from analytical.roughness import bore_depth_m, sand_roughness_m
from orchestrator.scene.geometry import body_rotation, flume_extent, half_extent_z
from orchestrator.scene.schema import DebrisBody, Scene
from orchestrator.scene.validation import plausibility_warnings

__all__ = ["SceneFacts", "rests_on_bed", "scene_facts"]


@dataclass(frozen=True)
class SceneFacts:
    """The figures of :func:`scene_facts`, in the scene's units (m, s)."""

    #: each body's rotation (body axes -> scene axes; :func:`orchestrator.scene.geometry.body_rotation`)
    rotations: tuple[np.ndarray, ...]
    #: whether each body rests on the bed (:func:`rests_on_bed`)
    on_bed: tuple[bool, ...]
    #: ((x0, x1), (y0, y1), (z0, z1)) of the flume (:func:`orchestrator.scene.geometry.flume_extent`)
    flume: tuple[tuple[float, float], tuple[float, float], tuple[float, float]]
    #: :func:`orchestrator.scene.validation.plausibility_warnings`
    warnings: tuple[str, ...]
    #: Stoker's state behind the bore on a wet bed shallower than the impoundment; None otherwise
    stoker: StokerState | None
    #: the dry-bed dam-break solution that times a resting body's hold (Chanson with the bed's
    #: friction factor, Ritter without); None when no body rests on the bed
    bed_flow: Any
    #: the depth the dam-break flow runs at (:func:`analytical.roughness.bore_depth_m`) where the
    #: bed's roughness is worked out (a RANS flow over a bed with friction); None otherwise
    bore_depth_m: float | None
    #: the bed's sand roughness for a RANS flow's wall function: the k_s that gives the scene's
    #: Darcy f at ``bore_depth_m``; 0 for a laminar flow or a frictionless bed
    bed_roughness_m: float


def rests_on_bed(body: DebrisBody, rot: np.ndarray) -> bool:
    """Whether the body's lowest corner is on the bed (``rot``: its rotation)."""
    return body.centre_m[2] - half_extent_z(body, rot) <= 1e-6


def scene_facts(scene: Scene) -> SceneFacts:
    """What the plan's sections take from the scene's geometry and the analytical flow."""
    rotations = tuple(body_rotation(body.yaw_deg, body.pitch_deg, body.roll_deg) for body in scene.debris)
    on_bed = tuple(rests_on_bed(body, rot) for body, rot in zip(scene.debris, rotations))
    flume = flume_extent(scene)
    warnings = tuple(plausibility_warnings(scene))
    h0, wet, g = scene.reservoir.depth_m, scene.bed.wet_depth_m, scene.fluids.gravity_m_s2
    stoker = stoker_state(h0, wet, g) if 0 < wet < h0 else None
    f = scene.bed.friction_factor
    bed_flow = None
    if any(on_bed):
        bed_flow = dam_break("chanson", h0, friction=f) if f > 0 else dam_break("ritter", h0)
    rough = scene.fluids.turbulence != "laminar" and f > 0
    depth = bore_depth_m(h0, wet, g) if rough else None
    ks = sand_roughness_m(f, depth) if depth is not None else 0.0
    return SceneFacts(rotations, on_bed, flume, warnings, stoker, bed_flow, depth, ks)
