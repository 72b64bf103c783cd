"""The debris and column catalogue: closed forms, sources, and scenes that name its entries.

Debris: every value has a source; the shell-plus-cargo inertia against the thin cubic shell's
5 m a^2 / 18 and the uniform block's; the full-size entries carry no contact law or k_d (none
found; Froude similarity does not scale elasticity), the 1:40 model its laboratory law.
Columns: section properties against their closed forms (a W-shape against its plates by the
parallel-axis theorem), the MDOF model's f1 against the Euler-Bernoulli cantilever's
3.516 / (2 pi L^2) sqrt(E I / rho A) for a slender column, and its tip stiffness against
Timoshenko statics (bending, shear and a base spring in series). Scenes: `type:` and `section:`
filled in, explicit fields overriding, a resolved scene reloading to itself, and every bad name or
missing property an exit 2 naming the file and the field.
"""

from __future__ import annotations

import math
from pathlib import Path

import pytest
import yaml

from analytical.study import STUDY_DEBRIS_STIFFNESS_N_M
from analytical.catalogue import (
    SOURCES,
    container_inertia,
    debris_type,
    list_debris,
    mass_range_kg,
    shell_inertia,
)
from analytical.column_fem import lateral_stiffness, modes
from analytical.contact_law import CONTAINER_DAMPING_RATIO, CONTAINER_STIFFNESS_N_M
from analytical.errors import InputError
from analytical.sections import MATERIALS, column_section, section_properties
from orchestrator.cli import main
from orchestrator.report.catalogue_page import markdown
from orchestrator.scene.catalogued import debris_from_catalogue
from orchestrator.scene.scenefile import dump_scene_yaml, load_scene
from orchestrator.scene.schema import column_for_analysis
from tests.conftest import ROOT

SCENE = {
    "name": "proto",
    "flume": {"length_m": 200.0, "width_m": 30.0, "height_m": 10.0, "downstream_end": "open"},
    "reservoir": {"length_m": 100.0, "depth_m": 8.0},
    "column": {"x_m": 40.0, "height_m": 8.0, "section": {"kind": "rc-square", "size_m": [0.6]}},
    "debris": [{"type": "container-20ft-empty", "centre_m": [20.0, 0.0],
                "contact": {"stiffness_N_m": 1.0e8, "damping_ratio": 0.5}}],
    "mesh": {"cell_size_m": 0.25},
    "run": {"end_time_s": 20.0},
}


def _scene_file(tmp_path: Path, **changes) -> Path:
    data = yaml.safe_load(yaml.safe_dump(SCENE))
    for dotted, value in changes.items():
        *parents, last = dotted.split("__")
        node = data
        for p in parents:
            node = node[int(p)] if p.isdigit() else node[p]
        if value is None:
            node.pop(last, None)
        else:
            node[last] = value
    path = tmp_path / "proto.yaml"
    path.write_text(yaml.safe_dump(data))
    return path


# ------------------------------------------------------------------------------ debris
def test_every_entry_has_its_sources_and_the_families_span_empty_to_loaded():
    names = list_debris()
    for name in ("container-20ft-empty", "container-20ft-loaded", "container-40ft-empty", "container-40ft-loaded"):
        assert name in names
    for name in names:
        e = debris_type(name)
        for field in ("size_m", "mass_kg", "moment_of_inertia_kg_m2", "contact_stiffness_N_m",
                      "contact_damping_ratio", "kd_N_m"):
            assert e.sources[field] in SOURCES, (name, field)
            if getattr(e, field) is None:
                assert SOURCES[e.sources[field]].startswith("not found"), (name, field)
        assert all(v for v in e.to_dict()["sources"].values())
        assert e.asce_kd_N_m is None and "not retrievable" in SOURCES[e.sources["asce_kd_N_m"]]
    assert mass_range_kg("container-20ft") == (2300.0, 30480.0)
    assert mass_range_kg("container-40ft-empty") == (3750.0, 30480.0)
    assert debris_type("container-20ft-loaded").size_m == (6.058, 2.438, 2.591)  # ISO 668 1CC
    assert debris_type("container-40ft-empty").size_m == (12.192, 2.438, 2.591)  # ISO 668 1AA


