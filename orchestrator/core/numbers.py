"""Numbers as records keep them: a finite float, or None for anything else.

Summaries (summary.json, the stability table) hold plain floats or null; a NaN or an
infinity, a missing value or text that is not a number all become None there.
"""
from __future__ import annotations

import math


def finite_or_none(value) -> float | None:
    """``float(value)`` when that is a finite number, else None."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        return None
    return v if math.isfinite(v) else None
