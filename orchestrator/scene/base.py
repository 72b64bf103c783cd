"""The base of every scene section (unknown keys are errors, instances immutable, finite numbers, no
boolean for a number) and the constrained floats the sections share; :mod:`orchestrator.scene.schema` re-exports them."""

from __future__ import annotations

import typing
from typing import Annotated, Any

from pydantic import BaseModel, ConfigDict, Field, ValidationInfo, field_validator

__all__ = ["NonNeg", "Pos", "SceneSection"]

#: A float that must be > 0 (inside tuples, so the error names the component).
Pos = Annotated[float, Field(gt=0)]
#: A float that must be >= 0.
NonNeg = Annotated[float, Field(ge=0)]


def _takes_bool(annotation: Any) -> bool:
    """Whether a field's type admits a boolean (``bool``, ``bool | None``, ...)."""
    return annotation is bool or any(_takes_bool(a) for a in typing.get_args(annotation))


class SceneSection(BaseModel):
    """Base of every scene section: unknown keys are errors, instances are immutable, a number
    is finite (``.inf`` and ``.nan`` are refused, naming the field) and a boolean is refused
    where a number (or any other non-boolean) belongs: pydantic would read ``end_time_s: true``
    as 1.0."""

    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)

    @field_validator("*", mode="before")
    @classmethod
    def _no_bool_for_numbers(cls, value: Any, info: ValidationInfo) -> Any:
        items = value if isinstance(value, (list, tuple)) else (value,)
        if any(isinstance(v, bool) for v in items) and not _takes_bool(cls.model_fields[info.field_name].annotation):
            raise ValueError("must be a number (or the field's type), not a boolean (true/false)")
        return value
