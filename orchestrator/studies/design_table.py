"""What a design study's table holds and the small rules both its run and its page use: the
demands and design.csv's columns, the realisations' shares among inundation cases, the masses
a body is drawn between, and each realisation's demand (the largest over its bodies)."""

from __future__ import annotations

from typing import Sequence

import numpy as np
import pandas as pd

from analytical import catalogue
from orchestrator.core.errors import InputError
from orchestrator.scene.schema import DebrisBody, Design

__all__ = ["DEMANDS", "DESIGN_COLUMNS", "allocate", "case_names", "debris_types", "mass_range",
           "realisation_demands"]

#: The demands of a design study: column of design.csv -> (what it is, unit).
DEMANDS = {"peak_force_N": ("peak impact force", "N"), "base_shear_N": ("base shear", "N"),
           "base_moment_Nm": ("base moment", "N m"),
           "displacement_m": ("member's largest displacement", "m")}
"""``displacement_m``: the largest over the member's length (its nodes and the strike point) and
over time (:func:`analytical.column_demand.strike_demands`): a cantilever's top; a member held at
its top as well moves most between the strike point and mid-height."""

DESIGN_COLUMNS = ["case", "realisation", "case_weight", "sample_weight", "body", "mass_kg", "draft_m", "start_depth_m",
                  "carried", "start_x_m", "start_y_m", "start_yaw_deg", "struck", "strikes", "strike", "impact_time_s",
                  "impact_speed_m_s", "impact_velocity_m_s", "flow_speed_m_s", "flow_speed_max_m_s", "impact_height_m",
                  "face", "obliquity_deg", "eccentricity_m", "torsion_Nm", "duration_s", "impulse_Ns", *DEMANDS,
                  "wall_time_s"]
"""design.csv: one row per column strike (``strike`` 1, 2, ... of its body, in time order), and
one row for a body that never struck (``strike`` 0, demands 0): its case and weights (the
case's, normalised, and each of its realisations' share ``case_weight / n_case``), the body's
drawn mass and start, its draft and the deepest water at its start (``carried`` False: it
cannot float there and is not carried), its number of column strikes, then the strike: time,
centre speed, normal velocity, the water it came in with (depth-averaged and fastest), contact
height, face, obliquity, eccentricity and torsion (:mod:`orchestrator.studies.design_strikes`),
pulse duration and impulse, and its demands; the realisation's share of the batch's wall time."""


def allocate(n: int, weights: Sequence[float]) -> list[int]:
    """``n`` realisations shared in proportion to ``weights`` (largest remainders), at least one each."""
    w = np.asarray(weights, dtype=float)
    w = w / w.sum()
    if n < w.size:
        raise InputError("design.realisations", f"must be at least the number of inundation cases ({w.size}), got {n}")
    exact = w * n
    counts = np.floor(exact).astype(int)
    for i in np.argsort(-(exact - counts), kind="stable")[: n - int(counts.sum())]:
        counts[i] += 1
    for i in np.flatnonzero(counts == 0):  # every case keeps one, taken from the largest
        counts[int(np.argmax(counts))] -= 1
        counts[i] = 1
    return [int(c) for c in counts]


def case_names(spec: Design) -> list[str]:
    """Each case's name (``case<k>``, k from 1, where none is given)."""
    return [c.name or f"case{k + 1}" for k, c in enumerate(spec.inundation)]


def mass_range(body: DebrisBody, spec: Design, debris_type: str | None = None) -> tuple[float, float]:
    """The masses a body is drawn between: ``design.mass_kg``; else, for a body the debris
    catalogue names (``debris[].type`` of a container family), its family's empty and loaded
    masses (analytical.catalogue.mass_range_kg); else its own mass."""
    if spec.mass_kg is not None:
        return float(spec.mass_kg[0]), float(spec.mass_kg[1])
    if debris_type is not None and catalogue.debris_type(debris_type).family is not None:
        lo, hi = catalogue.mass_range_kg(debris_type)
        return float(lo), float(hi)
    return float(body.mass_kg), float(body.mass_kg)


def debris_types(scene) -> dict[str, str | None]:
    """Each body's catalogue type (None where the scene gives its properties itself)."""
    return {b.name: getattr(b, "type", None) for b in scene.debris}


def realisation_demands(table: pd.DataFrame) -> pd.DataFrame:
    """One row per (case, realisation): each demand's largest over its strikes (every strike of
    every body), whether any body struck, its number of column strikes, and its sample weight."""
    agg = {k: "max" for k in DEMANDS} | {"struck": "any", "sample_weight": "first", "case_weight": "first"}
    table = table.assign(strikes_counted=(pd.to_numeric(table["strike"], errors="coerce").fillna(0) > 0).astype(int))
    agg["strikes_counted"] = "sum"
    per = table.groupby(["case", "realisation"], sort=False).agg(agg).reset_index()
    return per.rename(columns={"strikes_counted": "strikes"})
