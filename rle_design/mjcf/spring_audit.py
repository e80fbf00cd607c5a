"""Build-ability of springs: each end sits on material, and the straight path cuts no part.

A spring is a stiff spatial tendon between sites. It can be built only if

* each end (site) sits on material of its own body: the surface distance from the site to the
  nearest geom of that body is at most ``tol`` (a site floating beside a link has nothing to hook
  on; a printed bracket that carries it is a geom of the body and counts);
* its straight path between consecutive sites passes through no geom at any pose of a workspace,
  except the body each end is mounted on within ``mount_tol`` of that end (the hook at the tip of
  its post).

Distances use MuJoCo itself: a probe sphere of radius 0.1 mm at each site and ``mj_geomDistance``
(meshes on their convex hulls), and ``mj_ray`` marched along each path segment (every geom made
opaque; ``mj_ray`` reports exits as well as entries, so a ray leaving a part is seen too).
"""

from __future__ import annotations

import copy
from collections.abc import Iterable
from dataclasses import dataclass

import mujoco
import numpy as np

__all__ = ["SpringFault", "spring_anchor_faults", "spring_path_faults"]

_PROBE_R = 1e-4  # probe sphere radius [m]
_SEARCH_M = 1.0  # distances beyond this are reported as this [m]
OBJ = mujoco.mjtObj


@dataclass(frozen=True)
class SpringFault:
    """A spring that could not be built as modelled.

    Attributes:
        tendon: The spring's tendon name.
        kind: ``"anchor"`` (an end not on material) or ``"path"`` (the path cuts a part).
        element: The site (anchor) or the geom the path cuts.
        value: Gap from the site to its body's material [m] (anchor), or the distance along the path
            from its first site to where it enters the geom [m] (path).
        pose: Index of the first workspace pose where the path cuts (path faults), else -1.
    """

    tendon: str
    kind: str
    element: str
    value: float
    pose: int = -1

    @property
    def message(self) -> str:
        if self.kind == "anchor":
            return (
                f"spring '{self.tendon}': end '{self.element}' is not on material of its body "
                f"({self.value * 1e3:.1f} mm from the nearest part)"
            )
        return (
            f"spring '{self.tendon}': its path passes through '{self.element}' at workspace pose "
            f"{self.pose} ({self.value * 1e3:.1f} mm from its first end)"
        )


def _name(model: mujoco.MjModel, kind: mujoco.mjtObj, i: int) -> str:
    return mujoco.mj_id2name(model, kind, i) or f"{kind.name[6:].lower()}{i}"


def _spring_sites(model: mujoco.MjModel) -> list[tuple[int, list[int]]]:
    """(tendon id, site ids) of every stiff tendon made only of sites."""
    out = []
    for t in range(model.ntendon):
        if model.tendon_stiffness[t] <= 0.0:
            continue
        adr, num = int(model.tendon_adr[t]), int(model.tendon_num[t])
        if all(int(model.wrap_type[w]) == int(mujoco.mjtWrap.mjWRAP_SITE) for w in range(adr, adr + num)):
            out.append((t, [int(model.wrap_objid[w]) for w in range(adr, adr + num)]))
    return out


def _material(model: mujoco.MjModel, body: int, probes: frozenset[int] = frozenset()) -> list[int]:
    skip = {int(mujoco.mjtGeom.mjGEOM_PLANE), int(mujoco.mjtGeom.mjGEOM_HFIELD)}
    return [
        g
        for g in range(model.ngeom)
        if int(model.geom_bodyid[g]) == body and int(model.geom_type[g]) not in skip and g not in probes
    ]


