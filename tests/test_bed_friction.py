"""Bed friction: a container sliding on the bed decelerates under Coulomb friction.

The scene (tests/data/scenes/bed-friction.yaml) stands the study's container on the 7.5 mm gap
over a 15 mm wet bed, far from the dam break, and gives it 0.6 m/s along the flume. The water is
shallower than its draft, so the runner keeps it on the bed and gives it the friction of
orchestrator.run.bedwatch: a sixDoF linearDamper sized at every restart to mu N at the speed then,
N its weight less the buoyancy of the 7.5 mm of it under water. Run once with the scene's
bed_friction_coefficient 0.3 and once with 0: the difference of the two decelerations is the
friction's, mu g (1 - buoyancy fraction) = 2.10 m/s2; the water's own drag on the body is in both.
"""

from __future__ import annotations


import numpy as np
import pandas as pd
import pytest

from conftest import ROOT, render_and_run
from orchestrator.run.bedwatch import FRICTION_BAND

SCENE = ROOT / "tests" / "data" / "scenes" / "bed-friction.yaml"
RHO, G = 998.2, 9.81


def _slide(tmp_path, mu: float) -> tuple[pd.DataFrame, dict, pd.DataFrame]:
    case = tmp_path / f"mu{mu:g}"
    plan = render_and_run(SCENE, case, f"debris.0.contact.bed_friction_coefficient={mu}")
    track = pd.read_csv(case / "bodies.csv").drop_duplicates("time_s", keep="last").sort_values("time_s")
    return track, plan, pd.read_csv(case / "body_depth.csv")


def _deceleration(track: pd.DataFrame) -> float:
    """The mean deceleration (m/s2) while the body still slides faster than 0.1 m/s."""
    moving = track[(track["u_m_s"] > 0.1) & (track["time_s"] > 0.0)]
    slope = np.polyfit(moving["time_s"], moving["u_m_s"], 1)[0]
    return -float(slope)


@pytest.mark.openfoam
@pytest.mark.slow
def test_a_container_sliding_on_the_bed_decelerates_at_mu_g_less_its_buoyancy(openfoam, tmp_path):
    with_friction, plan, depth = _slide(tmp_path, 0.3)
    frictionless, _, _ = _slide(tmp_path, 0.0)
    body = plan["bodies"][0]
    (length, width, _), mass = body["size_m"], body["mass_kg"]
    # it stays held on the gap (the water is too shallow to float it): the immersed depth is the wet
    # bed's above the gap's top, as the runner measured it
    assert np.ptp(with_friction["z_m"]) < 1e-9
    measured = depth.dropna(subset=["depth_m"])["depth_m"].median()
    assert measured == pytest.approx(0.015, abs=0.002)
    immersed = measured - plan["bed_gap_m"]
    buoyant = RHO * length * width * immersed / mass
    expected = 0.3 * G * (1 - buoyant)  # 2.10 m/s2
    friction = _deceleration(with_friction) - _deceleration(frictionless)
    # the damper is resized whenever the speed leaves a band of FRICTION_BAND around the speed it
    # was sized for, so its force is mu N within that band: +-25 % at worst, about +-10 % on average
    assert friction == pytest.approx(expected, rel=FRICTION_BAND - 1)
    # without friction the water's drag alone barely slows it
    assert _deceleration(frictionless) < 0.25 * expected
    # the friction acts at its centre: 0.1 m off the axis, a force at the origin (v1912's
    # linearDamper) would have turned it by some 40 degrees by the end (about -0.05 N m on its
    # 6.6e-4 kg m2); here it keeps its heading
    turned = np.degrees(np.arctan2(with_friction["q_yx"], with_friction["q_xx"]))
    assert np.abs(turned).max() < 1.0
    assert np.abs(with_friction["omega_z_rad_s"]).max() < 0.5
