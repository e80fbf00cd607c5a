"""Kitchen conventions the skills rely on (the same in every kitchen, measured in development): one
straight run of base units against the wall, the wall is the plane y = 0 and the units' fronts face -y at
y = ``FRONT_Y`` (the fridge's at -0.7 m); counter tops at ``COUNTER_Z``; the robot starts facing the wall
(heading ``FACING``). Every position is in the world frame [m], every angle in radians. Also the records
the skills pass between them (``Held``, ``Drawer``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

FACING = np.pi / 2
"""Base heading that faces the wall [rad]."""
FRONT_Y = -0.6
"""y of the base units' fronts [m]."""
COUNTER_Z = 0.92
"""Height of the counter tops [m]."""
LANE_Y = -1.45
"""Base y for long drives along the run: clear of open doors (up to 0.6 m out) and drawers [m]."""
STAND_Y = -1.25
"""Base y in front of a unit for work at its front (drawer handle, knobs, the open drawer's tray) [m]."""
SIDE_GAP = 0.16
"""Base centre's distance from the side of an open drawer when standing beside it [m]."""
BESIDE_Y = -0.81
"""Base y beside an open drawer, as near the units as the deck allows [m]."""
FINGER_CLEARANCE = 0.022
"""Least height of the tool above the support under a grasped object [m]."""
GRASP_DEPTH = 0.021
"""Grasp depth below the top of a flat-topped object [m] (the palm stays clear)."""
GRASP_DEPTH_ROUND = 0.03
"""Grasp depth below the top of a round object (fruit) [m]: the fingers reach its equator."""
EMPTY = 0.008
"""Finger opening [m] below which the closed fingers hold nothing."""
WORK_TORSO = 0.15
"""Torso height at the start and for work at the fronts of the units (drawer, knobs) [m]."""
PICK_TORSO = 0.15
"""Torso height for picking and placing [m]: the arm's root 1.0 m up, where it reaches the counter
tops far out without sagging."""
FAR_TURN = 1.45
"""Turn of the hand off the base's heading for a look along the run [rad]."""
FAR_PITCH = 0.5
"""Tilt below the horizontal of the eye-in-hand camera for a look along the run [rad]."""
ROAM = (-1.6, 1.6)
"""Offsets along the run from where ``find_far`` looks again when it saw nothing [m]."""
LOOK_PITCH = 1.1
"""Tilt below the horizontal of the eye-in-hand camera in the look pose [rad]."""

DOOR_Y = FRONT_Y - 0.021
"""y of a hinged base-cabinet door's hinge axis (the closed door's front face) [m]."""


@dataclass(frozen=True)
class Held:
    """An object in the hand: ``below`` is the tool's height above the object's lowest point [m]."""

    prompt: str
    below: float


@dataclass(frozen=True)
class Drawer:
    """An open drawer seen by ``Skills.find_open_drawer``.

    Attributes:
        x: Centre along the run [m].
        width: Width of its cabinet [m].
        front_y: y of the drawer front's outer face [m].
        handle_z: Height of its handle bar [m].
        floor_z: Height of the tray's floor [m].
        open_by: How far it is pulled out [m].
    """

    x: float
    width: float
    front_y: float
    handle_z: float
    floor_z: float
    open_by: float

    @property
    def tray(self) -> np.ndarray:
        """Centre (x, y) of the part of the tray in front of the counter top [m]."""
        return np.array([self.x, (self.front_y + 0.03 + FRONT_Y - 0.02) / 2])
