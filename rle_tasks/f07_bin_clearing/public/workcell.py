"""The bin-clearing workcell as an ``MjSpec``: Panda with a contact electromagnet, KLT bin, brackets,
conveyor with a one-part nest, outfeed tote and two RGB-D cameras.

Frame: world z up, floor at z = 0, the Panda's base (``link0``) at ``ROBOT_BASE``. The bin stands in
front of the robot (+x), the conveyor runs along +x on the robot's right (-y); its upstream end is the
nest, closed downstream by a gate the cell opens only when the nest holds exactly one part.

Geometry (SI units throughout):

* U-bracket (stamped steel, rho = 7850 kg/m^3): web 60 x 25 x 2 mm, two flanges 30 x 25 x 2 mm at
  the web's ends; true volume 6000 mm^3, mass 47.1 g. Collision plates are 3 mm thick proxies (2 mm
  plates tunnel in dropped piles); each plate carries the mass of its true 2 mm plate.
* Bin (VDA KLT 4147-like): outer 396 x 297 x 147.5 mm, inner 346 x 265 mm, 10 mm floor.
* Electromagnet: a 40 mm square pad on a 140 mm stem at the flange; the pad touches only brackets; adhesion gain
  ``MAGNET_GAIN_WEIGHTS`` bracket weights.
* Conveyor: belt top at ``BELT_TOP``, surface velocity ``BELT_SPEED`` along +x.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from rle_design.scene import (
    AdhesionActuator,
    Arena,
    CameraConfig,
    FloorConfig,
    PhysicsOptions,
    PositionActuators,
    attach_arm,
    robot_constants,
)

STEEL_DENSITY = 7850.0
"""Density of the brackets' steel [kg/m^3]."""
WEB = (0.060, 0.025, 0.002)
"""Web length, width, thickness [m]."""
FLANGE_HEIGHT = 0.030
"""Flange height (outer, from the web's underside) [m]; flanges are 25 mm wide and 2 mm thick."""
PROXY_T = 0.003
"""Thickness of the collision plates [m] (3 mm proxies against tunnelling)."""
BRACKET_VOLUME = WEB[0] * WEB[1] * WEB[2] + 2 * FLANGE_HEIGHT * WEB[1] * WEB[2]
"""True steel volume of one bracket [m^3] (6000 mm^3)."""
BRACKET_MASS = STEEL_DENSITY * BRACKET_VOLUME
"""Mass of one bracket [kg] (47.1 g)."""
BRACKET_FRICTION = 0.5
"""Nominal sliding friction of a bracket [1] (steel on plastic and rubber)."""
G = 9.81
MAGNET_GAIN_WEIGHTS = 10.0
"""Adhesion gain as a multiple of one bracket's weight [1]."""
MAGNET_GAIN = MAGNET_GAIN_WEIGHTS * BRACKET_MASS * G
"""Adhesion force at command 1 [N] (4.62 N)."""
MAGNET_PAD = (0.020, 0.005)
"""Pad half width (square pad) and half height [m]; a flat box keeps a four-point contact."""
STEM_LENGTH = 0.14
"""Length of the magnet's stem from the flange to the pad [m]: keeps the wrist above the bin walls."""
TOOL_LENGTH = STEM_LENGTH + 2 * MAGNET_PAD[1]
"""Flange to pad face along the flange's z axis [m]."""

