"""Evaluation items drawn from a generator: independent frame groups and kinematic push episodes.

A frame group is ten independent frames (block pose and shape uniform over the workspace, the stick
either beside the block, where it may occlude it, or raised out of the way). A push episode is up to
60 frames at ``FRAME_DT``: the block slides along a gently curving path while turning, and the stick
tip stays in contact behind it (quasi-static pushing, kinematic). Everything is a pure function of
the generator, so the same seed gives the same item.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .scene import STICK_RADIUS, TIP_HEIGHT, BlockPose
from .shapes import BLOCKS

FRAME_DT = 0.1
"""Time between trajectory frames [s] (10 Hz camera)."""
WORKSPACE = ((-0.12, 0.14), (-0.14, 0.14))
"""Ranges of block x and y in independent frames [m]."""
RAISED_TIP = (-0.2, 0.0, 0.25)
"""Stick tip position when the stick is out of the way [m]."""
NEAR_FRACTION = 0.6
"""Share of independent frames with the stick beside the block."""


@dataclass(frozen=True)
class FrameSpec:
    """One frame to render.

    Attributes:
        pose: Block pose and shape (the label).
        tip: Stick tip position [m].
        t: Time stamp [s].
    """

    pose: BlockPose
    tip: tuple[float, float, float]
    t: float


def wrap(theta: float | np.ndarray) -> float | np.ndarray:
    """Angle wrapped to [-pi, pi) [rad]."""
    return (np.asarray(theta) + math.pi) % (2 * math.pi) - math.pi


def support(shape: int, theta: float, direction: np.ndarray) -> float:
    """Largest extent of the footprint of ``shape`` at rotation ``theta`` along a unit ``direction`` [m]."""
    c, s = math.cos(theta), math.sin(theta)
    best = -math.inf
    for cx, cy, hx, hy in BLOCKS[shape].boxes_in_frame():
        for sx in (-1, 1):
            for sy in (-1, 1):
                px, py = cx + sx * hx, cy + sy * hy
                best = max(best, (c * px - s * py) * direction[0] + (s * px + c * py) * direction[1])
    return best


def contact_tip(pose: BlockPose, push_dir: np.ndarray, gap: float = 0.002) -> tuple[float, float, float]:
    """Stick tip behind the block for a push along ``push_dir`` (unit, world xy) [m]."""
    d = support(pose.shape, pose.theta, -push_dir) + STICK_RADIUS + gap
    return (pose.x - d * push_dir[0], pose.y - d * push_dir[1], TIP_HEIGHT)


def frame_group(rng: np.random.Generator, n: int = 10) -> list[FrameSpec]:
    """``n`` independent frames."""
    out = []
    for _ in range(n):
        pose = BlockPose(
            float(rng.uniform(*WORKSPACE[0])),
            float(rng.uniform(*WORKSPACE[1])),
            float(wrap(rng.uniform(-math.pi, math.pi))),
            int(rng.integers(0, 3)),
        )
        phi = rng.uniform(-math.pi, math.pi)
        near = rng.random() < NEAR_FRACTION
        if near:
            tip = contact_tip(
                pose, np.array([math.cos(phi), math.sin(phi)]), gap=float(rng.uniform(0.002, 0.03))
            )
        else:
            tip = RAISED_TIP
        out.append(FrameSpec(pose, tip, 0.0))
    return out


def push_episode(rng: np.random.Generator, n: int = 60) -> list[FrameSpec]:
    """A push of ``n`` frames: speed 2-4 cm/s, turn rate up to 0.5 rad/s, path curvature up to 0.3 rad/s."""
    shape = int(rng.integers(0, 3))
    phi0 = rng.uniform(-math.pi, math.pi)
    speed = rng.uniform(0.02, 0.04)
    omega = rng.uniform(-0.5, 0.5)
    kappa = rng.uniform(-0.3, 0.3)
    theta0 = rng.uniform(-math.pi, math.pi)
    duration = n * FRAME_DT
    # start so that the path's midpoint lies near the workspace centre
    centre = np.array([0.01, 0.0]) + rng.uniform(-0.03, 0.03, 2)
    start = centre - 0.5 * speed * duration * np.array([math.cos(phi0), math.sin(phi0)])
    pos, out = start.copy(), []
    for k in range(n):
        t = k * FRAME_DT
        phi = phi0 + kappa * t
        direction = np.array([math.cos(phi), math.sin(phi)])
        pose = BlockPose(float(pos[0]), float(pos[1]), float(wrap(theta0 + omega * t)), shape)
        out.append(FrameSpec(pose, contact_tip(pose, direction), float(t)))
        pos = pos + speed * FRAME_DT * direction
    return out
