"""The errors of debrisfoam, for every stage of orchestrator/ (the CLI maps them to exit codes).

One base, :class:`DebrisfoamError`; bad input is :class:`InputError`, which is also a
``ValueError`` and names the field (and the file) at fault: exit code 2. Each stage's own
errors derive from these and from the matching built-in (a failed OpenFOAM step or run is also
a ``RuntimeError``), so code that catches the built-in catches them too. The two bases live in
:mod:`analytical.errors` because the physics package, which imports nothing of orchestrator/,
raises them as well; orchestrator/ takes them from here.
"""

from analytical.errors import DebrisfoamError, InputError, require_finite, require_positive

__all__ = ["DebrisfoamError", "InputError", "MissingFeatureError", "require_finite", "require_positive"]


class MissingFeatureError(DebrisfoamError, NotImplementedError):
    """A verb whose implementation has not landed yet; the message names what is missing."""
