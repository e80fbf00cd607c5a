"""Shapes the fixture builders share: boxes and cylinders on a body, bar handles, a cabinet carcass, a
fixture's root body on the floor, a counter top and a hinged door (``fixture`` states the frame and
the conventions)."""

from __future__ import annotations

import math

import mujoco

from .fixture import DOOR_DAMPING, DOOR_RANGE, GAP, PANEL, TOP_THICKNESS, Style

__all__ = [
    "ALONG_X",
    "ALONG_Y",
    "bar_handle",
    "box",
    "carcass",
    "counter_top",
    "cyl",
    "handle",
    "hinged_door",
    "root",
]


def box(body: mujoco.MjsBody, name: str, center, half, rgba, **kw) -> mujoco.MjsGeom:
    return body.add_geom(
        name=name, type=mujoco.mjtGeom.mjGEOM_BOX, pos=list(center), size=list(half), rgba=list(rgba), **kw
    )


def cyl(body: mujoco.MjsBody, name: str, center, radius, half_len, rgba, quat=(1, 0, 0, 0), **kw):
    return body.add_geom(
        name=name,
        type=mujoco.mjtGeom.mjGEOM_CYLINDER,
        pos=list(center),
        size=[radius, half_len, 0],
        quat=list(quat),
        rgba=list(rgba),
        **kw,
    )


ALONG_X = (math.cos(math.pi / 4), 0.0, math.sin(math.pi / 4), 0.0)
ALONG_Y = (math.cos(math.pi / 4), math.sin(math.pi / 4), 0.0, 0.0)


def bar_handle(body: mujoco.MjsBody, name: str, center, length: float, vertical: bool, style: Style) -> str:
    """A bar handle standing 35 mm proud of a front face (``center`` on the face); returns its site."""
    x, y, z = center
    off = 0.035
    quat = (1, 0, 0, 0) if vertical else ALONG_X
    cyl(body, name, (x, y - off, z), 0.01, length / 2, style.handle, quat=quat, mass=0.2, condim=4)
    for k, s in enumerate((-1, 1)):
        dx, dz = (0.0, s * length * 0.4) if vertical else (s * length * 0.4, 0.0)
        box(
            body,
            f"{name}_post{k}",
            (x + dx, y - off / 2, z + dz),
            (0.006, off / 2, 0.006),
            style.handle,
            mass=0.02,
        )
    site = body.add_site(name=name, pos=[x, y - off, z], size=[0.012, 0, 0], rgba=[1, 0, 0, 0], group=5)
    return site.name


def handle(body: mujoco.MjsBody, name: str, center, length: float, vertical: bool, style: Style) -> str:
    """The style's cabinet handle on a front face (``center`` on the face); returns its grasp site.

    ``bar``: ``bar_handle``; ``boxed``: a rectangular pull 25 mm proud of the face, as long as a bar;
    ``knob``: a round knob (radius 15 mm) 30 mm proud of the face.
    """
    if style.handle_type == "bar":
        return bar_handle(body, name, center, length, vertical, style)
    x, y, z = center
    if style.handle_type == "boxed":
        off = 0.025
        half = (0.008, 0.006, length / 2) if vertical else (length / 2, 0.006, 0.008)
        box(body, name, (x, y - off, z), half, style.handle, mass=0.2, condim=4)
        for k, s in enumerate((-1, 1)):
            dx, dz = (0.0, s * (length / 2 - 0.008)) if vertical else (s * (length / 2 - 0.008), 0.0)
            box(body, f"{name}_post{k}", (x + dx, y - off / 2, z + dz), (0.008, off / 2, 0.008), style.handle)
    elif style.handle_type == "knob":
        off = 0.03
        cyl(body, f"{name}_stem", (x, y - off / 2, z), 0.006, off / 2, style.handle, quat=ALONG_Y, mass=0.02)
        body.add_geom(
            name=name, type=mujoco.mjtGeom.mjGEOM_SPHERE, pos=[x, y - off, z], size=[0.015, 0, 0],
            rgba=list(style.handle), mass=0.05, condim=4,
        )  # fmt: skip
    else:
        raise ValueError(f"unknown handle type {style.handle_type!r}")
    site = body.add_site(name=name, pos=[x, y - off, z], size=[0.012, 0, 0], rgba=[1, 0, 0, 0], group=5)
    return site.name


def carcass(
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
    box(body, f"{name}_left", (-w / 2 + t / 2, 0, zc), (t / 2, d / 2, h / 2), rgba)
    box(body, f"{name}_right", (w / 2 - t / 2, 0, zc), (t / 2, d / 2, h / 2), rgba)
    box(body, f"{name}_back", (0, d / 2 - t / 2, zc), (w / 2 - t, t / 2, h / 2), rgba)
    box(body, f"{name}_bottom", (0, 0, z0 + t / 2), (w / 2 - t, d / 2 - t, t / 2), rgba)
    if top:
        box(body, f"{name}_ceiling", (0, 0, z0 + h - t / 2), (w / 2 - t, d / 2 - t, t / 2), rgba)
    if front:
        box(body, f"{name}_front", (0, -d / 2 + t / 2, zc), (w / 2 - t, t / 2, h / 2), rgba)


def root(world: mujoco.MjsBody, name: str, x: float, d: float, z: float = 0.0) -> mujoco.MjsBody:
    return world.add_body(name=name, pos=[x, -d / 2, z])


def counter_top(body: mujoco.MjsBody, name: str, w: float, d: float, style: Style) -> str:
    geom = box(
        body,
        f"{name}_top",
        (0, -0.01, style.counter_height - TOP_THICKNESS / 2),
        (w / 2, d / 2 + 0.01, TOP_THICKNESS / 2),
        style.counter,
        friction=[1.0, 0.005, 0.0001],
    )
    return geom.name


def hinged_door(
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
    styled_handle: bool = False,
) -> tuple[mujoco.MjsBody, str, str]:
    """A door panel of width ``w`` hinged on its left (-x) or right edge; returns (body, joint, handle site).

    The hinge axis runs through the panel's mid-plane, or with ``front_pivot`` through the edge of its
    front face (an overlay hinge): a door flush with its neighbours' fronts needs the latter, else its
    hinge-side edge swings into the neighbour's front and stops it short of 90 deg (base cabinets beside
    a drawer were held at 0.1-0.3 of their range). The closed door is the same either way. With
    ``styled_handle`` the handle is the style's (``handle``), else a bar.
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
    box(
        door,
        f"{name}_door_panel",
        (s * (w / 2), back, h / 2 - GAP),
        ((w - 2 * GAP) / 2, PANEL / 2, h / 2 - GAP),
        rgba,
        mass=mass,
    )
    hz = h * 0.5 if handle_z is None else handle_z
    make = handle if styled_handle else bar_handle
    site = make(door, f"{name}_handle", (s * (w - 0.06), back - PANEL / 2, hz), handle_len, True, style)
    return door, joint.name, site