def test_unknown_names_are_input_errors_naming_the_field():
    with pytest.raises(InputError) as err:
        debris_type("container-30ft")
    assert err.value.field == "type" and "container-20ft-empty" in err.value.rule
    with pytest.raises(InputError) as err:
        mass_range_kg("container-20ft-study-1to40")
    assert err.value.field == "type"


def test_the_thin_cubic_shell_has_five_eighteenths_m_a_squared():
    for axis in shell_inertia((2.0, 2.0, 2.0), 9.0):
        assert axis == pytest.approx(5 * 9.0 * 4.0 / 18, rel=1e-12)


def test_a_loaded_container_is_its_shell_plus_a_uniform_cargo_block():
    e = debris_type("container-20ft-loaded")
    shell = shell_inertia(e.size_m, e.tare_kg)
    cargo = e.mass_kg - e.tare_kg
    a, b, c = e.inner_size_m
    block = (cargo * (b * b + c * c) / 12, cargo * (a * a + c * c) / 12, cargo * (a * a + b * b) / 12)
    assert e.moment_of_inertia_kg_m2 == pytest.approx(tuple(s + k for s, k in zip(shell, block)), rel=1e-12)
    assert debris_type("container-20ft-empty").moment_of_inertia_kg_m2 == pytest.approx(shell, rel=1e-12)
    # between empty and loaded the inertia grows with the cargo; below the tare the shell carries it
    middle = container_inertia(e, 15000.0)
    assert all(s < m < f for s, m, f in zip(shell, middle, e.moment_of_inertia_kg_m2))
    assert container_inertia(e, 1150.0) == pytest.approx(tuple(v / 2 for v in shell), rel=1e-12)


def test_full_size_entries_carry_no_contact_law_and_the_model_keeps_its_laboratory_law():
    """No full-scale source gives a container's contact law or k_d (docs/fullscale-sources.md): the
    full-size entries say "not found" and no Froude-scaled stand-in; the 1:40 model keeps its law."""
    for name in ("container-20ft-empty", "container-20ft-loaded", "container-40ft-empty", "container-40ft-loaded"):
        e = debris_type(name)
        assert (e.contact_stiffness_N_m, e.contact_damping_ratio, e.kd_N_m) == (None, None, None)
        assert "contact" not in e.scene_fields()
        for field in ("contact_stiffness_N_m", "contact_damping_ratio", "kd_N_m"):
            text = e.to_dict()["sources"][field]
            assert text.startswith("not found") and "Froude similarity does not scale elasticity" in text
    model = debris_type("container-20ft-study-1to40")
    assert model.contact_stiffness_N_m == CONTAINER_STIFFNESS_N_M and model.mass_kg == 0.236
    assert model.contact_damping_ratio == CONTAINER_DAMPING_RATIO and model.kd_N_m == STUDY_DEBRIS_STIFFNESS_N_M
    assert model.scene_fields()["contact"]["stiffness_N_m"] == CONTAINER_STIFFNESS_N_M


