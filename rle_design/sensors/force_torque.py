"""Force/torque readings of MJCF ``<force>`` and ``<torque>`` sensors as one wrench array.

MuJoCo's force and torque sensors report the interaction wrench between the sensor site's body and
its parent, expressed in the site frame; the torque is taken about the site position. A body hanging
at rest from its parent therefore reads ``|F| = m g`` for the subtree mass ``m`` below the site.
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
) -> np.ndarray:
    """Wrench ``[fx, fy, fz, tx, ty, tz]`` from a force and a torque sensor.

    Args:
        model: Compiled model.
        data: Data after ``mj_forward`` or ``mj_step`` (sensors are evaluated there).
        force_sensor: Name of an MJCF ``<force>`` sensor.
        torque_sensor: Name of an MJCF ``<torque>`` sensor.
        frame: ``"site"`` (MuJoCo's frame, the default) or ``"world"`` (rotated by the force
            sensor's site orientation).

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
    if frame == "world":
        force = data.site_xmat[fsite].reshape(3, 3) @ force
        torque = data.site_xmat[tsite].reshape(3, 3) @ torque
    return np.concatenate([force, torque])
