"""Agent programs behind the shipped ledgers: they drive a metered session as an agent would.

Each program takes ``step`` (one metered action, e.g. ``LedgerClient.step``) and the observation of
a reset, and moves the arm only through ``rle_design.control.CartesianHelper``. **They read
privileged state the card withholds from agents**: the environment is served with
``privileged=True``, so observations carry each piece's pose and size (``bodies``, ``sizes``). Their
job is to show that the verifier gives full credit to a near-optimal scene built by real metered
actions, not to show how an agent perceives the pieces.

- ``harmonic_cantilever(scale)``: the four blocks as a harmonic stack, block k from the top
  overhanging the one below by ``scale`` x L/(2k); ``scale = 0.93`` is the reference (overhang
  0.93 x 25/24 L = 0.969 L, 0.83 of the optimum; at 0.97 the top block, 2 mm from its tipping point,
  fell in one of two trials), ``scale = 1.15`` the baseline past its tipping point.
- ``tower(plan, knock_over)``: stacks the pieces of a tower plan bottom-up at the build spot; with
  ``knock_over`` it then sweeps the arm through the tower.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from rle_design.control import CartesianHelper

DOWN = np.array([0.0, 0.7071067811865476, 0.7071067811865476, 0.0])
"""Tool orientation of the home posture: gripper pointing down, fingers closing along world y."""
CLEAR = 0.10
"""Height above a grasp or placement from which the arm descends [m]."""
GRIP_BELOW_TOP = 0.012
"""The tool site goes this far below a piece's top face to grasp it [m]."""


def _yaw_quat(yaw: float) -> np.ndarray:
    turn = np.array([np.cos(yaw / 2), 0.0, 0.0, np.sin(yaw / 2)])
    w1, x1, y1, z1 = turn
    w2, x2, y2, z2 = DOWN
    return np.array([
        w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2,
        w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
        w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2,
        w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2,
    ])  # fmt: skip


def pick_and_place(
    helper: CartesianHelper, name: str, goal: np.ndarray, yaw: float = 0.0, settle_steps: int = 10
) -> None:
    """Grasp piece ``name`` from above and put its centre at ``goal`` [m] with heading ``yaw`` [rad]."""
    pose = np.asarray(helper.obs["bodies"][name])
    half = np.asarray(helper.obs["sizes"][name])
    top = pose[2] + half[2]
    grip = np.array([pose[0], pose[1], top - GRIP_BELOW_TOP])
    quat = _yaw_quat(0.0)
    helper.move_to(grip + [0, 0, CLEAR], quat, tol_pos=0.005)
    helper.move_to(grip, quat, speed=0.5)
    helper.grasp()
    offset = np.asarray(helper.state["ee_pos"]) - np.asarray(helper.obs["bodies"][name])[:3]
    helper.move_to(grip + [0, 0, CLEAR], quat, tol_pos=0.005)
    place = np.asarray(goal, dtype=float) + offset + [0.0, 0.0, 0.002]
    helper.move_to(place + [0, 0, CLEAR / 2], _yaw_quat(yaw), tol_pos=0.004)
    # correct the residual of the carried piece against its measured pose before the last descent
    for _ in range(2):
        err = np.asarray(goal)[:2] - np.asarray(helper.obs["bodies"][name])[:2]
        place[:2] += err
        helper.move_to(place + [0, 0, CLEAR / 2], _yaw_quat(yaw), tol_pos=0.002)
    helper.move_to(place, _yaw_quat(yaw), speed=0.3, tol_pos=0.0015)
    helper.release()
    helper.wait(settle_steps)
    helper.move_to(np.asarray(helper.state["ee_pos"]) + [0, 0, CLEAR], _yaw_quat(yaw), tol_pos=0.005)


def harmonic_cantilever(
    step: Callable[[np.ndarray], dict[str, Any]], obs: dict[str, Any], edge_x: float, top_z: float,
    scale: float = 0.93,
) -> CartesianHelper:  # fmt: skip
    """Build the harmonic stack of the four blocks (bottom first) at the table edge ``edge_x``."""
    helper = CartesianHelper(step, obs)
    names = sorted(obs["bodies"])
    n = len(names)
    length = 2.0 * float(obs["sizes"][names[0]][0])
    height = 2.0 * float(obs["sizes"][names[0]][2])
    for level, name in enumerate(names):  # level 0 = bottom = k = n
        k = n - level
        right = edge_x + 0.5 * length * scale * sum(1.0 / j for j in range(k, n + 1))
        goal = np.array([right - length / 2, 0.0, top_z + height * (level + 0.5)])
        pick_and_place(helper, name, goal)
    helper.wait(20)
    return helper


def tower(
    step: Callable[[np.ndarray], dict[str, Any]], obs: dict[str, Any], plan: Sequence[tuple[str, float]],
    spot: tuple[float, float], top_z: float, knock_over: bool = False,
) -> CartesianHelper:  # fmt: skip
    """Stack ``plan`` ((piece, yaw) bottom-up, each resting on its spawn face) at ``spot`` (x, y)."""
    helper = CartesianHelper(step, obs)
    z = top_z
    for name, yaw in plan:
        half = np.asarray(helper.obs["sizes"][name])
        pick_and_place(helper, name, np.array([spot[0], spot[1], z + half[2]]), yaw)
        z += 2.0 * half[2]
    if knock_over:
        helper.move_to(np.array([spot[0], spot[1] - 0.2, top_z + 0.05]), DOWN, tol_pos=0.01)
        helper.move_to(np.array([spot[0], spot[1] + 0.2, top_z + 0.05]), DOWN, tol_pos=0.01, max_steps=60)
    helper.wait(20)
    return helper
