"""Reading a case for post-processing: its records, gauge samples, body tracks and impact pulses.

:func:`load_case` gathers what the tool wrote beside the OpenFOAM case (plan.json,
scene.yaml, run.json) into a :class:`CaseData`; every part is optional, so a run stopped
early or rendered by hand is still read as far as it goes. The readers below turn the raw
outputs into arrays and frames: the ``sets`` samples of the gauges, the bodies' six-DoF
reports in the solver logs, the contact events' force histories. The contact events themselves
are read by :mod:`orchestrator.contact.events`, the function objects' forces and water balance
by :mod:`orchestrator.case.outputs`.

Restarts: function objects start a new ``postProcessing/<name>/<start time>/`` folder at
every restart; the pieces are joined in time order and a later piece replaces anything an
earlier one wrote after its start. The solver logs (``log.<solver>.<k>``, then
``log.<solver>``) are joined the same way.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Sequence

import numpy as np
import pandas as pd

from orchestrator.core.errors import DebrisfoamError, InputError
from orchestrator.case.bodystate import read_mesh_poses
from orchestrator.case.folder import EPS_T, CaseFolder
from orchestrator.case.outputs import numeric_dirs
from orchestrator.case.run_state import RunState
from orchestrator.plan.model import ModelPlan
from orchestrator.run.monitor import parse_log
from orchestrator.scene.schema import column_for_analysis

__all__ = [
    "BODY_COLUMNS",
    "CaseData",
    "load_case",
    "read_body_tracks",
    "read_force_history",
    "read_gauge_samples",
]


# --------------------------------------------------------------------------- the case


@dataclass
class CaseData:
    """What post-processing knows about a case: its plan, scene, run record and column.

    Every part is optional (None when absent or unreadable; ``notes`` says why).
    ``column`` is the scene's column as an :class:`analytical.column.Column`.
    """

    case: Path
    plan: ModelPlan | None
    scene: Any | None
    run: RunState
    solver: str | None
    column: Any | None
    notes: list[str] = field(default_factory=list)

    @property
    def debris(self) -> tuple:
        """The case's bodies, each with ``name``, ``mass_kg`` and ``size_m``: the plan's
        (:class:`~orchestrator.plan.model.BodyPlan`, bodies in the flow), else the scene's
        (one-way: the bodies are carried through the recorded flow, not in it)."""
        if self.plan and self.plan.bodies:
            return self.plan.bodies
        return tuple(self.scene.debris) if self.scene is not None else ()

    @property
    def body_names(self) -> list[str]:
        try:
            names = [b.name for b in read_mesh_poses(self.case)]
        except Exception:  # an unreadable dictionary: fall back on the plan, else the scene
            names = []
        return names or [b.name for b in self.debris]

    @property
    def body_masses_kg(self) -> dict[str, float]:
        return {b.name: float(b.mass_kg) for b in self.debris}

    @property
    def depth_m(self) -> float | None:
        return float(self.scene.reservoir.depth_m) if self.scene is not None else None

    @property
    def bed_z_m(self) -> float:
        if self.plan:
            return float(self.plan.domain_m[2][0])
        return 0.0

    def column_base_m(self) -> np.ndarray | None:
        """Centre of the column's footprint on the bed (x, y, z), m."""
        if self.scene is None or self.scene.column is None:
            return None
        return np.array([self.scene.column.x_m, self.scene.column.y_m, self.bed_z_m])


