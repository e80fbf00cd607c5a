"""The kitchen environment: one scene (``KitchenEnv``) and the scenes of a metered session (``KitchenScenes``).

``KitchenEnv`` is a ``MobileManipulatorEnv`` over one ``KitchenScene`` (12-D actions at 20 Hz, see
``rle_design.control.mobile``). What it observes depends on the harness level:

- **L1** (robot and sensor API): the proprioception, ``rgb`` and metric ``depth`` of the three
  cameras (``robot/agentview_left``, ``robot/agentview_right``, ``robot/arm/eye_in_hand``, 128 x 128),
  ``instruction`` and ``success`` (the task's predicate on the current state);
- **L2** adds ``cameras`` (per camera ``K``, the 3 x 3 intrinsics [px], and ``world_from_camera``, the
  4 x 4 OpenCV-convention pose [m]) and the ``segment`` query: ``query("segment", prompt=...,
  camera=...)`` returns SAM3's output for a text prompt (``masks`` (N, H, W) bool, ``boxes`` (N, 4)
  x0 y0 x1 y1 [px], ``scores`` (N,)) from the simulator's segmentation with documented noise
  (``SEGMENT_NOISE``);
- **L3** adds world-frame ``objects`` (category, pos, quat, bounding box ``center``/``half`` in the
  body frame), ``fixtures`` (kind, pos, size, normalised joint states, interior box, named sites'
  positions), ``target`` (the task's roles -> names) and ``grasped`` (the target object touches both
  fingers).

``KitchenScenes`` is the ``SceneSet`` of one task and level: development resets play ``pretrain``
kitchens (public seeds), the evaluation phase plays five ``target`` kitchens whose seeds the task
derives from the verifier secret.
"""

from __future__ import annotations

import functools
import hashlib
import re
from dataclasses import dataclass, field
from typing import Any

import mujoco
import numpy as np

from rle_design.control.mobile import MobileManipulatorEnv
from rle_design.ledger import EvaluationPhase, LedgerError, SceneSet
from rle_design.sensors import RgbdSensor
from rle_design.sensors.camera import camera_spec
from rle_tasks.envs.kitchen import predicates as pr
from rle_tasks.envs.kitchen.composite_tasks import kitchen_task
from rle_tasks.envs.kitchen.fixture import Fixture
from rle_tasks.envs.kitchen.objects import extent
from rle_tasks.envs.kitchen.scene import ROBOT, KitchenScene, build_scene
from rle_tasks.envs.kitchen.tasks import Condition

__all__ = [
    "GroupScenes",
    "KitchenEnv",
    "KitchenScenes",
    "LEVELS",
    "PRETRAIN_KITCHENS",
    "SEGMENT_NOISE",
    "noisy_mask",
    "pretrain_seed",
]

LEVELS = (1, 2, 3)
PRETRAIN_KITCHENS = 50
"""Number of pretrain kitchen layouts (public)."""
PRETRAIN_BASE = 1_000_003
"""Layout seed of pretrain kitchen k is ``PRETRAIN_BASE + k`` (public)."""
SEGMENT_NOISE = {"miss": 0.03, "miss_small": 0.3, "small_px": 30, "boundary_flip": 0.1, "score": (0.6, 0.98)}
"""Noise of the simulated segmenter: an instance is missed with probability ``miss`` (``miss_small``
below ``small_px`` pixels); its mask is eroded (unless that erases it) or dilated by one pixel (each
with probability 1/3) and a ``boundary_flip`` fraction of its boundary pixels (either side of the
edge) flipped, so every mask lies between the exact mask eroded and dilated twice; scores are uniform
in ``score``. The draws are seeded by the scene, the simulation time, the prompt's words and the
camera: the same query on the same state gets the same answer (rewording does not redraw)."""
_KIND_WORDS = {
    "fridge": "fridge",
    "hinge_cabinet": "cabinet",
    "drawer_cabinet": "drawer cabinet",
    "stove": "stove",
    "sink": "sink",
    "microwave": "microwave",
    "dish_rack": "dish rack",
    "counter": "counter",
    "wall_cabinet": "wall cabinet",
}