ROBOT_BASE = (0.0, 0.0, 0.40)
"""Position of the Panda's base on its pedestal [m]."""
BIN_CENTER = (0.50, 0.0)
"""Bin centre in the floor plane [m]; the bin's long side runs along y."""
BIN_OUTER = (0.297, 0.396, 0.1475)
"""Bin outer size x, y, z [m]."""
BIN_INNER = (0.265, 0.346)
"""Bin inner size x, y [m]."""
BIN_FLOOR_T = 0.010
"""Bin floor thickness [m]."""
BIN_FLOOR_TOP = 0.40
"""Height of the bin's inner floor [m]."""
BELT_Y = -0.42
"""Conveyor centre line [m]."""
BELT_X = (0.20, 0.95)
"""Conveyor start and end along x [m]."""
BELT_WIDTH = 0.14
"""Conveyor width between its rails [m]."""
BELT_TOP = 0.45
"""Belt surface height [m]."""
BELT_SPEED = 0.20
"""Belt surface speed along +x [m/s]."""
NEST_X = (0.20, 0.34)
"""Nest extent along the belt [m]: from the belt's start to the gate."""
GATE_T = 0.006
"""Gate thickness along x [m]."""
GATE_HEIGHT = 0.05
"""Gate height above the belt [m]."""
COVER_HEIGHT = 0.065
"""Clearance under the guard that covers the belt past the gate [m]: a bracket standing on a flange
(60 mm) passes under it, nothing can be dropped onto the belt past the nest."""
RAIL_HEIGHT = 0.04
"""Belt side rails above the belt [m]."""
TOTE_X = (0.97, 1.30)
"""Outfeed tote extent along x [m]."""
CONTROL_HZ = 20
"""Proprioception and command rate [Hz]."""
CAMERA_HZ = 10
"""Image rate [Hz]."""
OVERHEAD = ("overhead", (0.45, -0.12, 1.45), 42.0, (240, 320))
"""Overhead camera: name, position [m], vertical field of view [deg], (height, width) [px]."""
WRIST = ("wrist", (0.07, 0.0, 0.03), 60.0, (120, 160))
"""Wrist camera: name, position in the flange frame [m], field of view [deg], (height, width) [px]."""
ARM = "panda"
ARM_PREFIX = "panda/"
JOINT_KP = (600.0, 600.0, 600.0, 600.0, 250.0, 150.0, 50.0)
"""Joint position-servo stiffness [N m/rad]."""
JOINT_KV = (50.0, 50.0, 50.0, 50.0, 15.0, 10.0, 5.0)
"""Joint position-servo damping [N m s/rad]."""
HOME = (0.0, -0.3, 0.0, -2.2, 0.0, 1.9, 0.785)
"""Start posture of every episode [rad]: the hand above the bin, pointing down."""

GROUP_PART = 2
"""Contact bit of brackets and the magnet pad (the pad touches nothing else)."""
GROUP_SCENE = 1
"""Contact bit of everything else."""


@dataclass(frozen=True)
class Names:
    """Element names of the workcell."""

    magnet_body: str = "magnet"
    magnet_pad: str = "magnet_pad"
    magnet_act: str = "magnet"
    ft_site: str = "ft_site"
    force: str = "wrist_force"
    torque: str = "wrist_torque"
    bin_body: str = "bin"
    belt: str = "belt"
    gate: str = "gate"
    floor: str = "floor"
    tote: str = "tote"

    @staticmethod
    def part(i: int) -> str:
        return f"bracket{i:02d}"


NAMES = Names()


def joint_names() -> tuple[str, ...]:
    """Prefixed Panda joint names, base to flange."""
    return tuple(ARM_PREFIX + j for j in robot_constants(ARM).joints)


def _box(body, name, size, pos, rgba, *, group=GROUP_SCENE, mass=None, friction=None, visual=0):
    g = body.add_geom(name=name, type=mujoco.mjtGeom.mjGEOM_BOX, size=list(size), pos=list(pos))
    g.rgba = list(rgba)
    g.contype = g.conaffinity = group
    g.group = visual
    if mass is not None:
        g.mass = mass
    if friction is not None:
        g.friction = [friction, 0.005, 0.0001]
    return g


