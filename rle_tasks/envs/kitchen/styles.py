"""Kitchen style families and the pretrain/target split over layout kind x style family.

A style family (``FAMILIES``, after RoboCasa's named styles) fixes the palettes a kitchen's colours are
drawn from, its cabinet handle type and the counter heights and depths it may take; ``sample_style``
draws one ``fixture.Style`` from a family. Dimensions stay within RoboCasa's kitchen layouts
(``robocasa/models/assets/kitchen_layouts/*.yaml``): counter tops 0.92 m high (0.89 m: its
dishwasher and filler boxes) and 0.65 m deep over 0.6 m-deep base cabinets; handle types bar, boxed
and knob (``fixture_defaults/cabinet_default.yaml``).

Split (``split``): kinds and families are numbered in the order of ``KINDS`` and ``FAMILIES``;
combination (kind k, family f) is a ``target`` combination when (f - k) mod 6 is 0 or 3, else
``pretrain``. Each kind then has two target families and four pretrain ones, each family two target
kinds and four pretrain ones: every kind and every family is seen in pretrain, but no pretrain kitchen
has a target kitchen's combination (12 target, 24 pretrain combinations).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rle_tasks.envs.kitchen import fixture as fx

__all__ = ["FAMILIES", "KINDS", "Family", "combinations", "sample_style", "split"]

KINDS = ("one_wall", "l_shaped", "u_shaped", "galley", "island", "peninsula")
"""Layout kinds (RoboCasa's floor-plan families; built by ``layout`` and ``layout_kinds``)."""

RGBA = tuple[float, float, float, float]


@dataclass(frozen=True)
class Family:
    """A style family: palettes (RGBA) and shapes a kitchen of the family draws from.

    Attributes:
        cabinet, counter, floor, wall: Palettes of the cabinets, counter tops, floor and walls.
        handle_type: Cabinet handle (``fixture.HANDLE_TYPES``).
        counter_height: Counter-top heights [m].
        counter_depth: Base-unit depths [m].
    """

    cabinet: tuple[RGBA, ...]
    counter: tuple[RGBA, ...]
    floor: tuple[RGBA, ...]
    wall: tuple[RGBA, ...]
    handle_type: str
    counter_height: tuple[float, ...] = (0.92,)
    counter_depth: tuple[float, ...] = (0.6, 0.65)


FAMILIES: dict[str, Family] = {
    "scandinavian": Family(
        cabinet=((0.93, 0.93, 0.93, 1.0), (0.86, 0.86, 0.83, 1.0)),
        counter=((0.78, 0.66, 0.50, 1.0), (0.88, 0.87, 0.84, 1.0)),
        floor=((0.78, 0.70, 0.58, 1.0),),
        wall=((0.95, 0.95, 0.94, 1.0),),
        handle_type="bar",
    ),
    "industrial": Family(
        cabinet=((0.50, 0.51, 0.53, 1.0), (0.20, 0.21, 0.23, 1.0)),
        counter=((0.35, 0.33, 0.32, 1.0), (0.55, 0.42, 0.30, 1.0)),
        floor=((0.62, 0.64, 0.66, 1.0),),
        wall=((0.62, 0.32, 0.26, 1.0),),
        handle_type="boxed",
        counter_height=(0.92, 0.89),
    ),
    "coastal": Family(
        cabinet=((0.20, 0.28, 0.45, 1.0), (0.55, 0.70, 0.80, 1.0)),
        counter=((0.88, 0.87, 0.84, 1.0),),
        floor=((0.72, 0.70, 0.66, 1.0),),
        wall=((0.82, 0.86, 0.88, 1.0),),
        handle_type="knob",
    ),
    "rustic": Family(
        cabinet=((0.45, 0.55, 0.42, 1.0), (0.62, 0.46, 0.32, 1.0)),
        counter=((0.40, 0.30, 0.22, 1.0), (0.30, 0.30, 0.28, 1.0)),
        floor=((0.40, 0.30, 0.22, 1.0),),
        wall=((0.90, 0.84, 0.78, 1.0),),
        handle_type="knob",
        counter_height=(0.89, 0.92),
    ),
    "mediterranean": Family(
        cabinet=((0.62, 0.46, 0.32, 1.0), (0.90, 0.86, 0.76, 1.0)),
        counter=((0.15, 0.15, 0.17, 1.0), (0.88, 0.87, 0.84, 1.0)),
        floor=((0.70, 0.45, 0.32, 1.0),),
        wall=((0.93, 0.91, 0.86, 1.0),),
        handle_type="bar",
    ),
    "modern": Family(
        cabinet=((0.32, 0.40, 0.48, 1.0), (0.93, 0.93, 0.93, 1.0)),
        counter=((0.95, 0.95, 0.95, 1.0), (0.15, 0.15, 0.17, 1.0)),
        floor=((0.55, 0.45, 0.36, 1.0),),
        wall=((0.86, 0.86, 0.86, 1.0),),
        handle_type="boxed",
    ),
}
"""Style families, in split order."""


def _pick(rng: np.random.Generator, options: tuple):
    return options[int(rng.integers(len(options)))]


def sample_style(rng: np.random.Generator, family: str) -> fx.Style:
    """A kitchen style drawn from ``family``'s palettes and dimensions."""
    f = FAMILIES[family]
    return fx.Style(
        cabinet=_pick(rng, f.cabinet),
        counter=_pick(rng, f.counter),
        floor=_pick(rng, f.floor),
        wall=_pick(rng, f.wall),
        handle_type=f.handle_type,
        counter_height=float(_pick(rng, f.counter_height)),
        counter_depth=float(_pick(rng, f.counter_depth)),
    )


def split(kind: str, family: str) -> str:
    """``pretrain`` or ``target``: the part (kind, family) belongs to (see the module docstring)."""
    k, f = KINDS.index(kind), list(FAMILIES).index(family)
    return "target" if (f - k) % len(KINDS) in (0, 3) else "pretrain"


def combinations(part: str) -> tuple[tuple[str, str], ...]:
    """The (kind, family) combinations of ``part`` (``pretrain`` or ``target``), kind-major."""
    if part not in ("pretrain", "target"):
        raise ValueError(f"part must be 'pretrain' or 'target', got {part!r}")
    return tuple((k, f) for k in KINDS for f in FAMILIES if split(k, f) == part)
