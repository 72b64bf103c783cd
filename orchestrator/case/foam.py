"""What a case's OpenFOAM v1912 steps are: the applications, in order, and when each is done.

A `Step` is one application run in the case directory: its argv (relative to the case),
its rank count, one line for README.md and progress messages, and a done-predicate that
says whether its outputs already exist, so that runs are idempotent and resumable.

`mesh_steps` lists the steps from a rendered case to a mesh ready for the solver
(blockMesh of the background and of every body sub-case, mergeMeshes, topoSet,
setFields, checkMesh), `solve_steps` those from the mesh to the solver's results
(decomposePar, the solver, reconstructPar); `render` writes both into the case's
README.md, with `ENV_EXPORTS`, and the runner runs them (`orchestrator.run.openfoam`).

`constant/polyMesh/boundary` is read for the done-predicates (foamlib, through
`orchestrator.case.dictionary`).
"""

from __future__ import annotations

import re
import shlex
import sys
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Sequence

from orchestrator.case import split_bodies
from orchestrator.case.dictionary import edit_dictionary, read_dictionary
from orchestrator.case.folder import BED_LAYER_ZONE, BODIES_DIR

#: OpenFOAM v1912 from Debian: binaries in /usr/bin, project files here.
WM_PROJECT_DIR = "/usr/share/openfoam"
#: What a user exports by hand before running a case (rendered into README.md).
ENV_EXPORTS = (
    f"export WM_PROJECT_DIR={WM_PROJECT_DIR}",
    "export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1  # mpirun as root only",
)
#: checkMesh's verdict on a mesh it passed, a line of log.checkMesh.
MESH_OK = re.compile(r"^\s*Mesh OK\.", re.M)


def parallel_argv(argv: Sequence[str], np: int) -> list[str]:
    """argv for `np` ranks: `mpirun -np N <app> ... -parallel` (unchanged for np == 1)."""
    argv = list(argv)
    if np <= 1:
        return argv
    return ["mpirun", "-np", str(np), *argv, "-parallel"]


# --------------------------------------------------------------------------- steps


#: the `debrisfoam` command of this Python, for the steps that are debrisfoam's own
DEBRISFOAM = (sys.executable, "-m", "orchestrator.cli")


@dataclass(frozen=True)
class Step:
    """One application to run in the case directory.

    `argv` is relative to the case (cwd); `done(case_dir)` says whether its outputs
    already exist; `what` is one line for README.md and progress messages.
    """

    name: str
    argv: tuple[str, ...]
    what: str
    np: int = 1
    done: Callable[[Path], bool] | None = field(default=None, compare=False)

    def shell(self) -> str:
        """The command as a user types it in the case directory."""
        return shlex.join(parallel_argv(self.argv, self.np))


def patch_names(case_dir: Path) -> list[str]:
    """Patch names of `case_dir/constant/polyMesh/boundary` ([] when there is no mesh)."""
    boundary = Path(case_dir) / "constant" / "polyMesh" / "boundary"
    if not boundary.is_file():
        return []
    return [str(name) for name, _ in read_dictionary(boundary)[None]]


def _has_mesh(sub: str = "") -> Callable[[Path], bool]:
    def done(case: Path) -> bool:
        return (case / sub / "constant" / "polyMesh" / "owner").is_file()
    return done


def _has_patch(patch: str) -> Callable[[Path], bool]:
    def done(case: Path) -> bool:
        return patch in patch_names(case)
    return done


def _has_cell_sets(names: Sequence[str]) -> Callable[[Path], bool]:
    def done(case: Path) -> bool:
        return all((case / "constant" / "polyMesh" / "sets" / n).is_file() for n in names)
    return done


def _fields_set(case: Path) -> bool:
    alpha = case / "0" / "alpha.water"
    return alpha.is_file() and "nonuniform" in alpha.read_text(errors="replace")[:4000]


def _mesh_checked(case: Path) -> bool:
    log, owner = case / "log.checkMesh", case / "constant" / "polyMesh" / "owner"
    if not (log.is_file() and owner.is_file()) or log.stat().st_mtime < owner.stat().st_mtime:
        return False
    return MESH_OK.search(log.read_text(errors="replace")) is not None