# ------------------------------------------------------------------------------ columns
def test_section_properties_are_the_closed_forms():
    rect = section_properties("rc-rectangular", [0.5, 0.3], 0.2)
    assert (rect.area_m2, rect.second_moment_m4) == pytest.approx((0.15, 0.3 * 0.5**3 / 12), rel=1e-12)
    assert rect.stiffness_factor == 0.70 and rect.wall_thickness_m == 0.15
    assert rect.shear_coefficient == pytest.approx(10 * 1.2 / (12 + 2.2), rel=1e-12)  # Cowper, solid rectangle
    circle = section_properties("rc-circular", [0.8], 0.2, cracked_factor=0.35)
    assert (circle.area_m2, circle.second_moment_m4) == pytest.approx((math.pi * 0.16, math.pi * 0.8**4 / 64))
    assert circle.stiffness_factor == 0.35
    pipe = section_properties("steel-pipe", [0.5], 0.3, wall_thickness_m=0.02)
    assert pipe.second_moment_m4 == pytest.approx(math.pi * (0.5**4 - 0.46**4) / 64, rel=1e-12)
    assert pipe.stiffness_factor == 1.0
    d, bf, tf, tw = 0.36, 0.37, 0.018, 0.011
    w = section_properties("steel-w", [d, bf], 0.3, flange_thickness_m=tf, web_thickness_m=tw)
    plates = 2 * (bf * tf**3 / 12 + bf * tf * ((d - tf) / 2) ** 2) + tw * (d - 2 * tf) ** 3 / 12
    assert w.second_moment_m4 == pytest.approx(plates, rel=1e-12)
    assert w.area_m2 == pytest.approx(2 * bf * tf + (d - 2 * tf) * tw, rel=1e-12)
    weak = section_properties("steel-w", [d, bf], 0.3, flange_thickness_m=tf, web_thickness_m=tw, axis="weak")
    assert weak.second_moment_m4 < w.second_moment_m4 and (weak.size_x_m, weak.size_y_m) == (bf, d)
    # the hollow box's shear area gives the study's 0.5 for its acrylic column
    acrylic = section_properties("steel-hss-square", [0.2], 0.375, wall_thickness_m=0.005)
    assert acrylic.shear_coefficient == pytest.approx(0.51, abs=0.01)


def test_a_slender_fixed_cantilever_has_the_euler_bernoulli_first_frequency():
    c = column_section("steel-pipe", [0.3], 15.0, wall_thickness_m=0.01)
    ei, rho_a = c.bending_stiffness_Nm2, c.mass_per_length_kg_m
    f1 = 3.516 / (2 * math.pi * 15.0**2) * math.sqrt(ei / rho_a)
    assert modes(c)[0] == pytest.approx(f1, rel=2e-3)
    assert c.natural_frequency_Hz == pytest.approx(modes(c)[0], rel=1e-12)
    assert c.damping_ratio == MATERIALS["steel"].damping_ratio == 0.02


def test_the_tip_stiffness_is_bending_shear_and_base_spring_in_series():
    rigid = column_section("rc-square", [0.6], 4.0)
    ei = 0.70 * MATERIALS["concrete-28mpa"].youngs_modulus_Pa * 0.6**4 / 12
    assert rigid.bending_stiffness_Nm2 == pytest.approx(ei, rel=1e-12)
    flex = 4.0**3 / (3 * ei) + 4.0 / rigid.shear_stiffness_N
    assert rigid.stiffness_N_m == pytest.approx(1 / flex, rel=1e-9)
    k_theta = 5e8
    sprung = column_section("rc-square", [0.6], 4.0, base="spring", base_spring_Nm_rad=k_theta)
    assert lateral_stiffness(sprung, 4.0) == pytest.approx(1 / (flex + 4.0**2 / k_theta), rel=1e-9)
    assert sprung.natural_frequency_Hz < rigid.natural_frequency_Hz
    tuned = column_section("rc-square", [0.6], 4.0, base="calibrated", natural_frequency_Hz=10.0)
    assert modes(tuned)[0] == pytest.approx(10.0, rel=1e-9)


def test_bad_column_input_names_the_argument():
    for kwargs, field in (({"kind": "steel-pipe", "size_m": [0.3]}, "wall_thickness_m"),
                          ({"kind": "rc-square", "size_m": [0.3], "material_name": "steel"}, "material"),
                          ({"kind": "rc-square", "size_m": [0.3], "base": "pinned"}, "base"),
                          ({"kind": "rc-square", "size_m": [0.3, 0.4]}, "size_m"),
                          ({"kind": "timber", "size_m": [0.3]}, "kind")):
        with pytest.raises(InputError) as err:
            column_section(height_m=3.0, **kwargs)
        assert err.value.field == field


