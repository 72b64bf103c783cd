"""debrisfoam's analytical package: pure physics, numbers and arrays in, result objects out.

No file I/O and no printing here; the orchestrator and the CLI do that.

Public names (imported lazily, so `import analytical` stays cheap):

* pulses: `HalfSine`, `Rectangular`, `Triangular`, `Tabulated`, `make_pulse`
* SDOF: `SDOF`, `sdof_response`, `oscillator_response`, `ForceResponse`
* MDOF column: `Column`, `column_model`, `mdof_response`, `modes`
* ASCE 7-22 6.11: `asce7_impact`, `dynamic_response_ratio`, `effective_stiffness`
* contact law: `ContactLaw`, `contact_law`, `column_impact`, `study_fit`; its calibration
  on the study's Table 2: `calibrate`, `scatter`
* added mass of a floating box: `box_added_mass`
* empirical formulas: `haehnel_daly`, `matsutomi`, `ikeno`
* fitting: `fit_sdof`, `fit_mdof`
* dam break: `dam_break` (Ritter, Stoker, Chanson)
"""

from importlib import import_module

_EXPORTS = {
    "HalfSine": "pulses", "Rectangular": "pulses", "Triangular": "pulses", "Tabulated": "pulses",
    "make_pulse": "pulses",
    "SDOF": "sdof", "sdof_response": "sdof", "oscillator_response": "oscillator", "ForceResponse": "sdof",
    "Column": "column", "column_model": "column_fem", "mdof_response": "mdof", "modes": "column_fem",
    "asce7_impact": "asce7", "dynamic_response_ratio": "asce7", "effective_stiffness": "asce7",
    "ContactLaw": "contact_law", "contact_law": "contact_law", "column_impact": "contact_law",
    "study_fit": "contact_law", "calibrate": "contact_calibration", "scatter": "contact_calibration",
    "box_added_mass": "added_mass",
    "haehnel_daly": "formulas", "matsutomi": "formulas", "ikeno": "formulas",
    "fit_sdof": "fitting", "fit_mdof": "fitting",
    "dam_break": "dambreak",
    "InputError": "errors", "DebrisfoamError": "errors",
}
__all__ = sorted(_EXPORTS)


def __getattr__(name: str):
    module = _EXPORTS.get(name)
    if module is None:
        raise AttributeError(f"module 'analytical' has no attribute {name!r}")
    return getattr(import_module(f".{module}", __name__), name)