def add_bracket(spec: mujoco.MjSpec, i: int, pos=(0.0, 0.0, 1.0)) -> mujoco.MjsBody:
    """A free U-bracket body (web in the body's xy plane, flanges up along +z)."""
    body = spec.worldbody.add_body(name=NAMES.part(i), pos=list(pos))
    body.add_freejoint(name=NAMES.part(i) + "_free")
    L, W, T = WEB
    rgba = (0.62, 0.64, 0.68, 1.0)
    m_web = STEEL_DENSITY * L * W * T
    m_flange = STEEL_DENSITY * FLANGE_HEIGHT * W * T
    both = GROUP_PART | GROUP_SCENE
    _box(body, NAMES.part(i) + "_web", (L / 2, W / 2, PROXY_T / 2), (0, 0, PROXY_T / 2), rgba,
         group=both, mass=m_web, friction=BRACKET_FRICTION)  # fmt: skip
    for side, sx in (("a", -1.0), ("b", 1.0)):
        _box(body, f"{NAMES.part(i)}_flange_{side}", (PROXY_T / 2, W / 2, FLANGE_HEIGHT / 2),
             (sx * (L / 2 - PROXY_T / 2), 0, FLANGE_HEIGHT / 2), rgba, group=both, mass=m_flange,
             friction=BRACKET_FRICTION)  # fmt: skip
    return body


def _bin(spec: mujoco.MjSpec) -> None:
    ox, oy, oz = BIN_OUTER
    ix, iy = BIN_INNER
    green = (0.16, 0.55, 0.25, 1.0)
    base = BIN_FLOOR_TOP - BIN_FLOOR_T
    stand = spec.worldbody.add_body(name="bin_stand", pos=[BIN_CENTER[0], BIN_CENTER[1], 0])
    _box(stand, "bin_stand", (ox / 2 - 0.01, oy / 2 - 0.01, base / 2), (0, 0, base / 2), (0.3, 0.3, 0.32, 1))
    body = spec.worldbody.add_body(name=NAMES.bin_body, pos=[BIN_CENTER[0], BIN_CENTER[1], base])
    _box(body, "bin_floor", (ox / 2, oy / 2, BIN_FLOOR_T / 2), (0, 0, BIN_FLOOR_T / 2), green)
    tx, ty = (ox - ix) / 2, (oy - iy) / 2
    for name, size, pos in (
        ("bin_wall_xn", (tx / 2, oy / 2, oz / 2), (-(ox - tx) / 2, 0, oz / 2)),
        ("bin_wall_xp", (tx / 2, oy / 2, oz / 2), ((ox - tx) / 2, 0, oz / 2)),
        ("bin_wall_yn", (ix / 2, ty / 2, oz / 2), (0, -(oy - ty) / 2, oz / 2)),
        ("bin_wall_yp", (ix / 2, ty / 2, oz / 2), (0, (oy - ty) / 2, oz / 2)),
    ):
        _box(body, name, size, pos, green)


