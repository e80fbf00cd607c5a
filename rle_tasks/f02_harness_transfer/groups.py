"""The fifteen activity groups of family 02: three development tasks whose atomic skills cover one
held-out task (composite kitchen tasks of ``rle_tasks.envs.kitchen.composite_tasks``).

Atomic skills: ``pick-place`` (grasp an object and put it somewhere), ``open-door`` / ``close-door``
(hinged doors: cabinets, microwave, fridge), ``open-drawer`` / ``close-drawer``, ``turn-knob`` (burners
on or off), ``navigate`` (drive the base between fixtures).
"""

from __future__ import annotations

from dataclasses import dataclass

from rle_tasks.envs.kitchen.composite_tasks import COMPOSITES

__all__ = ["GROUPS", "Group", "SKILLS"]

SKILLS: dict[str, tuple[str, ...]] = {
    "FruitToOpenDrawer": ("pick-place",),
    "CloseDrawer": ("close-drawer",),
    "OpenDrawer": ("open-drawer",),
    "StowFruitInDrawer": ("pick-place", "close-drawer"),
    "CanToDrawer": ("pick-place",),
    "FruitFromDrawer": ("pick-place",),
    "FruitToPlate": ("pick-place",),
    "ServeFromDrawer": ("pick-place", "close-drawer"),
    "PlaceOnDishRack": ("pick-place",),
    "CupSinkToCounter": ("pick-place",),
    "CupToSink": ("pick-place",),
    "RackCupFromSink": ("pick-place", "navigate"),
    "SortingCleanup": ("pick-place", "navigate"),
    "StackBowlsInSink": ("pick-place",),
    "DumpLeftovers": ("pick-place",),
    "CupFromRackToCounter": ("pick-place",),
    "PutAwayCup": ("pick-place", "close-door", "navigate"),
    "TurnOnBurner": ("turn-knob",),
    "TurnOffBurner": ("turn-knob",),
    "TurnOnTwoBurners": ("turn-knob",),
    "SwitchBurners": ("turn-knob",),
    "CupToBurner": ("pick-place",),
    "HeatCup": ("pick-place", "turn-knob", "navigate"),
    "OpenMicrowave": ("open-door",),
    "CloseMicrowave": ("close-door",),
    "FoodToMicrowave": ("pick-place",),
    "MicrowaveAndClose": ("pick-place", "close-door"),
    "FoodFromMicrowaveToPlate": ("pick-place",),
    "ReheatFood": ("open-door", "pick-place", "close-door"),
    "StartCooking": ("pick-place", "close-door", "turn-knob", "navigate"),
    "OpenCabinetDoor": ("open-door",),
    "CloseCabinetDoor": ("close-door",),
    "ItemToOpenCabinet": ("pick-place",),
    "StoreInCabinetAndClose": ("pick-place", "close-door"),
    "RestockCabinet": ("open-door", "pick-place"),
    "FoodFromCabinet": ("pick-place",),
    "ServeBreakfast": ("pick-place", "close-door"),
    "CleanUpKitchen": ("pick-place", "close-door", "turn-knob", "navigate"),
    "OpenFridgeDoor": ("open-door",),
    "CloseFridgeDoor": ("close-door",),
    "MilkToFridge": ("pick-place",),
    "RestockFridge": ("open-door", "pick-place", "close-door"),
}
"""Atomic skills each composite task needs."""


@dataclass(frozen=True)
class Group:
    """One activity group.

    Attributes:
        number: 1-15 (task id ``02-group-NN``).
        difficulty: ``easy``, ``medium`` or ``hard``.
        title: What the group is about.
        develop: The three development tasks.
        held_out: The held-out task the fresh agents attempt.
    """

    number: int
    difficulty: str
    title: str
    develop: tuple[str, str, str]
    held_out: str

    @property
    def task_id(self) -> str:
        return f"02-group-{self.number:02d}"

    def covered(self) -> bool:
        """The development tasks' skills cover the held-out task's."""
        have = {s for t in self.develop for s in SKILLS[t]} | {"navigate"}
        return set(SKILLS[self.held_out]) <= have


GROUPS: tuple[Group, ...] = (
    Group(
        1,
        "easy",
        "stocking a drawer",
        ("FruitToOpenDrawer", "CloseDrawer", "OpenDrawer"),
        "StowFruitInDrawer",
    ),
    Group(
        2, "easy", "the dish rack", ("PlaceOnDishRack", "CupSinkToCounter", "CupToSink"), "RackCupFromSink"
    ),
    Group(3, "easy", "burners", ("TurnOnBurner", "TurnOffBurner", "TurnOnTwoBurners"), "SwitchBurners"),
    Group(
        4,
        "easy",
        "the microwave",
        ("OpenMicrowave", "CloseMicrowave", "FoodToMicrowave"),
        "MicrowaveAndClose",
    ),
    Group(
        5,
        "easy",
        "a cabinet",
        ("OpenCabinetDoor", "CloseCabinetDoor", "ItemToOpenCabinet"),
        "StoreInCabinetAndClose",
    ),
    Group(
        6,
        "medium",
        "washing dishes",
        ("PlaceOnDishRack", "SortingCleanup", "StackBowlsInSink"),
        "DumpLeftovers",
    ),
    Group(
        7,
        "medium",
        "restocking the pantry",
        ("ItemToOpenCabinet", "OpenCabinetDoor", "CanToDrawer"),
        "RestockCabinet",
    ),
    Group(8, "medium", "reheating", ("FoodToMicrowave", "CloseMicrowave", "OpenMicrowave"), "ReheatFood"),
    Group(
        9, "medium", "serving a snack", ("FruitToPlate", "FruitFromDrawer", "CloseDrawer"), "ServeFromDrawer"
    ),
    Group(10, "medium", "boiling water", ("CupToBurner", "TurnOnBurner", "CupSinkToCounter"), "HeatCup"),
    Group(
        11,
        "hard",
        "restocking the fridge",
        ("OpenFridgeDoor", "MilkToFridge", "CloseFridgeDoor"),
        "RestockFridge",
    ),
    Group(12, "hard", "cleaning up", ("CupToSink", "CloseCabinetDoor", "TurnOffBurner"), "CleanUpKitchen"),
    Group(13, "hard", "breakfast", ("FoodFromCabinet", "FruitToPlate", "CloseCabinetDoor"), "ServeBreakfast"),
    Group(
        14,
        "hard",
        "putting dishes away",
        ("CupFromRackToCounter", "ItemToOpenCabinet", "CloseCabinetDoor"),
        "PutAwayCup",
    ),
    Group(
        15,
        "hard",
        "starting to cook",
        ("FoodFromMicrowaveToPlate", "CloseMicrowave", "TurnOnBurner"),
        "StartCooking",
    ),
)
"""The activity groups, five per difficulty."""

for _g in GROUPS:
    if (
        not _g.covered()
        or _g.held_out in _g.develop
        or any(t not in COMPOSITES for t in (*_g.develop, _g.held_out))
    ):
        raise RuntimeError(
            f"group {_g.number}: its development tasks must be composite tasks covering its held-out task"
        )


def group_of(task_id: str) -> Group:
    """The group of a task id (``02-group-NN``)."""
    for g in GROUPS:
        if g.task_id == task_id:
            return g
    raise KeyError(f"no family-02 task {task_id!r}")
