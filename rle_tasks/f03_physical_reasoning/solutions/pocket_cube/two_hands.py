"""The reference's moves, the cube in the air: the left hand holds the bottom half, the right wrist turns the top.

All moves are ordinary metered actions of both arms (``TwoHands``); no cube pose is read.

- ``take_up``: the right hand pinches the resting cube across both layers (its +-y faces at the
  centre height), lifts it ``HOLD_LIFT`` above its stand and hands it to the left (``to_left``):
  the left hand comes in horizontally from -x (pointing +x, fingers closing along y), pinches the
  bottom layer's +-y faces on its -x cubies (``LEFT_PAD``), and the right hand lets go.
- ``turn``: the right hand comes down over the cube, pinches the top layer's +-y faces and turns its
  wrist about the vertical in 5-degree target steps to 90 degrees while the left hand holds the
  bottom layer; then it opens, rises and turns back.
- ``pitch_y`` (the whole cube +90 deg about world y, the -x face to the top) and ``yaw`` (+90 deg
  about the vertical): the right hand takes the cube across both layers from above (``to_right``),
  the left hand lets go and backs off, the right wrist turns about its pinch axis (y) or the
  vertical, and the left hand takes the new bottom layer. These are the hand-offs that reorient the
  cube; with ``turn`` they reach every state.
- ``finish``: the right hand takes the cube and holds it still in the air ("held above the table").

Geometry and forces (measured with the shipped scene):

- The left arm reaches a horizontal pinch only with the cube high above the table: pointing +x at the
  cube's resting height, or 0.22 m above it, drives its joints 4 and 6 to their limits; hence
  ``HOLD_LIFT``. A pinch tilted 30-45 deg from the vertical is reachable lower, but its palm then
  meets the top layer.
- The hands pinch gently. A full 20 N pinch of one layer, whose contacts sit 16-22 mm off the core,
  tilts its cubies on their ball joints (measured: 40 deg with the left hand, 44 deg with the right).
  2-4 N per finger holds the 64 g cube and the layer detent with margin: friction 2 x 1.0 x 2 N = 4 N
  against 0.63 N of weight, and a friction couple about the turn axis of 2 x 2 N x 0.032 m = 0.128 N m
  against the detent's 4 x 4e-3 N m.
- The y pitch turns the cube with the right wrist so that its palm ends on the +x side, away from the
  left hand. The -90 deg pitch of the one-hand solve would leave it on the -x side, where the left
  hand comes in.
- Tried and not kept: an x pitch by the left wrist, which rolls the cube about its approach axis. The
  right hand must then take the cube from the +x side by one x half, and the cube swung 3-5 mm about
  that pinch or, pinched harder, kept a 4 deg layer offset. It failed 4 of 6 public scrambles; the
  yaw reaches the same states.

Public geometry only (stand top at z = 0.81 m, the 64 mm cube centred on it).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from rle_design.control import ArmGroup, CartesianHelper

from ...cube.env import ARM_ACTION
from .top_turns import ABOVE, CENTRE_Z, STEP_DEG, _about

HOLD_LIFT = 0.5
"""Height of the held cube's centre above its resting centre while the left hand holds it [m] (the
horizontal pinch is within the left arm's joint limits from about 0.4 m up)."""
LEFT_PAD = (-0.016, -0.022)
"""Left pinch centre relative to the cube's centre, (x, z) [m]: on the bottom layer's -x cubies. A
Panda finger is 21 mm wide, so lying flat on a 32 mm layer it keeps 11 mm from the layer boundary this
low (its lower edge passes under the cube), and 6 mm from the right hand's fingertips (``WHOLE_Z``)."""
GENTLE = -0.5
"""Gripper command of a holding pinch [-1 open, +1 closed]: finger targets 2 mm inside the 64 mm cube's
faces (opening 0.04 (1 - g) / 2 = 0.030 m per finger), 1000 N/m x 2 mm = 2 N per finger."""
LEFT_GRIP = -0.4
"""Gripper command of the left hand's holding pinch: 4 mm inside the faces, 4 N per finger. The cube's
centre is 16 mm off this pinch along x, so its weight turns it about the pinch axis with 0.63 N x
0.016 m = 0.01 N m; at ``GENTLE`` it swung down 4-8 mm after some hand-offs (measured), putting the
left pads on the layer boundary; 4 N holds it (all six public scrambles solved, against none at 2 N)."""
WHOLE_Z = 0.004
"""Right pinch centre above the cube's centre when it holds both layers [m]: its pads (16 mm) span the
layer boundary; its fingertips reach 9 mm past the pinch centre."""
TOP_Z = 0.020
"""Right pinch centre above the cube's centre for a top-layer turn [m]: the fingertips reach 11 mm past
the pinch centre, so they stop 9 mm above the layer boundary."""
LEFT_BACK = 0.08
"""Left hand's stand-off along its approach axis before and after its pinch [m]."""
ARMS = {"left": 0, "right": 1}
"""Index of each arm in the 14-D action."""
LEFT_ANGLE = math.pi / 2
"""Left approach tilt from pointing down [rad]: horizontal."""