def spring_anchor_faults(spec: mujoco.MjSpec, *, tol: float = 2e-3) -> list[SpringFault]:
    """Spring ends that do not sit on material of their own body.

    Args:
        spec: The model's spec (left unchanged; probes are added to a copy).
        tol: Largest surface gap from a site to its body's parts that still counts as mounted [m].

    Returns:
        One fault per spring end farther than ``tol`` from every geom of its body (or on a body with
        no geom at all), with the gap (capped at 1 m).
    """
    model = spec.compile()
    springs = _spring_sites(model)
    if not springs:
        return []
    data = mujoco.MjData(model)
    mujoco.mj_kinematics(model, data)
    probed = spec.copy()
    sites = sorted({s for _, ss in springs for s in ss})
    probe_name = {}
    for s in sites:
        name = f"__spring_probe_{s}"
        probed.worldbody.add_geom(
            name=name,
            type=mujoco.mjtGeom.mjGEOM_SPHERE,
            size=[_PROBE_R, 0, 0],
            pos=data.site_xpos[s].copy(),
            contype=0,
            conaffinity=0,
            density=0.0,
        )
        probe_name[s] = name
    pm = probed.compile()
    pd = mujoco.MjData(pm)
    pd.qpos[:] = model.qpos0 if pm.nq == model.nq else pm.qpos0
    mujoco.mj_kinematics(pm, pd)
    probe_ids = frozenset(mujoco.mj_name2id(pm, OBJ.mjOBJ_GEOM, n) for n in probe_name.values())
    out: list[SpringFault] = []
    for t, ss in springs:
        for s in ss:
            body = int(model.site_bodyid[s])
            probe = mujoco.mj_name2id(pm, OBJ.mjOBJ_GEOM, probe_name[s])
            geoms = _material(pm, body, probe_ids)
            gaps = [
                float(mujoco.mj_geomDistance(pm, pd, probe, g, _SEARCH_M, None)) + _PROBE_R for g in geoms
            ]
            gap = min(gaps) if gaps else _SEARCH_M
            if gap > tol:
                out.append(
                    SpringFault(
                        _name(model, OBJ.mjOBJ_TENDON, t), "anchor", _name(model, OBJ.mjOBJ_SITE, s), gap
                    )
                )
    return out


def _cut(
    model, data, a: np.ndarray, b: np.ndarray, mounts: dict[int, np.ndarray], mount_tol: float
) -> tuple[float, int]:
    """First part the segment ``a -> b`` passes through, marching past allowed touches.

    A hit is allowed where it lies within ``mount_tol`` of the end site mounted on the hit geom's
    body (``mounts``: body id -> site position), i.e. the spring's hook at the tip of its own post.

    Returns:
        (distance from ``a`` to the entry point [m], geom id), or (-1, -1) when the path is clear.
    """
    vec = b - a
    length = float(np.linalg.norm(vec))
    if length <= 1e-9:
        return -1.0, -1
    u = vec / length
    geomid = np.array([-1], dtype=np.int32)
    start = 0.0
    for _ in range(32):
        dist = mujoco.mj_ray(model, data, a + start * u, u, None, 1, -1, geomid)
        if dist < 0.0 or start + dist >= length:
            return -1.0, -1
        at = start + dist
        point = a + at * u
        g = int(geomid[0])
        site = mounts.get(int(model.geom_bodyid[g]))
        if site is None or np.linalg.norm(point - site) > mount_tol:
            return at, g
        start = at + 1e-4
    return -1.0, -1


def spring_path_faults(
    model: mujoco.MjModel,
    poses: Iterable[np.ndarray],
    *,
    qpos_index: np.ndarray | None = None,
    mount_tol: float = 0.015,
    every_pose: bool = False,
) -> list[SpringFault]:
    """Springs whose straight path passes through a part at some pose.

    Args:
        model: Compiled model (not modified; rays are cast on a copy with every geom opaque).
        poses: Workspace poses: joint positions written to ``qpos[qpos_index]`` [rad or m].
        qpos_index: Where each pose goes in ``qpos`` (default: the first ``len(pose)`` entries).
        mount_tol: Distance from an end site within which the spring may touch the body it is mounted
            on (the hook at the tip of its post) [m].

    Returns:
        At most one fault per spring: the first pose and the first geom its path cuts.
    """
    springs = _spring_sites(model)
    if not springs:
        return []
    m = copy.deepcopy(model)
    m.geom_rgba[:, 3] = 1.0  # mj_ray skips fully transparent geoms
    d = mujoco.MjData(m)
    out: list[SpringFault] = []
    done: set[int] = set()
    for k, q in enumerate(poses):
        q = np.asarray(q, float)
        idx = np.arange(q.size) if qpos_index is None else np.asarray(qpos_index)
        d.qpos[:] = m.qpos0
        d.qpos[idx] = q
        mujoco.mj_kinematics(m, d)
        for t, ss in springs:
            if t in done:
                continue
            for s0, s1 in zip(ss[:-1], ss[1:], strict=True):
                a, b = d.site_xpos[s0].copy(), d.site_xpos[s1].copy()
                mounts = {int(m.site_bodyid[s1]): b, int(m.site_bodyid[s0]): a}
                hit = _cut(m, d, a, b, mounts, mount_tol)
                if hit[1] >= 0:
                    out.append(
                        SpringFault(
                            _name(m, OBJ.mjOBJ_TENDON, t), "path", _name(m, OBJ.mjOBJ_GEOM, hit[1]), hit[0], k
                        )
                    )
                    if not every_pose:
                        done.add(t)
                    break
    return out