def load_case(case_dir: str | Path) -> CaseData:
    """Read plan.json, scene.yaml and run.json of a case (whichever exist).

    Raises InputError naming the directory when it is not a case (no plan.json and no
    system/controlDict).
    """
    case = Path(case_dir)
    if not case.is_dir():
        raise InputError("case_dir", "not a directory", str(case))
    if not CaseFolder(case).is_case():
        raise InputError("case_dir", "not a debrisfoam case: it has neither plan.json nor system/controlDict "
                                     "(render one with `debrisfoam render SCENE -o DIR`)", str(case))
    folder = CaseFolder(case.resolve())
    notes: list[str] = []
    plan = folder.model_plan(notes)
    run = folder.run_state(notes)
    scene = _load_scene(folder, notes)
    solver = run.solver or (plan.solver if plan else None)
    column = column_for_analysis(scene) if scene is not None and scene.column is not None else None
    return CaseData(folder.path, plan, scene, run, solver, column, notes)


def _load_scene(folder: CaseFolder, notes: list[str]):
    """The case's scene.yaml as a Scene, or None (a line in ``notes`` says why)."""
    if not folder.scene_path.is_file():
        notes.append("no scene.yaml: no initial levels from the scene, no analytical comparisons")
        return None
    try:
        return folder.scene()
    except DebrisfoamError as exc:
        notes.append(f"scene.yaml could not be loaded ({exc}): no analytical comparisons")
        return None


# --------------------------------------------------------------------------- outputs


def _read_xy(path: Path) -> tuple[np.ndarray, np.ndarray]:
    """(z, alpha) of a raw `sets` file (axis z: 2 columns; axis xyz: 4)."""
    rows = []
    with open(path, errors="replace") as fh:
        for line in fh:
            s = line.split()
            if not s or s[0].startswith("#"):
                continue
            try:
                rows.append([float(v) for v in s])
            except ValueError:
                continue
    if not rows:
        return np.empty(0), np.empty(0)
    width = max(set(len(r) for r in rows), key=[len(r) for r in rows].count)
    data = np.array([r for r in rows if len(r) == width])
    z_col = 2 if width >= 4 else 0
    return data[:, z_col], data[:, -1]


def read_gauge_samples(case_dir: str | Path, function_object: str = "gauges",
                       field_name: str = "alpha.water") -> dict[str, list[tuple[float, np.ndarray, np.ndarray]]]:
    """Every gauge's samples: name -> [(time_s, z_m, alpha), ...] in time order.

    From ``postProcessing/<function_object>/<time>/<gauge>_<field>.xy``; a time written
    twice (a restart) keeps the last folder read.
    """
    base = Path(case_dir) / "postProcessing" / function_object
    suffix = f"_{field_name}.xy"
    out: dict[str, dict[float, tuple[np.ndarray, np.ndarray]]] = {}
    for t, folder in numeric_dirs(base):
        for path in sorted(folder.glob(f"*{suffix}")):
            name = path.name[: -len(suffix)]
            out.setdefault(name, {})[t] = _read_xy(path)
    return {name: [(t, *v) for t, v in sorted(samples.items())] for name, samples in out.items()}


def _solver_logs(case: Path, solver: str) -> list[Path]:
    """log.<solver>.1, .2, ... (older segments) then log.<solver> (the latest)."""
    numbered = []
    for p in case.glob(f"log.{solver}.*"):
        suffix = p.name[len(f"log.{solver}."):]
        if suffix.isdigit():
            numbered.append((int(suffix), p))
    logs = [p for _, p in sorted(numbered)]
    if (case / f"log.{solver}").is_file():
        logs.append(case / f"log.{solver}")
    return logs


def _angles_deg(q: np.ndarray) -> tuple[float, float, float]:
    """(yaw, pitch, roll) of R = Rz(yaw) Ry(pitch) Rx(roll), degrees."""
    pitch = math.asin(max(-1.0, min(1.0, -q[2, 0])))
    yaw = math.atan2(q[1, 0], q[0, 0])
    roll = math.atan2(q[2, 1], q[2, 2])
    return math.degrees(yaw), math.degrees(pitch), math.degrees(roll)


