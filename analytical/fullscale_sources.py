"""Full-scale debris values from full-scale sources: what was found, where, and what was not.

A full-scale contact law cannot be the study's 1:40 polyethylene box Froude-scaled (k x 40^2):
Froude similarity keeps gravity and inertia, not the elasticity of a steel container. This module
holds, as data, what the design code and the full-scale container tests give, each figure with the
source a reader can open and the place in it (docs/fullscale-sources.md). It holds **only figures
read in a source text**: a value the search found no source text for is a record with
``value=None`` that says so, and a prototype scene must state it itself (no lab default).

Two tables:

* :data:`SOURCE_RECORDS` (:class:`SourceRecord`): one quantity each, as printed (its unit as
  printed; :attr:`SourceRecord.si` gives the SI value where the unit converts exactly).
* :data:`FULL_SCALE_TESTS` (:class:`FullScaleTest`): the full-scale container impact tests, in SI,
  with ``None`` where the source gives nothing. A record is usable for calibration only when it
  pairs a speed, a mass and a measured peak force (:attr:`FullScaleTest.complete`);
  :mod:`analytical.fullscale_check` compares a contact law with such a record.

What was searched (December 2026): the stored public pages, documentation, code and issue
corpora, and the reference study's text. Found: the ASCE 7-22 formulas and C_o as the study
applies them; the tests' set-up and a few figures from Lehigh's and NSF's reports of them; the
papers' bibliographic records and abstracts. Not found (:data:`NOT_FOUND`): ASCE 7-22 Table 6.11-2,
the simplified static load's clause, FEMA P-646 (2019), and any test-by-test speed, mass, peak force
and duration of the full-scale tests (Piran Aghl et al. 2014, 2015; Riggs et al. 2014; Ko et al.
2015). With no complete test record, no full-scale law can be calibrated or checked here
(:func:`analytical.fullscale_check.calibration_possible` is False).

Units: SI in :class:`FullScaleTest`; :class:`SourceRecord` keeps the printed unit.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = [
    "CITATIONS",
    "FULL_SCALE_TESTS",
    "NOT_FOUND",
    "SOURCE_RECORDS",
    "UNIT_TO_SI",
    "FullScaleTest",
    "SourceRecord",
    "record",
    "fullscale_test",
]

#: Exact conversions of the printed units (NIST SP 811): lb (avoirdupois), lbf, mph, short ton.
UNIT_TO_SI = {
    "kg": ("kg", 1.0),
    "lb": ("kg", 0.45359237),
    "short ton": ("kg", 907.18474),
    "lbf": ("N", 4.4482216152605),
    "MN/m": ("N/m", 1.0e6),
    "mph": ("m/s", 0.44704),
    "ft": ("m", 0.3048),
    "s": ("s", 1.0),
    "1": ("1", 1.0),
}

CITATIONS = {
    "study": "Joynt, Nistor, Palermo & Stolle, the reference study (analytical/study.py; a secondary source for ASCE 7-22: it applies "
            "Clauses 6.11.2, 6.11.6 and 6.11.8 and quotes their formulas and C_o)",
    "riggs2014": "Riggs, H. R., Cox, D. T., Ko, H. T.-S., Naito, C. J., Piran Aghl, P., Kobayashi, M. H. and "
                 "Khowitar, E. (as the ASME page lists them, by affiliation) (2014). Experimental and analytical "
                 "study of water-driven debris impact forces on structures. J. Offshore Mech. Arct. Eng. 136(4), "
                 "041603, doi:10.1115/1.4028338 (its abstract, "
                 "offshoremechanics.asmedigitalcollection.asme.org/article.aspx?articleid=1899430)",
    "lehigh2012": "Lehigh University, 'Designing secure havens from the worst tsunamis', Resolve vol. 2 (2012), "
                  "engineering.lehigh.edu/research/resolve/volume-2-2012/designing-secure-havens-worst-tsunamis "
                  "(C. Naito's full-scale container tests at the ATLSS center)",
    "nsf2014": "NSF Science Nation, 'Engineers re-create tsunami debris impacts to measure their force' "
               "(M. O'Brien, March 2014; C. Naito interviewed), transcript at willinolanspeaks.com/engineers-re-"
               "create-tsunami-debris-impacts-to-measure-their-force-science-nation/",
    "ase2017": "Advances in Structural Engineering, doi:10.1177/1369433216668361 ('a simplified one-dimensional "
               "model to predict the impact force and duration for axial impact of the debris with "
               "non-uniformly distributed nonstructural mass'), its introduction",
    "haehnel2002": "Haehnel, R. B. and Daly, S. F. (2002). Maximum impact force of woody debris on floodplain "
                   "structures. ERDC/CRREL TR-02-2, DTIC ADA398916, its abstract (dtic.minsky.ai/index/ADA398916)",
    "purdue2013": "Purdue University news release 'Cargo container research to improve buildings' ability to "
                  "withstand tsunamis', ScienceDaily, 5 February 2013 "
                  "(sciencedaily.com/releases/2013/02/130205102118.htm)",
}
"""Every source a record cites, by key."""


@dataclass(frozen=True)
class SourceRecord:
    """One quantity as a source prints it.

    ``value`` is the printed number (or the printed formula, a string), in ``unit`` as printed;
    None when no source text was found (``where`` then says what was searched). ``source`` is a
    key of :data:`CITATIONS` (None when not found); ``note`` says what the figure is and is not.
    """

    key: str
    quantity: str
    value: float | str | None
    unit: str
    source: str | None
    where: str
    note: str = ""

    def __post_init__(self):
        if self.value is not None and self.source not in CITATIONS:
            raise AssertionError(f"{self.key}: a value needs a cited source, got {self.source!r}")
        if isinstance(self.value, float | int) and self.unit not in UNIT_TO_SI:
            raise AssertionError(f"{self.key}: unit {self.unit!r} has no conversion")

    @property
    def found(self) -> bool:
        return self.value is not None

    @property
    def citation(self) -> str | None:
        """The full citation of :attr:`source`."""
        return CITATIONS.get(self.source) if self.source else None

    @property
    def si(self) -> float | None:
        """The numeric value in SI (None for a formula or a value not found)."""
        if not isinstance(self.value, float | int) or isinstance(self.value, bool):
            return None
        return float(self.value) * UNIT_TO_SI[self.unit][1]


def _r(key, quantity, value, unit, source, where, note="") -> SourceRecord:
    return SourceRecord(key, quantity, value, unit, source, where, note)


SOURCE_RECORDS: tuple[SourceRecord, ...] = (
    # ---- ASCE 7-22 section 6.11, as the reference study applies it (a secondary source)
    _r("asce_Co_container", "ASCE 7-22 orientation coefficient C_o, shipping containers", 0.65, "1", "study",
       "Sec. 3.2.3, after eq. [10]: 'following Clause 6.11.6, the orientation is equal to 0.65 for shipping "
       "containers'", "the standard's own clause was not retrieved"),
    _r("asce_Itsu_II", "ASCE 7-22 tsunami importance factor I_tsu, Tsunami Risk Category II", 1.0, "1", "study",
       "Sec. 3.2.3: 'the importance factor was selected to be one, corresponding to a Tsunami Risk Category of II'"),
    _r("asce_Fi", "ASCE 7-22 design impact force", "F_i = I_tsu C_o F_ni", "N", "study", "Sec. 3.2.3, eq. [8]"),
    _r("asce_Fni", "ASCE 7-22 nominal maximum instantaneous impact force", "F_ni = u_max sqrt(k m_d)", "N", "study",
       "Sec. 3.2.3, eq. [9]; Sec. 2.1 eq. [1] (Haehnel and Daly 2004)"),
    _r("asce_k", "ASCE 7-22 stiffness k in F_ni", "the lesser of the debris' effective stiffness and the lateral "
       "stiffness of the impacted structural element", "N/m", "study", "Sec. 2.1, on Clause 6.11.2"),
    _r("asce_td", "ASCE 7-22 impact duration", "t_d = 2 m_d u_max / F_ni", "s", "study",
       "Sec. 3.2.3, eq. [10]; Sec. 2.1 eq. [3] (Clause 6.11.2)"),
    _r("asce_pulse", "ASCE 7-22 impact load history", "rectangular pulse of F_i over t_d", "N", "study",
       "Sec. 3.2.3: 'following Clause 6.11.8, the impact force history will take the shape of a rectangular pulse'"),
    # ---- ASCE 7-22 values not found in any source text
    *(_r(f"asce_table_6_11_2_{c}_{q}", f"ASCE 7-22 Table 6.11-2, {c.replace('_', ' ')} container, {q}", None,
         "lb" if q == "weight" else "kip/in", None,
         "not found: of the stored ASCE 7-22 C6 commentary (scribd 512409449) and ASCE's 'Tsunami Loads and "
         "Effects' guide the search returned the opening pages only; no other source text prints the table")
      for c in ("20ft_empty", "20ft_loaded", "40ft_empty", "40ft_loaded") for q in ("weight", "stiffness")),
    _r("asce_simplified_static_load", "ASCE 7-22 6.11 simplified (alternative) static debris impact load and "
       "when it applies", None, "kip", None,
       "not found: no source text of the clause; analytical.asce7.SIMPLIFIED_STATIC_LOAD_N is unverified"),
    _r("fema_p646_2019", "FEMA P-646 (2019) debris impact force, container mass and stiffness", None, "N", None,
       "not found: only the 2008 edition's front matter and hydrostatic example (Appendix C) were retrieved"),
    # ---- the full-scale container tests (Lehigh ATLSS, NSF NEES project of Riggs, Naito, Cox et al.)
    _r("riggs_model_scale", "scale of the in-water shipping container model (OSU large wave flume)", 5.0, "1",
       "riggs2014", "abstract: 'a 1:5 scale shipping container model was used for in-water tests'",
       "the full-scale tests (Lehigh) were in air, with a wooden utility pole and a shipping container; the "
       "abstract gives no force, speed or mass"),
    _r("lehigh_container_weight", "full-scale test container, 20-ft, weight", 3.5, "short ton", "lehigh2012",
       "'hoisted a standard, 3.5-ton, 20-foot intermodal shipping container on 30-foot cables'",
       "the ton is not defined; taken as the US short ton. NSF 2014 says 'five thousand pound' for the same series"),
    _r("lehigh_pendulum_length", "pendulum cable length", 30.0, "ft", "lehigh2012", "'on 30-foot cables'"),
    _r("lehigh_speed_low", "impact speed, elastic series, low end", 2.0, "mph", "lehigh2012",
       "'We started looking at impact events that were low velocity, 2 to 4 mph' (Naito); 'the container "
       "remained elastic'"),
    _r("lehigh_speed_high", "impact speed, elastic series, high end", 4.0, "mph", "lehigh2012",
       "'low velocity, 2 to 4 mph'", "the final tests ('cranking the test container away from the wall far eno...') are "
       "cut off in the stored text: their speed is not given"),
    _r("lehigh_loaded_weight", "a fully loaded container's weight", 53000.0, "lb", "lehigh2012",
       "'fully loaded, one container can weigh 53,000 pounds'", "not a tested mass"),
    _r("nsf_container_weight", "full-scale test container weight", 5000.0, "lb", "nsf2014",
       "O'Brien: 'then moved on to a five thousand pound shipping container'"),
    _r("nsf_peak_force", "largest impact force quoted for the tests", 500000.0, "lbf", "nsf2014",
       "Naito: 'forces as high as half a million pounds'",
       "an order of magnitude for the programme, not tied to a speed or a mass: no test record"),
    _r("nsf_duration", "impact duration quoted", 0.01, "s", "nsf2014",
       "Naito: 'a very, very short duration of maybe 100th of a second'", "approximate, as spoken"),
    _r("ase_tare_20ft", "20-ft container tare weight", 2300.0, "kg", "ase2017",
       "introduction: 'Standard 6.10 m (20 ft) shipping containers have a tare weight of 2300 kg'"),
    _r("purdue_loaded_container", "a fully loaded cargo container's weight", 60000.0, "lb", "purdue2013",
       "'60,000-pound fully loaded cargo containers'"),
    _r("purdue_default_log", "the default log of U.S. building-design guidelines", 1000.0, "lb", "purdue2013",
       "'the telephone-pole-size 1,000-pound default log assumed by most U.S. building-design guidelines'"),
    _r("haehnel_log_stiffness", "effective contact stiffness, logs striking structures (laboratory flume and basin)",
       2.4, "MN/m", "haehnel2002", "abstract: 'with an effective contact stiffness of 2.4 MN/m'",
       "the model ASCE 7-22 6.11 derives from (study Sec. 2.1); woody debris, not containers"),
    # ---- the full-scale papers whose data were not found
    _r("piran_aghl_2014_2015_tests", "Piran Aghl, Naito, Riggs et al. (2014, 2015), 'Full-scale experimental study "
       "of impact demands resulting from high mass, low velocity debris', J. Struct. Eng.: test speeds, masses, "
       "peak forces, durations", None, "N", None,
       "not found: no stored page, abstract or repository holds the paper's text or tables"),
    _r("riggs_2014_tests", "Riggs et al. (2014), J. Offshore Mech. Arct. Eng.: test speeds, masses, peak forces, "
       "durations", None, "N", None, "not found: only its abstract (no figures) was retrieved"),
    _r("ko_2015_tests", "Ko et al. (2015), shipping containers struck in water: speeds, masses, peak forces, added "
       "mass", None, "N", None, "not found: no stored text of the paper"),
)
"""Every quantity searched for: the ones found, as printed, and the ones not found."""

NOT_FOUND: tuple[str, ...] = tuple(r.key for r in SOURCE_RECORDS if not r.found)
"""Keys of the quantities no source text was found for: a prototype scene must state them."""

_BY_KEY = {r.key: r for r in SOURCE_RECORDS}


def record(key: str) -> SourceRecord:
    """The :class:`SourceRecord` ``key`` (KeyError naming the known keys otherwise)."""
    if key not in _BY_KEY:
        raise KeyError(f"no source record {key!r}; known: {', '.join(_BY_KEY)}")
    return _BY_KEY[key]


# ------------------------------------------------------------------------------ the full-scale tests
@dataclass(frozen=True)
class FullScaleTest:
    """One full-scale container impact test (or a published mean), in SI; None where not given.

    ``velocity_m_s`` is the impact speed, ``mass_kg`` the container's mass, ``peak_force_N`` the
    measured peak contact force, ``duration_s`` the pulse's duration, ``stiffness_N_m`` an effective
    or measured stiffness if the source reports one; ``in_water`` whether the strike was in water
    (else in air). ``sources`` are keys of :data:`CITATIONS`; ``note`` says what the numbers are.
    """

    name: str
    sources: tuple[str, ...]
    where: str
    velocity_m_s: float | None = None
    mass_kg: float | None = None
    peak_force_N: float | None = None
    duration_s: float | None = None
    stiffness_N_m: float | None = None
    in_water: bool = False
    note: str = ""

    @property
    def missing(self) -> tuple[str, ...]:
        """The fields a calibration needs (speed, mass, peak force) that the source does not give."""
        return tuple(f for f in ("velocity_m_s", "mass_kg", "peak_force_N") if getattr(self, f) is None)

    @property
    def complete(self) -> bool:
        """Whether the record pairs a speed, a mass and a measured peak force."""
        return not self.missing


def _si(key: str) -> float:
    return record(key).si


FULL_SCALE_TESTS: tuple[FullScaleTest, ...] = (
    FullScaleTest(
        name="lehigh-20ft-pendulum-series (press reports)",
        sources=("lehigh2012", "nsf2014"),
        where="Resolve 2012 (set-up, speeds); Science Nation 2014 (mass, largest force, duration)",
        velocity_m_s=None, mass_kg=None,
        peak_force_N=_si("nsf_peak_force"), duration_s=_si("nsf_duration"),
        note=f"the elastic series ran at {_si('lehigh_speed_low'):.3f}-{_si('lehigh_speed_high'):.3f} m/s (2-4 mph) "
             f"with a container of {_si('nsf_container_weight'):.0f} kg (5,000 lb, NSF) or "
             f"{_si('lehigh_container_weight'):.0f} kg (3.5 short tons, Resolve); the force and duration are "
             "the programme's largest quoted, tied to no speed or mass, so neither is set here"),
    FullScaleTest(name="piran-aghl-2014-2015", sources=(), where="not found",
                  note="J. Struct. Eng. full-scale tests: no text retrieved"),
    FullScaleTest(name="riggs-2014", sources=("riggs2014",), where="abstract only: no figures",
                  note="full-scale in-air tests at Lehigh (utility pole, shipping container)"),
    FullScaleTest(name="ko-2015", sources=(), where="not found", in_water=True,
                  note="1:5 containers in water (Riggs et al. 2014 abstract): no text retrieved"),
)
"""The full-scale container impact tests searched for. None is complete (:attr:`FullScaleTest.complete`)."""

_TESTS = {t.name: t for t in FULL_SCALE_TESTS}


def fullscale_test(name: str) -> FullScaleTest:
    """The :class:`FullScaleTest` ``name`` (KeyError naming the known ones otherwise)."""
    if name not in _TESTS:
        raise KeyError(f"no full-scale test {name!r}; known: {', '.join(_TESTS)}")
    return _TESTS[name]

