"""What a kitchen fixture is: RoboCasa's dimensions and joint conventions, the colours of a kitchen
(``Style``) and the record a builder returns (``Fixture``).

The builders are in ``cabinetry`` (counter, cabinets) and ``appliances`` (fridge, stove, sink,
microwave, dish rack), over the shared shapes of ``geometry``.


Frame of a counter run (``layout.Run``): z up, the run's back line is ``y = 0`` and fixtures stand in
front of it (``y < 0``), their fronts facing -y; x runs along the run. A builder works in the frame of
the body it is given (the world for the one-wall kitchen, whose run frame is the world's; a static
``run_<k>`` body with the run's origin and yaw otherwise) and adds one static body (named after the
fixture) at the fixture's centre on the floor, with moving parts as children:

- hinged doors: a hinge about the door's vertical edge (cabinets: the edge of its front face, so a door
  flush with its neighbours swings clear of them), range 0..1.57 rad (0 closed), damping
  ``DOOR_DAMPING``; the axis is chosen so a positive angle swings the free edge out (towards -y);
- drawers: a slide along -y (out of the cabinet), range 0..``depth - 0.15`` m, damping
  ``DRAWER_DAMPING``;
- stove knobs: hinges about -y (out of the front panel), range [-pi, pi], a knob is "on" when its
  wrapped angle lies in [0.35, 2 pi - 0.35] rad (``rle_tasks.envs.kitchen.predicates``).

A builder returns a ``Fixture`` in its run's frame: its names, box, joints, interior region (a box in
the frame of the body that holds it) and the sites the tasks use; ``layout`` moves it to the world
(``Fixture.placed``: world ``pos`` and the facing ``yaw``). Units: metres, radians, kilograms.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

__all__ = [
    "BURNERS",
    "COUNTER_DEPTH",
    "COUNTER_HEIGHT",
    "DOOR_DAMPING",
    "DOOR_RANGE",
    "DRAWER_DAMPING",
    "GAP",
    "KNOB_RANGE",
    "KNOB_X",
    "PANEL",
    "TOE_KICK",
    "TOP_THICKNESS",
    "HANDLE_TYPES",
    "Fixture",
    "Interior",
    "Style",
]

COUNTER_HEIGHT = 0.92
"""Height of a counter top's surface [m]."""
COUNTER_DEPTH = 0.6
"""Depth of a base cabinet, front to wall [m]."""
TOP_THICKNESS = 0.04
"""Counter-top slab [m]."""
PANEL = 0.018
"""Cabinet panel thickness [m]."""
GAP = 0.003
"""Clearance between a moving part and the carcass [m]."""
TOE_KICK = 0.1
"""Height of the recessed plinth under base cabinets [m]."""
DOOR_RANGE = (0.0, 1.57)
"""Hinged door range [rad] (RoboCasa)."""
DOOR_DAMPING = 2.0
"""Hinged door damping [N m s/rad] (RoboCasa)."""
DRAWER_DAMPING = 10.0
"""Drawer slide damping [N s/m] (RoboCasa)."""
KNOB_RANGE = (-math.pi, math.pi)
"""Stove knob range [rad]."""
BURNERS = ("front_left", "front_right", "rear_left", "rear_right")
"""Burner names as the robot facing the stove sees them (left = -x)."""
KNOB_X = {"rear_left": -0.33, "front_left": -0.11, "front_right": 0.11, "rear_right": 0.33}
"""Knob position on the front panel per burner, as a fraction of the stove's width."""


HANDLE_TYPES = ("bar", "boxed", "knob")
"""Cabinet handle shapes (RoboCasa's cabinet handle types)."""