def _conveyor(spec: mujoco.MjSpec) -> None:
    x0, x1 = BELT_X
    length, cx = x1 - x0, (x0 + x1) / 2
    frame = spec.worldbody.add_body(name="conveyor", pos=[cx, BELT_Y, 0])
    _box(frame, "conveyor_frame", (length / 2, BELT_WIDTH / 2 + 0.02, (BELT_TOP - 0.02) / 2),
         (0, 0, (BELT_TOP - 0.02) / 2), (0.25, 0.25, 0.28, 1))  # fmt: skip
    belt = _box(frame, NAMES.belt, (length / 2, BELT_WIDTH / 2, 0.01), (0, 0, BELT_TOP - 0.01), (0.1, 0.1, 0.1, 1),
                friction=0.8)  # fmt: skip
    belt.surfacevel = np.array([BELT_SPEED, 0.0, 0.0, 0.0, 0.0, 0.0])
    for side in (-1.0, 1.0):
        _box(frame, f"rail_{'l' if side > 0 else 'r'}", (length / 2, 0.005, RAIL_HEIGHT / 2),
             (0, side * (BELT_WIDTH / 2 + 0.005), BELT_TOP + RAIL_HEIGHT / 2), (0.8, 0.6, 0.1, 1))  # fmt: skip
    _box(frame, "nest_back", (0.005, BELT_WIDTH / 2, RAIL_HEIGHT / 2),
         (x0 - cx - 0.005, 0, BELT_TOP + RAIL_HEIGHT / 2), (0.8, 0.6, 0.1, 1))  # fmt: skip
    c0, c1 = NEST_X[1] + GATE_T + 0.005 - cx, x1 - 0.02 - cx
    _box(frame, "belt_cover", ((c1 - c0) / 2, BELT_WIDTH / 2 + 0.01, 0.002),
         ((c0 + c1) / 2, 0, BELT_TOP + COVER_HEIGHT + 0.002), (0.75, 0.75, 0.78, 1))  # fmt: skip
    gate = spec.worldbody.add_body(
        name=NAMES.gate, pos=[NEST_X[1] + GATE_T / 2, BELT_Y, BELT_TOP + GATE_HEIGHT / 2]
    )
    gate.mocap = True
    _box(gate, NAMES.gate, (GATE_T / 2, BELT_WIDTH / 2, GATE_HEIGHT / 2), (0, 0, 0), (0.85, 0.15, 0.1, 1))
    tote = spec.worldbody.add_body(name=NAMES.tote, pos=[(TOTE_X[0] + TOTE_X[1]) / 2, BELT_Y, 0])
    tl = TOTE_X[1] - TOTE_X[0]
    _box(tote, "tote_floor", (tl / 2, 0.15, 0.1), (0, 0, 0.1), (0.2, 0.3, 0.6, 1))
    for side in (-1.0, 1.0):
        _box(tote, f"tote_wall_x{int(side)}", (0.005, 0.15, 0.1), (side * tl / 2, 0, 0.3), (0.2, 0.3, 0.6, 1))
        _box(tote, f"tote_wall_y{int(side)}", (tl / 2, 0.005, 0.1), (0, side * 0.15, 0.3), (0.2, 0.3, 0.6, 1))