class TwoHands(ArmGroup):
    """Both arms of one session (``ArmGroup``), named, with their home orientations."""

    def __init__(self, step: Any, obs: dict[str, Any]) -> None:
        super().__init__(step, obs, n_arms=2, arm_size=ARM_ACTION)
        self.home_left = np.asarray(obs["arms"][0]["ee_quat"], dtype=float)
        self.home_right = np.asarray(obs["arms"][1]["ee_quat"], dtype=float)

    def arm(self, which: str) -> CartesianHelper:  # type: ignore[override]
        return super().arm(ARMS[which])

    @property
    def left_pinch(self) -> np.ndarray:
        """Left hand orientation of the horizontal pinch (home turned about world y)."""
        return _about(self.home_left, (0.0, 1.0, 0.0), -LEFT_ANGLE)

    @property
    def left_approach(self) -> np.ndarray:
        """Unit vector along which the left hand comes in."""
        return np.array([math.sin(LEFT_ANGLE), 0.0, -math.cos(LEFT_ANGLE)])


def _centre(lifted: bool) -> np.ndarray:
    return np.array([0.0, 0.0, CENTRE_Z + (HOLD_LIFT if lifted else 0.0)])


def _turn_about(
    helper: CartesianHelper, pos: np.ndarray, start: np.ndarray, axis: tuple, angle: float
) -> None:
    """Turn ``helper``'s hand about the world ``axis`` through its tool site at ``pos`` by ``angle`` [rad]
    from orientation ``start``, in ``STEP_DEG`` target steps, and settle."""
    n = int(round(abs(math.degrees(angle)) / STEP_DEG))
    for k in range(1, n + 1):
        helper.move_to(pos, _about(start, axis, angle * k / n), tol_pos=0.01, tol_rot=0.05, max_steps=6)
    helper.move_to(pos, _about(start, axis, angle), tol_pos=0.004, tol_rot=0.02, max_steps=60)


def take_up(hands: TwoHands) -> None:
    """The right hand lifts the resting cube off its stand (its +-y faces, across both layers) to the
    holding height; the left hand takes its bottom layer (``to_left``)."""
    rest, held = _centre(False), _centre(True)
    right = hands.arm("right")
    right.move_to(rest + [0, 0, ABOVE], hands.home_right, tol_pos=0.01, max_steps=200)
    right.move_to(rest, hands.home_right, tol_pos=0.004, max_steps=200)
    right.set_gripper(GENTLE, 15)
    right.move_to(held, hands.home_right, speed=0.5, tol_pos=0.004, max_steps=300)
    to_left(hands, away=np.array([0.0, 0.0, 1.0]))


def to_left(hands: TwoHands, away: np.ndarray) -> None:
    """Hand-off to the left: the left hand pinches the bottom layer of the cube the right hand holds at
    the holding point; the right hand opens, backs off along ``away`` and returns above the cube."""
    held = _centre(True)
    left = hands.arm("left")
    pad = held + [LEFT_PAD[0], 0.0, LEFT_PAD[1]]
    left.move_to(pad - LEFT_BACK * hands.left_approach, hands.left_pinch, tol_pos=0.01, max_steps=300)
    left.move_to(pad, hands.left_pinch, tol_pos=0.003, max_steps=200)
    left.set_gripper(LEFT_GRIP, 15)
    right = hands.arm("right")
    right.release()
    here = np.asarray(right.state["ee_pos"], dtype=float)
    right.move_to(here + ABOVE * away, None, tol_pos=0.01, max_steps=100)
    right.move_to(held + [0, 0, ABOVE], hands.home_right, tol_pos=0.01, max_steps=200)


