"""Knobs: find a burner's knob, grip it face-on and twist it on or off (``turn_knob``)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from .geometry import quat_mul
from .kitchen import FRONT_Y
from .perception import HAND, clean

if TYPE_CHECKING:
    from .skills import Skills

__all__ = ["turn_knob"]


FORWARD = np.array([np.cos(-np.pi / 4), np.sin(-np.pi / 4), 0.0, 0.0])
"""Tool z along world +y (into a unit's front), fingers closing along x."""
KNOB_STANDOFF = 0.15
"""Distance of the look-and-refine pose in front of a knob [m]."""
KNOB_BASE_Y = -1.15
"""Base y for work on the stove's knobs [m]."""


def _knob_refine(sk: Skills, prompt: str) -> np.ndarray | None:
    """Knob grip position [m] from the eye-in-hand camera looking at it face-on: the mask's median
    across, its front-most 30 % along the view."""
    pts = sk.see(prompt, cameras=(HAND,), tries=4)
    pts = clean(pts, 0.04)
    if len(pts) < 3:
        return None
    return np.array([np.median(pts[:, 0]), np.percentile(pts[:, 1], 30), np.median(pts[:, 2])])


def turn_knob(sk: Skills, burner: str, on: bool) -> bool:
    """Turn the ``burner`` ("front left" ...) knob on or off (a lit burner's knob stands at +0.9 rad about
    its axis, off within 0.35 rad of 0): find the knob (turning the look pose, else the stove first), stand in
    front of it, look at it face-on from ``KNOB_STANDOFF``, grip its bar and twist."""
    prompt = f"{burner} knob"
    lo, hi = (-np.inf, -np.inf, 0.6), (np.inf, FRONT_Y + 0.02, 1.0)
    pts = sk.find(prompt, lo, hi, turns=(0.0, 0.8, -0.8, 1.3, -1.3), radius=0.04)
    if len(pts) < 3:
        stove = sk.find("stove", (-np.inf, -np.inf, 0.3), (np.inf, 0.0, 1.0), radius=None)
        if len(stove) < 3:
            stove = sk.find_far("stove", (-np.inf, -np.inf, 0.3), (np.inf, 0.0, 1.0))
        if len(stove) < 3:
            sk.note("no stove in sight")
            return False
        sk.tuck()
        sk.goto(float(np.median(stove[:, 0])), KNOB_BASE_Y)
        pts = sk.find(prompt, lo, hi, radius=0.04)
        if len(pts) < 3:
            sk.note(f"no {prompt} in sight")
            return False
    knob = np.median(pts, axis=0)
    sk.note(f"{prompt} near {np.round(knob, 3)}")
    sk.tuck()
    sk.goto(float(knob[0]), KNOB_BASE_Y)
    sk.home()
    sk.motion.open_gripper(steps=2)
    sk.motion.move_tool(knob + [0.0, -KNOB_STANDOFF, 0.0], FORWARD, max_steps=200)
    fine = _knob_refine(sk, prompt)
    if fine is not None:
        knob = fine
    sk.motion.move_tool(knob, FORWARD, max_steps=100, speed=0.5)
    sk.motion.close_gripper(steps=8)
    # The tool turns about +y, the knob's axis points along -y: +0.7 takes an off knob (0) to -0.7 (on),
    # +0.9 takes a lit burner's knob (+0.9) back to 0 (off).
    twist = 0.7 if on else 0.9
    turn = np.array([np.cos(twist / 2), 0.0, np.sin(twist / 2), 0.0])
    sk.motion.move_tool(sk.obs["ee_pos"], quat_mul(turn, FORWARD), max_steps=60, gripper=1.0)
    sk.motion.open_gripper(steps=6)
    sk.motion.move_tool_by([0.0, -0.12, 0.0], max_steps=40)
    sk.note(f"turned {prompt} {'on' if on else 'off'} at {np.round(knob, 3)}")
    sk.tuck()
    return True