def mesh_steps(case_dir: str | Path, plan) -> list[Step]:
    """The ordered steps from a rendered case to a mesh ready for the solver.

    Background blockMesh; for overset plans, blockMesh of each body sub-case
    (`bodies/<name>`), `mergeMeshes . bodies/<name> -overwrite` per body (v1912
    takes the master and the added case as arguments; there is no dictionary),
    topoSet (a cellSet per body, a faceZone of each body's faces that decomposePar
    keeps on one rank, and the bed layer's cell zone when the bed has friction);
    then setFields (alpha.water, zoneID) and checkMesh.
    """

    steps = [Step("blockMesh", ("blockMesh",), "background mesh (the column is a hole)", done=_has_mesh())]
    bodies = [b.name for b in plan.bodies]
    for name in bodies:
        sub = f"{BODIES_DIR}/{name}"
        steps.append(Step(f"blockMesh.{name}", ("blockMesh", "-case", sub),
                          f"mesh of body {name} (the body is a hole)", done=_has_mesh(sub)))
    for name in bodies:
        steps.append(Step(f"mergeMeshes.{name}", ("mergeMeshes", ".", f"{BODIES_DIR}/{name}", "-overwrite"),
                          f"add body {name}'s mesh to the background", done=_has_patch(f"{name}Overset")))
    friction = float(plan.bed_friction_per_m) > 0
    gate = [band.name for band in plan.gate_bands]
    sets = list(bodies) + [f"{name}_faces" for name in bodies] + ([BED_LAYER_ZONE] if friction else []) + gate
    if sets:
        what = ["one cellSet and one faceZone (for decomposePar) per body mesh"] if bodies else []
        what += ["the bed layer for friction"] if friction else []
        what += ["the gate's bands"] if gate else []
        steps.append(Step("topoSet", ("topoSet",), " and ".join(what), done=_has_cell_sets(sets)))
    steps.append(Step("setFields", ("setFields",),
                      "water (alpha.water)" + (" and overset zones (zoneID)" if bodies else ""), done=_fields_set))
    steps.append(Step("checkMesh", ("checkMesh",), "mesh quality verdict", done=_mesh_checked))
    return steps


def solve_steps(case_dir: str | Path, plan, np: int | None = None) -> list[Step]:
    """:func:`decompose_steps`, the solver on `np` ranks, reconstructPar.

    `np` defaults to the plan's decomposition. The runner decides itself when the solver is
    finished.
    """
    steps = decompose_steps(case_dir, plan, np)
    ranks = _ranks(plan, np)
    steps.append(Step(plan.solver, (plan.solver,), f"the solver on {ranks} core(s)", np=ranks))
    if ranks > 1:
        steps.append(Step("reconstructPar", ("reconstructPar",), "gather the time directories"))
    return steps


def _ranks(plan, np: int | None) -> int:
    n = plan.decomposition
    return np or int(n[0]) * int(n[1]) * int(n[2])


def decompose_steps(case_dir: str | Path, plan, np: int | None = None) -> list[Step]:
    """The case split into `np` subdomains (none on one rank): decomposePar (hierarchical), or,
    with two or more body meshes, the split of :mod:`orchestrator.case.split_bodies` in three
    steps. Done-predicates: processor0 exists (decomposePar), the manual dictionary exists (the
    two before it)."""
    ranks = _ranks(plan, np)
    steps = []
    if ranks > 1 and split_bodies.needed(len(plan.bodies), ranks):
        # v1912's overset hangs when two body meshes share a rank (orchestrator/case/split_bodies.py)
        table = split_bodies.TABLE
        steps.append(Step("decomposePar.cellDist", ("decomposePar", "-cellDist", "-dry-run"),
                          f"the planned split into {ranks} subdomains, written to 0/cellDist only",
                          done=lambda case: (Path(case) / split_bodies.DICT).is_file()))
        steps.append(Step("splitBodies", (*DEBRISFOAM, "split-bodies", ".", "--ranks", str(ranks)),
                          f"move half of each body mesh that sits whole on one rank to the next: {table} and "
                          f"{split_bodies.DICT}",
                          done=lambda case: (Path(case) / split_bodies.DICT).is_file()))
        steps.append(Step("decomposePar", ("decomposePar", "-force", "-decomposeParDict", split_bodies.DICT),
                          f"split the case into {ranks} subdomains, every body mesh across two ranks",
                          done=lambda case: (Path(case) / "processor0").is_dir()))
    elif ranks > 1:
        steps.append(Step("decomposePar", ("decomposePar",), f"split the case into {ranks} subdomains",
                          done=lambda case: (Path(case) / "processor0").is_dir()))
    return steps


def set_subdomains(case_dir: str | Path, ranks: int) -> int | None:
    """system/decomposeParDict for `ranks` subdomains, split along x (hierarchical `ranks` 1 1);
    returns the planned count it replaced, or None when the dictionary already had `ranks`."""
    with edit_dictionary(Path(case_dir) / "system" / "decomposeParDict") as parsed:
        planned = parsed["numberOfSubdomains"]
        if int(planned) == ranks:
            return None
        parsed["numberOfSubdomains"] = ranks
        parsed["coeffs" if "coeffs" in parsed else "hierarchicalCoeffs"]["n"] = [ranks, 1, 1]
    return int(planned)
