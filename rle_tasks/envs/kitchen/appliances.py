"""Appliance builders: fridge, stove (burners and knobs), sink, microwave, dish rack (each adds one
fixture's bodies to the world and returns its ``Fixture``)."""

from __future__ import annotations

import mujoco

from .fixture import (
    BURNERS,
    KNOB_RANGE,
    KNOB_X,
    PANEL,
    TOP_THICKNESS,
    Fixture,
    Interior,
    Style,
)
from .geometry import ALONG_Y, box, carcass, cyl, hinged_door, root

__all__ = ["add_dish_rack", "add_fridge", "add_microwave", "add_sink", "add_stove"]


def add_fridge(
    world: mujoco.MjsBody, name: str, x: float, w: float, hinge_left: bool, style: Style
) -> Fixture:
    """A tall fridge (1.8 m): insulated carcass with two shelves and one hinged door."""
    d, h = 0.7, 1.8
    body = root(world, name, x, d)
    carcass(body, name, w, d, h, 0.0, style.appliance, top=True)
    for k, zf in enumerate((0.45, 0.9)):
        box(
            body,
            f"{name}_shelf{k}",
            (0, 0.02, h * zf),
            (w / 2 - PANEL, d / 2 - PANEL - 0.02, 0.006),
            (0.8, 0.85, 0.9, 0.6),
        )
    door, joint, handle = hinged_door(
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
    d = style.counter_depth
    body = root(world, name, x, d)
    box(
        body,
        f"{name}_body",
        (0, 0.0, (style.counter_height - 0.03) / 2),
        (w / 2, d / 2, (style.counter_height - 0.03) / 2),
        style.appliance,
    )
    cook = box(
        body,
        f"{name}_cooktop",
        (0, 0, style.counter_height - 0.015),
        (w / 2, d / 2, 0.015),
        (0.08, 0.08, 0.09, 1.0),
    )
    box(
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
    panel_z = style.counter_height - 0.12
    box(body, f"{name}_panel", (0, -d / 2 - 0.01, panel_z), (w / 2, 0.01, 0.06), (0.2, 0.2, 0.22, 1.0))
    for burner in BURNERS:
        bx = (-1 if "left" in burner else 1) * w * 0.22
        by = -0.12 if "front" in burner else 0.12
        ring = cyl(
            body,
            f"{name}_{burner}_burner",
            (bx, by, style.counter_height + 0.001),
            0.09,
            0.001,
            (0.25, 0.25, 0.27, 1.0),
            contype=0,
            conaffinity=0,
        )
        kx = KNOB_X[burner] * w
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
        cyl(
            knob,
            f"{name}_{burner}_knob",
            (0, -0.015, 0),
            0.022,
            0.015,
            (0.85, 0.85, 0.85, 1.0),
            quat=ALONG_Y,
            mass=0.05,
            condim=4,
        )
        box(
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
            pos=[bx, by, style.counter_height + 0.002],
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
        (w, d, style.counter_height),
        joints=tuple(j for j, _ in burners.values()),
        top=style.counter_height,
        sites=sites,
        top_geoms=(cook.name,),
        burners=burners,
    )


def add_sink(world: mujoco.MjsBody, name: str, x: float, w: float, style: Style) -> Fixture:
    """A base cabinet whose counter top holds a basin (0.5 x 0.38 x 0.2 m) and a faucet."""
    d = style.counter_depth
    body = root(world, name, x, d)
    zt = style.counter_height - TOP_THICKNESS
    box(body, f"{name}_body", (0, 0.01, zt / 2 - 0.12), (w / 2, d / 2 - 0.01, zt / 2 - 0.12), style.cabinet)
    bw, bd, bh = 0.25, 0.19, 0.2
    yc = -0.03
    rim = style.counter
    tz = style.counter_height - TOP_THICKNESS / 2
    box(
        body,
        f"{name}_top_front",
        (0, (-d / 2 - 0.02 + yc - bd) / 2, tz),
        (w / 2, (yc - bd + d / 2 + 0.02) / 2, TOP_THICKNESS / 2),
        rim,
    )
    box(
        body,
        f"{name}_top_back",
        (0, (d / 2 + yc + bd) / 2, tz),
        (w / 2, (d / 2 - yc - bd) / 2, TOP_THICKNESS / 2),
        rim,
    )
    for k, sx in enumerate((-1, 1)):
        box(
            body,
            f"{name}_top_side{k}",
            (sx * (w / 2 + bw) / 2, yc, tz),
            ((w / 2 - bw) / 2, bd, TOP_THICKNESS / 2),
            rim,
        )
    steel = (0.75, 0.76, 0.78, 1.0)
    zb = style.counter_height - bh
    box(body, f"{name}_basin_bottom", (0, yc, zb - 0.005), (bw, bd, 0.005), steel)
    box(
        body,
        f"{name}_basin_front",
        (0, yc - bd - 0.005, zb + bh / 2 - TOP_THICKNESS / 2),
        (bw + 0.01, 0.005, bh / 2 - TOP_THICKNESS / 2),
        steel,
    )
    box(
        body,
        f"{name}_basin_back",
        (0, yc + bd + 0.005, zb + bh / 2 - TOP_THICKNESS / 2),
        (bw + 0.01, 0.005, bh / 2 - TOP_THICKNESS / 2),
        steel,
    )
    for k, sx in enumerate((-1, 1)):
        box(
            body,
            f"{name}_basin_side{k}",
            (sx * (bw + 0.005), yc, zb + bh / 2 - TOP_THICKNESS / 2),
            (0.005, bd, bh / 2 - TOP_THICKNESS / 2),
            steel,
        )
    cyl(body, f"{name}_faucet", (0, d / 2 - 0.06, style.counter_height + 0.15), 0.015, 0.15, steel)
    cyl(
        body,
        f"{name}_spout",
        (0, d / 2 - 0.14, style.counter_height + 0.29),
        0.012,
        0.08,
        steel,
        quat=ALONG_Y,
    )
    interior = Interior(name, (0, yc, zb + bh / 2), (bw, bd, bh / 2))
    return Fixture(
        name,
        "sink",
        (x, -d / 2, 0.0),
        (w, d, style.counter_height),
        interior=interior,
        top=style.counter_height,
        top_geoms=(f"{name}_top_front", f"{name}_top_back", f"{name}_top_side0", f"{name}_top_side1"),
    )


def add_microwave(world: mujoco.MjsBody, name: str, x: float, y_back: float, style: Style) -> Fixture:
    """A microwave (0.5 x 0.38 x 0.3 m) standing on a counter top, its back at ``y_back``: a
    turntable plate inside and a door hinged on its left edge."""
    w, d, h = 0.5, 0.38, 0.3
    body = world.add_body(name=name, pos=[x, y_back - d / 2, style.counter_height])
    dark = (0.12, 0.12, 0.13, 1.0)
    carcass(body, name, w, d, h, 0.0, style.appliance, top=True)
    panel_w = 0.12
    box(
        body,
        f"{name}_controls",
        (w / 2 - panel_w / 2, -d / 2 + PANEL / 2, h / 2),
        (panel_w / 2 - PANEL, PANEL / 2, h / 2 - PANEL),
        dark,
    )
    cavity_w = w - panel_w
    plate = cyl(
        body,
        f"{name}_plate",
        (-panel_w / 2, 0.0, PANEL + 0.004),
        0.12,
        0.004,
        (0.9, 0.9, 0.92, 1.0),
        friction=[1.0, 0.005, 0.0001],
    )
    door, joint, handle = hinged_door(
        body, name, True, w, h - 0.004, -d / 2, 0.002, dark, style, mass=1.0, handle_len=0.16, handle_z=h / 2
    )
    interior = Interior(
        name, (-panel_w / 2, 0.0, h / 2), (cavity_w / 2 - PANEL, d / 2 - PANEL, h / 2 - PANEL)
    )
    return Fixture(
        name,
        "microwave",
        (x, y_back - d / 2, style.counter_height),
        (w, d, h),
        joints=(joint,),
        interior=interior,
        top=style.counter_height + PANEL + 0.008,
        sites={"handle": handle},
        parts={"door": door.name},
        top_geoms=(plate.name,),
        hinge_left=True,
    )


def add_dish_rack(world: mujoco.MjsBody, name: str, x: float, y: float, style: Style) -> Fixture:
    """A dish rack (0.4 x 0.3 m tray with tines) on a counter top centred at (x, y)."""
    w, d = 0.4, 0.3
    body = world.add_body(name=name, pos=[x, y, style.counter_height])
    wire = (0.85, 0.86, 0.88, 1.0)
    box(body, f"{name}_tray", (0, 0, 0.005), (w / 2, d / 2, 0.005), wire)
    for k in range(5):
        box(
            body,
            f"{name}_tine{k}",
            (-w / 2 + 0.06 + k * (w - 0.12) / 4, 0.05, 0.06),
            (0.003, 0.003, 0.05),
            wire,
        )
    for k, sy in enumerate((-1, 1)):
        box(body, f"{name}_rail{k}", (0, sy * (d / 2 - 0.005), 0.03), (w / 2, 0.005, 0.025), wire)
    interior = Interior(name, (0, 0, 0.1), (w / 2, d / 2, 0.1))
    return Fixture(
        name,
        "dish_rack",
        (x, y, style.counter_height),
        (w, d, 0.12),
        interior=interior,
        top=style.counter_height + 0.01,
        top_geoms=(f"{name}_tray",),
    )
