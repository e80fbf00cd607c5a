"""Kitchen fixtures as articulated MjSpec bodies, with RoboCasa's joint conventions.

Frame of the counter run: world z up, the back wall is the plane ``y = 0`` and fixtures stand in
front of it (``y < 0``), their fronts facing -y; x runs along the wall. Each builder adds one static
body (named after the fixture) at the fixture's centre on the floor, with moving parts as children:

- hinged doors: a hinge about the door's vertical edge (cabinets: the edge of its front face, so a door
  flush with its neighbours swings clear of them), range 0..1.57 rad (0 closed), damping
  ``DOOR_DAMPING``; the axis is chosen so a positive angle swings the free edge out (towards -y);
- drawers: a slide along -y (out of the cabinet), range 0..``depth - 0.15`` m, damping
  ``DRAWER_DAMPING``;
- stove knobs: hinges about -y (out of the front panel), range [-pi, pi], a knob is "on" when its
  wrapped angle lies in [0.35, 2 pi - 0.35] rad (``rle_tasks.envs.kitchen.predicates``).

A builder returns a ``Fixture``: its names, box, joints, interior region (a box in the frame of the
body that holds it) and the sites the tasks use. Units: metres, radians, kilograms.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import mujoco

__all__ = [
    "COUNTER_DEPTH",
    "COUNTER_HEIGHT",
    "DOOR_DAMPING",
    "DOOR_RANGE",
    "DRAWER_DAMPING",
    "KNOB_RANGE",
    "Fixture",
    "Interior",
    "Style",
    "add_counter",
    "add_dish_rack",
    "add_drawer_cabinet",
    "add_fridge",
    "add_hinge_cabinet",
    "add_microwave",
    "add_sink",
    "add_stove",
    "add_wall_cabinet",
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
_KNOB_X = {"rear_left": -0.33, "front_left": -0.11, "front_right": 0.11, "rear_right": 0.33}
"""Knob position on the front panel per burner, as a fraction of the stove's width."""


@dataclass(frozen=True)
class Style:
    """Colours of one kitchen (RGBA in [0, 1])."""

    cabinet: tuple[float, float, float, float] = (0.85, 0.85, 0.82, 1.0)
    counter: tuple[float, float, float, float] = (0.35, 0.33, 0.32, 1.0)
    handle: tuple[float, float, float, float] = (0.7, 0.7, 0.72, 1.0)
    appliance: tuple[float, float, float, float] = (0.8, 0.81, 0.83, 1.0)
    wall: tuple[float, float, float, float] = (0.93, 0.91, 0.86, 1.0)
    floor: tuple[float, float, float, float] = (0.55, 0.45, 0.36, 1.0)


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

    @property
    def front_y(self) -> float:
        """y of the fixture's front face [m]."""
        return self.pos[1] - self.size[1] / 2


def _box(body: mujoco.MjsBody, name: str, center, half, rgba, **kw) -> mujoco.MjsGeom:
    return body.add_geom(
        name=name, type=mujoco.mjtGeom.mjGEOM_BOX, pos=list(center), size=list(half), rgba=list(rgba), **kw
    )


def _cyl(body: mujoco.MjsBody, name: str, center, radius, half_len, rgba, quat=(1, 0, 0, 0), **kw):
    return body.add_geom(
        name=name,
        type=mujoco.mjtGeom.mjGEOM_CYLINDER,
        pos=list(center),
        size=[radius, half_len, 0],
        quat=list(quat),
        rgba=list(rgba),
        **kw,
    )


_ALONG_X = (math.cos(math.pi / 4), 0.0, math.sin(math.pi / 4), 0.0)
_ALONG_Y = (math.cos(math.pi / 4), math.sin(math.pi / 4), 0.0, 0.0)


