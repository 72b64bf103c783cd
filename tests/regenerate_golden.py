"""Regenerate the golden files of rendered dictionaries: `python tests/regenerate_golden.py`.

The golden cases are rendered from small hand-made plans (below) rather than from
the planner, so that they change only when a template or the render context
changes. Review the diff (`git diff tests/golden`) before committing it.

The plans are real `orchestrator.plan.planner.ModelPlan`s, built by hand.
"""

from __future__ import annotations

import math
import shutil
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from orchestrator.plan.grid import BoxGrid, Segment  # noqa: E402
from orchestrator.plan.case_numbers import case_numbers  # noqa: E402
from orchestrator.plan.model import BodyPlan, GaugePlan, ModelPlan, WaterBox  # noqa: E402

GOLDEN_DIR = Path(__file__).resolve().parent / "golden"


def _seg(a: float, b: float, h: float) -> Segment:
    return Segment(a, b, max(1, round((b - a) / h)))


def _yaw(deg: float) -> tuple[tuple[float, ...], ...]:
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    return ((c, -s, 0.0), (s, c, 0.0), (0.0, 0.0, 1.0))


def body(name: str, centre, size=(0.15, 0.06, 0.06), mass_kg=0.236, yaw_deg=0.0, h=0.01, margin=0.03) -> BodyPlan:
    """A box body on its own mesh: the body is the hole, `margin` of fluid around it."""
    half = np.asarray(size) / 2

    def axis(i: int):
        return (_seg(-half[i] - margin, -half[i], h), _seg(-half[i], half[i], h), _seg(half[i], half[i] + margin, h))

    rot = _yaw(yaw_deg)
    grid = BoxGrid(name, axis(0), axis(1), axis(2), holes=frozenset({(1, 1, 1)}),
                   patch_names={**{s: f"{name}Overset" for s in ("xmin", "xmax", "ymin", "ymax", "zmin", "zmax")},
                                "hole": name},
                   origin=tuple(centre), rotation=rot)
    lx, ly, lz = size
    inertia = tuple(mass_kg * v / 12 for v in (ly**2 + lz**2, lx**2 + lz**2, lx**2 + ly**2))
    return BodyPlan(name, grid, mass_kg, tuple(centre), inertia, rot, tuple(size), cell_size_m=h)


def flume_plan(n_bodies: int = 0, h: float = 0.04, two_d: bool = False, end_time_s: float = 0.02,
               decomposition=(2, 1, 1), friction: float = 0.0293, friction_calibration: float = 1.0) -> ModelPlan:
    """A 2.4 m flume segment (gate at x = 0), 0.6 m wide, with a 0.18 m column at x = 1.2 m.

    Reservoir 0.3 m deep upstream of the gate, a 0.06 m wet bed downstream (deep
    enough to float the bodies), gauges upstream, mid-way and at the column face.
    `n_bodies` box bodies (0.15 x 0.06 x 0.06 m, 0.236 kg) upstream of the column,
    the second one yawed 20 degrees. `friction`: the bed's Darcy friction factor.
    """
    patches = {"xmin": "upstreamWall", "xmax": "downstream", "zmin": "bed", "zmax": "atmosphere", "hole": "column"}
    if two_d:
        bg = BoxGrid("background", x=(_seg(-0.6, 1.8, h),), y=(Segment(-0.3, 0.3, 1),), z=(_seg(0.0, 0.45, h),),
                     patch_names={**patches, "ymin": "frontAndBack", "ymax": "frontAndBack"})
    else:
        bg = BoxGrid("background",
                     x=(_seg(-0.6, 1.2, h), _seg(1.2, 1.38, h), _seg(1.38, 1.8, h)),
                     y=(_seg(-0.3, -0.09, h), _seg(-0.09, 0.09, h), _seg(0.09, 0.3, h)),
                     z=(_seg(0.0, 0.45, h),),
                     holes=frozenset({(1, 1, 0)}),
                     patch_names={**patches, "ymin": "sideWalls", "ymax": "sideWalls"})
    centres = [(0.5, 0.0, 0.1), (0.5, 0.16, 0.1)]
    bodies = tuple(body(f"debris{i + 1}", centres[i], yaw_deg=20.0 * i) for i in range(n_bodies))
    water = (WaterBox("reservoir", (-0.6, -0.3, 0.0), (0.0, 0.3, 0.3)),
             WaterBox("wetBed", (0.0, -0.3, 0.0), (1.8, 0.3, 0.06)))
    gauges = (GaugePlan("WG1", -0.1, 0.0, 0.45), GaugePlan("WG2", 0.6, 0.2, 0.45), GaugePlan("WG4", 1.17, 0.0, 0.45))
    cells = bg.cell_count() + sum(b.grid.cell_count() for b in bodies)
    # the numbers the dictionaries need, as the planner decides them (scene defaults: g = 9.81, no maxDeltaT)
    numbers = case_numbers(bg, water, gauges, two_d=two_d, max_courant=0.8, write_interval_s=0.01, max_delta_t=None,
                           gravity_m_s2=9.81, bed_friction_factor=friction,
                           bed_friction_calibration=friction_calibration)
    return ModelPlan(
        scene_name="fixture",
        solver="overInterDyMFoam" if n_bodies else "interFoam",
        two_d=two_d, background=bg, bodies=bodies, water=water, gauges=gauges, cell_count=cells,
        decomposition=tuple(decomposition), end_time_s=end_time_s, write_interval_s=0.01, max_courant=0.8,
        domain_m=((-0.6, 1.8), (-0.3, 0.3), (0.0, 0.45)), fine_region_m=((-0.6, 1.8), (-0.3, 0.3), (0.0, 0.45)),
        downstream_type="wall", bed_friction_factor=friction, bed_friction_calibration=friction_calibration,
        velocity_scale_m_s=3.4,
        time_step_estimate_s=0.8 * h / 3.4, reasons={"fixture": "a short flume segment for tests"}, **numbers,
    )


#: name -> plan of each golden case
GOLDEN_PLANS = {
    "interfoam-3d": lambda: flume_plan(0),
    "interfoam-2d-frictionless": lambda: flume_plan(0, two_d=True, friction=0.0),
    "overset-2bodies": lambda: flume_plan(2, decomposition=(1, 2, 1)),
}


def golden_files(name: str) -> dict[str, str]:
    """The rendered OpenFOAM files of golden case `name` (path -> text)."""
    from orchestrator.case.render import build_context, render_files

    return render_files(build_context(None, GOLDEN_PLANS[name]()))


def main() -> None:
    for name in GOLDEN_PLANS:
        target = GOLDEN_DIR / name
        if target.exists():
            shutil.rmtree(target)
        for rel, text in golden_files(name).items():
            path = target / rel
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_text(text)
        print(f"wrote {target}")


if __name__ == "__main__":
    main()
