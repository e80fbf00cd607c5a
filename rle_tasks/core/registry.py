"""Registry of all 51 task instances of the paper.

Every id is registered; families whose environment and verifier exist provide full ``TaskSpec``s through
their package's ``tasks()`` function, the others stay as placeholders with ``implemented = False``.
"""

from __future__ import annotations

import functools
import importlib

from rle_design.errors import RleError
from rle_tasks.core.task import TaskSpec

_F01_TASKS = (
    ("open-fridge", "OpenFridge: open the refrigerator door"),
    ("close-cabinet", "CloseCabinet: close the cabinet door"),
    ("turn-on-stove", "TurnOnStove: turn on the specified burner"),
    ("pnp-counter-to-drawer", "PickPlaceCounterToDrawer: move the target into the drawer"),
    ("pnp-microwave-to-counter", "PickPlaceMicrowaveToCounter: move the target to the counter"),
)
_F02_LEVELS = ("easy",) * 5 + ("medium",) * 5 + ("hard",) * 5


def _placeholders() -> list[TaskSpec]:
    specs: list[TaskSpec] = []
    for level in ("l1", "l2", "l3"):
        for key, title in _F01_TASKS:
            specs.append(
                TaskSpec(f"01-{key}-{level}", 1, f"RoboCasa speed-run, {title} (harness {level.upper()})")
            )
    for i, level in enumerate(_F02_LEVELS, start=1):
        specs.append(TaskSpec(f"02-group-{i:02d}", 2, f"RoboCasa harness transfer, group {i} ({level})"))
    for key, title in (
        ("tower", "build a stable tower from 12 mixed pieces"),
        ("cantilever", "maximise the overhang of four blocks"),
        ("balance-coins", "find the heavy cube among nine with a balance"),
        ("pocket-cube", "solve a physical 2x2x2 cube with two arms"),
        ("hidden-com", "identify the ballast quadrant of three sealed boxes"),
    ):
        specs.append(TaskSpec(f"03-{key}", 3, f"Tabletop physical reasoning: {title}"))
    for key in ("dance", "fight", "fall-getup", "run", "sprint"):
        specs.append(
            TaskSpec(f"04-{key}", 4, f"Whole-body motion tracking: G1 {key.replace('-', ' and ')} clip")
        )
    for env in ("libero", "robotwin"):
        for track in ("open", "robust"):
            specs.append(TaskSpec(f"05-{env}-{track}", 5, f"nanoVLA recipe engineering: {env} {track} track"))
    for key, title in (
        ("a-rgb", "A, RGB-only estimator"),
        ("b-rgbd", "B, RGB-D estimator"),
        ("c-learned", "C, learned RGB-D model"),
        ("d-agnostic", "D, method-agnostic estimator"),
    ):
        specs.append(TaskSpec(f"06-pose-{key}", 6, f"Blind planar pose estimation, variant {title}"))
    specs.append(TaskSpec("07-bin-clearing", 7, "Contact-rich bin clearing onto a conveyor"))
    specs.append(TaskSpec("08-mobile-base", 8, "Universal mobile-manipulator base"))
    specs.append(TaskSpec("09-gello", 9, "Multi-robot GELLO gravity-compensation co-design"))
    return specs


# Families with an implementation: family number -> package exposing ``tasks() -> list[TaskSpec]``.
FAMILY_PACKAGES: dict[int, str] = {
    8: "rle_tasks.f08_mobile_base",
    9: "rle_tasks.f09_gello",
}


def _implemented(family: int) -> list[TaskSpec]:
    name = FAMILY_PACKAGES.get(family)
    if name is None:
        return []
    try:
        module = importlib.import_module(name)
    except ModuleNotFoundError as exc:
        if exc.name and name.startswith(exc.name.split(".")[0]) and exc.name.startswith(name):
            return []  # family package not present in this checkout
        raise
    return list(module.tasks())


@functools.cache
def all_tasks() -> tuple[TaskSpec, ...]:
    """All 51 tasks, in paper order; implemented families replace their placeholders."""
    specs = _placeholders()
    by_id = {s.id: i for i, s in enumerate(specs)}
    for family in FAMILY_PACKAGES:
        for spec in _implemented(family):
            if spec.id not in by_id:
                raise RleError(f"family {family} registers unknown task id '{spec.id}'")
            specs[by_id[spec.id]] = spec
    return tuple(specs)


def get_task(task_id: str) -> TaskSpec:
    """Task by id; raises ``RleError`` listing close matches."""
    for spec in all_tasks():
        if spec.id == task_id:
            return spec
    ids = [s.id for s in all_tasks()]
    close = [i for i in ids if i.split("-")[0] == task_id.split("-")[0]] or ids
    raise RleError(f"task '{task_id}' does not exist. Known ids: {', '.join(close)}", code="task.unknown")