def _bar_handle(body: mujoco.MjsBody, name: str, center, length: float, vertical: bool, style: Style) -> str:
    """A bar handle standing 35 mm proud of a front face (``center`` on the face); returns its site."""
    x, y, z = center
    off = 0.035
    quat = (1, 0, 0, 0) if vertical else _ALONG_X
    _cyl(body, name, (x, y - off, z), 0.01, length / 2, style.handle, quat=quat, mass=0.2, condim=4)
    for k, s in enumerate((-1, 1)):
        dx, dz = (0.0, s * length * 0.4) if vertical else (s * length * 0.4, 0.0)
        _box(
            body,
            f"{name}_post{k}",
            (x + dx, y - off / 2, z + dz),
            (0.006, off / 2, 0.006),
            style.handle,
            mass=0.02,
        )
    site = body.add_site(name=name, pos=[x, y - off, z], size=[0.012, 0, 0], rgba=[1, 0, 0, 0], group=5)
    return site.name


def _carcass(
    body: mujoco.MjsBody,
    name: str,
    w: float,
    d: float,
    h: float,
    z0: float,
    rgba,
    *,
    top: bool = False,
    front: bool = False,
) -> None:
    """Open-fronted box of panels in ``body``'s frame: x in [-w/2, w/2], y in [-d/2, d/2], z in [z0, z0 + h]."""
    t = PANEL
    zc = z0 + h / 2
    _box(body, f"{name}_left", (-w / 2 + t / 2, 0, zc), (t / 2, d / 2, h / 2), rgba)
    _box(body, f"{name}_right", (w / 2 - t / 2, 0, zc), (t / 2, d / 2, h / 2), rgba)
    _box(body, f"{name}_back", (0, d / 2 - t / 2, zc), (w / 2 - t, t / 2, h / 2), rgba)
    _box(body, f"{name}_bottom", (0, 0, z0 + t / 2), (w / 2 - t, d / 2 - t, t / 2), rgba)
    if top:
        _box(body, f"{name}_ceiling", (0, 0, z0 + h - t / 2), (w / 2 - t, d / 2 - t, t / 2), rgba)
    if front:
        _box(body, f"{name}_front", (0, -d / 2 + t / 2, zc), (w / 2 - t, t / 2, h / 2), rgba)


def _root(world: mujoco.MjsBody, name: str, x: float, d: float, z: float = 0.0) -> mujoco.MjsBody:
    return world.add_body(name=name, pos=[x, -d / 2, z])


def _counter_top(body: mujoco.MjsBody, name: str, w: float, d: float, style: Style) -> str:
    geom = _box(
        body,
        f"{name}_top",
        (0, -0.01, COUNTER_HEIGHT - TOP_THICKNESS / 2),
        (w / 2, d / 2 + 0.01, TOP_THICKNESS / 2),
        style.counter,
        friction=[1.0, 0.005, 0.0001],
    )
    return geom.name


def _hinged_door(
    parent: mujoco.MjsBody,
    name: str,
    hinge_left: bool,
    w: float,
    h: float,
    front_y: float,
    z0: float,
    rgba,
    style: Style,
    *,
    mass: float = 2.0,
    handle_len: float = 0.16,
    handle_z: float | None = None,
    front_pivot: bool = False,
) -> tuple[mujoco.MjsBody, str, str]:
    """A door panel of width ``w`` hinged on its left (-x) or right edge; returns (body, joint, handle site).

    The hinge axis runs through the panel's mid-plane, or with ``front_pivot`` through the edge of its
    front face (an overlay hinge): a door flush with its neighbours' fronts needs the latter, else its
    hinge-side edge swings into the neighbour's front and stops it short of 90 deg (base cabinets beside
    a drawer were held at 0.1-0.3 of their range). The closed door is the same either way.
    """
    s = 1.0 if hinge_left else -1.0
    hinge_x = -s * w / 2
    back = PANEL / 2 if front_pivot else 0.0  # panel centre behind the axis
    door = parent.add_body(name=f"{name}_door", pos=[hinge_x, front_y - PANEL / 2 - GAP - back, z0 + GAP])
    joint = door.add_joint(
        name=f"{name}_hinge",
        type=mujoco.mjtJoint.mjJNT_HINGE,
        axis=[0, 0, -s],
        range=list(DOOR_RANGE),
        damping=[DOOR_DAMPING, 0, 0],
        frictionloss=0.05,
        armature=0.01,
    )
    joint.limited = 1
    _box(
        door,
        f"{name}_door_panel",
        (s * (w / 2), back, h / 2 - GAP),
        ((w - 2 * GAP) / 2, PANEL / 2, h / 2 - GAP),
        rgba,
        mass=mass,
    )
    hz = h * 0.5 if handle_z is None else handle_z
    site = _bar_handle(
        door, f"{name}_handle", (s * (w - 0.06), back - PANEL / 2, hz), handle_len, True, style
    )
    return door, joint.name, site


