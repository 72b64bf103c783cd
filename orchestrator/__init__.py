"""debrisfoam orchestration: scene -> plan -> case -> run -> results -> analysis.

One module per stage of the data flow; `cli` turns errors into messages and exit codes.
"""

__version__ = "0.1.0"
