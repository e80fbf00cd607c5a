"""Baseline of ``03-pocket-cube``: a pitch the arm cannot follow, which forces an illegal twist.

The right hand pinches the cube at its centre, lifts it 35 mm and turns its wrist +90 degrees about
world y, one hand turning the whole cube just above its stand. The arm cannot keep the pinch point in that
posture: the hand sinks and drives the cube against the stand, the layers are forced and the cube
settles in a state that is no quarter or half turn of one layer from the last (an unclassified
transition, measured), off its stand. Expected: score 0, the report lists the ``unclassified`` cap.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from rle_design.control import CartesianHelper

from ...cube.env import ARM_ACTION
from .top_turns import ABOVE, CENTRE_Z, PITCH_LIFT, STEP_DEG, _about


def solve(env: Any) -> None:
    obs = env.reset()
    right = CartesianHelper(env.step, obs, arm=1, n_arms=2, arm_size=ARM_ACTION)
    home = np.asarray(obs["arms"][1]["ee_quat"], dtype=float)
    centre = np.array([0.0, 0.0, CENTRE_Z])
    right.move_to(centre + [0, 0, ABOVE], home, tol_pos=0.01, max_steps=200)
    right.move_to(centre, home, tol_pos=0.004, max_steps=200)
    right.grasp()
    right.move_to(centre + [0, 0, PITCH_LIFT], home, speed=0.3, tol_pos=0.004, max_steps=200)
    for k in range(1, int(round(90.0 / STEP_DEG)) + 1):
        quat = _about(home, (0.0, 1.0, 0.0), math.radians(k * STEP_DEG))
        right.move_to(centre + [0, 0, PITCH_LIFT], quat, tol_pos=0.01, tol_rot=0.05, max_steps=6)
    right.move_to(centre + [0, 0, 0.002], None, speed=0.3, tol_pos=0.003, max_steps=200)
    right.release()
    right.move_to(centre + [0, 0, ABOVE + 0.02], None, tol_pos=0.01, max_steps=100)
    right.wait(20)