def add_counter(world: mujoco.MjsBody, name: str, x: float, w: float, style: Style) -> Fixture:
    """A solid base cabinet with a counter top."""
    d = COUNTER_DEPTH
    body = _root(world, name, x, d)
    _box(
        body,
        f"{name}_body",
        (0, 0.01, (COUNTER_HEIGHT - TOP_THICKNESS) / 2),
        (w / 2, d / 2 - 0.01, (COUNTER_HEIGHT - TOP_THICKNESS) / 2),
        style.cabinet,
    )
    top = _counter_top(body, name, w, d, style)
    return Fixture(
        name, "counter", (x, -d / 2, 0.0), (w, d, COUNTER_HEIGHT), top=COUNTER_HEIGHT, top_geoms=(top,)
    )


def add_hinge_cabinet(
    world: mujoco.MjsBody, name: str, x: float, w: float, hinge_left: bool, style: Style
) -> Fixture:
    """A base cabinet with one hinged door, a shelf and a counter top."""
    d = COUNTER_DEPTH
    body = _root(world, name, x, d)
    h = COUNTER_HEIGHT - TOP_THICKNESS - TOE_KICK
    _box(body, f"{name}_plinth", (0, 0.03, TOE_KICK / 2), (w / 2, d / 2 - 0.03, TOE_KICK / 2), style.cabinet)
    _carcass(body, name, w, d, h, TOE_KICK, style.cabinet)
    _box(
        body,
        f"{name}_shelf",
        (0, 0.01, TOE_KICK + h / 2),
        (w / 2 - PANEL, d / 2 - PANEL - 0.01, PANEL / 2),
        style.cabinet,
    )
    top = _counter_top(body, name, w, d, style)
    door, joint, handle = _hinged_door(
        body,
        name,
        hinge_left,
        w,
        h,
        -d / 2,
        TOE_KICK,
        style.cabinet,
        style,
        handle_z=h * 0.8,
        front_pivot=True,
    )
    interior = Interior(name, (0, 0.0, TOE_KICK + h / 2), (w / 2 - PANEL, d / 2 - PANEL, h / 2 - PANEL))
    return Fixture(
        name,
        "hinge_cabinet",
        (x, -d / 2, 0.0),
        (w, d, COUNTER_HEIGHT),
        joints=(joint,),
        interior=interior,
        top=COUNTER_HEIGHT,
        sites={"handle": handle},
        parts={"door": door.name},
        top_geoms=(top,),
        hinge_left=hinge_left,
    )


