"""Baseline ``floor_dropper``: the reference policy with its drop point over the floor between the bin
and the conveyor (a wrong nest calibration): every part it picks lands on the floor (``N_floor``)."""

from . import ref
from .ref import act, make_policy, reset

ref.NEST[:] = (0.45, -0.25, 0.60 + ref.TOOL)

__all__ = ["act", "make_policy", "reset"]
