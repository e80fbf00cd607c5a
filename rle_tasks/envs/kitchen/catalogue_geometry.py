"""Collision and render geometry of catalogue instances: the source's collision geoms, or a cached
CoACD decomposition of its render mesh where it has none; an instance added to a scene or written
as a standalone model."""

from __future__ import annotations

import functools
import hashlib
import os
import tempfile
from dataclasses import dataclass
from pathlib import Path

import mujoco
import numpy as np

from rle_tasks.envs.kitchen.catalogue_data import CATEGORIES, Instance, instance
from rle_tasks.envs.kitchen.objects import OBJECT_FRICTION

COACD_PARAMS = {"threshold": 0.1, "max_convex_hull": 16, "seed": 0, "resolution": 1000, "mcts_iterations": 60}
"""CoACD parameters of the cached decompositions (``rle_design.mjcf.mesh.collision_hulls``)."""


SOLREF = (0.004, 1.0)
"""Contact time constant [s] and damping ratio of catalogue objects (the kitchen objects')."""


@dataclass(frozen=True)
class Part:
    """One collision geom in the body frame.

    Attributes:
        kind: MuJoCo geom type name (``box``, ``cylinder``, ``sphere``, ``capsule``, ``ellipsoid`` or
            ``mesh``: a convex piece of a CoACD decomposition).
        size: MuJoCo size parameters [m] (unused for meshes).
        pos: Position [m].
        quat: Orientation (w, x, y, z).
        density: The source's density [kg/m^3].
        mesh: Absolute path of the convex piece (OBJ in the cache), meshes only.
    """

    kind: str
    size: tuple[float, float, float]
    pos: tuple[float, float, float]
    quat: tuple[float, float, float, float]
    density: float
    mesh: str | None = None


@dataclass(frozen=True)
class Visual:
    """A render mesh of the source: file, scale [1] and pose in the body frame [m]."""

    file: str
    scale: tuple[float, float, float]
    pos: tuple[float, float, float]
    quat: tuple[float, float, float, float]


@dataclass(frozen=True)
class Geometry:
    """Collision parts, render meshes and how the collision geometry was made (``source`` or ``coacd``)."""

    parts: tuple[Part, ...]
    visuals: tuple[Visual, ...]
    collision: str


