"""Errors raised by the orchestration layer (the CLI maps them to exit codes)."""

from analytical.errors import DebrisfoamError, InputError

__all__ = ["DebrisfoamError", "InputError", "MissingFeatureError"]


class MissingFeatureError(DebrisfoamError):
    """A verb whose implementation has not landed yet; the message names what is missing."""
