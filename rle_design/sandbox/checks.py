"""Checks on values returned by submitted code: type, shape and finiteness."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from rle_design.excerpt import excerpt
from rle_design.sandbox.faults import ParticipantFault


def _describe(value: Any) -> str:
    if isinstance(value, np.ndarray):
        return f"ndarray of dtype {value.dtype} and shape {tuple(value.shape)}"
    if isinstance(value, str):
        return f"str {excerpt(value, 40)}"
    return type(value).__name__


def _shape_text(shape: tuple) -> str:
    """``(3,)``, ``(any, 2)``: an expected shape as messages write it."""
    dims = ", ".join("any" if d in (None, -1) else str(d) for d in shape)
    return f"({dims}{',' if len(shape) == 1 else ''})"


def as_array(value: Any, shape: tuple, where: str) -> np.ndarray:
    """``value`` as an ndarray of ``shape`` (``None`` or ``-1`` entries match any size).

    Lists and numbers are converted to float64 arrays; strings, dicts and None are refused.

    Raises:
        ParticipantFault: ``sandbox.bad_type`` or ``sandbox.bad_shape``.
    """
    if isinstance(value, np.ndarray):
        arr = value
    elif isinstance(value, list | tuple | int | float) and not isinstance(value, bool):
        try:
            arr = np.asarray(value, dtype=np.float64)
        except (TypeError, ValueError):
            raise ParticipantFault(
                "sandbox.bad_type",
                f"{where}: expected an array of shape {_shape_text(shape)}, got a ragged or non-numeric list",
            ) from None
    else:
        raise ParticipantFault(
            "sandbox.bad_type",
            f"{where}: expected an array of shape {_shape_text(shape)}, got {_describe(value)}",
        )
    if arr.dtype.kind not in "biuf":
        raise ParticipantFault("sandbox.bad_type", f"{where}: expected a real array, got {_describe(arr)}")
    got = tuple(arr.shape)
    if len(got) != len(shape) or any(d not in (None, -1) and d != g for d, g in zip(shape, got)):
        raise ParticipantFault(
            "sandbox.bad_shape", f"{where}: expected shape {_shape_text(shape)}, got {excerpt(got, 40)}"
        )
    return arr


def count_non_finite(value: Any, depth: int = 0) -> int:
    """Number of NaN or infinite numbers anywhere in ``value`` (arrays, lists, dicts, floats)."""
    if isinstance(value, float):
        return 0 if math.isfinite(value) else 1
    if isinstance(value, np.ndarray):
        return int(value.size - np.count_nonzero(np.isfinite(value))) if value.dtype.kind in "fc" else 0
    if depth < 64 and isinstance(value, list | tuple):
        return sum(count_non_finite(v, depth + 1) for v in value)
    if depth < 64 and isinstance(value, dict):
        return sum(count_non_finite(v, depth + 1) for v in value.values())
    return 0


def check_output(value: Any, *, shape: tuple | None, finite: bool, where: str) -> Any:
    """Apply the ``shape`` and ``finite`` checks of ``Sandbox.call`` and return the (converted) value.

    Raises:
        ParticipantFault: ``sandbox.bad_type``, ``sandbox.bad_shape`` or ``sandbox.non_finite``.
    """
    if shape is not None:
        value = as_array(value, tuple(shape), where)
    if finite:
        n = count_non_finite(value)
        if n:
            raise ParticipantFault(
                "sandbox.non_finite", f"{where}: output holds {n} non-finite value(s) (NaN or inf)"
            )
    return value