def pretrain_seed(kitchen: int) -> int:
    """Layout seed of pretrain kitchen ``kitchen`` (0-based)."""
    return PRETRAIN_BASE + int(kitchen)


@functools.lru_cache(maxsize=16)
def _labels(
    model: mujoco.MjModel, fixtures_key: tuple[tuple[str, str], ...], objects: tuple[tuple[str, str], ...]
) -> tuple[np.ndarray, tuple[str, ...], tuple[str, ...]]:
    """Per geom: instance index; instance names; instance labels (words)."""
    kinds = dict(fixtures_key)
    cats = dict(objects)
    inst_of: dict[str, int] = {}
    names: list[str] = []
    labels: list[str] = []
    ids = np.full(model.ngeom, -1, dtype=np.int64)

    def instance(name: str, label: str) -> int:
        if name not in inst_of:
            inst_of[name] = len(names)
            names.append(name)
            labels.append(label)
        return inst_of[name]

    for g in range(model.ngeom):
        geom = model.geom(g).name
        body = model.body(model.geom_bodyid[g]).name
        if body in cats:
            ids[g] = instance(body, cats[body])
        elif body.startswith(ROBOT.prefix):
            ids[g] = instance("robot", "robot")
        elif geom in ("wall", "floor", "range_hood"):
            ids[g] = instance(geom, geom.replace("_", " "))
        else:
            fixture = next(
                (f for f in sorted(kinds, key=len, reverse=True) if geom.startswith(f + "_")), None
            )
            if fixture is None:
                continue
            word = _KIND_WORDS[kinds[fixture]]
            rest = geom[len(fixture) + 1 :]
            if "handle" in rest:
                ids[g] = instance(f"{fixture}_handle", f"{word} handle")
            elif "knob" in rest:
                burner = rest.split("_knob")[0].replace("_", " ")
                ids[g] = instance(f"{fixture}_{rest.split('_knob')[0]}_knob", f"{burner} knob")
            elif "burner" in rest:
                ids[g] = instance(geom, f"{rest.replace('_burner', '').replace('_', ' ')} burner")
            elif rest.startswith("door"):
                ids[g] = instance(f"{fixture}_door", f"{word} door")
            elif rest.startswith("drawer"):
                ids[g] = instance(f"{fixture}_drawer", "drawer")
            elif rest.startswith("top") or rest == "cooktop":
                ids[g] = instance(f"{fixture}_top", "counter" if rest.startswith("top") else "cooktop")
            elif rest.startswith("basin"):
                ids[g] = instance(f"{fixture}_basin", "sink basin")
            elif rest == "plate":
                ids[g] = instance(f"{fixture}_plate", "microwave plate")
            else:
                ids[g] = instance(fixture, word)
    return ids, tuple(names), tuple(labels)


def _words(text: str) -> list[str]:
    return [w[:-1] if len(w) > 3 and w.endswith("s") else w for w in re.findall(r"[a-z]+", text.lower())]


_SEGMENTERS: dict[tuple[int, str, tuple[int, int]], tuple[mujoco.MjModel, RgbdSensor]] = {}


def _segmenter(model: mujoco.MjModel, camera: str, size: tuple[int, int]) -> RgbdSensor:
    key = (id(model), camera, tuple(size))
    entry = _SEGMENTERS.get(key)
    if entry is None or entry[0] is not model:
        if len(_SEGMENTERS) > 12:
            for _, s in _SEGMENTERS.values():
                s.close()
            _SEGMENTERS.clear()
        entry = _SEGMENTERS[key] = (
            model,
            RgbdSensor(
                model, camera, size[1], size[0], fast=True, segmentation=True, sites=False, box_quads=1
            ),
        )
    return entry[1]


