"""The L2 ``segment`` query's simulated segmenter: instance labels from the kitchen's fixtures and
objects, the words a prompt is matched on, and the documented noise (``SEGMENT_NOISE``)."""

from __future__ import annotations

import functools
import re

import mujoco
import numpy as np

from rle_design.sensors import RgbdSensor
from rle_tasks.envs.kitchen.scene import ROBOT

__all__ = ["KIND_WORDS", "SEGMENT_NOISE", "labels", "noisy_mask", "segmenter", "shift_or", "words"]

SEGMENT_NOISE = {"miss": 0.03, "miss_small": 0.3, "small_px": 30, "boundary_flip": 0.1, "score": (0.6, 0.98)}
"""Noise of the simulated segmenter: an instance is missed with probability ``miss`` (``miss_small``
below ``small_px`` pixels); its mask is eroded (unless that erases it) or dilated by one pixel (each
with probability 1/3) and a ``boundary_flip`` fraction of its boundary pixels (either side of the
edge) flipped, so every mask lies between the exact mask eroded and dilated twice; scores are uniform
in ``score``. The draws are seeded by the scene, the simulation time, the prompt's words and the
camera: the same query on the same state gets the same answer (rewording does not redraw)."""
KIND_WORDS = {
    "fridge": "fridge",
    "hinge_cabinet": "cabinet",
    "drawer_cabinet": "drawer cabinet",
    "stove": "stove",
    "sink": "sink",
    "microwave": "microwave",
    "dish_rack": "dish rack",
    "counter": "counter",
    "wall_cabinet": "wall cabinet",
    "corner": "corner unit",
}


@functools.lru_cache(maxsize=16)
def labels(
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
            word = KIND_WORDS[kinds[fixture]]
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


def words(text: str) -> list[str]:
    return [w[:-1] if len(w) > 3 and w.endswith("s") else w for w in re.findall(r"[a-z]+", text.lower())]


_SEGMENTERS: dict[tuple[int, str, tuple[int, int]], tuple[mujoco.MjModel, RgbdSensor]] = {}


def segmenter(model: mujoco.MjModel, camera: str, size: tuple[int, int]) -> RgbdSensor:
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


def shift_or(mask: np.ndarray) -> np.ndarray:
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
        eroded = ~shift_or(~mask)
        mask = eroded if eroded.any() else mask  # a thin instance is kept, not erased
    elif op == 2:
        mask = shift_or(mask)
    edge = shift_or(mask) & shift_or(~mask)
    flip = edge & (rng.random(mask.shape) < SEGMENT_NOISE["boundary_flip"])
    mask = mask ^ flip
    return mask if mask.any() else None