# ------------------------------------------------------------------------------ scenes
def test_a_scene_names_catalogue_entries_and_reloads_to_itself(tmp_path):
    scene = load_scene(_scene_file(tmp_path))
    body, entry = scene.debris[0], debris_type("container-20ft-empty")
    assert body.size_m == entry.size_m and body.mass_kg == entry.mass_kg
    assert body.moment_of_inertia_kg_m2 == pytest.approx(entry.moment_of_inertia_kg_m2)
    assert body.contact.law == "container" and entry.contact_stiffness_N_m is None
    assert (body.contact.stiffness_N_m, body.contact.damping_ratio) == (1.0e8, 0.5)  # the scene's own
    col = column_for_analysis(scene)
    assert (col.size_x_m, col.stiffness_factor, col.damping_ratio) == (0.6, 0.7, 0.05)
    assert col.natural_frequency_Hz == pytest.approx(modes(col)[0], rel=1e-12)
    resolved = tmp_path / "resolved.yaml"
    resolved.write_text(dump_scene_yaml(scene))
    assert load_scene(resolved) == scene.model_copy(update={"name": "proto"})


def test_fields_beside_a_type_override_it(tmp_path):
    path = _scene_file(tmp_path, debris__0__mass_kg=15000.0, debris__0__contact={"law": "asce7_kd",
                                                                                  "stiffness_N_m": 4e9},
                       column__damping_ratio=0.03)
    scene = load_scene(path)
    body, entry = scene.debris[0], debris_type("container-20ft-empty")
    assert body.mass_kg == 15000.0
    assert body.moment_of_inertia_kg_m2 == pytest.approx(container_inertia(entry, 15000.0))
    assert body.contact.stiffness_N_m == 4e9
    assert scene.column.damping_ratio == 0.03
    own = load_scene(_scene_file(tmp_path, debris__0__contact={"stiffness_N_m": 1e7, "restitution": 0.4}))
    assert own.debris[0].contact.stiffness_N_m == 1e7
    model = debris_from_catalogue({"type": "container-20ft-study-1to40"})
    assert model["contact"]["stiffness_N_m"] == CONTAINER_STIFFNESS_N_M  # the 1:40 model's law filled in
    assert "stiffness_N_m" not in debris_from_catalogue({"type": "container-20ft-empty"})["contact"]


@pytest.mark.parametrize(("changes", "field"), [
    ({"debris__0__type": "container-45ft"}, "debris.0.type"),
    ({"column__section": {"kind": "steel-pipe", "size_m": [0.5]}}, "column.section.wall_thickness_m"),
    ({"column__section": {"kind": "rc-hexagonal", "size_m": [0.5]}}, "column.section.kind"),
    ({"column__section": {"kind": "rc-square", "size_m": [0.5], "material": "granite"}}, "column.section.material"),
    ({"column__size_x_m": 0.7}, "column.size_x_m"),
    ({"column__base": "calibrated"}, "column.natural_frequency_Hz"),
    ({"column__base": "spring"}, "column.base_spring_Nm_rad"),
    ({"debris__0__type": None}, "debris.0.size_m"),
    ({"debris__0__contact": None}, "debris.0.contact.stiffness_N_m"),
    ({"debris__0__contact": {"stiffness_N_m": 1.0e8}}, "debris.0.contact.damping_ratio"),
    ({"debris__0__contact": {"law": "asce7_kd"}}, "debris.0.contact.stiffness_N_m"),
])
def test_bad_catalogue_names_and_missing_properties_exit_2_naming_file_and_field(tmp_path, capsys, changes, field):
    path = _scene_file(tmp_path, **changes)
    assert main(["validate", str(path)]) == 2
    err = capsys.readouterr().err
    assert f"{path}: {field}:" in err, err


def test_the_cli_lists_the_catalogue(capsys):
    assert main(["catalogue"]) == 0
    out = capsys.readouterr().out
    assert all(name in out for name in list_debris()) and "rc-square" in out and "concrete-28mpa" in out


def test_the_committed_page_is_the_catalogues():
    assert (ROOT / "docs" / "catalogue.md").read_text() == markdown()
