"""The kitchen environment of one scene (``KitchenEnv``; the scenes of a metered session are in ``sessions``).

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
  body frame), ``fixtures`` (kind, pos, ``size`` in the fixture's frame (width along its run, depth,
  height), ``yaw`` of that frame and ``facing``, the world xy unit vector its front faces, (sin yaw,
  -cos yaw); normalised joint states, interior box, named sites' positions), ``target`` (the task's roles -> names) and ``grasped`` (the target object touches both
  fingers).
"""

from __future__ import annotations

import functools
import hashlib
from dataclasses import dataclass, field
from typing import Any

import mujoco
import numpy as np

from rle_design.control.mobile import MobileManipulatorEnv
from rle_design.ledger import LedgerError
from rle_design.sensors.camera import camera_spec
from rle_tasks.envs.kitchen import predicates as pr
from rle_tasks.envs.kitchen import segmentation as seg
from rle_tasks.envs.kitchen.composite_tasks import kitchen_task
from rle_tasks.envs.kitchen.fixture import Fixture
from rle_tasks.envs.kitchen.objects import extent
from rle_tasks.envs.kitchen.scene import ROBOT, KitchenScene
from rle_tasks.envs.kitchen.tasks import Condition

__all__ = ["LEVELS", "KitchenEnv"]

LEVELS = (1, 2, 3)
"""Harness levels."""


@dataclass(frozen=True)
class KitchenEnv(MobileManipulatorEnv):
    """One kitchen scene at a harness level (see the module docstring)."""

    scene: KitchenScene | None = field(default=None, compare=False)
    level: int = 1

    @functools.cached_property
    def _conditions(self) -> tuple[Condition, ...]:
        """The task's conditions, names made unique: two objects of one category (two lemons in a bowl)
        give two conditions of one wording, which ``conditions`` would merge into one entry."""
        ep = self.scene.episode
        out: list[Condition] = []
        seen: dict[str, int] = {}
        for c in kitchen_task(ep.task).conditions(ep, self.scene.fixtures, ROBOT):
            seen[c.name] = seen.get(c.name, 0) + 1
            out.append(c if seen[c.name] == 1 else Condition(f"{c.name} ({seen[c.name]})", c.fn))
        return tuple(out)

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
        frame = seg.segmenter(model, camera, size).render(data)
        fixtures_key = tuple(sorted((f.name, f.kind) for f in self.scene.fixtures.values()))
        objects = tuple((p.name, p.category) for p in self.scene.episode.objects)
        inst, names, labels = seg.labels(model, fixtures_key, objects)
        geoms = frame.geom_ids()
        return np.where(geoms >= 0, inst[np.clip(geoms, 0, None)], -1), names, labels

    def segment(
        self, model: mujoco.MjModel, data: mujoco.MjData, prompt: str, camera: str
    ) -> dict[str, np.ndarray]:
        """Noisy instance masks of the instances whose label contains every word of ``prompt``
        (``SEGMENT_NOISE``), in the order of ``instances``; the same state, prompt and camera give the
        same answer."""
        pix, _, labels = self.instances(model, data, camera)
        want = seg.words(prompt)
        seed = hashlib.sha256(
            f"{self.scene.layout_seed}|{self.scene.episode_seed}|{data.time:.6f}|{' '.join(want)}|{camera}".encode()
        ).digest()
        rng = np.random.default_rng(int.from_bytes(seed[:8], "little"))
        masks, boxes, scores = [], [], []
        for i, label in enumerate(labels):
            words = seg.words(label)
            if not all(w in words for w in want):
                continue
            mask = seg.noisy_mask(pix == i, rng)
            if mask is None:
                continue
            rows, cols = np.nonzero(mask)
            masks.append(mask)
            boxes.append([cols.min(), rows.min(), cols.max(), rows.max()])
            scores.append(rng.uniform(*seg.SEGMENT_NOISE["score"]))
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
        "yaw": float(f.yaw),
        "facing": np.array(f.facing),
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
