"""State-based scripted experts for LIBERO-10 (they make family 05's demonstrations).

An expert reads the simulator's state (``LiberoEnv.scene``: end effector, object poses and collision
boxes, region sites, articulated joints, the BDDL goal), never an image, and drives the robot through
the policy interface: 7-D OSC actions at 20 Hz. It turns each goal predicate into a skill:

- ``in``/``on`` object, region-or-object: pick the object from above (fingers across its narrower
  side where the hand fits, else at an angle or at its rim) and release it above the target;
- ``in`` a region behind a hinged door: pinch the object's outward part (a mug's handle) with the
  hand pointing through the opening, carry it in, back out;
- ``close`` a drawer: push it shut along its slide; a hinged door: swing it shut along its arc;
- ``turnon`` a stove: pinch the knob's bar and turn it about the knob's axis.

``supported(scene)`` tells whether every predicate of a task's goal has a skill: every LIBERO-10
task has (success rates per task in the README).

Each skill is a generator of actions; ``run_expert`` chains the skills of the goal in an order that
keeps them feasible (a drawer is filled before it is closed) and stops at success or the horizon.
Randomness (start jitter, grasp offsets) comes from the caller's seeded generator, so demonstrations
are reproducible.

The skills live in ``expert_place`` (``in``/``on``), ``expert_fixtures`` (``close``, ``turnon``),
``expert_grasp`` (grasp planning) and ``expert_motion`` (the driver, motion primitives, rotations).
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass

import numpy as np

from rle_tasks.envs.libero import LiberoEnv
from rle_tasks.envs.libero.expert_fixtures import _close_hinge, _close_slide, _door_front, _joint_of, _turn_on
from rle_tasks.envs.libero.expert_motion import OPEN, _Driver, _hold, _settle
from rle_tasks.envs.libero.expert_place import _pick_place, _through_door

__all__ = ["ExpertResult", "run_expert", "supported"]

SETTLE_STEPS = 20
"""Steps held after the last skill for released objects to come to rest (success is checked per step)."""


@dataclass(frozen=True)
class ExpertResult:
    success: bool
    steps: int
    actions: np.ndarray
    """(steps, 7) the actions sent."""
    log: tuple[str, ...] = ()
    """One line per skill: what it did and what it left (for statistics and debugging)."""
    sim_states: np.ndarray | None = None
    """(steps + 1, n) MuJoCo states before each action and after the last (when recorded)."""
    observations: np.ndarray | None = None
    """(steps + 1, 8) the policy's ``state`` observation at the same instants (when recorded)."""
    views: dict[str, np.ndarray] | None = None
    """``agentview`` and ``wrist``, uint8 (len(view_frames), H, W, 3): the images the policy would
    have seen at the frames ``view_frames`` (when recorded with a rendering environment)."""
    executed: np.ndarray | None = None
    """(steps, 7) the actions executed when noise was injected (``actions`` then holds the expert's
    clean actions: the labels); None without noise, when the two are the same."""
    view_frames: np.ndarray | None = None
    """Frames (0 .. steps) whose views were recorded: every ``view_every``-th (when views were)."""


def supported(scene: dict) -> bool:
    """Whether every predicate of the scene's goal has a skill: ``in``/``on``, ``close`` for drawers
    (slides) and hinged doors, ``turnon`` for hinged knobs."""
    for p in scene["goal"]:
        if p[0] == "close":
            try:
                _joint_of(scene, p[1])
            except NotImplementedError:
                return False
        elif p[0] == "turnon":
            try:
                if not scene["joints"][_joint_of(scene, p[1])]["hinge"]:
                    return False
            except NotImplementedError:
                return False
        elif p[0] not in ("in", "on"):
            return False
    return True


_ORDER = {"in": 0, "on": 0, "turnon": 1, "close": 2}
"""Skills run in this order: objects go into a drawer before it is closed."""


def _skills(d: _Driver, rng: np.random.Generator) -> Iterator[None]:
    goal = sorted(d.scene["goal"], key=lambda p: _ORDER.get(p[0], 9))
    targets = [p[2] for p in goal if p[0] in ("in", "on")]
    placed: dict[str, int] = {}
    for pred in goal:
        kind = pred[0]
        if kind in ("in", "on") and _door_front(d.scene, pred[2]) is not None:
            yield from _through_door(d, pred[1], pred[2], _door_front(d.scene, pred[2]), rng)
        elif kind in ("in", "on"):
            k = placed.get(pred[2], 0)
            placed[pred[2]] = k + 1
            yield from _pick_place(d, pred[1], pred[2], rng, (k, targets.count(pred[2])))
        elif kind == "close" and not d.scene["joints"][_joint_of(d.scene, pred[1])]["hinge"]:
            yield from _close_slide(d, pred[1])
        elif kind == "close":
            yield from _close_hinge(d, pred[1])
        elif kind == "turnon":
            yield from _turn_on(d, pred[1])
        else:
            raise NotImplementedError(f"no expert skill for predicate {pred}")


def run_expert(
    env: LiberoEnv,
    init_index: int,
    rng: np.random.Generator,
    *,
    record: bool = False,
    noise: float = 0.0,
    view_every: int = 1,
) -> ExpertResult:
    """One demonstration from the official initial state ``init_index`` (``env`` started); with
    ``record`` the MuJoCo state and the policy's state observation of every step are kept, and the
    two views when ``env`` renders. ``noise`` > 0 adds N(0, noise) to the six motion components of
    every executed action (action units) while the expert's own action is kept as the label (DART):
    the expert corrects the drift, so the data covers states a drifting policy visits. ``view_every``
    K > 1 records the views of frames 0, K, 2K, ... only (the other steps are not rendered)."""
    first = env.reset(init_index)
    task = env.start()
    kicks = np.random.default_rng(rng.integers(2**63)) if noise > 0.0 else None  # rng untouched without noise
    d = _Driver(env, task.max_steps, first, record, noise, kicks, view_every)
    _settle(d)
    for _ in _skills(d, rng):
        if d.done:
            break
    for _ in _hold(d, OPEN, SETTLE_STEPS):  # objects released last may need a moment to come to rest
        pass
    return ExpertResult(
        d.success,
        len(d.actions),
        np.asarray(d.actions).reshape(-1, 7),
        tuple(d.log),
        np.asarray(d.sim_states) if record else None,
        np.asarray(d.observations) if record else None,
        {v: np.asarray(f, dtype=np.uint8) for v, f in d.views.items()} or None,
        np.asarray(d.executed).reshape(-1, 7) if noise > 0.0 else None,
        np.asarray(d.view_frames, dtype=np.int64) if d.views else None,
    )
