"""Froude scale: the factor by which a scene is larger than the study's flume, for the tool's
absolute constants that were chosen or measured there.

Some of the tool's defaults are times, lengths or speeds fixed on the study's 0.40 m impoundment
(:data:`REFERENCE_DEPTH_M`): the cap on the time step (0.01 s), the first time step's cap (1 ms),
the one-way transport's forcing interval (1 ms) and its thresholds. Under Froude similarity a
scene ``lambda`` times larger (lengths x lambda) runs the same flow with times and speeds
x sqrt(lambda); those constants must follow or the larger scene takes sqrt(lambda) times the steps
(or, for a threshold, sees a different event). :func:`froude_factor` is
``lambda = max(1, h0 / 0.40 m)``: a scene deeper than the study's is scaled, a shallower one keeps
the constants as they are (every shipped laboratory scene, and the tests' small tanks, are at
most 0.40 m deep, so their plans are unchanged). Everything the planner derives from the scene's
own lengths (cells, layers, domain, gauges, bed friction per metre) scales by construction
(docs/prototype.md).
"""

from __future__ import annotations

import math

from orchestrator.core.errors import require_positive

__all__ = ["REFERENCE_DEPTH_M", "froude_factor", "length_scale", "time_scale"]

#: The study's impoundment depth (study 3.1, 4.1.1), at which the tool's absolute constants were set (m).
REFERENCE_DEPTH_M = 0.40


def froude_factor(depth_m: float) -> float:
    """lambda = max(1, depth_m / :data:`REFERENCE_DEPTH_M`) (-): how much larger than the study's
    flume a scene whose impoundment is ``depth_m`` deep is, for the constants set there."""
    return max(1.0, require_positive("depth_m", depth_m) / REFERENCE_DEPTH_M)


def length_scale(depth_m: float) -> float:
    """The factor on a length set at the study's depth: lambda."""
    return froude_factor(depth_m)


def time_scale(depth_m: float) -> float:
    """The factor on a time or a speed set at the study's depth: sqrt(lambda)."""
    return math.sqrt(froude_factor(depth_m))
