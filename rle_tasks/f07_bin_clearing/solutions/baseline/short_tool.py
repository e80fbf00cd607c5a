"""Baseline ``short_tool``: the reference policy believing the magnet's stem 100 mm shorter than it is
(a wrong tool calibration): its descents drive the stem through the pile into the bin (``N_bin``,
``N_damage``)."""

from . import ref
from .ref import act, make_policy, reset

ref.TOOL = ref.TOOL - 0.10

__all__ = ["act", "make_policy", "reset"]
