"""Stage 3, the case: the case folder and its records, the plan rendered into OpenFOAM dictionaries,
OpenFOAM applications run with their logs, body states, function-object outputs read back."""
