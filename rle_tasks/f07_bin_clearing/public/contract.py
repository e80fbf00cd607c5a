"""The policy contract, checked the same way by ``devrun`` and by the verifier.

``policy/__init__.py`` defines three functions, each answering within ``HANG_CAP_S``:

* ``make_policy()`` -> None: builds the policy once, after import;
* ``reset()`` -> None: start of a pile;
* ``act(obs: dict)`` -> an array of ``ACTION_SIZE`` finite numbers: seven joint-position targets [rad]
  then the magnet command in [0, 1] (``env.py`` documents ``obs``).

Return values cross a typed channel (numbers, strings, lists, dicts, NumPy arrays; no other objects):
``make_policy()`` and ``reset()`` should return None (what they return is ignored, but an object
that cannot cross the channel is refused: ``sandbox.bad_type``); ``act``'s result is checked for
type (``sandbox.bad_type``), shape (``sandbox.bad_shape``) and NaN or infinity
(``sandbox.non_finite``). In the evaluation the policy runs in a sandbox with 360 s of CPU time per
pile; a fault ends that pile where it stands.
"""

from __future__ import annotations

from typing import Any

from rle_design.excerpt import excerpt
from rle_design.sandbox import ParticipantFault
from rle_design.sandbox.checks import check_output
from rle_design.sandbox.codec import CodecError, encode_frame

ACTION_SIZE = 8
HANG_CAP_S = 30.0
"""Longest answer of one call [s]; the evaluation ends the pile (or, in the smoke test, the run)."""
FUNCTIONS: dict[str, tuple[int, ...] | None] = {"make_policy": None, "reset": None, "act": (ACTION_SIZE,)}
"""Function -> the shape its result must have (None: not checked beyond crossing the channel)."""


def check_return(name: str, value: Any) -> Any:
    """``value`` as the verifier would receive it from ``policy.<name>()``, or the fault it raises.

    Raises:
        ParticipantFault: ``sandbox.bad_type``, ``sandbox.bad_shape`` or ``sandbox.non_finite``.
    """
    where = f"policy.{name}()"
    try:
        encode_frame({}, value)
    except CodecError as exc:
        raise ParticipantFault("sandbox.bad_type", f"{where}: {excerpt(f'cannot return {exc}')}") from None
    shape = FUNCTIONS[name]
    return check_output(value, shape=shape, finite=shape is not None, where=where)


__all__ = ["ACTION_SIZE", "FUNCTIONS", "HANG_CAP_S", "check_return"]
