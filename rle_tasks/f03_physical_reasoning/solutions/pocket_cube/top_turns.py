"""Top-layer turns by the right hand alone, the cube on its stand: the building block ``top_turns``.

Per quarter turn: the right hand comes down over the cube (pointing down, fingers closing along world y),
pinches the top layer's two side faces at mid-height of the layer, and turns its wrist about the
vertical in 5-degree target steps to 90 degrees; the stand's friction and the layer detent keep the
bottom layer in place. Then the hand opens, rises and turns back. A positive ``sense`` turns
counter-clockwise seen from above (``U'`` in the frame of a cube whose DBL cubie is home), a negative
one clockwise (``U``). With ``lift`` the hand finally pinches the cube across both layers (at its centre
height) and lifts it 20 mm off its stand and holds it still (the end predicate's "held above the table").
The reference (``reference``, ``two_hands``) holds the bottom layer with the left hand instead.

Public geometry only (stand top at z = 0.81 m, the 64 mm cube centred on it); no cube pose is read.
The left arm stays at home.
"""

from __future__ import annotations

import math
from typing import Any

import mujoco
import numpy as np

from rle_design.control import CartesianHelper

from ...cube.env import ARM_ACTION

TOP_Z = 0.858
"""Mid-height of the top layer when the cube rests on its stand [m] (0.81 + 0.032 + 0.016)."""
ABOVE = 0.08
"""Clearance above the grasp height for the approach and the retreat [m]."""
STEP_DEG = 5.0
"""Wrist target increment per move [deg]."""
LIFT = 0.02
"""Final lift of the held cube [m]."""
CENTRE_Z = 0.842
"""Height of the resting cube's centre [m]: the final pinch spans both layers (pads 16 mm tall)."""
PITCH_LIFT = 0.035
"""Lift before turning the whole cube on its stand (``forced_twist``) [m]: the turning cube's corners reach
45 mm below its centre, the stand top is 32 mm below it when resting."""


def _about(quat: np.ndarray, axis: tuple[float, float, float], angle: float) -> np.ndarray:
    """``quat`` (w, x, y, z) turned by ``angle`` [rad] about the world ``axis``."""
    about = np.zeros(4)
    mujoco.mju_axisAngle2Quat(about, np.array(axis), angle)
    out = np.zeros(4)
    mujoco.mju_mulQuat(out, about, quat)
    return out


def quarter_turn(right: CartesianHelper, home_quat: np.ndarray, sense: float) -> None:
    """One top-layer quarter turn with the right hand, ending open above the cube at ``home_quat``."""
    grasp = np.array([0.0, 0.0, TOP_Z])
    right.move_to(grasp + [0, 0, ABOVE], home_quat, tol_pos=0.01, max_steps=200)
    right.move_to(grasp, home_quat, tol_pos=0.004, max_steps=200)
    right.grasp()
    for k in range(1, int(round(90.0 / STEP_DEG)) + 1):
        quat = _about(home_quat, (0.0, 0.0, 1.0), math.copysign(math.radians(k * STEP_DEG), sense))
        right.move_to(grasp, quat, tol_pos=0.02, tol_rot=0.05, max_steps=6)
    right.release()
    right.move_to(grasp + [0, 0, ABOVE], None, tol_pos=0.01, max_steps=100)
    right.move_to(grasp + [0, 0, ABOVE], home_quat, tol_pos=0.01, max_steps=100)


def hold_up(right: CartesianHelper, home_quat: np.ndarray) -> None:
    """Pinch the cube across both layers, lift it ``LIFT`` off its stand and hold it still."""
    grasp = np.array([0.0, 0.0, CENTRE_Z])
    right.move_to(grasp + [0, 0, ABOVE], home_quat, tol_pos=0.01, max_steps=200)
    right.move_to(grasp, home_quat, tol_pos=0.004, max_steps=200)
    right.grasp()
    right.move_to(grasp + [0, 0, LIFT], home_quat, speed=0.3, tol_pos=0.003, max_steps=200)
    right.wait(30)


def solve(env: Any, senses: tuple[float, ...] = (1.0,), lift: bool = True) -> None:
    obs = env.reset()
    right = CartesianHelper(env.step, obs, arm=1, n_arms=2, arm_size=ARM_ACTION)
    home_quat = np.asarray(obs["arms"][1]["ee_quat"], dtype=float)
    for sense in senses:
        quarter_turn(right, home_quat, sense)
    right.wait(20)
    if lift:
        hold_up(right, home_quat)
