"""The ``03-hidden-com`` scene, its metered environment and the answer protocol.

Scene: the tabletop of ``rle_design.scene.tabletop`` (one Panda at (-0.05, 0), table top at
z = 0.75 m) and three sealed boxes (``scene``) resting with their centres at ``BOX_XY``;
each box's heading is a multiple of 90 deg and its ballast quadrant one of A..D, both drawn from the
secret (``HiddenComInstance.draw``). The observation is the tabletop's: the arm's state and three RGB
views (``IMAGE_SIZE``), no object pose, force, contact or mass reading; plus ``answers``.

Answer protocol: an action whose **mode** entry (index 11) is above 0.5 is an answer. Its base-x
entry (index 7) names the box (-1, 0, +1 for boxes 0, 1, 2; nearest within 0.25) and its torso entry
(index 10) the quadrant (-0.75, -0.25, 0.25, 0.75 for A, B, C, D; nearest within 0.125);
``answer_action`` builds one. The first valid answer for a box is final (irreversible); later answers
for it and malformed answer actions are ignored and counted (``invalid``).

Step split (the card's "12,000 steps per box"): the charged steps since the session's start or the
last accepted answer are counted, resets and the answer action included; an answer given after more
than ``STEPS_PER_BOX`` of them is late, refused and counted (``late``), so the box it names stays
unanswered. Working box by box, each box gets its 12,000 steps and unused steps do not carry over.

Answers and counters live in ``MjData.userdata`` (answers 0 none, 1..4 for A..D; all survive resets),
so the ledger's replay reproduces them. The observation ``answers`` = {``given``: 3 booleans,
``invalid``: int, ``late``: int, ``steps_left``: steps before the next answer is late} gives no
correctness feedback.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import mujoco
import numpy as np

from rle_design.control import TabletopEnv
from rle_design.control.layout import ACTION_SIZE, BASE, GRIPPER, MODE, TORSO
from rle_design.scene.tabletop import TabletopConfig, build_tabletop, finish

from ..constants import N_BOXES, STEPS_PER_BOX
from .scene import QUADRANTS, BoxParams, add_box, box_name

TABLE = TabletopConfig()
BOX_XY = ((0.30, -0.20), (0.36, 0.0), (0.30, 0.20))
"""Box centres on the table (x, y) [m] (published)."""
IMAGE_SIZE = (240, 320)
"""RGB size (H, W) [px]: a corner patch spans about 5 px in the top view."""
BOX_CODES = (-1.0, 0.0, 1.0)
QUADRANT_CODES = (-0.75, -0.25, 0.25, 0.75)
INVALID = N_BOXES
"""``MjData.userdata`` index of the ignored-answer counter (0..2 hold the answers)."""
LATE = N_BOXES + 1
"""``MjData.userdata`` index of the late-answer counter."""
SINCE = N_BOXES + 2
"""``MjData.userdata`` index of the charged steps since the start or the last accepted answer."""


@dataclass(frozen=True)
class HiddenComInstance:
    """The secret part of a scene.

    Attributes:
        quadrants: Ballast quadrant of each box ("A".."D").
        yaws: Heading of each box, in quarter turns (0..3).
    """

    quadrants: tuple[str, ...]
    yaws: tuple[int, ...]

    @classmethod
    def draw(cls, rng: np.random.Generator) -> HiddenComInstance:
        """Quadrants and headings uniform and independent per box."""
        quads = tuple(QUADRANTS[int(k)] for k in rng.integers(4, size=N_BOXES))
        yaws = tuple(int(k) for k in rng.integers(4, size=N_BOXES))
        return cls(quads, yaws)

    def box(self, i: int) -> BoxParams:
        return BoxParams(quadrant=self.quadrants[i])


def scene_xml(instance: HiddenComInstance) -> str:
    """MJCF of the full scene with keyframe ``initial``."""
    spec = build_tabletop(TABLE)
    for i, (x, y) in enumerate(BOX_XY):
        add_box(spec, box_name(i), instance.box(i), (x, y, TABLE.top_z), yaw=instance.yaws[i] * math.pi / 2)
    spec.nuserdata = N_BOXES + 3
    finish(spec, TABLE)
    return spec.to_xml()


def answer_action(box: int, quadrant: str) -> np.ndarray:
    """The 12-D action that answers ``quadrant`` for ``box`` (arm held, gripper open)."""
    a = np.zeros(ACTION_SIZE)
    a[GRIPPER] = -1.0
    a[MODE] = 1.0
    a[BASE.start] = BOX_CODES[box]
    a[TORSO] = QUADRANT_CODES[QUADRANTS.index(quadrant)]
    return a


def decode_answer(action: np.ndarray) -> tuple[int, str] | None:
    """(box, quadrant) of an answer action, or None when its codes are not valid."""
    box_v, quad_v = float(action[BASE.start]), float(action[TORSO])
    box = int(np.argmin([abs(box_v - c) for c in BOX_CODES]))
    quad = int(np.argmin([abs(quad_v - c) for c in QUADRANT_CODES]))
    if abs(box_v - BOX_CODES[box]) > 0.25 or abs(quad_v - QUADRANT_CODES[quad]) > 0.125:
        return None
    return box, QUADRANTS[quad]


def recorded_answers(data: mujoco.MjData) -> tuple[str | None, ...]:
    """The final answer per box (None: not answered)."""
    return tuple(QUADRANTS[int(v) - 1] if v >= 1 else None for v in data.userdata[:N_BOXES])


def answers_observation(model: mujoco.MjModel, data: mujoco.MjData) -> dict[str, Any]:
    """The ``answers`` observation: which boxes are answered, ignored and late answer actions
    (``HiddenComEnv.observe`` adds the steps left before the next answer is late)."""
    return {
        "given": [bool(v >= 1) for v in data.userdata[:N_BOXES]],
        "invalid": int(data.userdata[INVALID]),
        "late": int(data.userdata[LATE]),
    }


@dataclass(frozen=True)
class HiddenComEnv(TabletopEnv):
    """The tabletop environment with the answer protocol (module docstring)."""

    observers: tuple = (("answers", answers_observation),)
    image_size: tuple[int, int] | None = IMAGE_SIZE
    steps_per_box: int = STEPS_PER_BOX
    """Steps allowed between answers (tests shorten it; the task and its verifier use the card's)."""

    def reset(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        kept = data.userdata.copy()
        super().reset(model, data)
        data.userdata[:] = kept
        data.userdata[SINCE] += 1

    def observe(self, model: mujoco.MjModel, data: mujoco.MjData) -> dict[str, Any]:
        obs = super().observe(model, data)
        obs["answers"]["steps_left"] = max(0, self.steps_per_box - int(data.userdata[SINCE]))
        return obs

    def step(self, model: mujoco.MjModel, data: mujoco.MjData, ctrl: np.ndarray) -> None:
        action = np.nan_to_num(np.asarray(ctrl, dtype=float))
        data.userdata[SINCE] += 1
        if action[MODE] > 0.5:
            decoded = decode_answer(action)
            if decoded is None or data.userdata[decoded[0]] >= 1:
                data.userdata[INVALID] += 1
            elif data.userdata[SINCE] > self.steps_per_box:
                data.userdata[LATE] += 1
            else:
                data.userdata[decoded[0]] = QUADRANTS.index(decoded[1]) + 1
                data.userdata[SINCE] = 0
        super().step(model, data, ctrl)


def make_env(
    instance: HiddenComInstance,
    *,
    privileged: bool = False,
    image_size: tuple[int, int] | None = IMAGE_SIZE,
    camera_every: int = 10,
) -> HiddenComEnv:
    """The metered environment of ``instance`` (``privileged``: tests only; ``camera_every``: actions
    between renders, which leaves the scene and its ledger fingerprint unchanged)."""
    return HiddenComEnv(
        xml=scene_xml(instance), privileged=privileged, image_size=image_size, camera_every=camera_every
    )
