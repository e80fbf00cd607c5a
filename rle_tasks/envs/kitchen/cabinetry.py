"""Cabinetry builders: the counter, base cabinets with a hinged door or a drawer, wall cabinets (each
adds one fixture's bodies to the world and returns its ``Fixture``)."""

from __future__ import annotations

import mujoco

from .fixture import (
    DRAWER_DAMPING,
    GAP,
    PANEL,
    TOE_KICK,
    TOP_THICKNESS,
    Fixture,
    Interior,
    Style,
)
from .geometry import box, carcass, counter_top, hinged_door, root
from .geometry import handle as make_handle

__all__ = ["add_corner", "add_counter", "add_drawer_cabinet", "add_hinge_cabinet", "add_wall_cabinet"]


def add_counter(world: mujoco.MjsBody, name: str, x: float, w: float, style: Style) -> Fixture:
    """A solid base cabinet with a counter top."""
    d = style.counter_depth
    body = root(world, name, x, d)
    box(
        body,
        f"{name}_body",
        (0, 0.01, (style.counter_height - TOP_THICKNESS) / 2),
        (w / 2, d / 2 - 0.01, (style.counter_height - TOP_THICKNESS) / 2),
        style.cabinet,
    )
    top = counter_top(body, name, w, d, style)
    return Fixture(
        name,
        "counter",
        (x, -d / 2, 0.0),
        (w, d, style.counter_height),
        top=style.counter_height,
        top_geoms=(top,),
    )


def add_hinge_cabinet(
    world: mujoco.MjsBody, name: str, x: float, w: float, hinge_left: bool, style: Style
) -> Fixture:
    """A base cabinet with one hinged door, a shelf and a counter top."""
    d = style.counter_depth
    body = root(world, name, x, d)
    h = style.counter_height - TOP_THICKNESS - TOE_KICK
    box(body, f"{name}_plinth", (0, 0.03, TOE_KICK / 2), (w / 2, d / 2 - 0.03, TOE_KICK / 2), style.cabinet)
    carcass(body, name, w, d, h, TOE_KICK, style.cabinet)
    box(
        body,
        f"{name}_shelf",
        (0, 0.01, TOE_KICK + h / 2),
        (w / 2 - PANEL, d / 2 - PANEL - 0.01, PANEL / 2),
        style.cabinet,
    )
    top = counter_top(body, name, w, d, style)
    door, joint, handle = hinged_door(
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
        styled_handle=True,
    )
    interior = Interior(name, (0, 0.0, TOE_KICK + h / 2), (w / 2 - PANEL, d / 2 - PANEL, h / 2 - PANEL))
    return Fixture(
        name,
        "hinge_cabinet",
        (x, -d / 2, 0.0),
        (w, d, style.counter_height),
        joints=(joint,),
        interior=interior,
        top=style.counter_height,
        sites={"handle": handle},
        parts={"door": door.name},
        top_geoms=(top,),
        hinge_left=hinge_left,
    )


