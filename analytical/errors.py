"""Error types shared by the whole package.

Library code raises these; only the CLI turns them into messages and exit codes.
`InputError` also is a `ValueError`, so callers who do not know this package can
still catch it as one.
"""

from __future__ import annotations


class DebrisfoamError(Exception):
    """Base class of every error this package raises on purpose."""


class InputError(DebrisfoamError, ValueError):
    """Bad input: names the argument/field, the rule it broke and, when known, the file.

    Parameters
    ----------
    field:
        The argument name or dotted scene key (``"mass_kg"``, ``"column.base"``).
    rule:
        What is wrong, in words (``"must be > 0, got -1"``).
    source:
        The file the value came from, if any.
    """

    def __init__(self, field: str, rule: str, source: str | None = None):
        self.field = field
        self.rule = rule
        self.source = source
        super().__init__(self._text())

    def _text(self) -> str:
        where = f"{self.source}: " if self.source else ""
        return f"{where}{self.field}: {self.rule}"

    def with_source(self, source: str) -> "InputError":
        """The same error, attributed to ``source`` (a file path)."""
        return InputError(self.field, self.rule, source)


def require_finite(name: str, value: float) -> float:
    """Return ``float(value)``; raise InputError naming ``name`` unless it is a finite number."""
    import math

    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(name, f"must be a number, got {value!r}") from None
    if not math.isfinite(v):
        raise InputError(name, f"must be finite, got {value!r}")
    return v


def require_positive(name: str, value: float) -> float:
    """Return ``float(value)``; raise InputError naming ``name`` unless it is finite and > 0."""
    import math

    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(name, f"must be a number, got {value!r}") from None
    if not math.isfinite(v) or v <= 0.0:
        raise InputError(name, f"must be a finite number > 0, got {value!r}")
    return v