def _shift_or(mask: np.ndarray) -> np.ndarray:
    out = mask.copy()
    out[1:] |= mask[:-1]
    out[:-1] |= mask[1:]
    out[:, 1:] |= mask[:, :-1]
    out[:, :-1] |= mask[:, 1:]
    return out


def noisy_mask(mask: np.ndarray, rng: np.random.Generator) -> np.ndarray | None:
    """The segmenter's answer for one exact instance mask (``SEGMENT_NOISE``); None when it is missed
    or empty. The answer lies between the exact mask eroded and dilated twice by one pixel."""
    area = int(mask.sum())
    if area == 0:
        return None
    miss = SEGMENT_NOISE["miss_small"] if area < SEGMENT_NOISE["small_px"] else SEGMENT_NOISE["miss"]
    if rng.random() < miss:
        return None
    op = rng.integers(3)
    if op == 1:
        eroded = ~_shift_or(~mask)
        mask = eroded if eroded.any() else mask  # a thin instance is kept, not erased
    elif op == 2:
        mask = _shift_or(mask)
    edge = _shift_or(mask) & _shift_or(~mask)
    flip = edge & (rng.random(mask.shape) < SEGMENT_NOISE["boundary_flip"])
    mask = mask ^ flip
    return mask if mask.any() else None


