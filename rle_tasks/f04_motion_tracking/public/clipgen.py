"""Generated reference clips in five styles: keyframes for the root and upper body, footsteps for
the feet, leg inverse kinematics for the contacts.

Each style is a ``MotionPlan``: per foot a list of stances (time interval, foothold, yaw), a root
trajectory (pelvis position and roll/pitch/yaw) and upper-body joint angles as functions of time.
Between two stances a foot swings on a minimum-jerk path with a vertical arc. Every 50 Hz frame,
``LegIK`` places the feet (stance: on the ground, flat); the clip's body poses are the forward
kinematics of the result. Run and sprint have flight phases in which the pelvis translation is
ballistic: constant horizontal velocity and ``z'' = -g``; in stance the pelvis height follows a cubic
Hermite segment joining the landing and take-off velocities. Plans that stay on their feet (dance,
fight, fall-getup) are then balanced: the pelvis is moved so that the zero-moment point stays on the stance sole
(``balance``), which makes the clip physically trackable.

The plan and its keying primitives are in ``motion_plan``, the kinematic keying (leg IK, swings) in
``keying``, the balancing and the zero-moment point in ``balance``; ``generate`` joins them.
"""

from __future__ import annotations

import mujoco

from .balance import balance
from .clip import CLIP_FPS, Clip
from .keying import _kinematic
from .motion_plan import CLIP_SECONDS, MotionPlan

__all__ = ["generate"]


def generate(
    model: mujoco.MjModel, plan: MotionPlan, seconds: float = CLIP_SECONDS, fps: float = CLIP_FPS
) -> Clip:
    """The clip of a plan (``model``: the free-base G1), balanced (``balance``) when ``plan.balanced``.

    Raises:
        ValueError: A stance foot could not be placed within 0.1 mm (the plan is out of reach).
    """
    if plan.refine is not None:
        return plan.refine(model, plan, seconds, fps)
    clip = _kinematic(model, plan, seconds, fps)
    return balance(model, plan, clip, seconds, fps) if plan.balanced else clip