def add_drawer_cabinet(world: mujoco.MjsBody, name: str, x: float, w: float, style: Style) -> Fixture:
    """A base cabinet whose top drawer slides out along -y (below it a fixed front) and a counter top."""
    d = style.counter_depth
    body = root(world, name, x, d)
    h = style.counter_height - TOP_THICKNESS - TOE_KICK
    box(body, f"{name}_plinth", (0, 0.03, TOE_KICK / 2), (w / 2, d / 2 - 0.03, TOE_KICK / 2), style.cabinet)
    carcass(body, name, w, d, h, TOE_KICK, style.cabinet)
    front_h = 0.2
    z_drawer = style.counter_height - TOP_THICKNESS - front_h
    lower_h = z_drawer - TOE_KICK - GAP
    box(
        body,
        f"{name}_lower_front",
        (0, -d / 2 - PANEL / 2 - GAP, TOE_KICK + lower_h / 2),
        (w / 2 - GAP, PANEL / 2, lower_h / 2),
        style.cabinet,
    )
    box(
        body,
        f"{name}_runner",
        (0, 0.0, z_drawer - GAP - PANEL / 2),
        (w / 2 - PANEL, d / 2 - PANEL, PANEL / 2),
        style.cabinet,
    )
    top = counter_top(body, name, w, d, style)
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
    box(
        drawer,
        f"{name}_drawer_front",
        (0, -d / 2 - PANEL / 2 - GAP, front_h / 2),
        (w / 2 - GAP, PANEL / 2, front_h / 2 - GAP),
        rgba,
        mass=1.0,
    )
    box(drawer, f"{name}_drawer_bottom", (0, yc, 0.01 + 0.005), (iw, idp, 0.005), rgba, mass=0.8)
    box(
        drawer,
        f"{name}_drawer_back",
        (0, tray_back - 0.005, 0.01 + ih / 2),
        (iw, 0.005, ih / 2),
        rgba,
        mass=0.3,
    )
    for k, sx in enumerate((-1, 1)):
        box(
            drawer,
            f"{name}_drawer_side{k}",
            (sx * (iw - 0.005), yc, 0.01 + ih / 2),
            (0.005, idp, ih / 2),
            rgba,
            mass=0.3,
        )
    handle_site = make_handle(
        drawer, f"{name}_handle", (0, -d / 2 - PANEL - GAP, front_h / 2), min(0.3, w * 0.5), False, style
    )
    interior = Interior(drawer.name, (0, yc, 0.02 + ih / 2), (iw - 0.01, idp - 0.01, ih / 2))
    return Fixture(
        name,
        "drawer_cabinet",
        (x, -d / 2, 0.0),
        (w, d, style.counter_height),
        joints=(joint.name,),
        interior=interior,
        top=style.counter_height,
        sites={"handle": handle_site},
        parts={"drawer": drawer.name},
        top_geoms=(top,),
    )


def add_wall_cabinet(
    world: mujoco.MjsBody, name: str, x: float, w: float, hinge_left: bool, style: Style
) -> Fixture:
    """A wall cabinet (0.35 m deep, 0.7 m tall, bottom at 1.45 m) with one hinged door."""
    d, h, z0 = 0.35, 0.7, 1.45
    body = root(world, name, x, d, z0)
    carcass(body, name, w, d, h, 0.0, style.cabinet, top=True)
    box(
        body,
        f"{name}_shelf",
        (0, 0.01, h / 2),
        (w / 2 - PANEL, d / 2 - PANEL - 0.01, PANEL / 2),
        style.cabinet,
    )
    door, joint, handle = hinged_door(
        body, name, hinge_left, w, h, -d / 2, 0.0, style.cabinet, style, handle_z=0.12, front_pivot=True,
        styled_handle=True,
    )  # fmt: skip
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


def add_corner(
    world: mujoco.MjsBody, name: str, x: float, w: float, leg: float, side: int, style: Style
) -> Fixture:
    """A blind corner piece: a solid base unit with a counter top at the end of a run where another
    run meets it, plus a leg ``leg`` deep in front of its ``side`` end (+1: the run's +x end) as wide as
    the counter is deep, on which the other run's first unit abuts. It fills the corner square and
    keeps the units on both sides of the corner ``leg`` apart (doors and handles clear each other)."""
    d, top_h = style.counter_depth, style.counter_height
    body = root(world, name, x, d)
    zc = (top_h - TOP_THICKNESS) / 2
    box(body, f"{name}_body", (0, 0.01, zc), (w / 2, d / 2 - 0.01, zc), style.cabinet)
    top = counter_top(body, name, w, d, style)
    lx = side * (w / 2 - d / 2)
    box(body, f"{name}_leg", (lx, -d / 2 - leg / 2, zc), (d / 2, leg / 2, zc), style.cabinet)
    leg_top = box(
        body,
        f"{name}_leg_top",
        (lx - side * 0.01, -d / 2 - 0.02 - (leg - 0.02) / 2, top_h - TOP_THICKNESS / 2),
        (d / 2 + 0.01, (leg - 0.02) / 2, TOP_THICKNESS / 2),
        style.counter,
        friction=[1.0, 0.005, 0.0001],
    )
    return Fixture(name, "corner", (x, -d / 2, 0.0), (w, d, top_h), top=top_h, top_geoms=(top, leg_top.name))
