"""debrisfoam orchestration, one subpackage per stage of the data flow (bottom first):

core -> scene -> plan -> case -> run -> transport -> results -> report -> pipeline -> studies -> cli

A stage imports only from itself and the stages below it (tests/test_layers.py checks it);
`cli` turns errors into messages and exit codes. docs/architecture.md is the map.
"""

__version__ = "0.1.0"
