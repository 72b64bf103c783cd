"""Where an overset run loses (or makes) water: the flux into each mesh's fringe.

v1912's overInterDyMFoam overwrites every fringe (interpolated, ``cellTypes`` 1) cell with
values interpolated from the other mesh, and its pressure equation has no continuity row
there. Faces between a calculated cell (0) and a fringe cell keep their flux (the solver's
``faceMask`` zeroes only the faces of holes, 2), so the alpha flux that enters a fringe cell
is lost to the mesh and what leaves one is created. The water balance of the background
(:func:`orchestrator.case.outputs.read_water_balance`) changes at exactly the background's net
inflow into its fringe, apart from the water held in its fringe and hole cells changing
(small once the bodies stop). docs/openfoam-notes.md ("Water balance: where the overset loses
water") has the measurement that
tied the two together on `make case-1debris`.

:func:`fringe_flux` reads one written (reconstructed) time: ``cellTypes``, ``zoneID``,
``phi`` and ``alphaPhi0.water`` with the mesh's ``owner``/``neighbour`` (foamlib parses
them) and returns, per overset zone (0: the background), the cell counts and the net water
and volume flux from calculated cells into fringe cells. :func:`fringe_table` does every
reconstructed time of a case.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from orchestrator.case.folder import time_names
from orchestrator.core.errors import InputError

__all__ = ["FringeFlux", "fringe_flux", "fringe_table", "FIELDS"]

#: the written fields the fringe flux needs (besides the mesh)
FIELDS = ("cellTypes", "zoneID", "phi", "alphaPhi0.water")

CALCULATED, FRINGE, HOLE = 0, 1, 2


@dataclass(frozen=True)
class FringeFlux:
    """One overset zone at one written time (fluxes m3/s, > 0 into the fringe)."""

    time_s: float
    zone: int
    calculated: int
    fringe: int
    holes: int
    water_into_fringe_m3_s: float
    volume_into_fringe_m3_s: float
    fringe_faces: int


def _internal(path: Path) -> np.ndarray:
    from foamlib import FoamFieldFile

    return np.asarray(FoamFieldFile(path).internal_field)


def _mesh_faces(case: Path) -> tuple[np.ndarray, np.ndarray]:
    """owner and neighbour of the internal faces (the bodies' motion moves points only, so
    the topology is constant/'s)."""
    from foamlib import FoamFile

    mesh = case / "constant" / "polyMesh"
    neighbour = np.asarray(FoamFile(mesh / "neighbour")[None], dtype=np.int64)
    owner = np.asarray(FoamFile(mesh / "owner")[None], dtype=np.int64)
    return owner[: len(neighbour)], neighbour


def has_fringe_fields(time_dir: str | Path) -> bool:
    """Whether a written time holds every field :func:`fringe_flux` reads."""
    return all((Path(time_dir) / name).is_file() for name in FIELDS)


def fringe_flux(case_dir: str | Path, time_name: str,
                faces: tuple[np.ndarray, np.ndarray] | None = None) -> list[FringeFlux]:
    """The net flux from calculated cells into fringe cells, per zone, at one written time.

    Only faces with both cells in the same zone count (the meshes of an overset case are
    merged but share no faces). faces: the mesh's (owner, neighbour) when already read.
    Raises InputError when a field is missing (a time written only in processor folders:
    reconstruct it first) or the fields do not match the mesh.
    """
    case = Path(case_dir)
    folder = case / time_name
    missing = [name for name in FIELDS if not (folder / name).is_file()]
    if missing:
        raise InputError(", ".join(missing), "missing (overset fields of a reconstructed time)", str(folder))
    types = np.rint(_internal(folder / "cellTypes")).astype(int)
    zones = np.rint(_internal(folder / "zoneID")).astype(int)
    phi = _internal(folder / "phi")
    water = _internal(folder / "alphaPhi0.water")
    owner, neighbour = faces if faces is not None else _mesh_faces(case)
    if not (len(phi) == len(water) == len(neighbour)) or len(types) != len(zones):
        raise InputError("phi", f"fields do not match the mesh ({len(phi)} face fluxes, "
                         f"{len(neighbour)} internal faces, {len(types)} cell types, {len(zones)} zone ids)",
                         str(folder))
    same_zone = zones[owner] == zones[neighbour]
    # a face's flux is positive from owner to neighbour: into the fringe when the owner is
    # calculated and the neighbour a fringe cell, out of it the other way round
    into = same_zone & (types[owner] == CALCULATED) & (types[neighbour] == FRINGE)
    out = same_zone & (types[neighbour] == CALCULATED) & (types[owner] == FRINGE)
    sign = into.astype(float) - out.astype(float)
    face_zone = zones[owner]
    rows = []
    for zone in np.unique(zones):
        in_zone = zones == zone
        ring = (into | out) & (face_zone == zone)
        rows.append(FringeFlux(
            time_s=float(time_name), zone=int(zone),
            calculated=int(np.sum(in_zone & (types == CALCULATED))),
            fringe=int(np.sum(in_zone & (types == FRINGE))),
            holes=int(np.sum(in_zone & (types == HOLE))),
            water_into_fringe_m3_s=float(np.sum(sign[ring] * water[ring])),
            volume_into_fringe_m3_s=float(np.sum(sign[ring] * phi[ring])),
            fringe_faces=int(np.sum(ring))))
    return rows


def fringe_table(case_dir: str | Path) -> pd.DataFrame | None:
    """:func:`fringe_flux` at every reconstructed time of a case that has the overset fields
    (None when there is none: not overset, or nothing reconstructed)."""

    case = Path(case_dir)
    names = [name for _, name in time_names(case) if has_fringe_fields(case / name)]
    if not names:
        return None
    faces = _mesh_faces(case)
    return pd.DataFrame([asdict(row) for name in names for row in fringe_flux(case, name, faces)])