@dataclass(frozen=True)
class Style:
    """Colours (RGBA in [0, 1]) and the style's shapes and dimensions of one kitchen.

    Attributes:
        handle_type: Handle of the cabinets' doors and drawers, one of ``HANDLE_TYPES`` (the fridge's
            and the microwave's are bars whatever the style).
        counter_height: Height of the counter tops' surface [m].
        counter_depth: Depth of the base units, front to back [m].
    """

    cabinet: tuple[float, float, float, float] = (0.85, 0.85, 0.82, 1.0)
    counter: tuple[float, float, float, float] = (0.35, 0.33, 0.32, 1.0)
    handle: tuple[float, float, float, float] = (0.7, 0.7, 0.72, 1.0)
    appliance: tuple[float, float, float, float] = (0.8, 0.81, 0.83, 1.0)
    wall: tuple[float, float, float, float] = (0.93, 0.91, 0.86, 1.0)
    floor: tuple[float, float, float, float] = (0.55, 0.45, 0.36, 1.0)
    handle_type: str = "bar"
    counter_height: float = COUNTER_HEIGHT
    counter_depth: float = COUNTER_DEPTH


@dataclass(frozen=True)
class Interior:
    """An axis-aligned box in the frame of ``body``: its centre and half extents [m]."""

    body: str
    center: tuple[float, float, float]
    half: tuple[float, float, float]


@dataclass(frozen=True)
class Fixture:
    """One fixture of a kitchen.

    Attributes:
        name: Unique name (also its root body's name).
        kind: ``fridge``, ``hinge_cabinet``, ``drawer_cabinet``, ``stove``, ``sink``, ``microwave``,
            ``dish_rack``, ``counter`` or ``wall_cabinet``.
        pos: Centre of the fixture's footprint on its support (floor or counter top) [m].
        size: Full extents (width along x, depth along y, height) [m].
        joints: Articulated joints (doors, drawer, knobs), in a fixed order.
        interior: Region inside the fixture (None when it has none).
        top: Height of the surface objects can stand on (counter top, cooktop) [m], or None.
        sites: Named sites (handles, burners, knobs) by role.
        parts: Named bodies by role (``door``, ``drawer``, ``plate`` ...).
        top_geoms: Geoms of the surface objects stand on (counter top, cooktop, microwave plate, rack
            tray); a drawer's floor is not one (an object in the drawer touches no counter top).
        burners: Burner name -> (knob joint, burner geom) for a stove.
        hinge_left: The door is hinged on its left (-x) edge (None without a hinged door).
        yaw: Facing of the fixture's frame (its run's yaw) [rad]: the front faces the direction
            (sin yaw, -cos yaw) in the world; 0 for the one-wall kitchen (front towards -y). ``pos`` is
            in the world; ``size`` is in the fixture's own frame (width along its run, depth, height).
    """

    name: str
    kind: str
    pos: tuple[float, float, float]
    size: tuple[float, float, float]
    joints: tuple[str, ...] = ()
    interior: Interior | None = None
    top: float | None = None
    sites: dict[str, str] = field(default_factory=dict)
    parts: dict[str, str] = field(default_factory=dict)
    top_geoms: tuple[str, ...] = ()
    burners: dict[str, tuple[str, str]] = field(default_factory=dict)
    hinge_left: bool | None = None
    yaw: float = 0.0

    @property
    def front_y(self) -> float:
        """y of the fixture's front face [m] (a fixture facing -y, ``yaw`` = 0)."""
        return self.pos[1] - self.size[1] / 2

    @property
    def facing(self) -> tuple[float, float]:
        """Unit vector of the direction the front faces, in the world's xy plane."""
        return (math.sin(self.yaw), -math.cos(self.yaw))

    @property
    def front(self) -> tuple[float, float]:
        """World xy of the centre of the front face's footprint [m]."""
        fx_, fy_ = self.facing
        return (self.pos[0] + fx_ * self.size[1] / 2, self.pos[1] + fy_ * self.size[1] / 2)

    def placed(self, origin: tuple[float, float], yaw: float) -> Fixture:
        """This fixture, built in a run frame (``origin`` [m], ``yaw`` [rad]), with world ``pos`` and ``yaw``."""
        if origin == (0.0, 0.0) and yaw == 0.0:
            return self
        c, s = math.cos(yaw), math.sin(yaw)
        x, y, z = self.pos
        pos = (origin[0] + c * x - s * y, origin[1] + s * x + c * y, z)
        return replace(self, pos=pos, yaw=yaw)
