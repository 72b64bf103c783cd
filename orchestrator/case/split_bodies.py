"""Every body mesh split across two ranks: the decomposition v1912's overset needs with several bodies.

v1912's cellVolumeWeight stencil maps every pair of overset zones with a meshToMesh
(cellVolumeWeightCellCellStencil::update). When all the cells of a pair sit on one rank,
meshToMesh::calcDistribution sends every rank down the serial branch, and only the rank holding
the cells searches; its first point search (cellVolumeWeightMethod::findInitialSeeds ->
cellTree().findInside) builds the target mesh's tet base points, whose face synchronisation
(polyMeshTetDecomposition::findFaceBasePts -> syncTools -> PstreamBuffers::finishedSends) is a
collective MPI_Alltoall. The other ranks are already in the next pair's collective (the gather
in calcDistribution), so both wait for ever. It happens when two body meshes are on one rank and
their bounding boxes overlap (meshToMeshMethod::maskCells is then not empty). A pair spread over
two or more ranks takes the distributed branch on every rank, which builds the tet base points on
all of them. So with two or more bodies on several ranks:

1. `decomposePar -cellDist -dry-run` with the planned hierarchical dictionary (each body whole
   on one rank, preserveFaceZones) writes the split as 0/cellDist, and no processor directories;
2. :func:`split` moves the second half (in cell order) of each body mesh that sits on one rank to
   the next rank and writes constant/cellDecomposition and a `manual` dictionary beside the
   planned one; the case runs it as a step of its own, `debrisfoam split-bodies . --ranks N` in
   the case folder (:func:`orchestrator.case.foam.decompose_steps`), logged to log.splitBodies like
   the OpenFOAM steps around it;
3. `decomposePar -force` with that dictionary.

Cells never change rank while the bodies move, so every pair stays spread. docs/stability.md
("Several body meshes on one rank") has the evidence.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from orchestrator.core.errors import InputError
from orchestrator.core.files import write_text_atomic

__all__ = ["DICT", "TABLE", "needed", "split"]

DICT = "system/decomposeParDict.bodies"  # the manual dictionary, relative to the case
TABLE = "constant/cellDecomposition"


def needed(n_bodies: int, ranks: int) -> bool:
    """True when a zone pair could sit on one rank: two or more body meshes on two or more ranks."""
    return n_bodies >= 2 and ranks >= 2


def _internal(path: Path) -> np.ndarray:
    """A volScalarField's cell values as integers (zoneID, cellDist)."""
    from foamlib import FoamFieldFile

    return np.rint(np.asarray(FoamFieldFile(path).internal_field, dtype=float)).astype(np.int64)


def split(case: str | Path, ranks: int) -> dict[int, list[int]]:
    """From 0/cellDist (`decomposePar -cellDist -dry-run`), write constant/cellDecomposition with
    every overset zone but the background (zoneID 0) on at least two ranks, and the manual
    dictionary `DICT`; return each body zone's cell count per rank."""
    case = Path(case)
    proc = _internal(case / "0" / "cellDist")
    zone = _internal(case / "0" / "zoneID")
    if proc.shape != zone.shape:
        raise InputError("0/zoneID", f"{zone.size} cells, but decomposePar's 0/cellDist has {proc.size}: the "
                                     "mesh is not the one the case was rendered for", str(case))
    counts = {}
    for z in range(1, int(zone.max()) + 1):
        cells = np.flatnonzero(zone == z)
        if cells.size >= 2 and np.unique(proc[cells]).size == 1:
            proc[cells[cells.size // 2:]] = (proc[cells[0]] + 1) % ranks
        counts[z] = np.bincount(proc[cells], minlength=ranks).tolist()
    body = "\n".join(str(int(p)) for p in proc)
    write_text_atomic(case / TABLE,
        'FoamFile\n{\n    version 2.0;\n    format ascii;\n    class labelList;\n    location "constant";\n'
        f"    object cellDecomposition;\n}}\n\n{proc.size}\n(\n{body}\n)\n")
    (case / "0" / "cellDist").unlink()  # a picture of the split, not a field to run
    # the dictionary last, atomically: it marks the planned split as done (foam.solve_steps)
    write_text_atomic(case / DICT,
        "FoamFile\n{\n    version 2.0;\n    format ascii;\n    class dictionary;\n    location \"system\";\n"
        "    object decomposeParDict;\n}\n\n"
        "// written by debrisfoam (orchestrator/case/split_bodies.py): the planned hierarchical split\n"
        "// with every body mesh spread over two ranks (docs/openfoam-notes.md, \"Decomposition\")\n"
        f"numberOfSubdomains {ranks};\n\nmethod          manual;\n\n"
        f"coeffs\n{{\n    dataFile        \"cellDecomposition\";\n}}\n")
    return counts