def _read_mesh(path: Path, scale: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(vertices [m], faces) of an STL/OBJ file or a legacy MuJoCo MSH file, scaled."""
    if path.suffix.lower() == ".msh":
        raw = path.read_bytes()
        nv, nn, nt, nf = np.frombuffer(raw[:16], dtype=np.int32)
        floats = np.frombuffer(raw[16 : 16 + 4 * (3 * nv + 3 * nn + 2 * nt)], dtype=np.float32)
        verts = floats[: 3 * nv].reshape(-1, 3).astype(float)
        faces = np.frombuffer(raw[16 + 4 * (3 * nv + 3 * nn + 2 * nt) :], dtype=np.int32).reshape(nf, 3)
    else:
        import trimesh

        mesh = trimesh.load(str(path), force="mesh")
        verts, faces = np.asarray(mesh.vertices, dtype=float), np.asarray(mesh.faces)
    return verts * scale, faces.astype(np.int64)


def _coacd_parts(path: Path, scale: np.ndarray) -> tuple[str, ...]:
    """OBJ files of the cached CoACD decomposition of a mesh file at ``scale`` (computed on first use)."""
    from rle_tasks.core.solutions import cache_root

    digest = hashlib.sha256(path.read_bytes())
    digest.update(repr((tuple(float(s) for s in scale), sorted(COACD_PARAMS.items()))).encode())
    folder = cache_root() / "catalogue" / "coacd" / digest.hexdigest()
    if not (folder / "done").exists():
        import trimesh

        from rle_design.mjcf.mesh import collision_hulls

        verts, faces = _read_mesh(path, scale)
        hulls = collision_hulls(trimesh.Trimesh(verts, faces, process=True), **COACD_PARAMS)
        folder.parent.mkdir(parents=True, exist_ok=True)
        tmp = Path(tempfile.mkdtemp(dir=folder.parent))
        for k, hull in enumerate(hulls):
            hull.export(tmp / f"part_{k:02d}.obj")
        (tmp / "source.txt").write_text(f"{path}\nscale {tuple(scale)}\n{COACD_PARAMS}\n")
        (tmp / "done").write_text("")
        try:
            os.rename(tmp, folder)
        except OSError:  # another process finished first
            import shutil

            shutil.rmtree(tmp, ignore_errors=True)
    return tuple(str(p) for p in sorted(folder.glob("part_*.obj")))


def _visual(geom: mujoco.MjsGeom) -> bool:
    return geom.contype == 0 and geom.conaffinity == 0


@functools.cache
def geometry(instance_id: str) -> Geometry:
    """Collision parts and render meshes of an instance in the frame of its root body.

    The source's MJCF is read with MjSpec; its render meshes are stood in for by points while it is
    compiled (so the geoms' poses come out in the source's own conventions, nested bodies included) and
    its textures and materials are dropped.
    """
    inst = instance(instance_id)
    xml = inst.xml
    spec = mujoco.MjSpec.from_file(str(xml))
    mesh_dir = xml.parent / (spec.meshdir or "")
    meshes: dict[int, tuple[Path, np.ndarray]] = {}
    coll_meshes: dict[int, tuple[Path, np.ndarray]] = {}
    densities: dict[int, float] = {}
    for k, geom in enumerate(spec.geoms):
        geom.name = f"g{k}"
        geom.material = ""
        if geom.type == mujoco.mjtGeom.mjGEOM_MESH:
            m = spec.mesh(geom.meshname)
            entry = (mesh_dir / m.file, np.asarray(m.scale, dtype=float))
            (meshes if _visual(geom) else coll_meshes)[k] = entry
            geom.type = mujoco.mjtGeom.mjGEOM_SPHERE
            geom.size = [0.001, 0, 0]
            geom.meshname = ""
        densities[k] = float(geom.density)
    for collection in (spec.meshes, spec.materials, spec.textures):
        for element in list(collection):
            spec.delete(element)
    model = spec.compile()
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    root = next(b for b in range(1, model.nbody) if model.body_parentid[b] == 0)
    r0, p0 = data.xmat[root].reshape(3, 3), data.xpos[root]
    q0 = np.zeros(4)
    mujoco.mju_mat2Quat(q0, data.xmat[root])
    q0inv = np.zeros(4)
    mujoco.mju_negQuat(q0inv, q0)

    def pose(g: int) -> tuple[tuple, tuple]:
        q = np.zeros(4)
        mujoco.mju_mat2Quat(q, data.geom_xmat[g])
        rel = np.zeros(4)
        mujoco.mju_mulQuat(rel, q0inv, q)
        pos = r0.T @ (data.geom_xpos[g] - p0)
        return tuple(float(v) for v in pos), tuple(float(v) for v in rel)

    parts: list[Part] = []
    visuals: list[Visual] = []
    kinds = {mujoco.mjtGeom(t): mujoco.mjtGeom(t).name[7:].lower() for t in range(8)}
    for k in range(model.ngeom):
        body = model.geom_bodyid[k]
        while body not in (root, 0):
            body = model.body_parentid[body]
        if body != root:
            continue
        idx = int(model.geom(k).name[1:])
        pos, quat = pose(k)
        if idx in meshes:
            f, s = meshes[idx]
            visuals.append(Visual(str(f), tuple(float(v) for v in s), pos, quat))
        elif idx in coll_meshes:
            f, s = coll_meshes[idx]
            parts += [Part("mesh", (0.0, 0.0, 0.0), pos, quat, densities[idx], p) for p in _coacd_parts(f, s)]
            if not meshes:
                visuals.append(Visual(str(f), tuple(float(v) for v in s), pos, quat))
        elif model.geom_contype[k] or model.geom_conaffinity[k]:
            kind = kinds[mujoco.mjtGeom(model.geom_type[k])]
            parts.append(Part(kind, tuple(float(v) for v in model.geom_size[k]), pos, quat, densities[idx]))
    if not parts:
        raise ValueError(f"{instance_id}: the source has no collision geometry")
    collision = "coacd" if coll_meshes else "source"
    rest = CATEGORIES[inst.category].rest
    if rest is not None:
        parts = [Part(p.kind, p.size, *_turn(rest, p.pos, p.quat), p.density, p.mesh) for p in parts]
        visuals = [Visual(v.file, v.scale, *_turn(rest, v.pos, v.quat)) for v in visuals]
    return Geometry(tuple(parts), tuple(visuals), collision)


def _turn(rest: tuple, pos: tuple, quat: tuple) -> tuple[tuple, tuple]:
    """A pose (pos [m], quat) in the body frame turned by the rest rotation ``rest`` (w, x, y, z)."""
    rot = np.zeros(9)
    mujoco.mju_quat2Mat(rot, np.asarray(rest, dtype=float))
    q = np.zeros(4)
    mujoco.mju_mulQuat(q, np.asarray(rest, dtype=float), np.asarray(quat, dtype=float))
    return tuple(float(v) for v in rot.reshape(3, 3) @ np.asarray(pos)), tuple(float(v) for v in q)


def add_geoms(
    body: mujoco.MjsBody,
    spec: mujoco.MjSpec,
    name: str,
    inst: Instance,
    visual: bool,
    density: float | None = None,
) -> None:
    """The instance's collision geoms (``density`` [kg/m^3] for all, or the source's) and, when
    ``visual``, its render meshes, on ``body``."""
    geo = geometry(inst.id)
    rgba = list(CATEGORIES[inst.category].rgba)
    for k, part in enumerate(geo.parts):
        common = dict(
            name=f"{name}_c{k}",
            pos=list(part.pos),
            quat=list(part.quat),
            density=part.density if density is None else density,
            friction=list(OBJECT_FRICTION),
            condim=4,
            solref=list(SOLREF),
            group=0 if not visual else 3,
            rgba=rgba,
        )
        if part.kind == "mesh":
            mesh_name = f"catalogue_{hashlib.sha1(part.mesh.encode()).hexdigest()[:12]}"
            if spec.mesh(mesh_name) is None:
                spec.add_mesh(name=mesh_name, file=part.mesh)
            body.add_geom(type=mujoco.mjtGeom.mjGEOM_MESH, meshname=mesh_name, **common)
        else:
            body.add_geom(
                type=getattr(mujoco.mjtGeom, f"mjGEOM_{part.kind.upper()}"), size=list(part.size), **common
            )
    if not visual:
        return
    for k, vis in enumerate(geo.visuals):
        mesh_name = f"catalogue_vis_{hashlib.sha1(repr((vis.file, vis.scale)).encode()).hexdigest()[:12]}"
        if spec.mesh(mesh_name) is None:
            spec.add_mesh(name=mesh_name, file=vis.file, scale=list(vis.scale))
        body.add_geom(
            name=f"{name}_v{k}",
            type=mujoco.mjtGeom.mjGEOM_MESH,
            meshname=mesh_name,
            pos=list(vis.pos),
            quat=list(vis.quat),
            contype=0,
            conaffinity=0,
            group=1,
            density=0.0,
            rgba=rgba,
        )