@dataclass(frozen=True)
class KitchenEnv(MobileManipulatorEnv):
    """One kitchen scene at a harness level (see the module docstring)."""

    scene: KitchenScene | None = field(default=None, compare=False)
    level: int = 1

    @functools.cached_property
    def _conditions(self) -> tuple[Condition, ...]:
        ep = self.scene.episode
        return kitchen_task(ep.task).conditions(ep, self.scene.fixtures, ROBOT)

    def conditions_names(self) -> tuple[str, ...]:
        """Names of the task's success conditions, in order."""
        return tuple(c.name for c in self._conditions)

    def conditions(self, model: mujoco.MjModel, data: mujoco.MjData) -> dict[str, bool]:
        """Each success condition of the task, by name."""
        return {c.name: bool(c.fn(model, data)) for c in self._conditions}

    def success(self, model: mujoco.MjModel, data: mujoco.MjData) -> bool:
        """The task's success predicate: every condition holds."""
        return all(c.fn(model, data) for c in self._conditions)

    observation_doc = (
        "time, base_pos, base_yaw, torso, q, dq, ee_pos, ee_quat, ee_pos_base, ee_quat_base, target_pos_base, "
        "target_quat_base, gripper, rgb and depth (per camera), instruction, success; L2 adds cameras (K, world_from_camera) and query('segment', "
        "prompt=..., camera=...); L3 adds objects, fixtures, target, grasped"
    )

    def _burner_glow(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        for joint, ring in (b for f in self.scene.fixtures.values() for b in f.burners.values()):
            on = pr.knob_on(model, data, joint)
            model.geom_rgba[model.geom(ring).id] = (0.9, 0.2, 0.05, 1.0) if on else (0.25, 0.25, 0.27, 1.0)

    def observe(self, model: mujoco.MjModel, data: mujoco.MjData) -> dict[str, Any]:
        self._burner_glow(model, data)
        obs = super().observe(model, data)
        obs["instruction"] = self.scene.episode.instruction
        obs["success"] = self.success(model, data)
        if self.level >= 2 and self.image_size is not None:
            h, w = self.image_size
            obs["cameras"] = {
                cam: {"K": spec.intrinsics.matrix, "world_from_camera": spec.world_from_camera}
                for cam in ROBOT.cameras
                for spec in (camera_spec(model, data, cam, w, h),)
            }
        if self.level >= 3:
            obs.update(self.world_state(model, data))
        return obs

    def world_state(self, model: mujoco.MjModel, data: mujoco.MjData) -> dict[str, Any]:
        """The L3 observation: objects, fixtures, target and grasp state."""
        objects = {}
        for p in self.scene.episode.objects:
            b = model.body(p.name).id
            center, half = extent(p.category)
            objects[p.name] = {
                "category": p.category,
                "pos": data.xpos[b].copy(),
                "quat": data.xquat[b].copy(),
                "center": np.array(center),
                "half": np.array(half),
            }
        fixtures = {}
        for f in self.scene.fixtures.values():
            fixtures[f.name] = _fixture_state(model, data, f)
        target = dict(self.scene.episode.target)
        obj = target.get("object")
        grasped = bool(obj) and all(
            pr.bodies_touch(model, data, obj, _subtree_geoms(model, pad)) for pad in ROBOT.finger_pads
        )
        return {"objects": objects, "fixtures": fixtures, "target": target, "grasped": grasped}

    def query(self, model: mujoco.MjModel, data: mujoco.MjData, name: str, args: dict[str, Any]) -> Any:
        """``segment`` (L2 and L3): SAM3-schema instance masks of a text prompt in one camera."""
        if name != "segment":
            raise LedgerError(f"unknown query '{name}'. Queries: segment", code="ledger.bad_request")
        if self.level < 2:
            raise LedgerError(
                "segmentation is a harness level 2 tool; this task is level 1", code="ledger.bad_request"
            )
        prompt, camera = args.get("prompt"), args.get("camera", ROBOT.cameras[0])
        if not isinstance(prompt, str) or not prompt.strip():
            raise LedgerError("segment needs prompt=<text>", code="ledger.bad_request")
        if camera not in ROBOT.cameras:
            raise LedgerError(
                f"unknown camera '{camera}'. Cameras: {', '.join(ROBOT.cameras)}", code="ledger.bad_request"
            )
        return self.segment(model, data, prompt, camera)

    def instances(
        self, model: mujoco.MjModel, data: mujoco.MjData, camera: str
    ) -> tuple[np.ndarray, tuple[str, ...], tuple[str, ...]]:
        """The simulator's exact instance segmentation of ``camera``'s current image.

        Returns:
            (H, W) int64 instance index per pixel (-1: no instance), instance names, instance labels.
        """
        self._burner_glow(model, data)
        size = self.image_size or (128, 128)
        frame = _segmenter(model, camera, size).render(data)
        fixtures_key = tuple(sorted((f.name, f.kind) for f in self.scene.fixtures.values()))
        objects = tuple((p.name, p.category) for p in self.scene.episode.objects)
        inst, names, labels = _labels(model, fixtures_key, objects)
        geoms = frame.geom_ids()
        return np.where(geoms >= 0, inst[np.clip(geoms, 0, None)], -1), names, labels

    def segment(
        self, model: mujoco.MjModel, data: mujoco.MjData, prompt: str, camera: str
    ) -> dict[str, np.ndarray]:
        """Noisy instance masks of the instances whose label contains every word of ``prompt``
        (``SEGMENT_NOISE``), in the order of ``instances``; the same state, prompt and camera give the
        same answer."""
        pix, _, labels = self.instances(model, data, camera)
        want = _words(prompt)
        seed = hashlib.sha256(
            f"{self.scene.layout_seed}|{self.scene.episode_seed}|{data.time:.6f}|{' '.join(want)}|{camera}".encode()
        ).digest()
        rng = np.random.default_rng(int.from_bytes(seed[:8], "little"))
        masks, boxes, scores = [], [], []
        for i, label in enumerate(labels):
            words = _words(label)
            if not all(w in words for w in want):
                continue
            mask = noisy_mask(pix == i, rng)
            if mask is None:
                continue
            rows, cols = np.nonzero(mask)
            masks.append(mask)
            boxes.append([cols.min(), rows.min(), cols.max(), rows.max()])
            scores.append(rng.uniform(*SEGMENT_NOISE["score"]))
        h, w = pix.shape
        return {
            "masks": np.array(masks, dtype=bool).reshape(len(masks), h, w),
            "boxes": np.array(boxes, dtype=np.float64).reshape(len(boxes), 4),
            "scores": np.array(scores, dtype=np.float64),
        }


def _subtree_geoms(model: mujoco.MjModel, body: str) -> set[int]:
    """Geoms of ``body`` and of every body below it (a finger and its pad)."""
    root = model.body(body).id
    bodies = {b for b in range(model.nbody) if _descends(model, b, root)}
    return {g for g in range(model.ngeom) if model.geom_bodyid[g] in bodies}


def _descends(model: mujoco.MjModel, b: int, root: int) -> bool:
    while b > 0:
        if b == root:
            return True
        b = model.body_parentid[b]
    return b == root


def _fixture_state(model: mujoco.MjModel, data: mujoco.MjData, f: Fixture) -> dict[str, Any]:
    out: dict[str, Any] = {
        "kind": f.kind,
        "pos": np.array(f.pos),
        "size": np.array(f.size),
        "joints": {j: pr.joint_fraction(model, data, j) for j in f.joints},
        "sites": {role: data.site_xpos[model.site(s).id].copy() for role, s in f.sites.items()},
    }
    if f.interior is not None:
        b = model.body(f.interior.body).id
        out["interior"] = {
            "center": data.xpos[b] + data.xmat[b].reshape(3, 3) @ np.array(f.interior.center),
            "half": np.array(f.interior.half),
            "quat": data.xquat[b].copy(),
        }
    if f.hinge_left is not None:
        out["hinge_left"] = f.hinge_left
    for role, body in f.parts.items():
        out[f"{role}_pos"] = data.xpos[model.body(body).id].copy()
        out[f"{role}_quat"] = data.xquat[model.body(body).id].copy()
    return out


@dataclass(frozen=True)
class KitchenScenes(SceneSet):
    """The scenes of one kitchen task at one harness level.

    Attributes:
        task: Kitchen task name (``rle_tasks.envs.kitchen.tasks.TASKS``).
        level: Harness level (1-3).
        targets: (layout seed, episode seed) of each evaluation trial (from the verifier secret).
        evaluation: The terminal evaluation phase.
        image_size: Camera image size (None renders none: verification replays).
        pretrain_kitchens: Number of pretrain layouts.
    """

    task: str
    level: int = 1
    targets: tuple[tuple[int, int], ...] = ()
    evaluation: EvaluationPhase | None = EvaluationPhase(trials=5, actions_per_trial=1000, wall_time_s=3600.0)
    image_size: tuple[int, int] | None = (128, 128)
    pretrain_kitchens: int = PRETRAIN_KITCHENS
    n_substeps: int = 25
    observation_doc: str = KitchenEnv.observation_doc

    def __post_init__(self) -> None:
        kitchen_task(self.task)  # KeyError listing the tasks when unknown
        if self.level not in LEVELS:
            raise ValueError(f"harness level must be one of {LEVELS}, got {self.level}")
        if self.evaluation is not None and len(self.targets) < self.evaluation.trials:
            raise ValueError(
                f"{self.evaluation.trials} evaluation trials need as many targets, got {len(self.targets)}"
            )

    def describe(self) -> str:
        return f"kitchen {self.task} L{self.level} pretrain {self.pretrain_kitchens}"

    def session_doc(self) -> str:
        return (
            f"Development: env.reset() starts the next of {self.pretrain_kitchens} pretrain kitchens; "
            f"env.reset(kitchen=k, seed=s) picks kitchen k (0-{self.pretrain_kitchens - 1}) and episode s. "
            + self.evaluation_doc()
        )

    def _env(self, scene: KitchenScene) -> KitchenEnv:
        return KitchenEnv(xml=scene.xml, scene=scene, level=self.level, image_size=self.image_size)

    def scene(self, key: str) -> KitchenEnv:
        parts = key.split("/")
        numbers = [int(p) for p in parts[1:] if p.isdigit()]
        if (
            parts[0] == "pretrain"
            and len(parts) == 3
            and len(numbers) == 2
            and numbers[0] < self.pretrain_kitchens
        ):
            k, s = numbers
            return self._env(build_scene(pretrain_seed(k), self.task, _episode_seed(k, s)))
        if parts[0] == "target" and len(parts) == 2 and len(numbers) == 1 and numbers[0] < len(self.targets):
            layout, episode = self.targets[numbers[0]]
            return self._env(build_scene(layout, self.task, episode))
        raise LedgerError(f"unknown scene '{key}'", code="ledger.bad_scene")

    def development_key(self, index: int, options: dict[str, Any]) -> str:
        unknown = set(options) - {"kitchen", "seed"}
        if unknown:
            raise LedgerError(
                f"unknown reset options {sorted(unknown)}; options: kitchen, seed, evaluation",
                code="ledger.bad_request",
            )
        kitchen, seed = options.get("kitchen", index % self.pretrain_kitchens), options.get("seed", index)
        if not (isinstance(kitchen, int) and 0 <= kitchen < self.pretrain_kitchens):
            raise LedgerError(
                f"kitchen must be an integer in [0, {self.pretrain_kitchens}), got {kitchen!r}",
                code="ledger.bad_request",
            )
        if not (isinstance(seed, int) and 0 <= seed < 2**31):
            raise LedgerError(
                f"seed must be an integer in [0, 2**31), got {seed!r}", code="ledger.bad_request"
            )
        return f"pretrain/{kitchen}/{seed}"

    def evaluation_key(self, trial: int) -> str:
        return f"target/{trial}"

    def success(self, env: KitchenEnv, model: mujoco.MjModel, data: mujoco.MjData) -> bool:
        return env.success(model, data)


def _episode_seed(kitchen: int, seed: int) -> int:
    return int.from_bytes(hashlib.sha256(f"pretrain|{kitchen}|{seed}".encode()).digest()[:8], "little") >> 1


@dataclass(frozen=True)
class GroupScenes(KitchenScenes):
    """Development scenes of several kitchen tasks in one session (family 02): ``reset(task=...)`` picks
    the task (by default the tasks take turns), ``kitchen`` and ``seed`` as for ``KitchenScenes``; there
    is no evaluation phase.

    Attributes:
        tasks: The tasks a reset may pick (``task`` is the first).
    """

    tasks: tuple[str, ...] = ()
    evaluation: EvaluationPhase | None = None

    def __post_init__(self) -> None:
        super().__post_init__()
        for t in self.tasks:
            kitchen_task(t)
        if self.task not in self.tasks:
            raise ValueError(f"GroupScenes.task '{self.task}' must be one of its tasks {self.tasks}")

    def describe(self) -> str:
        return f"kitchen group {','.join(self.tasks)} L{self.level} pretrain {self.pretrain_kitchens}"

    def session_doc(self) -> str:
        return (
            f"Development: env.reset() starts the next episode, the tasks {', '.join(self.tasks)} taking turns "
            f"over {self.pretrain_kitchens} pretrain kitchens; env.reset(task=name, kitchen=k, seed=s) picks one. "
            "Every reset and action is charged."
        )

    def scene(self, key: str) -> KitchenEnv:
        parts = key.split("/")
        if parts[0] == "pretrain" and len(parts) == 4 and parts[1] in self.tasks:
            try:
                k, s = int(parts[2]), int(parts[3])
            except ValueError:
                k, s = -1, -1
            if 0 <= k < self.pretrain_kitchens and s >= 0:
                return self._env(build_scene(pretrain_seed(k), parts[1], _episode_seed(k, s)))
        raise LedgerError(f"unknown scene '{key}'", code="ledger.bad_scene")

    def development_key(self, index: int, options: dict[str, Any]) -> str:
        task = options.get("task", self.tasks[index % len(self.tasks)])
        if task not in self.tasks:
            raise LedgerError(
                f"task must be one of {', '.join(self.tasks)}, got {task!r}", code="ledger.bad_request"
            )
        rest = {k: v for k, v in options.items() if k != "task"}
        key = super().development_key(index, rest)
        return key.replace("pretrain/", f"pretrain/{task}/", 1)