def add_drawer_cabinet(world: mujoco.MjsBody, name: str, x: float, w: float, style: Style) -> Fixture:
    """A base cabinet whose top drawer slides out along -y (below it a fixed front) and a counter top."""
    d = COUNTER_DEPTH
    body = _root(world, name, x, d)
    h = COUNTER_HEIGHT - TOP_THICKNESS - TOE_KICK
    _box(body, f"{name}_plinth", (0, 0.03, TOE_KICK / 2), (w / 2, d / 2 - 0.03, TOE_KICK / 2), style.cabinet)
    _carcass(body, name, w, d, h, TOE_KICK, style.cabinet)
    front_h = 0.2
    z_drawer = COUNTER_HEIGHT - TOP_THICKNESS - front_h
    lower_h = z_drawer - TOE_KICK - GAP
    _box(
        body,
        f"{name}_lower_front",
        (0, -d / 2 - PANEL / 2 - GAP, TOE_KICK + lower_h / 2),
        (w / 2 - GAP, PANEL / 2, lower_h / 2),
        style.cabinet,
    )
    _box(
        body,
        f"{name}_runner",
        (0, 0.0, z_drawer - GAP - PANEL / 2),
        (w / 2 - PANEL, d / 2 - PANEL, PANEL / 2),
        style.cabinet,
    )
    top = _counter_top(body, name, w, d, style)
    drawer = body.add_body(name=f"{name}_drawer", pos=[0, 0, z_drawer])
    travel = d - 0.15
    joint = drawer.add_joint(
        name=f"{name}_slide",
        type=mujoco.mjtJoint.mjJNT_SLIDE,
        axis=[0, -1, 0],
        range=[0.0, travel],
        damping=[DRAWER_DAMPING, 0, 0],
        frictionloss=0.5,
        armature=0.05,
    )
    joint.limited = 1
    iw, ih = w / 2 - PANEL - GAP - 0.01, 0.13
    # the tray runs from the front panel's inner face to 2 cm short of the carcass's back panel
    tray_front, tray_back = -d / 2 - GAP, d / 2 - PANEL - 0.02
    yc, idp = (tray_front + tray_back) / 2, (tray_back - tray_front) / 2
    rgba = style.cabinet
    _box(
        drawer,
        f"{name}_drawer_front",
        (0, -d / 2 - PANEL / 2 - GAP, front_h / 2),
        (w / 2 - GAP, PANEL / 2, front_h / 2 - GAP),
        rgba,
        mass=1.0,
    )
    _box(drawer, f"{name}_drawer_bottom", (0, yc, 0.01 + 0.005), (iw, idp, 0.005), rgba, mass=0.8)
    _box(
        drawer,
        f"{name}_drawer_back",
        (0, tray_back - 0.005, 0.01 + ih / 2),
        (iw, 0.005, ih / 2),
        rgba,
        mass=0.3,
    )
    for k, sx in enumerate((-1, 1)):
        _box(
            drawer,
            f"{name}_drawer_side{k}",
            (sx * (iw - 0.005), yc, 0.01 + ih / 2),
            (0.005, idp, ih / 2),
            rgba,
            mass=0.3,
        )
    handle = _bar_handle(
        drawer, f"{name}_handle", (0, -d / 2 - PANEL - GAP, front_h / 2), min(0.3, w * 0.5), False, style
    )
    interior = Interior(drawer.name, (0, yc, 0.02 + ih / 2), (iw - 0.01, idp - 0.01, ih / 2))
    return Fixture(
        name,
        "drawer_cabinet",
        (x, -d / 2, 0.0),
        (w, d, COUNTER_HEIGHT),
        joints=(joint.name,),
        interior=interior,
        top=COUNTER_HEIGHT,
        sites={"handle": handle},
        parts={"drawer": drawer.name},
        top_geoms=(top,),
    )


def add_fridge(
    world: mujoco.MjsBody, name: str, x: float, w: float, hinge_left: bool, style: Style
) -> Fixture:
    """A tall fridge (1.8 m): insulated carcass with two shelves and one hinged door."""
    d, h = 0.7, 1.8
    body = _root(world, name, x, d)
    _carcass(body, name, w, d, h, 0.0, style.appliance, top=True)
    for k, zf in enumerate((0.45, 0.9)):
        _box(
            body,
            f"{name}_shelf{k}",
            (0, 0.02, h * zf),
            (w / 2 - PANEL, d / 2 - PANEL - 0.02, 0.006),
            (0.8, 0.85, 0.9, 0.6),
        )
    door, joint, handle = _hinged_door(
        body,
        name,
        hinge_left,
        w,
        h - 0.02,
        -d / 2,
        0.01,
        style.appliance,
        style,
        mass=6.0,
        handle_len=0.4,
        handle_z=1.0,
    )
    interior = Interior(name, (0, 0, h / 2), (w / 2 - PANEL, d / 2 - PANEL, h / 2 - PANEL))
    return Fixture(
        name, "fridge", (x, -d / 2, 0.0), (w, d, h), joints=(joint,), interior=interior, sites={"handle": handle},
        parts={"door": door.name}, hinge_left=hinge_left,
    )  # fmt: skip