def to_right(hands: TwoHands) -> None:
    """Hand-off to the right: the right hand pinches the cube at the holding point across both layers by
    its +-y faces; the left hand opens and backs off."""
    centre = _centre(True)
    right = hands.arm("right")
    right.move_to(centre + [0, 0, WHOLE_Z + ABOVE / 2], hands.home_right, tol_pos=0.01, max_steps=200)
    right.move_to(centre + [0, 0, WHOLE_Z], hands.home_right, tol_pos=0.003, max_steps=200)
    right.set_gripper(GENTLE, 15)
    left = hands.arm("left")
    left.release()
    here = np.asarray(left.state["ee_pos"], dtype=float)
    left.move_to(here - LEFT_BACK * hands.left_approach, None, tol_pos=0.01, max_steps=200)


def turn(hands: TwoHands, sense: float) -> None:
    """One quarter turn of the top layer (``sense`` > 0 counter-clockwise seen from above) while the left
    hand holds the bottom layer."""
    top = _centre(True) + [0, 0, TOP_Z]
    right = hands.arm("right")
    right.move_to(top + [0, 0, ABOVE / 2], hands.home_right, tol_pos=0.01, max_steps=200)
    right.move_to(top, hands.home_right, tol_pos=0.003, max_steps=200)
    right.set_gripper(GENTLE, 15)
    for k in range(1, int(round(90.0 / STEP_DEG)) + 1):
        quat = _about(hands.home_right, (0.0, 0.0, 1.0), math.copysign(math.radians(k * STEP_DEG), sense))
        right.move_to(top, quat, tol_pos=0.02, tol_rot=0.05, max_steps=6)
    right.release()
    right.move_to(top + [0, 0, ABOVE / 2], None, tol_pos=0.01, max_steps=100)
    right.move_to(top + [0, 0, ABOVE / 2], hands.home_right, tol_pos=0.01, max_steps=100)


def pitch_y(hands: TwoHands) -> None:
    """Whole cube +90 deg about world y (the -x face comes on top): the right hand takes it and turns its
    wrist about its pinch axis (its palm ends on the +x side, away from the left hand), the left hand
    takes the new bottom layer."""
    to_right(hands)
    right = hands.arm("right")
    pinch = _centre(True) + [0, 0, WHOLE_Z]
    _turn_about(right, pinch, hands.home_right, (0.0, 1.0, 0.0), math.pi / 2)
    # the cube turned about the pinch centre, WHOLE_Z above its own, so its centre is now WHOLE_Z
    # beside it along -x: bring the centre back to the holding point
    right.move_to(pinch + [WHOLE_Z, 0.0, -WHOLE_Z], None, tol_pos=0.003, max_steps=100)
    to_left(hands, away=np.array([1.0, 0.0, 0.0]))


def yaw(hands: TwoHands, sense: float = 1.0) -> None:
    """Whole cube 90 deg about the vertical (``sense`` > 0 counter-clockwise seen from above): the right
    hand takes it across both layers and turns its wrist; the left hand takes the new bottom layer."""
    to_right(hands)
    right = hands.arm("right")
    pinch = _centre(True) + [0, 0, WHOLE_Z]
    _turn_about(right, pinch, hands.home_right, (0.0, 0.0, 1.0), math.copysign(math.pi / 2, sense))
    to_left(hands, away=np.array([0.0, 0.0, 1.0]))


def finish(hands: TwoHands) -> None:
    """The right hand takes the cube across both layers and holds it still in the air."""
    to_right(hands)
    hands.arm("right").wait(30)


def solve(env: Any, senses: tuple[float, ...] = (1.0,)) -> None:
    """Building block: quarter turns of the top layer with both hands, the cube held up at the end."""
    hands = TwoHands(env.step, env.reset())
    take_up(hands)
    for sense in senses:
        turn(hands, sense)
    finish(hands)
