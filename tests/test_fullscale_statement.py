"""Full-scale values a scene must state (issue 48, item 1 and its first "done when"): no full-scale
source gives a container's contact law or k_d, and Froude similarity does not scale elasticity,
so the catalogue's full-size containers carry neither; a full-scale scene states them, else every
verb exits 2 naming the scene file and the field before anything runs. The design page names
where each full-scale input comes from, and prints no probability of exceeding the code's values
while no published full-scale test checks the scene's law."""

from __future__ import annotations

import json
from types import SimpleNamespace

import numpy as np
import pandas as pd
import pytest
import yaml

from analytical.fullscale_check import calibration_possible
from orchestrator.cli import main
from orchestrator.results.asce_design import SiteFlow
from orchestrator.scene.scenefile import load_scene
from orchestrator.studies import design_report
from orchestrator.studies.design import DESIGN_COLUMNS, DesignCase, DesignResult
from orchestrator.studies.design_report import NO_EXCEEDANCE, write_report
from tests.conftest import ROOT

STREET = ROOT / "cases" / "design-street.yaml"
PROTOTYPE = ROOT / "cases" / "prototype-1debris.yaml"
WALL = {"wall_time_s": 1.0, "flow_phase_wall_s": 0.0, "workers": 1, "executor": "local", "batch_size": 32}


def _edited(tmp_path, source, edit) -> object:
    """``source`` copied to ``tmp_path`` with ``edit`` applied to its YAML data."""
    data = yaml.safe_load(source.read_text())
    edit(data)
    path = tmp_path / source.name
    path.write_text(yaml.safe_dump(data, sort_keys=False))
    return path


def _verbs(path, out):
    return (["validate", str(path)],
            ["analytical", "asce7", "--scene", str(path), "--velocity", "4"],
            ["analytical", "impact", "--scene", str(path), "--velocity", "4"],
            ["design", str(path), "-o", str(out)])


@pytest.mark.parametrize("source, edit, field", [
    (STREET, lambda d: d["debris"][0].pop("contact"), "debris.0.contact.stiffness_N_m"),
    (STREET, lambda d: d["debris"][0]["contact"].pop("damping_ratio"), "debris.0.contact.damping_ratio"),
    (PROTOTYPE, lambda d: d["debris"][0]["contact"].pop("damping_ratio"), "debris.0.contact.damping_ratio"),
    (STREET, lambda d: d["design"].pop("debris_stiffness_N_m"), "design.debris_stiffness_N_m"),
], ids=["street-no-law", "street-no-damping", "prototype-no-damping", "street-no-kd"])
def test_a_full_scale_scene_that_leaves_out_a_value_no_source_gives_is_exit_2_in_every_verb(
        tmp_path, capfd, source, edit, field):
    path = _edited(tmp_path, source, edit)
    out = tmp_path / "study"
    verbs = _verbs(path, out)
    if field.startswith("design."):
        verbs = verbs[1:]  # k_d is the code comparison's: a scene without it still validates
    for argv in verbs:
        code = main(argv)
        err = capfd.readouterr().err
        assert code == 2, (argv, err)
        assert f"{path}: {field}:" in err, (argv, err)
        assert "full scale" in err or "full-scale" in err
    assert not out.exists()


def test_the_shipped_full_scale_scenes_state_their_law_and_k_d_as_assumed_stand_ins():
    """The street and the 40:1 scene state the contact stiffness, damping and k_d themselves (the
    catalogue gives none), each with a comment saying it is an assumed stand-in without a source."""
    for path in (STREET, PROTOTYPE):
        scene = load_scene(path)
        contact = scene.debris[0].contact
        assert contact.stiffness_N_m is not None and contact.damping_ratio is not None
        assert scene.design.debris_stiffness_N_m is not None
        text = path.read_text()
        lines = text.splitlines()
        after = lines[next(i for i, ln in enumerate(lines) if ln.strip() == "contact:"):]
        for key in ("stiffness_N_m:", "damping_ratio:"):
            line = next(ln for ln in after if ln.strip().startswith(key))
            assert "assumed stand-in" in line, line
        assert text.count("ASSUMED STAND-IN") >= 2 and text.count("docs/fullscale-sources.md") >= 2


def _street_page(tmp_path):
    scene = load_scene(STREET)
    rows = [{"case": "nominal", "realisation": r, "case_weight": 1.0, "sample_weight": 0.1, "body": "container",
             "mass_kg": 30480.0, "struck": True, "strikes": 1, "impact_speed_m_s": 4.0, "impact_height_m": 2.0,
             "peak_force_N": 1e6 * (r + 1), "base_shear_N": 1e6 * (r + 1), "base_moment_Nm": 3e6 * (r + 1),
             "displacement_m": 0.01 * (r + 1), "wall_time_s": 0.1} for r in range(10)]
    site = SiteFlow(4.0, 8.0, 3.0, 45.0, 2.0, "test")
    result = DesignResult(pd.DataFrame(rows, columns=DESIGN_COLUMNS),
                          [DesignCase("nominal", [], 1.0, 10, scene, site=site)], {})
    write_report(tmp_path, result, STREET, [], scene.design, WALL)
    return json.loads((tmp_path / "design.json").read_text()), (tmp_path / "design.md").read_text()


def test_a_full_scale_page_names_every_inputs_origin_and_prints_no_probability_of_exceeding_the_code(tmp_path):
    assert not calibration_possible()
    summary, page = _street_page(tmp_path)
    asce = summary["asce"]
    assert asce["prototype"] and not asce["exceedance_shown"] and asce["exceedance_note"] == NO_EXCEEDANCE
    assert all("asce" not in d for d in summary["demands"].values())
    assert "P(exceed" not in page and NO_EXCEEDANCE in page
    # each full-scale input: the scene's field (the author's statement) or a cited source
    sources = asce["sources"]
    assert set(sources) >= {"m_d", "k_d", "k_s", "law", "C_o", "I_tsu"}
    for key in ("k_d", "law", "k_s"):
        assert "the scene author's statement" in sources[key], key
    assert "docs/fullscale-sources.md" in sources["law"] and "k = 1.0144e+08 N/m, zeta = 0.62" in sources["law"]
    assert "maximum gross mass" in sources["m_d"] and "docs/catalogue.md" in sources["m_d"] and "docs/fullscale-sources.md" in sources["C_o"]
    assert "Table 6.8-1" in sources["I_tsu"] and "the scene author's statement" in sources["I_tsu"]
    assert "- u_max: the designer's stated speed at the site, inundation.speed_m_s (the scene author's statement)" \
        in page


def test_the_page_prints_p_exceed_again_once_a_test_checks_the_law(tmp_path, monkeypatch):
    """The switch, with a stand-in for a published test the law agrees with (not published data)."""
    monkeypatch.setattr(design_report, "calibration_possible", lambda: True)
    monkeypatch.setattr(design_report, "agreeing_test", lambda law: SimpleNamespace(outcome=lambda: "agrees"))
    summary, page = _street_page(tmp_path)
    assert summary["asce"]["exceedance_shown"] and "P(exceed k_s value)" in page and NO_EXCEEDANCE not in page
    assert np.isfinite(summary["demands"]["peak_force_N"]["asce"]["k_s"]["probability"])
