"""The contact-law page's inputs: strikes taken from an ensemble's ensemble.csv (a small
constructed one), the verb's refusals, and (slow) the whole page from an ensemble."""

import json

import numpy as np
import pytest

from orchestrator.core.errors import InputError
from orchestrator.report.contact_report import ensemble_strikes


def _ensemble(path, rows):
    header = ("realisation,body,struck,impact_height_m,face_water_level_m,effective_mass_kg,obliquity_deg,"
              "impact_speed_m_s\n")
    path.write_text(header + "".join(",".join(str(v) for v in r) + "\n" for r in rows))
    return path


ROWS = [
    (0, "c", True, 0.21, 0.27, 0.14, 4.0, 1.7),
    (1, "c", False, "", "", "", "", ""),
    (2, "c", True, 0.18, "", 0.12, -8.0, 1.6),
    (3, "c", True, 0.25, 0.31, 0.22, 0.5, 1.8),
    (4, "c", True, 0.20, 0.24, 0.16, 12.0, 1.5),
]


def test_the_first_strikes_of_an_ensemble_are_the_population(tmp_path):
    population, info = ensemble_strikes(_ensemble(tmp_path / "ensemble.csv", ROWS), count=10)
    assert info["struck"] == 4 and info["used"] == 4 and info["level_from_contact"] == 1
    np.testing.assert_allclose(population.effective_mass_kg, [0.14, 0.12, 0.22, 0.16])
    np.testing.assert_allclose(population.contact_height_m, [0.21, 0.18, 0.25, 0.20])
    np.testing.assert_allclose(population.water_level_m, [0.27, 0.18, 0.31, 0.24])  # no level: the contact's
    np.testing.assert_allclose(population.obliquity_deg, [4.0, -8.0, 0.5, 12.0])
    assert np.all(population.lateral_offset_m == 0.0)
    assert info["effective_mass_kg"]["mean"] == pytest.approx(0.16)


def test_more_strikes_than_asked_are_drawn_with_a_fixed_seed(tmp_path):
    path = _ensemble(tmp_path / "ensemble.csv", ROWS)
    a, info = ensemble_strikes(path, count=2)
    b, _ = ensemble_strikes(path, count=2)
    assert info["struck"] == 4 and info["used"] == 2
    np.testing.assert_array_equal(a.effective_mass_kg, b.effective_mass_kg)


def test_an_ensemble_without_the_masses_is_refused_naming_the_option(tmp_path):
    path = tmp_path / "ensemble.csv"
    path.write_text("realisation,struck,impact_height_m\n0,True,0.2\n1,True,0.3\n")
    with pytest.raises(InputError, match="effective_mass_kg") as err:
        ensemble_strikes(path, count=4)
    assert err.value.field == "--ensemble"
    with pytest.raises(InputError) as err:
        ensemble_strikes(tmp_path / "absent.csv", count=4)
    assert err.value.field == "--ensemble"


def test_an_ensemble_strike_off_the_column_is_refused(tmp_path):
    rows = [(0, "c", True, 0.21, 0.27, 0.14, 0.0, 1.7), (1, "c", True, 0.95, 0.3, 0.14, 0.0, 1.7)]
    with pytest.raises(InputError) as err:
        ensemble_strikes(_ensemble(tmp_path / "ensemble.csv", rows), count=4)
    assert err.value.field == "impact_height_m"


def test_the_verb_refuses_no_workers(tmp_path):
    from tests.conftest import run_cli

    proc = run_cli("analytical", "contact-law", "-o", str(tmp_path / "cl"), "--workers", "0")
    assert proc.returncode == 2 and "--workers" in proc.stderr


@pytest.mark.slow
def test_the_page_from_an_ensemble(tmp_path):
    from tests.conftest import run_cli

    path = _ensemble(tmp_path / "ensemble.csv", ROWS)
    proc = run_cli("analytical", "contact-law", "-o", str(tmp_path / "cl"), "--strikes", "2", "--ensemble", str(path),
                   "--workers", "2", "--json")
    assert proc.returncode == 0, proc.stderr
    cal = json.loads((tmp_path / "cl" / "calibration.json").read_text())
    assert cal["population"]["used"] == 2 and len(cal["multistart"]["starts"]) >= 6
    assert "ensemble" in (tmp_path / "cl" / "report.md").read_text()
