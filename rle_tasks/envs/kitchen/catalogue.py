"""The kitchen's object catalogue: categories of graspable and receiving objects from the installed asset
wheels (robosuite's objects and the LIBERO-PRO asset wheels), each instance with its source, licence,
mass, size, collision geometry and grasp width.

The data is ``catalogue.yaml`` beside this module (categories -> instances, the sources and their
licences). Everything numeric is derived here from the source files, in SI units:

- collision geometry: the source's own collision geoms (the LIBERO objects' primitives, in the frame of
  the object's root body) or, where the source has none but its render mesh (robosuite: the collision
  geom is the render mesh, which MuJoCo would replace by one convex hull), a CoACD convex decomposition
  of that mesh, computed once and cached under ``cache_root()/catalogue/coacd/<key>`` where the key is
  the sha256 of the mesh file's bytes, its scale and ``COACD_PARAMS`` (nothing copied from the wheels
  is committed);
- mass [kg]: the source's density [kg/m^3] (the collision geoms' ``density`` attribute, MuJoCo's 1000
  where it has none) times the volume of the collision geometry [m^3], as MuJoCo integrates it;
- size [m]: the axis-aligned box around the collision geometry in the body frame (z up);
- grasp width [m]: the reference grasp planner's (family 01's ``pick``: top-down, closing across the
  narrower horizontal side, the finger pads ``PALM`` below the top, ``PALM_ROUND`` for round objects,
  at least ``FINGER_CLEARANCE`` above the support) view of the object: the extent of the collision
  geometry along the closing axis in the pads' height band. ``graspable``: the band's geometry lies
  within ``GRASP_REACH`` of the box centre on either side (the 0.08 m opening less twice the planner's
  5 mm positioning tolerance), is at least ``EMPTY`` wide (the planner's empty-hand test), and the
  pads' centre is not above the object's top (a flat object lower than ``FINGER_CLEARANCE`` meets only
  the pads' lower edges and slips out: the HOPE butter, 17 mm, did in the lift test).

Pretrain and target kitchens draw disjoint instances of a category (``split``). The wheels are asset
sources only: their files are located through the import system's metadata, never imported.
"""

from __future__ import annotations

import functools
import hashlib
import importlib.metadata
import math
import os
import tempfile
from dataclasses import dataclass
from pathlib import Path

import mujoco
import numpy as np
import yaml

from rle_design.paths import package_dir
from rle_tasks.envs.kitchen.objects import OBJECT_FRICTION

__all__ = [
    "CATEGORIES",
    "COACD_PARAMS",
    "Instance",
    "Part",
    "Properties",
    "add_instance",
    "catalogue_table",
    "geometry",
    "instance",
    "instances",
    "mjcf_body",
    "properties",
    "split",
]

DATA = Path(__file__).with_name("catalogue.yaml")
"""The catalogue's data file."""
COACD_PARAMS = {"threshold": 0.1, "max_convex_hull": 16, "seed": 0, "resolution": 1000, "mcts_iterations": 60}
"""CoACD parameters of the cached decompositions (``rle_design.mjcf.mesh.collision_hulls``)."""
GRIPPER_OPENING = 0.08
"""Panda gripper's full opening [m]."""
POSITION_TOL = 0.005
"""The grasp planner's positioning tolerance before it closes (``pick``'s final ``tol``) [m]."""
GRASP_REACH = GRIPPER_OPENING / 2 - POSITION_TOL
"""Farthest the grasped band may reach from the box centre along the closing axis [m]."""
PALM = 0.016
"""Grasp depth below the top [m] (``pick.PALM``)."""
PALM_ROUND = 0.03
"""Grasp depth below a round object's top [m] (``pick.PALM_ROUND``)."""
ROUND = 0.008
"""Spread of the half extents below which an object counts as round [m] (``pick.ROUND``)."""
FINGER_CLEARANCE = 0.022
"""Least height of the pads' centre above the support [m] (``pick.FINGER_CLEARANCE``)."""
EMPTY = 0.01
"""Finger opening below which the closed hand holds nothing [m] (``pick.EMPTY``)."""
PAD_HALF_HEIGHT = 0.008
"""Half height of the Panda gripper's finger pads [m] (robosuite ``panda_gripper.xml``)."""
SOLREF = (0.004, 1.0)
"""Contact time constant [s] and damping ratio of catalogue objects (the kitchen objects')."""