def add_stove(world: mujoco.MjsBody, name: str, x: float, w: float, style: Style) -> Fixture:
    """A range: oven body, a glass cooktop with four burners, four knobs on the front panel."""
    d = COUNTER_DEPTH
    body = _root(world, name, x, d)
    _box(
        body,
        f"{name}_body",
        (0, 0.0, (COUNTER_HEIGHT - 0.03) / 2),
        (w / 2, d / 2, (COUNTER_HEIGHT - 0.03) / 2),
        style.appliance,
    )
    cook = _box(
        body,
        f"{name}_cooktop",
        (0, 0, COUNTER_HEIGHT - 0.015),
        (w / 2, d / 2, 0.015),
        (0.08, 0.08, 0.09, 1.0),
    )
    _box(
        body,
        f"{name}_oven_window",
        (0, -d / 2 - 0.001, 0.45),
        (w / 2 - 0.08, 0.001, 0.15),
        (0.1, 0.1, 0.12, 1.0),
        contype=0,
        conaffinity=0,
    )
    burners: dict[str, tuple[str, str]] = {}
    sites: dict[str, str] = {}
    panel_z = COUNTER_HEIGHT - 0.12
    _box(body, f"{name}_panel", (0, -d / 2 - 0.01, panel_z), (w / 2, 0.01, 0.06), (0.2, 0.2, 0.22, 1.0))
    for burner in BURNERS:
        bx = (-1 if "left" in burner else 1) * w * 0.22
        by = -0.12 if "front" in burner else 0.12
        ring = _cyl(
            body,
            f"{name}_{burner}_burner",
            (bx, by, COUNTER_HEIGHT + 0.001),
            0.09,
            0.001,
            (0.25, 0.25, 0.27, 1.0),
            contype=0,
            conaffinity=0,
        )
        kx = _KNOB_X[burner] * w
        knob = body.add_body(name=f"{name}_{burner}_knob", pos=[kx, -d / 2 - 0.02, panel_z])
        joint = knob.add_joint(
            name=f"{name}_{burner}_knob_joint",
            type=mujoco.mjtJoint.mjJNT_HINGE,
            axis=[0, -1, 0],
            range=list(KNOB_RANGE),
            damping=[0.05, 0, 0],
            frictionloss=0.03,
            armature=0.002,
        )
        joint.limited = 1
        _cyl(
            knob,
            f"{name}_{burner}_knob",
            (0, -0.015, 0),
            0.022,
            0.015,
            (0.85, 0.85, 0.85, 1.0),
            quat=_ALONG_Y,
            mass=0.05,
            condim=4,
        )
        _box(
            knob,
            f"{name}_{burner}_knob_grip",
            (0, -0.025, 0),
            (0.005, 0.012, 0.02),
            (0.3, 0.3, 0.3, 1.0),
            mass=0.01,
            condim=4,
        )
        knob.add_site(
            name=f"{name}_{burner}_knob_site",
            pos=[0, -0.03, 0],
            size=[0.01, 0, 0],
            rgba=[1, 0, 0, 0],
            group=5,
        )
        body.add_site(
            name=f"{name}_{burner}_site",
            pos=[bx, by, COUNTER_HEIGHT + 0.002],
            size=[0.01, 0, 0],
            rgba=[1, 0, 0, 0],
            group=5,
        )
        burners[burner] = (joint.name, ring.name)
        sites[f"{burner}_knob"] = f"{name}_{burner}_knob_site"
        sites[f"{burner}_burner"] = f"{name}_{burner}_site"
    return Fixture(
        name,
        "stove",
        (x, -d / 2, 0.0),
        (w, d, COUNTER_HEIGHT),
        joints=tuple(j for j, _ in burners.values()),
        top=COUNTER_HEIGHT,
        sites=sites,
        top_geoms=(cook.name,),
        burners=burners,
    )


