"""Top-layer turns and whole-cube pitches by the right hand: the moves of the reference solve.

Per quarter turn: the right hand comes down over the cube (pointing down, fingers closing along world y),
pinches the top layer's two side faces at mid-height of the layer, and turns its wrist about the
vertical in 5-degree target steps to 90 degrees; the stand's friction and the layer detent keep the
bottom layer in place. Then the hand opens, rises and turns back. A positive ``sense`` turns
counter-clockwise seen from above (``U'`` in the frame of a cube whose DBL cubie is home), a negative
one clockwise (``U``). With ``lift`` the hand finally pinches the cube across both layers (at its centre
height) and lifts it 20 mm off its stand and holds it still (the end predicate's "held above the table").

A pitch (``pitch``) turns the whole cube -90 degrees about world y (the face at +x comes on top) or x
(the face at -y comes on top): the hand pinches the two faces normal to that axis across both layers at
the cube's centre height, lifts it 35 mm (its corners then clear
the stand while it turns), turns its wrist about the finger axis in 5-degree steps, sets it back on the
stand, opens and rises.

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
"""Lift before a pitch [m]: the turning cube's corners reach 45 mm below its centre, the stand top is
32 mm below it when resting."""


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


def pitch(right: CartesianHelper, home_quat: np.ndarray, axis: str = "y") -> None:
    """Turn the whole cube -90 deg about world ``axis`` ("y": the +x face to the top; "x": the -y face
    to the top); ends open above the cube. The hand pinches the faces normal to ``axis`` (for "x" it
    first yaws 90 deg), so the cube turns about the pinch axis."""
    centre = np.array([0.0, 0.0, CENTRE_Z])
    grip = grip_quat(home_quat, axis)
    about = (0.0, 1.0, 0.0) if axis == "y" else (1.0, 0.0, 0.0)
    right.move_to(centre + [0, 0, ABOVE], grip, tol_pos=0.01, max_steps=200)
    right.move_to(centre, grip, tol_pos=0.004, max_steps=200)
    right.grasp()
    right.move_to(centre + [0, 0, PITCH_LIFT], grip, speed=0.3, tol_pos=0.004, max_steps=200)
    for k in range(1, int(round(90.0 / STEP_DEG)) + 1):
        quat = _about(grip, about, -math.radians(k * STEP_DEG))
        right.move_to(centre + [0, 0, PITCH_LIFT], quat, tol_pos=0.01, tol_rot=0.05, max_steps=6)
    quat = _about(grip, about, -math.pi / 2)
    right.move_to(centre + [0, 0, PITCH_LIFT], quat, tol_pos=0.004, tol_rot=0.02, max_steps=60)
    # set it down pressing 1 mm into the stand: released from 2 mm above, it is pushed sideways and the
    # rising fingers drag it off the stand (measured on the fourth pitch of a plan)
    right.move_to(centre + [0, 0, -0.001], None, speed=0.3, tol_pos=0.003, max_steps=200)
    right.release()
    right.move_to(centre + [0, 0, ABOVE + 0.02], None, tol_pos=0.01, max_steps=100)
    right.move_to(centre + [0, 0, ABOVE + 0.02], home_quat, tol_pos=0.01, max_steps=200)


def grip_quat(home_quat: np.ndarray, axis: str) -> np.ndarray:
    """Hand orientation that pinches the faces normal to world ``axis`` ("y": home; "x": yawed 90 deg)."""
    return home_quat if axis == "y" else _about(home_quat, (0.0, 0.0, 1.0), math.pi / 2)


def hold_up(right: CartesianHelper, home_quat: np.ndarray, axis: str = "y") -> None:
    """Pinch the cube across both layers (the faces normal to ``axis``), lift it ``LIFT`` off its stand
    and hold it still.

    Pinch the faces the last pitch released: the bottom layer rests where that hand orientation left it
    (within its yaw error), and pads closing at another yaw turn the top layer against the bottom one,
    which the stand's friction holds (measured: 9.6 deg off the lattice after an ``x`` pitch pinched
    along y).
    """
    grasp = np.array([0.0, 0.0, CENTRE_Z])
    quat = grip_quat(home_quat, axis)
    right.move_to(grasp + [0, 0, ABOVE], quat, tol_pos=0.01, max_steps=200)
    right.move_to(grasp, quat, tol_pos=0.004, max_steps=200)
    right.grasp()
    right.move_to(grasp + [0, 0, LIFT], quat, speed=0.3, tol_pos=0.003, max_steps=200)
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
