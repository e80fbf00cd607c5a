"""The composite kitchen tasks (data): each a set of roles, a start, and a conjunction of predicates.

Names follow RoboCasa where it has the task (``PlaceOnDishRack``, ``SortingCleanup``,
``StackBowlsInSink``, ``DumpLeftovers``); the rest are built from the same atomic skills: pick and place
between counters, drawers, cabinets, the sink, the dish rack, the microwave, plates and burners;
opening and closing doors and drawers; turning knobs. Family 02 groups them into activity groups.
"""

from __future__ import annotations

from rle_tasks.envs.kitchen.composition import Burner, CompositeTask, Fx, In, Into, Joint, Obj, On
from rle_tasks.envs.kitchen.goals import (
    BurnerOff,
    BurnerOn,
    GripperFar,
    InReceptacle,
    Inside,
    IsClosed,
    IsOpen,
    NotInReceptacle,
    NotInside,
    OnBurner,
    OnCounter,
)
from rle_tasks.envs.kitchen.tasks import TASKS, KitchenTask

__all__ = ["COMPOSITES", "kitchen_task"]

FRUIT = ("apple", "orange", "lemon")
FOOD = ("bread", "butter", "apple", "lemon")
CANS = ("can",)
CUP = ("cup",)
SMALL = ("lemon", "bread")

DRAWER = Fx("drawer", ("drawer_cabinet",))
CABINET = Fx("cabinet", ("hinge_cabinet",))
SINK = Fx("sink", ("sink",))
RACK = Fx("rack", ("dish_rack",))
STOVE = Fx("stove", ("stove",))
MICROWAVE = Fx("microwave", ("microwave",))
FRIDGE = Fx("fridge", ("fridge",))