#: Columns of bodies.csv, in order.
BODY_COLUMNS = ["time_s", "body", "x_m", "y_m", "z_m", "u_m_s", "v_m_s", "w_m_s", "speed_m_s",
                "omega_x_rad_s", "omega_y_rad_s", "omega_z_rad_s", "yaw_deg", "pitch_deg", "roll_deg"] + [
                   f"q_{a}{b}" for a in "xyz" for b in "xyz"]


def _body_row(time_s: float, name: str, centre, velocity, omega, orientation) -> list:
    q = np.asarray(orientation, dtype=float).reshape(3, 3)
    v = [float(x) for x in velocity]
    return [float(time_s), name, *map(float, centre), *v, math.sqrt(sum(x * x for x in v)),
            *map(float, omega), *_angles_deg(q), *map(float, q.ravel())]


def read_body_tracks(case_dir: str | Path, solver: str, names: Sequence[str]) -> pd.DataFrame:
    """bodies.csv rows from the solver logs' per-step six-DoF reports (see the module notes).

    Falls back on the runner's own ``bodies.csv`` in the case when no log reports a body.
    """
    case = Path(case_dir)
    pieces = _tracks_from_logs(case, solver, names) if names else []
    if pieces:
        return _join_restarts(pieces)
    if (case / "bodies.csv").is_file():
        return _tracks_from_runner(case / "bodies.csv")
    return pd.DataFrame(columns=BODY_COLUMNS)


def _tracks_from_logs(case: Path, solver: str, names: Sequence[str]) -> list[tuple[float, pd.DataFrame]]:
    """(start time, rows) of every solver log that reports a body, oldest first."""
    pieces = []
    for log in _solver_logs(case, solver):
        steps, _ = parse_log(log, names)
        rows = [_body_row(s.time_s, b.name, b.centre_of_mass_m, b.velocity_m_s, b.angular_velocity_rad_s,
                          b.orientation) for s in steps for b in s.bodies]
        if rows:
            start = steps[0].time_s - (steps[0].delta_t_s or 0.0)
            pieces.append((start, pd.DataFrame(rows, columns=BODY_COLUMNS)))
    return pieces


def _join_restarts(pieces: list[tuple[float, pd.DataFrame]]) -> pd.DataFrame:
    """The logs' rows joined by time, body by body (rows of one step share a time): a later
    log replaces what an earlier one wrote after its start."""
    joined = None
    for start, frame in pieces:
        if joined is not None:
            joined = joined[joined["time_s"] <= start + EPS_T * max(1.0, abs(start))]
            joined = pd.concat([joined, frame], ignore_index=True)
        else:
            joined = frame
    joined = joined.drop_duplicates(subset=["time_s", "body"], keep="last")
    return joined.sort_values(["body", "time_s"], kind="stable").reset_index(drop=True)


def _tracks_from_runner(track: Path) -> pd.DataFrame:
    """The runner's bodies.csv, with the derived columns (speed, angles) recomputed."""
    rows = []
    for r in pd.read_csv(track).itertuples(index=False):
        d = r._asdict()
        q = [d[f"q_{a}{b}"] for a in "xyz" for b in "xyz"]
        rows.append(_body_row(d["time_s"], d["body"], (d["x_m"], d["y_m"], d["z_m"]),
                              (d["u_m_s"], d["v_m_s"], d["w_m_s"]),
                              (d["omega_x_rad_s"], d["omega_y_rad_s"], d["omega_z_rad_s"]), q))
    frame = pd.DataFrame(rows, columns=BODY_COLUMNS)
    return frame.sort_values(["body", "time_s"], kind="stable").reset_index(drop=True)


def read_force_history(path: Path) -> tuple[np.ndarray, np.ndarray] | None:
    """(time_s, force_N) of a contact event's force history CSV; None when missing or too short."""
    if not path.is_file():
        return None
    frame = pd.read_csv(path)
    if "time_s" not in frame or "force_N" not in frame or len(frame) < 2:
        return None
    return frame["time_s"].to_numpy(float), frame["force_N"].to_numpy(float)