def _robot(spec: mujoco.MjSpec) -> None:
    ped = spec.worldbody.add_body(name="pedestal", pos=[ROBOT_BASE[0], ROBOT_BASE[1], 0])
    _box(ped, "pedestal", (0.12, 0.12, ROBOT_BASE[2] / 2), (-0.04, 0, ROBOT_BASE[2] / 2), (0.9, 0.9, 0.9, 1))
    ped.add_site(name="robot_mount", pos=[0, 0, ROBOT_BASE[2]])
    attach_arm(spec, ARM, "robot_mount", ARM_PREFIX)
    const = robot_constants(ARM)
    for name in const.actuators:  # the model's torque motors give way to the cell's joint servos
        spec.delete(spec.actuator(ARM_PREFIX + name))
    for b in spec.bodies:
        if b.name.startswith(ARM_PREFIX):
            b.gravcomp = 1.0
    for g in spec.geoms:  # cameras show the collision hulls (14k faces) instead of 140k-face visuals
        if not g.name and g.contype == 0 and g.conaffinity == 0 and g.type == mujoco.mjtGeom.mjGEOM_MESH:
            g.group = 3
    for g in spec.geoms:
        if g.name.startswith(ARM_PREFIX) and g.name.endswith("_collision"):
            g.contype = g.conaffinity = GROUP_SCENE
            g.rgba = [0.92, 0.92, 0.95, 1.0]
    for i, joint in enumerate(joint_names()):
        PositionActuators(
            joints=(joint,), kp=JOINT_KP[i], kv=JOINT_KV[i],
            forcerange=(-const.torque_limits[i] * 1.087, const.torque_limits[i] * 1.087), prefix="servo_",
        ).edit_spec(spec)  # fmt: skip
    hand = spec.body(ARM_PREFIX + const.tool_body)
    magnet = hand.add_body(name=NAMES.magnet_body, pos=[0, 0, 0])
    stem = magnet.add_geom(name="magnet_stem", type=mujoco.mjtGeom.mjGEOM_CYLINDER,
                           size=[0.012, STEM_LENGTH / 2, 0], pos=[0, 0, STEM_LENGTH / 2])  # fmt: skip
    stem.contype = stem.conaffinity = GROUP_SCENE
    stem.mass = 0.2
    stem.rgba = [0.3, 0.3, 0.3, 1]
    pad = magnet.add_geom(name=NAMES.magnet_pad, type=mujoco.mjtGeom.mjGEOM_BOX,
                          size=[MAGNET_PAD[0], MAGNET_PAD[0], MAGNET_PAD[1]],
                          pos=[0, 0, STEM_LENGTH + MAGNET_PAD[1]])  # fmt: skip
    pad.contype = pad.conaffinity = GROUP_PART
    pad.mass = 0.1
    pad.rgba = [0.7, 0.1, 0.1, 1]
    pad.solref = [0.005, 1.0]
    hand.add_site(name=NAMES.ft_site, pos=[0, 0, 0])
    spec.add_sensor(name=NAMES.force, type=mujoco.mjtSensor.mjSENS_FORCE, objtype=mujoco.mjtObj.mjOBJ_SITE,
                    objname=NAMES.ft_site)  # fmt: skip
    spec.add_sensor(name=NAMES.torque, type=mujoco.mjtSensor.mjSENS_TORQUE, objtype=mujoco.mjtObj.mjOBJ_SITE,
                    objname=NAMES.ft_site)  # fmt: skip
    AdhesionActuator(NAMES.magnet_act, NAMES.magnet_body, MAGNET_GAIN).edit_spec(spec)
    name, pos, fovy, (h, w) = WRIST
    cam = hand.add_camera(name=name, pos=list(pos), fovy=fovy, resolution=[w, h])
    cam.quat = [0.0, 1.0, 0.0, 0.0]  # looks along the flange's +z (towards the pad)


def _cameras(spec: mujoco.MjSpec) -> None:
    name, pos, fovy, (h, w) = OVERHEAD
    CameraConfig(name=name, pos=pos, look_at=(pos[0], pos[1], 0.0), fovy_deg=fovy).edit_spec(spec)
    spec.camera(name).resolution = [w, h]
    spec.visual.global_.offwidth = max(640, w)
    spec.visual.global_.offheight = max(480, h)


def build_workcell(n_parts: int, friction_scale: float = 1.0) -> mujoco.MjSpec:
    """The workcell with ``n_parts`` brackets (parked in a row above the bin until a pile is dropped).

    Args:
        n_parts: Number of brackets.
        friction_scale: Factor on the brackets' sliding friction [1].
    """
    spec = mujoco.MjSpec()
    spec.compiler.degree = False
    spec.option.o_solref = [0.005, 1.0]
    spec.option.cone = mujoco.mjtCone.mjCONE_ELLIPTIC
    spec.memory = 64 << 20
    spec.nuserdata = 4
    _robot(spec)
    _bin(spec)
    _conveyor(spec)
    _cameras(spec)
    for i in range(n_parts):
        b = add_bracket(spec, i, (BIN_CENTER[0], BIN_CENTER[1], 1.0 + 0.05 * i))
        for g in b.geoms:
            g.friction = [BRACKET_FRICTION * friction_scale, 0.005, 0.0001]
    Arena(floor=FloorConfig(), physics=PhysicsOptions(noslip_iterations=0)).edit_spec(spec)
    for g in spec.geoms:
        if g.name == NAMES.floor:
            g.contype = g.conaffinity = GROUP_SCENE
    return spec


def home_qpos() -> np.ndarray:
    """The arm's start posture [rad]."""
    return np.array(HOME)