@dataclass(frozen=True)
class Instance:
    """One object of a category.

    Attributes:
        id: ``<source>/<name>``.
        category: Its category.
        source: Source key of ``catalogue.yaml`` (robosuite, gso, hope, turbosquid, libero).
        package: Installed package that holds it.
        path: Its MJCF, relative to the package directory.
        licence: SPDX identifier, or ``unknown``.
        origin: Where the model comes from.
    """

    id: str
    category: str
    source: str
    package: str
    path: str
    licence: str
    origin: str

    @property
    def xml(self) -> Path:
        """Absolute path of the instance's MJCF."""
        return package_dir(self.package) / self.path

    @property
    def wheel(self) -> str:
        """The installed distribution (``name==version``) whose RECORD lists the MJCF."""
        return _wheel_of(self.package, self.path)


@dataclass(frozen=True)
class Category:
    """A category: its name, the rgba of its visual geoms, its instance ids and, where the reference grasp
    planner can take none of them, why (``not_graspable``)."""

    name: str
    rgba: tuple[float, float, float, float]
    instances: tuple[str, ...]
    not_graspable: str | None = None


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


@dataclass(frozen=True)
class Properties:
    """What the catalogue derives for an instance (SI units).

    Attributes:
        mass: Mass [kg].
        center: Centre of the box around the collision geometry, body frame [m].
        half: Half extents of that box [m].
        closing_axis: Body axis (0 x, 1 y) the planner closes the fingers along (the narrower side).
        grasp_height: Height of the pads' centre above the object's lowest point [m].
        band: (low, high) of the collision geometry along the closing axis in the pads' band, relative to
            the box centre [m].
        width: Extent of that band [m] (``band[1] - band[0]``).
        graspable: Fits the planner's grasp (see the module docstring).
    """

    mass: float
    center: tuple[float, float, float]
    half: tuple[float, float, float]
    closing_axis: int
    grasp_height: float
    band: tuple[float, float]
    width: float
    graspable: bool

    @property
    def size(self) -> tuple[float, float, float]:
        """Full extents of the bounding box [m]."""
        return tuple(2 * h for h in self.half)


@functools.cache
def _data() -> dict:
    return yaml.safe_load(DATA.read_text())


def _categories() -> dict[str, Category]:
    return {
        name: Category(name, tuple(c["rgba"]), tuple(c["instances"]), c.get("not_graspable"))
        for name, c in _data()["categories"].items()
    }


CATEGORIES: dict[str, Category] = _categories()
"""Every category by name."""


@functools.cache
def instance(instance_id: str) -> Instance:
    """The instance ``<source>/<name>``."""
    category = next((c.name for c in CATEGORIES.values() if instance_id in c.instances), None)
    if category is None:
        raise KeyError(f"no catalogue instance '{instance_id}'")
    key, name = instance_id.split("/", 1)
    src = _data()["sources"][key]
    rel = f"{name}.xml" if key == "robosuite" else f"{name}/{name}.xml"
    return Instance(
        id=instance_id,
        category=category,
        source=key,
        package=src["package"],
        path=f"{src['root']}/{rel}",
        licence=src["licence"],
        origin=" ".join(src["origin"].split()),
    )


def instances(category: str | None = None) -> tuple[str, ...]:
    """Instance ids of one category, or of all in catalogue order."""
    cats = [CATEGORIES[category]] if category else CATEGORIES.values()
    return tuple(i for c in cats for i in c.instances)


def split(category: str) -> tuple[tuple[str, ...], tuple[str, ...]]:
    """(pretrain, target) instances of a category.

    Rule: the graspable instances in catalogue order alternate pretrain, target, pretrain, ...; then the
    others likewise. The two sides are disjoint, and both hold a graspable instance wherever the
    category has two or more. A category with a single instance gives it to both (nothing to hold out).
    """
    ids = CATEGORIES[category].instances
    if len(ids) == 1:
        return ids, ids
    pre: list[str] = []
    tgt: list[str] = []
    for group in (
        [i for i in ids if properties(i).graspable],
        [i for i in ids if not properties(i).graspable],
    ):
        for k, iid in enumerate(group):
            (pre if k % 2 == 0 else tgt).append(iid)
    return tuple(pre), tuple(tgt)