def add_sink(world: mujoco.MjsBody, name: str, x: float, w: float, style: Style) -> Fixture:
    """A base cabinet whose counter top holds a basin (0.5 x 0.38 x 0.2 m) and a faucet."""
    d = COUNTER_DEPTH
    body = _root(world, name, x, d)
    zt = COUNTER_HEIGHT - TOP_THICKNESS
    _box(body, f"{name}_body", (0, 0.01, zt / 2 - 0.12), (w / 2, d / 2 - 0.01, zt / 2 - 0.12), style.cabinet)
    bw, bd, bh = 0.25, 0.19, 0.2
    yc = -0.03
    rim = style.counter
    tz = COUNTER_HEIGHT - TOP_THICKNESS / 2
    _box(
        body,
        f"{name}_top_front",
        (0, (-d / 2 - 0.02 + yc - bd) / 2, tz),
        (w / 2, (yc - bd + d / 2 + 0.02) / 2, TOP_THICKNESS / 2),
        rim,
    )
    _box(
        body,
        f"{name}_top_back",
        (0, (d / 2 + yc + bd) / 2, tz),
        (w / 2, (d / 2 - yc - bd) / 2, TOP_THICKNESS / 2),
        rim,
    )
    for k, sx in enumerate((-1, 1)):
        _box(
            body,
            f"{name}_top_side{k}",
            (sx * (w / 2 + bw) / 2, yc, tz),
            ((w / 2 - bw) / 2, bd, TOP_THICKNESS / 2),
            rim,
        )
    steel = (0.75, 0.76, 0.78, 1.0)
    zb = COUNTER_HEIGHT - bh
    _box(body, f"{name}_basin_bottom", (0, yc, zb - 0.005), (bw, bd, 0.005), steel)
    _box(
        body,
        f"{name}_basin_front",
        (0, yc - bd - 0.005, zb + bh / 2 - TOP_THICKNESS / 2),
        (bw + 0.01, 0.005, bh / 2 - TOP_THICKNESS / 2),
        steel,
    )
    _box(
        body,
        f"{name}_basin_back",
        (0, yc + bd + 0.005, zb + bh / 2 - TOP_THICKNESS / 2),
        (bw + 0.01, 0.005, bh / 2 - TOP_THICKNESS / 2),
        steel,
    )
    for k, sx in enumerate((-1, 1)):
        _box(
            body,
            f"{name}_basin_side{k}",
            (sx * (bw + 0.005), yc, zb + bh / 2 - TOP_THICKNESS / 2),
            (0.005, bd, bh / 2 - TOP_THICKNESS / 2),
            steel,
        )
    _cyl(body, f"{name}_faucet", (0, d / 2 - 0.06, COUNTER_HEIGHT + 0.15), 0.015, 0.15, steel)
    _cyl(body, f"{name}_spout", (0, d / 2 - 0.14, COUNTER_HEIGHT + 0.29), 0.012, 0.08, steel, quat=_ALONG_Y)
    interior = Interior(name, (0, yc, zb + bh / 2), (bw, bd, bh / 2))
    return Fixture(
        name,
        "sink",
        (x, -d / 2, 0.0),
        (w, d, COUNTER_HEIGHT),
        interior=interior,
        top=COUNTER_HEIGHT,
        top_geoms=(f"{name}_top_front", f"{name}_top_back", f"{name}_top_side0", f"{name}_top_side1"),
    )


