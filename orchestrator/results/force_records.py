"""Reading measured (or simulated) force-response records: CSV `time_s,force_N`.

I/O lives here, at the edge; `analytical.fitting` only sees validated arrays.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from orchestrator.core.errors import InputError

#: Fewer samples than this cannot resolve a pulse and the ringing after it.
MIN_SAMPLES = 20


def read_force_record(path: str | Path) -> tuple[np.ndarray, np.ndarray]:
    """Return (time_s, force_N) from a CSV with those two columns, validated (``response_N`` is read
    as ``force_N``: a force response written by ``analytical response --out`` is a record to fit).

    Raises InputError naming the file and the column for: a missing file or column,
    non-numeric values or NaNs, fewer than MIN_SAMPLES rows, time not strictly increasing.
    """
    import pandas as pd

    path = Path(path)
    source = str(path)
    if path.is_dir():
        raise InputError("record", "is a folder; give the CSV file (columns time_s,force_N)", source)
    if not path.is_file():
        raise InputError("record", "file not found", source)
    try:
        frame = pd.read_csv(path)
    except Exception as exc:  # pandas raises several types for unreadable CSV
        raise InputError("record", f"not a readable CSV: {exc}", source) from None
    frame.columns = [str(c).strip() for c in frame.columns]
    if "force_N" not in frame.columns and "response_N" in frame.columns:  # `analytical response --out`'s record
        frame = frame.rename(columns={"response_N": "force_N"})
    for column in ("time_s", "force_N"):
        if column not in frame.columns:
            also = " (or response_N, as `debrisfoam analytical response --out` writes)" if column == "force_N" else ""
            raise InputError(column, f"column missing{also} (found: {', '.join(frame.columns)})", source)
    arrays = {}
    for column in ("time_s", "force_N"):
        values = pd.to_numeric(frame[column], errors="coerce").to_numpy(dtype=float)
        bad = np.flatnonzero(~np.isfinite(values))
        if bad.size:
            raise InputError(column, f"{bad.size} non-numeric or NaN value(s), first at data row {bad[0] + 1}", source)
        arrays[column] = values
    t, f = arrays["time_s"], arrays["force_N"]
    if t.size < MIN_SAMPLES:
        raise InputError("time_s", f"only {t.size} samples; at least {MIN_SAMPLES} are needed", source)
    steps = np.diff(t)
    if np.any(steps <= 0):
        i = int(np.flatnonzero(steps <= 0)[0])
        raise InputError("time_s", f"must increase strictly; row {i + 2} ({t[i + 1]}) follows {t[i]}", source)
    return t, f