@functools.cache
def _records() -> dict[str, str]:
    """Installed file (``package/path``) -> ``name==version`` of the catalogue's source distributions."""
    roots = {f"{s['package']}/{s['root']}" for s in _data()["sources"].values()}
    index = {}
    for dist in importlib.metadata.distributions():
        for f in dist.files or ():
            name = str(f)
            if any(name.startswith(r) for r in roots):
                index[name] = f"{dist.metadata['Name']}=={dist.version}"
    return index


def _wheel_of(package: str, path: str) -> str:
    wheel = _records().get(f"{package}/{path}")
    if wheel is None:
        raise FileNotFoundError(f"no installed distribution lists {package}/{path}")
    return wheel


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
    return Geometry(tuple(parts), tuple(visuals), collision)


def _geoms(body: mujoco.MjsBody, spec: mujoco.MjSpec, name: str, inst: Instance, visual: bool) -> None:
    geo = geometry(inst.id)
    rgba = list(CATEGORIES[inst.category].rgba)
    for k, part in enumerate(geo.parts):
        common = dict(
            name=f"{name}_c{k}",
            pos=list(part.pos),
            quat=list(part.quat),
            density=part.density,
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


def _probe(instance_id: str) -> tuple[mujoco.MjModel, mujoco.MjData]:
    spec = mujoco.MjSpec()
    body = spec.worldbody.add_body(name="probe")
    body.add_freejoint()
    _geoms(body, spec, "probe", instance(instance_id), visual=False)
    model = spec.compile()
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    return model, data


def _part_mesh(part: Part):
    import trimesh

    if part.kind == "mesh":
        mesh = trimesh.load(part.mesh, force="mesh")
    elif part.kind == "box":
        mesh = trimesh.creation.box(extents=2 * np.asarray(part.size))
    elif part.kind == "cylinder":
        mesh = trimesh.creation.cylinder(radius=part.size[0], height=2 * part.size[1], sections=32)
    elif part.kind == "sphere":
        mesh = trimesh.creation.icosphere(subdivisions=2, radius=part.size[0])
    else:
        raise ValueError(f"grasp band of a '{part.kind}' part is not implemented")
    rot = np.zeros(9)
    mujoco.mju_quat2Mat(rot, np.asarray(part.quat))
    tf = np.eye(4)
    tf[:3, :3] = rot.reshape(3, 3)
    tf[:3, 3] = part.pos
    mesh.apply_transform(tf)
    return mesh


def _slab_points(mesh, z_lo: float, z_hi: float) -> np.ndarray:
    """Vertices of a convex piece's intersection with the slab z_lo <= z <= z_hi [m]: its vertices
    inside the slab and its edges' crossings of the two planes."""
    v = np.asarray(mesh.vertices)
    pts = [v[(v[:, 2] >= z_lo) & (v[:, 2] <= z_hi)]]
    a, b = v[mesh.edges_unique[:, 0]], v[mesh.edges_unique[:, 1]]
    for z in (z_lo, z_hi):
        dz = b[:, 2] - a[:, 2]
        cross = (a[:, 2] - z) * (b[:, 2] - z) < 0
        t = (z - a[cross, 2]) / dz[cross]
        pts.append(a[cross] + t[:, None] * (b[cross] - a[cross]))
    return np.concatenate(pts)


@functools.cache
def properties(instance_id: str) -> Properties:
    """Mass, bounding box and grasp band of an instance (see the module docstring)."""
    model, _ = _probe(instance_id)
    meshes = [_part_mesh(part) for part in geometry(instance_id).parts]
    verts = np.concatenate([np.asarray(m.vertices) for m in meshes])
    lo, hi = verts.min(axis=0), verts.max(axis=0)
    center, half = (lo + hi) / 2, (hi - lo) / 2
    axis = 0 if half[0] <= half[1] else 1
    depth = PALM_ROUND if float(np.ptp(half)) < ROUND else PALM
    z_tool = max(hi[2] - depth, lo[2] + FINGER_CLEARANCE)
    band_lo, band_hi = np.inf, -np.inf
    for mesh in meshes:
        pts = _slab_points(mesh, z_tool - PAD_HALF_HEIGHT, z_tool + PAD_HALF_HEIGHT)
        if len(pts):
            band_lo = min(band_lo, float(pts[:, axis].min()))
            band_hi = max(band_hi, float(pts[:, axis].max()))
    band = (band_lo - center[axis], band_hi - center[axis])
    width = band[1] - band[0] if np.isfinite(band_lo) else 0.0
    reach = max(abs(band[0]), abs(band[1])) if np.isfinite(band_lo) else math.inf
    return Properties(
        mass=float(model.body_subtreemass[1]),
        center=tuple(float(v) for v in center),
        half=tuple(float(v) for v in half),
        closing_axis=axis,
        grasp_height=float(z_tool - lo[2]),
        band=tuple(float(v) for v in band),
        width=float(width),
        graspable=bool(reach <= GRASP_REACH and width >= EMPTY and z_tool <= hi[2]),
    )


def add_instance(
    spec: mujoco.MjSpec,
    name: str,
    instance_id: str,
    pos: tuple[float, float, float],
    yaw: float = 0.0,
    visual: bool = True,
) -> mujoco.MjsBody:
    """A free body ``name`` of a catalogue instance whose lowest point stands at ``pos[2]`` [m] and whose
    bounding box is centred on ``pos[:2]`` [m] before the turn by ``yaw`` [rad] about z. Collision geoms
    are named ``name_c<k>`` (group 0; group 3 when ``visual``), render meshes ``name_v<k>`` (group 1,
    no contacts, no mass; untextured, the category's colour)."""
    props = properties(instance_id)
    c, h = np.asarray(props.center), np.asarray(props.half)
    quat = np.array([math.cos(yaw / 2), 0, 0, math.sin(yaw / 2)])
    rot = np.zeros(9)
    mujoco.mju_quat2Mat(rot, quat)
    offset = rot.reshape(3, 3) @ np.array([c[0], c[1], 0.0])
    origin = [pos[0] - offset[0], pos[1] - offset[1], pos[2] + h[2] - c[2]]
    body = spec.worldbody.add_body(name=name, pos=origin, quat=list(quat))
    body.add_freejoint(name=name)
    _geoms(body, spec, name, instance(instance_id), visual)
    return body


def mjcf_body(instance_id: str, visual: bool = True) -> str:
    """MJCF of a model holding the instance as a free body named after it (``/`` as ``_``) standing on
    z = 0, mesh files by absolute path; loads in the main MuJoCo."""
    spec = mujoco.MjSpec()
    spec.modelname = instance_id.replace("/", "_")
    add_instance(spec, instance_id.replace("/", "_"), instance_id, (0.0, 0.0, 0.0), visual=visual)
    return spec.to_xml()


def catalogue_table() -> str:
    """The catalogue as a markdown table: category, instances, source, licence, mass [kg], size [m],
    grasp width [m] and collision geometry."""
    rows = [
        "| category | instance | source (wheel: path) | licence | mass [kg] | size x y z [m] | grasp width [m] | collision |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for cat in CATEGORIES.values():
        pre, tgt = split(cat.name)
        for k, iid in enumerate(cat.instances):
            inst, props, geo = instance(iid), properties(iid), geometry(iid)
            role = "both" if len(cat.instances) == 1 else ("pretrain" if iid in pre else "target")
            size = " x ".join(f"{s:.3f}" for s in props.size)
            grasp = f"{props.width:.3f}" + ("" if props.graspable else " (not graspable)")
            n = len(geo.parts)
            coll = (
                f"CoACD, {n} hull{'s' * (n > 1)}"
                if geo.collision == "coacd"
                else f"source, {n} primitive{'s' * (n > 1)}"
            )
            rows.append(
                f"| {cat.name if k == 0 else ''} | `{iid}` ({role}) | {inst.wheel}: `{inst.path}` | "
                f"{inst.licence} | {props.mass:.3f} | {size} | {grasp} | {coll} |"
            )
    return "\n".join(rows)