_TASKS = (
    # -- drawers
    CompositeTask("FruitToOpenDrawer", "Put the {fruit} from the counter into the open drawer.", (DRAWER,),
                  (Obj("fruit", FRUIT, On("drawer")),), (Inside("fruit", "drawer"), GripperFar("fruit")),
                  (Joint("drawer", 1.0),), focus="drawer"),
    CompositeTask("CloseDrawer", "Close the open drawer.", (DRAWER,), (), (IsClosed("drawer"),), (Joint("drawer", 1.0),), focus="drawer"),
    CompositeTask("OpenDrawer", "Open the drawer.", (DRAWER,), (), (IsOpen("drawer"),), focus="drawer"),
    CompositeTask("StowFruitInDrawer", "Put the {fruit} into the open drawer, then close the drawer.", (DRAWER,),
                  (Obj("fruit", FRUIT, On("drawer")),), (Inside("fruit", "drawer"), IsClosed("drawer")),
                  (Joint("drawer", 1.0),), focus="drawer"),
    CompositeTask("CanToDrawer", "Put the {can} from the counter into the open drawer.", (DRAWER,),
                  (Obj("can", CANS, On("drawer")),), (Inside("can", "drawer"), GripperFar("can")), (Joint("drawer", 1.0),), focus="drawer"),
    CompositeTask("FruitFromDrawer", "Take the {fruit} out of the open drawer and put it on the counter.", (DRAWER,),
                  (Obj("fruit", FRUIT, In("drawer")),), (NotInside("fruit", "drawer"), OnCounter("fruit"), GripperFar("fruit")),
                  (Joint("drawer", 1.0),), focus="drawer"),
    CompositeTask("FruitToPlate", "Put the {fruit} on the plate.", (DRAWER,),
                  (Obj("plate", ("plate",), On("drawer")), Obj("fruit", FRUIT, On("drawer"))),
                  (InReceptacle("fruit", "plate"), GripperFar("fruit")), focus="drawer"),
    CompositeTask("ServeFromDrawer", "Take the {fruit} out of the open drawer, put it on the plate and close the drawer.", (DRAWER,),
                  (Obj("plate", ("plate",), On("drawer")), Obj("fruit", FRUIT, In("drawer"))),
                  (InReceptacle("fruit", "plate"), IsClosed("drawer"), GripperFar("fruit")), (Joint("drawer", 1.0),), focus="drawer"),
    # -- sink and dish rack
    CompositeTask("PlaceOnDishRack", "Put the {cup} from the counter on the dish rack.", (SINK, Fx("rack", ("dish_rack",), near="sink")),
                  (Obj("cup", CUP, On("rack")),), (Inside("cup", "rack"), GripperFar("cup")), focus="rack"),
    CompositeTask("CupSinkToCounter", "Take the {cup} out of the sink and put it on the counter.", (SINK,),
                  (Obj("cup", CUP, In("sink")),), (NotInside("cup", "sink"), OnCounter("cup"), GripperFar("cup")), focus="sink"),
    CompositeTask("CupToSink", "Put the {cup} from the counter into the sink.", (SINK,),
                  (Obj("cup", CUP, On("sink")),), (Inside("cup", "sink"), GripperFar("cup")), focus="sink"),
    CompositeTask("RackCupFromSink", "Move the {cup} from the sink to the dish rack.", (SINK, Fx("rack", ("dish_rack",), near="sink")),
                  (Obj("cup", CUP, In("sink")),), (Inside("cup", "rack"), GripperFar("cup")), focus="sink", between="rack"),
    CompositeTask("SortingCleanup", "Put the {fruit} into the open drawer and the {cup} into the sink.", (SINK, Fx("drawer", ("drawer_cabinet",), near="sink")),
                  (Obj("fruit", FRUIT, On("sink")), Obj("cup", CUP, On("sink"))),
                  (Inside("fruit", "drawer"), Inside("cup", "sink"), GripperFar("cup")), (Joint("drawer", 1.0),), focus="sink", between="drawer"),
    CompositeTask("StackBowlsInSink", "Put both bowls from the counter into the sink.", (SINK,),
                  (Obj("bowl", ("bowl",), On("sink")), Obj("bowl2", ("bowl",), On("sink"))),
                  (Inside("bowl", "sink"), Inside("bowl2", "sink"), GripperFar("bowl")), focus="sink"),
    CompositeTask("DumpLeftovers", "Dump the leftovers out of the bowl, then put the bowl in the sink.", (SINK,),
                  (Obj("bowl", ("bowl",), On("sink")), Obj("leftover", SMALL, Into("bowl")), Obj("leftover2", SMALL, Into("bowl"))),
                  (NotInReceptacle("leftover", "bowl"), NotInReceptacle("leftover2", "bowl"), Inside("bowl", "sink"), GripperFar("bowl")),
                  focus="sink"),
    CompositeTask("CupFromRackToCounter", "Take the {cup} off the dish rack and put it on the counter.", (SINK, Fx("rack", ("dish_rack",), near="sink")),
                  (Obj("cup", CUP, In("rack")),), (NotInside("cup", "rack"), OnCounter("cup"), GripperFar("cup")), focus="rack"),
    CompositeTask("PutAwayCup", "Put the {cup} from the dish rack into the cabinet and close its door.",
                  (SINK, Fx("rack", ("dish_rack",), near="sink"), Fx("cabinet", ("hinge_cabinet",), near="rack")),
                  (Obj("cup", CUP, In("rack")),), (Inside("cup", "cabinet"), IsClosed("cabinet"), GripperFar("cup")), focus="rack", between="cabinet"),
    # -- stove
    CompositeTask("TurnOnBurner", "Turn on the {burner} burner.", (STOVE,), (), (BurnerOn("burner"),), burners=(Burner("burner"),), focus="stove"),
    CompositeTask("TurnOffBurner", "Turn off the {burner} burner.", (STOVE,), (), (BurnerOff("burner"),), burners=(Burner("burner", on=True),), focus="stove"),
    CompositeTask("TurnOnTwoBurners", "Turn on the {burner} and the {burner2} burners.", (STOVE,), (), (BurnerOn("burner"), BurnerOn("burner2")),
                  burners=(Burner("burner"), Burner("burner2", other_than="burner")), focus="stove"),
    CompositeTask("SwitchBurners", "Turn off the {burner} burner and turn on the {burner2} burner.", (STOVE,), (), (BurnerOff("burner"), BurnerOn("burner2")),
                  burners=(Burner("burner", on=True), Burner("burner2", other_than="burner")), focus="stove"),
    CompositeTask("CupToBurner", "Put the {cup} on the {burner} burner.", (STOVE,), (Obj("cup", CUP, On("stove")),),
                  (OnBurner("cup", "burner"), GripperFar("cup")), burners=(Burner("burner"),), focus="stove"),
    CompositeTask("HeatCup", "Move the {cup} from the sink onto the {burner} burner and turn that burner on.", (SINK, Fx("stove", ("stove",), near="sink")),
                  (Obj("cup", CUP, In("sink")),), (OnBurner("cup", "burner"), BurnerOn("burner"), GripperFar("cup")),
                  burners=(Burner("burner"),), focus="sink", between="stove"),
    # -- microwave
    CompositeTask("OpenMicrowave", "Open the microwave door.", (MICROWAVE,), (), (IsOpen("microwave"),), focus="microwave"),
    CompositeTask("CloseMicrowave", "Close the microwave door.", (MICROWAVE,), (), (IsClosed("microwave"),), (Joint("microwave", 1.0),), focus="microwave"),
    CompositeTask("FoodToMicrowave", "Put the {food} from the counter into the microwave.", (MICROWAVE,), (Obj("food", FOOD, On("microwave")),),
                  (Inside("food", "microwave"), GripperFar("food")), (Joint("microwave", 1.0),), focus="microwave"),
    CompositeTask("MicrowaveAndClose", "Put the {food} into the microwave and close its door.", (MICROWAVE,), (Obj("food", FOOD, On("microwave")),),
                  (Inside("food", "microwave"), IsClosed("microwave")), (Joint("microwave", 1.0),), focus="microwave"),
    CompositeTask("FoodFromMicrowaveToPlate", "Take the {food} out of the microwave and put it on the plate.", (MICROWAVE,),
                  (Obj("plate", ("plate",), On("microwave")), Obj("food", FOOD, In("microwave"))),
                  (InReceptacle("food", "plate"), GripperFar("food")), (Joint("microwave", 1.0),), focus="microwave"),
    CompositeTask("ReheatFood", "Heat the {food} in the microwave: put it inside and close the door.", (MICROWAVE,), (Obj("food", FOOD, On("microwave")),),
                  (Inside("food", "microwave"), IsClosed("microwave"), GripperFar("food")), focus="microwave"),
    CompositeTask("StartCooking", "Take the {food} out of the microwave onto the plate, close the microwave and turn on the {burner} burner.",
                  (MICROWAVE, Fx("stove", ("stove",), near="microwave")),
                  (Obj("plate", ("plate",), On("microwave")), Obj("food", FOOD, In("microwave"))),
                  (InReceptacle("food", "plate"), IsClosed("microwave"), BurnerOn("burner"), GripperFar("food")),
                  (Joint("microwave", 1.0),), burners=(Burner("burner"),), focus="microwave", between="stove"),
    # -- cabinets
    CompositeTask("OpenCabinetDoor", "Open the cabinet door.", (CABINET,), (), (IsOpen("cabinet"),), focus="cabinet"),
    CompositeTask("CloseCabinetDoor", "Close the cabinet door.", (CABINET,), (), (IsClosed("cabinet"),), (Joint("cabinet", 1.0),), focus="cabinet"),
    CompositeTask("ItemToOpenCabinet", "Put the {item} from the counter into the open cabinet.", (CABINET,), (Obj("item", FOOD + CANS, On("cabinet")),),
                  (Inside("item", "cabinet"), GripperFar("item")), (Joint("cabinet", 1.0),), focus="cabinet"),
    CompositeTask("StoreInCabinetAndClose", "Put the {item} into the open cabinet and close its door.", (CABINET,), (Obj("item", FOOD + CANS, On("cabinet")),),
                  (Inside("item", "cabinet"), IsClosed("cabinet")), (Joint("cabinet", 1.0),), focus="cabinet"),
    CompositeTask("RestockCabinet", "Put the {can} from the counter into the cabinet.", (CABINET,), (Obj("can", CANS, On("cabinet")),),
                  (Inside("can", "cabinet"), GripperFar("can")), focus="cabinet"),
    CompositeTask("FoodFromCabinet", "Take the {food} out of the open cabinet and put it on the counter.", (CABINET,), (Obj("food", FOOD, In("cabinet")),),
                  (NotInside("food", "cabinet"), OnCounter("food"), GripperFar("food")), (Joint("cabinet", 1.0),), focus="cabinet"),
    CompositeTask("ServeBreakfast", "Take the {food} out of the open cabinet, put it on the plate and close the cabinet.", (CABINET,),
                  (Obj("plate", ("plate",), On("cabinet")), Obj("food", FOOD, In("cabinet"))),
                  (InReceptacle("food", "plate"), IsClosed("cabinet"), GripperFar("food")), (Joint("cabinet", 1.0),), focus="cabinet"),
    CompositeTask("CleanUpKitchen", "Put the {cup} into the sink, close the cabinet and turn off the {burner} burner.",
                  (SINK, Fx("stove", ("stove",), near="sink"), Fx("cabinet", ("hinge_cabinet",), near="sink")),
                  (Obj("cup", CUP, On("sink")),), (Inside("cup", "sink"), IsClosed("cabinet"), BurnerOff("burner"), GripperFar("cup")),
                  (Joint("cabinet", 1.0),), burners=(Burner("burner", on=True),), focus="sink", between="stove"),
    # -- fridge
    CompositeTask("OpenFridgeDoor", "Open the fridge door.", (FRIDGE,), (), (IsOpen("fridge"),), focus="fridge"),
    CompositeTask("CloseFridgeDoor", "Close the fridge door.", (FRIDGE,), (), (IsClosed("fridge"),), (Joint("fridge", 1.0),), focus="fridge"),
    CompositeTask("MilkToFridge", "Put the {milk} from the counter into the open fridge.", (FRIDGE,), (Obj("milk", ("milk",), On("fridge")),),
                  (Inside("milk", "fridge"), GripperFar("milk")), (Joint("fridge", 1.0),), focus="fridge"),
    CompositeTask("RestockFridge", "Put the {milk} from the counter into the fridge and close the fridge.", (FRIDGE,), (Obj("milk", ("milk",), On("fridge")),),
                  (Inside("milk", "fridge"), IsClosed("fridge"), GripperFar("milk")), focus="fridge"),
)  # fmt: skip

COMPOSITES: dict[str, CompositeTask] = {t.name: t for t in _TASKS}
"""Every composite task by name."""
if len(COMPOSITES) != len(_TASKS):
    raise RuntimeError("composite task names must be unique")


def kitchen_task(name: str) -> KitchenTask:
    """An atomic task (``tasks.TASKS``) or a composite one (``COMPOSITES``) by name.

    Raises:
        KeyError: Unknown name (the message lists the atomic tasks).
    """
    if name in TASKS:
        return TASKS[name]
    if name in COMPOSITES:
        return COMPOSITES[name]
    raise KeyError(
        f"unknown kitchen task '{name}'. Atomic tasks: {', '.join(TASKS)}; composite: {', '.join(COMPOSITES)}"
    )
