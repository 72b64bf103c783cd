"""The scene's water container: the flume, the reservoir behind its gate (with the gate's sill and
posts, where the flume has them) and the bed downstream. :mod:`orchestrator.scene.schema`
re-exports these sections."""

from __future__ import annotations

from typing import Literal

from pydantic import Field

from orchestrator.scene.base import SceneSection

__all__ = ["Bed", "Flume", "Reservoir"]


class Flume(SceneSection):
    """The tank or flume: a rectangular box of floor length x width, walls height high."""

    length_m: float = Field(gt=0, description="total length, reservoir included (m)")
    width_m: float = Field(gt=0, description="inside width (m)")
    height_m: float = Field(gt=0, description="wall height above the floor (m)")
    downstream_end: Literal["closed", "open"] = Field(
        "closed", description="closed: an end wall; open: water leaves (free outfall)"
    )


class Reservoir(SceneSection):
    """The impoundment at the upstream end, from the upstream wall to the gate at x = 0, and the
    gate's sill and posts where the flume has them (docs/bed-friction.md, "The study's flume")."""

    length_m: float = Field(gt=0, description="from the upstream wall to the gate (m)")
    depth_m: float = Field(gt=0, description="impoundment level h0 above the bed downstream (m)")
    gate: Literal["swing-gate", "instant"] = Field(
        "instant", description="instant, or swing-gate: removed at once or over opening_time_s"
    )
    opening_time_s: float = Field(0.0, ge=0, description="a swing gate lifting off the reservoir's floor at a "
                                  "constant rate clears the impoundment in this time (s); 0 = at once")
    sill_height_m: float = Field(0.0, ge=0, description="reservoir floor below the bed downstream: a step at "
                                 "the gate (m)")
    opening_width_m: float | None = Field(None, gt=0, description="the gate's clear opening, walls beside it; "
                                          "null = the flume's width (m)")
    opening_y_m: float = Field(0.0, description="the opening's centre (m)")
    opening_length_m: float = Field(0.10, gt=0, description="the walls' length downstream of the gate (m)")


class Bed(SceneSection):
    """The flume floor downstream of the gate."""

    wet_depth_m: float = Field(0.0, ge=0, description="still-water depth downstream of the gate; 0 = dry (m)")
    friction_factor: float = Field(0.0293, ge=0, description="Darcy friction factor f of the bed (-)")
    slip: bool = Field(False, description="the bed a slip wall (no shear: Stoker's and Ritter's inviscid bed; only "
                       "with friction_factor 0); false = no-slip")
    friction_calibration: float = Field(
        2.2, gt=0,
        description="laminar only: multiplier on the bed drag of the cell layers next to the bed, standing for the "
        "momentum the missing turbulence would share with the still wet bed; 2.2 puts the arrivals on Chanson's "
        "dry-bed solution, 3.2 WG2 on its measured 0.91 s and WG3 0.15 s early (docs/bed-friction.md)",
    )