def bracket_corners() -> np.ndarray:
    """The eight corners of a bracket's bounding box in its body frame [m], (8, 3)."""
    L, W, _ = WEB
    return np.array(
        [[sx * L / 2, sy * W / 2, z] for sx in (-1, 1) for sy in (-1, 1) for z in (0.0, FLANGE_HEIGHT)]
    )


__all__ = [
    "BRACKET_MASS",
    "BRACKET_VOLUME",
    "MAGNET_GAIN",
    "NAMES",
    "add_bracket",
    "calibration",
    "build_workcell",
    "home_qpos",
    "joint_names",
]


def calibration() -> dict:
    """Published geometry and camera calibration (``assets/calibration.json``), SI units.

    Intrinsics are pinhole ``K`` [px]; ``overhead.pose`` is world-from-camera (OpenCV axes: x right,
    y down, z forward); the wrist camera's ``mount_pos`` is its position in the hand frame (the
    observation carries its world pose at every frame). ``frames`` gives every frame between the arm's
    last link and the part: ``link7_to_hand`` (the Panda's flange-to-hand offset, 0.1065 m along the
    flange axis, turned -45 deg about it), the F/T sensor (at the hand's origin, hand axes, wrench on
    the tool from the arm including the magnet's reaction: a held part adds m g) and the pad's face
    (``tool_length`` along the hand's z).
    """
    import mujoco as mj

    from rle_design.sensors import camera_spec

    model = build_workcell(1).compile()
    data = mj.MjData(model)
    mj.mj_forward(model, data)
    out: dict = {"units": "SI (m, rad, kg, N)"}
    for name, _, _, (h, w) in (OVERHEAD, WRIST):
        spec = camera_spec(model, data, name, w, h)
        out[name] = {"width": w, "height": h, "K": np.round(spec.intrinsics.matrix, 9).tolist()}
    out["overhead"]["pose"] = np.round(camera_spec(model, data, OVERHEAD[0]).world_from_camera, 9).tolist()
    out["wrist"]["mount_pos"] = list(WRIST[1])
    out["robot_base"] = list(ROBOT_BASE)
    out["tool_length"] = TOOL_LENGTH
    hand = model.body(model.site(NAMES.ft_site).bodyid[0])
    link7 = model.body(hand.parentid[0])
    out["frames"] = {
        "link7_to_hand": {"pos": np.round(hand.pos, 9).tolist(), "quat_wxyz": np.round(hand.quat, 9).tolist(),
                          "from": link7.name, "to": hand.name},
        "ft_sensor": {"body": hand.name, "pos": np.round(model.site(NAMES.ft_site).pos, 9).tolist(),
                      "quat_wxyz": np.round(model.site(NAMES.ft_site).quat, 9).tolist(),
                      "reads": "wrench on the tool from the arm in the sensor frame [N, N m], the magnet's "
                               "reaction included: a part held still adds its weight m g"},
        "pad_face": {"body": hand.name, "pos": [0.0, 0.0, round(TOOL_LENGTH, 9)], "half_width": MAGNET_PAD[0]},
    }  # fmt: skip
    out["magnet"] = {"pad_half_width": MAGNET_PAD[0], "gain_N": round(MAGNET_GAIN, 9)}
    out["bin"] = {"center": list(BIN_CENTER), "inner": list(BIN_INNER), "floor_top": BIN_FLOOR_TOP,
                  "outer": list(BIN_OUTER)}  # fmt: skip
    out["conveyor"] = {"y": BELT_Y, "x": list(BELT_X), "width": BELT_WIDTH, "top": BELT_TOP,
                       "speed": BELT_SPEED, "nest_x": list(NEST_X)}  # fmt: skip
    out["bracket"] = {"web": list(WEB), "flange_height": FLANGE_HEIGHT, "mass": round(BRACKET_MASS, 9)}
    out["home"] = list(HOME)
    out["rates_hz"] = {"control": CONTROL_HZ, "camera": CAMERA_HZ}
    return out