def add_microwave(world: mujoco.MjsBody, name: str, x: float, y_back: float, style: Style) -> Fixture:
    """A microwave (0.5 x 0.38 x 0.3 m) standing on a counter top, its back at ``y_back``: a
    turntable plate inside and a door hinged on its left edge."""
    w, d, h = 0.5, 0.38, 0.3
    body = world.add_body(name=name, pos=[x, y_back - d / 2, COUNTER_HEIGHT])
    dark = (0.12, 0.12, 0.13, 1.0)
    _carcass(body, name, w, d, h, 0.0, style.appliance, top=True)
    panel_w = 0.12
    _box(
        body,
        f"{name}_controls",
        (w / 2 - panel_w / 2, -d / 2 + PANEL / 2, h / 2),
        (panel_w / 2 - PANEL, PANEL / 2, h / 2 - PANEL),
        dark,
    )
    cavity_w = w - panel_w
    plate = _cyl(
        body,
        f"{name}_plate",
        (-panel_w / 2, 0.0, PANEL + 0.004),
        0.12,
        0.004,
        (0.9, 0.9, 0.92, 1.0),
        friction=[1.0, 0.005, 0.0001],
    )
    door, joint, handle = _hinged_door(
        body, name, True, w, h - 0.004, -d / 2, 0.002, dark, style, mass=1.0, handle_len=0.16, handle_z=h / 2
    )
    interior = Interior(
        name, (-panel_w / 2, 0.0, h / 2), (cavity_w / 2 - PANEL, d / 2 - PANEL, h / 2 - PANEL)
    )
    return Fixture(
        name,
        "microwave",
        (x, y_back - d / 2, COUNTER_HEIGHT),
        (w, d, h),
        joints=(joint,),
        interior=interior,
        top=COUNTER_HEIGHT + PANEL + 0.008,
        sites={"handle": handle},
        parts={"door": door.name},
        top_geoms=(plate.name,),
        hinge_left=True,
    )


def add_dish_rack(world: mujoco.MjsBody, name: str, x: float, y: float) -> Fixture:
    """A dish rack (0.4 x 0.3 m tray with tines) on a counter top centred at (x, y)."""
    w, d = 0.4, 0.3
    body = world.add_body(name=name, pos=[x, y, COUNTER_HEIGHT])
    wire = (0.85, 0.86, 0.88, 1.0)
    _box(body, f"{name}_tray", (0, 0, 0.005), (w / 2, d / 2, 0.005), wire)
    for k in range(5):
        _box(
            body,
            f"{name}_tine{k}",
            (-w / 2 + 0.06 + k * (w - 0.12) / 4, 0.05, 0.06),
            (0.003, 0.003, 0.05),
            wire,
        )
    for k, sy in enumerate((-1, 1)):
        _box(body, f"{name}_rail{k}", (0, sy * (d / 2 - 0.005), 0.03), (w / 2, 0.005, 0.025), wire)
    interior = Interior(name, (0, 0, 0.1), (w / 2, d / 2, 0.1))
    return Fixture(
        name,
        "dish_rack",
        (x, y, COUNTER_HEIGHT),
        (w, d, 0.12),
        interior=interior,
        top=COUNTER_HEIGHT + 0.01,
        top_geoms=(f"{name}_tray",),
    )


def add_wall_cabinet(
    world: mujoco.MjsBody, name: str, x: float, w: float, hinge_left: bool, style: Style
) -> Fixture:
    """A wall cabinet (0.35 m deep, 0.7 m tall, bottom at 1.45 m) with one hinged door."""
    d, h, z0 = 0.35, 0.7, 1.45
    body = _root(world, name, x, d, z0)
    _carcass(body, name, w, d, h, 0.0, style.cabinet, top=True)
    _box(
        body,
        f"{name}_shelf",
        (0, 0.01, h / 2),
        (w / 2 - PANEL, d / 2 - PANEL - 0.01, PANEL / 2),
        style.cabinet,
    )
    door, joint, handle = _hinged_door(
        body, name, hinge_left, w, h, -d / 2, 0.0, style.cabinet, style, handle_z=0.12, front_pivot=True
    )
    interior = Interior(name, (0, 0, h / 2), (w / 2 - PANEL, d / 2 - PANEL, h / 2 - PANEL))
    return Fixture(
        name,
        "wall_cabinet",
        (x, -d / 2, z0),
        (w, d, h),
        joints=(joint,),
        interior=interior,
        sites={"handle": handle},
        parts={"door": door.name},
        hinge_left=hinge_left,
    )
