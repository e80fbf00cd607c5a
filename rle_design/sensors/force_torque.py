"""Force/torque readings of MJCF ``<force>`` and ``<torque>`` sensors as one wrench array.

MuJoCo's force and torque sensors report the interaction wrench between the sensor site's body and
its parent, expressed in the site frame; the torque is taken about the site position. A body hanging
at rest from its parent therefore reads ``|F| = m g`` for the subtree mass ``m`` below the site.

An adhesion actuator (a contact magnet or suction cup) acts in joint space: MuJoCo adds its pull to
the generalised forces of both bodies, so the sensor, built from the bodies' Cartesian external
forces, sees the contact's push on the tool but not the magnet's pull on it. Held still, a part would
read ``m g`` minus the adhesion force. ``ft_reading(..., adhesion=True)`` adds the missing reaction:
the negative of the wrench the subtree's adhesion actuators exert on the free bodies they hold
(exact: the two pulls are equal and opposite at the same contact points), so a held part reads its
weight, as a real wrist sensor above a magnet does.
"""

from __future__ import annotations

import mujoco
import numpy as np

from rle_design.errors import MissingElement, RleError
from rle_design.scene.elements import element_id, has_element

_TYPES = {"force": mujoco.mjtSensor.mjSENS_FORCE, "torque": mujoco.mjtSensor.mjSENS_TORQUE}


def _sensor(model: mujoco.MjModel, name: str, kind: str) -> tuple[int, int]:
    """(address in sensordata, site id) of a named sensor of the given kind."""
    want = _TYPES[kind]
    names = [
        mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_SENSOR, i) or f"#{i}"
        for i in range(model.nsensor)
        if model.sensor_type[i] == want
    ]
    if not has_element(model, "sensor", name):
        raise MissingElement(f"{kind} sensor", name, available=names)
    sid = element_id(model, "sensor", name)
    if model.sensor_type[sid] != want:
        raise RleError(
            f"sensor '{name}' is not a {kind} sensor. Available {kind} sensors: {', '.join(names) or '(none)'}",
            code="contract.sensor_type",
        )
    return int(model.sensor_adr[sid]), int(model.sensor_objid[sid])


def ft_reading(
    model: mujoco.MjModel,
    data: mujoco.MjData,
    force_sensor: str,
    torque_sensor: str,
    *,
    frame: str = "site",
    adhesion: bool = False,
) -> np.ndarray:
    """Wrench ``[fx, fy, fz, tx, ty, tz]`` from a force and a torque sensor.

    Args:
        model: Compiled model.
        data: Data after ``mj_forward`` or ``mj_step`` (sensors are evaluated there).
        force_sensor: Name of an MJCF ``<force>`` sensor.
        torque_sensor: Name of an MJCF ``<torque>`` sensor.
        frame: ``"site"`` (MuJoCo's frame, the default) or ``"world"`` (rotated by the force
            sensor's site orientation).
        adhesion: Add the reaction of the adhesion actuators below the site (module docstring).

    Returns:
        ``(6,)`` array: force [N] and torque [N m].

    Raises:
        MissingElement: A sensor does not exist (the message lists the sensors of that kind).
        RleError: A sensor has the wrong type, or ``frame`` is unknown.
    """
    if frame not in ("site", "world"):
        raise RleError(f"frame '{frame}' is unknown. Available frames: site, world", code="sensor.frame")
    fadr, fsite = _sensor(model, force_sensor, "force")
    tadr, tsite = _sensor(model, torque_sensor, "torque")
    force = np.array(data.sensordata[fadr : fadr + 3], dtype=float)
    torque = np.array(data.sensordata[tadr : tadr + 3], dtype=float)
    if adhesion:
        rot = data.site_xmat[fsite].reshape(3, 3)
        wrench = adhesion_reaction(model, data, fsite)
        force += rot.T @ wrench[:3]
        torque += data.site_xmat[tsite].reshape(3, 3).T @ wrench[3:]
    if frame == "world":
        force = data.site_xmat[fsite].reshape(3, 3) @ force
        torque = data.site_xmat[tsite].reshape(3, 3) @ torque
    return np.concatenate([force, torque])


def adhesion_reaction(model: mujoco.MjModel, data: mujoco.MjData, site: int) -> np.ndarray:
    """What the sensor at ``site`` misses of its adhesion actuators: ``[F, tau]`` in world axes [N, N m].

    ``F`` and ``tau`` (about the site) are minus the wrench that the adhesion actuators whose body is
    in the site's subtree exert on free bodies, i.e. the wrench their pull puts on the structure the
    sensor holds, negated as the sensor reports its parent's support.

    Args:
        model: Compiled model.
        data: Data after ``mj_forward`` or ``mj_step`` (actuator moments and forces are set there).
        site: Site id of the force sensor.
    """
    out = np.zeros(6)
    top = int(model.site_bodyid[site])
    below = {top} | {b for b in range(model.nbody) if _has_ancestor(model, b, top)}
    free = {
        int(model.jnt_dofadr[j]): int(model.jnt_bodyid[j])
        for j in range(model.njnt)
        if model.jnt_type[j] == mujoco.mjtJoint.mjJNT_FREE
    }
    p_site = data.site_xpos[site]
    for a in range(model.nu):
        if model.actuator_trntype[a] != mujoco.mjtTrn.mjTRN_BODY or model.actuator_trnid[a, 0] not in below:
            continue
        qfrc = np.zeros(model.nv)
        adr, n = int(data.moment_rowadr[a]), int(data.moment_rownnz[a])
        qfrc[data.moment_colind[adr : adr + n]] = data.actuator_moment[adr : adr + n] * data.actuator_force[a]
        for dof, body in free.items():
            if body in below or not qfrc[dof : dof + 6].any():
                continue
            f = qfrc[dof : dof + 3]  # world force at the body's origin
            t = data.xmat[body].reshape(3, 3) @ qfrc[dof + 3 : dof + 6]  # local torque, to world axes
            out[:3] += f  # the pull on the tool is -f; the sensor reports its parent's support: +f
            out[3:] += t + np.cross(data.xpos[body] - p_site, f)
    return out


def _has_ancestor(model: mujoco.MjModel, body: int, ancestor: int) -> bool:
    while body > 0:
        body = int(model.body_parentid[body])
        if body == ancestor:
            return True
    return False
