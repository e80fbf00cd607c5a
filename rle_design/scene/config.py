"""The base of every spec edit: a frozen dataclass that checks itself and then edits an ``MjSpec``.

A config is plain data (one docstring per field, SI units); ``validate()`` raises a ``ConfigError``
naming the field and the value, and ``edit_spec(spec)`` validates first, then changes the spec in
place. Configs compose: an ``Arena`` is a config made of configs.
"""

from __future__ import annotations

import abc
import math
from collections.abc import Sequence

import mujoco

from rle_design.errors import ConfigError

__all__ = ["SpecEdit", "check_finite", "check_positive", "check_range", "check_vector"]


class SpecEdit(abc.ABC):
    """A validated edit of an ``MjSpec``.

    Subclasses are frozen dataclasses; they implement ``validate`` and ``_edit``.
    """

    @abc.abstractmethod
    def validate(self) -> None:
        """Raise ``ConfigError`` when a field is out of its domain."""

    @abc.abstractmethod
    def _edit(self, spec: mujoco.MjSpec) -> None:
        """Apply the (already validated) edit."""

    def edit_spec(self, spec: mujoco.MjSpec) -> None:
        """Validate, then edit ``spec`` in place.

        Raises:
            ConfigError: The config is invalid.
            MissingElement: An element the config names does not exist in ``spec``.
        """
        self.validate()
        self._edit(spec)


def _where(owner: object, field: str) -> str:
    return f"{type(owner).__name__}.{field}"


def check_finite(owner: object, field: str, value: float) -> None:
    """``value`` is a finite number."""
    if not math.isfinite(value):
        raise ConfigError(f"{_where(owner, field)} must be finite, got {value}")


def check_positive(owner: object, field: str, value: float, *, strict: bool = True) -> None:
    """``value`` is finite and > 0 (``strict``) or >= 0."""
    check_finite(owner, field, value)
    if value < 0 or (strict and value == 0):
        raise ConfigError(f"{_where(owner, field)} must be {'>' if strict else '>='} 0, got {value}")


def check_vector(owner: object, field: str, value: Sequence[float], size: int) -> None:
    """``value`` has ``size`` finite entries."""
    if len(value) != size:
        raise ConfigError(f"{_where(owner, field)} must have {size} entries, got {len(value)}")
    for v in value:
        check_finite(owner, field, v)


def check_range(owner: object, field: str, value: Sequence[float]) -> None:
    """``value`` is an interval ``(low, high)`` of finite numbers with low < high."""
    check_vector(owner, field, value, 2)
    if not value[0] < value[1]:
        raise ConfigError(f"{_where(owner, field)} must be (low, high) with low < high, got {tuple(value)}")
