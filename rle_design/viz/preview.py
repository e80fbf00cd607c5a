"""``rle preview``: a design with an optional canonical arm, as a meshcat scene or an offscreen PNG."""

from __future__ import annotations

import time
from pathlib import Path

import mujoco
import numpy as np

from rle_design.errors import RleError
from rle_design.scene import compile_spec, compose
from rle_design.viz.render import collision_shadow_geoms, render_views


def load_preview_model(
    xml: str | Path, arm: str | None = None, payload: str | None = None, mount_site: str | None = None
) -> mujoco.MjModel:
    """Compile ``xml`` (through the safe loader) with an optional arm at ``mount_site`` and a floor.

    Raises:
        ConfigError: ``arm`` without ``mount_site``.
        MissingElement: ``mount_site`` is not a site of the design.
    """
    from rle_design.mjcf.loader import load_design

    path = Path(xml)
    if not path.is_file():
        raise RleError(f"file '{xml}' does not exist", code="preview.missing_file")
    design = load_design(path.parent, entry=path.name)
    spec = compose(design.spec, arm_id=arm, payload_id=payload, mount_site=mount_site)
    return compile_spec(spec)


def settle_pose(model: mujoco.MjModel) -> mujoco.MjData:
    """Data at the model's home keyframe if it has one, else qpos0, with kinematics computed."""
    data = mujoco.MjData(model)
    if model.nkey:
        mujoco.mj_resetDataKeyframe(model, data, 0)
    mujoco.mj_forward(model, data)
    return data


def preview(
    xml: str | Path,
    arm: str | None = None,
    png: str | Path | None = None,
    payload: str | None = None,
    port: int | None = None,
    block: bool = True,
    mount_site: str | None = None,
) -> str:
    """Write a PNG (front, side, top views) when ``png`` is given, else serve a meshcat scene.

    ``arm`` (a catalog arm id) is attached at the design's site ``mount_site``, ``payload`` (a catalog
    part) at the arm's tool site.

    Returns:
        The PNG path or the meshcat URL.
    """
    model = load_preview_model(xml, arm, payload, mount_site)
    data = settle_pose(model)
    if png is not None:
        out = render_views(
            model,
            data,
            png,
            [
                ("front", dict(azimuth=180.0, elevation=-15.0)),
                ("side", dict(azimuth=90.0, elevation=-15.0)),
                ("iso", dict(azimuth=135.0, elevation=-25.0)),
            ],
        )
        print(f"wrote {out}")
        return str(out)
    return serve_meshcat(model, data, port=port, block=block)


def _meshcat():
    try:
        import meshcat
        import meshcat.geometry as g
        import meshcat.transformations as tf
    except ImportError:
        raise RleError(
            "meshcat is not installed; install the viz extra: pip install 'rle-bench[viz]'",
            code="viz.missing_extra",
        ) from None
    return meshcat, g, tf


def serve_meshcat(
    model: mujoco.MjModel, data: mujoco.MjData, port: int | None = None, block: bool = True
) -> str:
    """Send every visible geom to a meshcat server; prints and returns its URL."""
    meshcat, g, tf = _meshcat()
    vis = (
        meshcat.Visualizer(zmq_url=None)
        if port is None
        else meshcat.Visualizer(zmq_url=f"tcp://127.0.0.1:{port}")
    )
    hidden = set(collision_shadow_geoms(model).tolist())
    for i in range(model.ngeom):
        if i in hidden or model.geom_rgba[i, 3] == 0:
            continue
        geom = _geom_to_meshcat(model, i, g)
        if geom is None:
            continue
        rgba = model.geom_rgba[i]
        colour = int(rgba[0] * 255) << 16 | int(rgba[1] * 255) << 8 | int(rgba[2] * 255)
        material = g.MeshLambertMaterial(color=colour, opacity=float(rgba[3]), transparent=bool(rgba[3] < 1))
        name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_GEOM, i) or f"geom{i}"
        T = np.eye(4)
        T[:3, :3] = data.geom_xmat[i].reshape(3, 3)
        T[:3, 3] = data.geom_xpos[i]
        node = vis[f"design/{name.replace('/', '_')}_{i}"]
        node.set_object(geom, material)
        node.set_transform(T)
    url = vis.url()
    print(f"meshcat preview: {url}")
    if block:
        print("Ctrl-C to stop")
        try:
            while True:
                time.sleep(1.0)
        except KeyboardInterrupt:
            pass
    return url


def _geom_to_meshcat(model: mujoco.MjModel, i: int, g):
    t, size = model.geom_type[i], model.geom_size[i]
    G = mujoco.mjtGeom
    if t == G.mjGEOM_BOX:
        return g.Box((2 * size).tolist())
    if t == G.mjGEOM_SPHERE:
        return g.Sphere(float(size[0]))
    if t == G.mjGEOM_CYLINDER:
        return _z_cylinder(g, float(size[0]), float(2 * size[1]))
    if t == G.mjGEOM_CAPSULE:
        return _z_cylinder(g, float(size[0]), float(2 * size[1] + 2 * size[0]))
    if t == G.mjGEOM_ELLIPSOID:
        return g.Ellipsoid(size.tolist())
    if t == G.mjGEOM_MESH:
        mid = model.geom_dataid[i]
        v0, nv = model.mesh_vertadr[mid], model.mesh_vertnum[mid]
        f0, nf = model.mesh_faceadr[mid], model.mesh_facenum[mid]
        verts = model.mesh_vert[v0 : v0 + nv]
        faces = model.mesh_face[f0 : f0 + nf]
        return g.TriangularMeshGeometry(verts.astype(np.float32), faces.astype(np.uint32))
    if t == G.mjGEOM_PLANE:
        return g.Box([4.0, 4.0, 0.002])
    return None


def _z_cylinder(g, radius: float, length: float):
    """meshcat cylinders run along y; MuJoCo's along z. The mesh is built along z directly."""
    n = 24
    ang = np.linspace(0, 2 * np.pi, n, endpoint=False)
    ring = np.stack([radius * np.cos(ang), radius * np.sin(ang)], 1)
    bottom = np.c_[ring, np.full(n, -length / 2)]
    top = np.c_[ring, np.full(n, length / 2)]
    verts = np.vstack([bottom, top, [[0, 0, -length / 2], [0, 0, length / 2]]])
    faces = []
    for k in range(n):
        a, b = k, (k + 1) % n
        faces += [[a, b, n + b], [a, n + b, n + a], [2 * n, b, a], [2 * n + 1, n + a, n + b]]
    return g.TriangularMeshGeometry(verts.astype(np.float32), np.array(faces, dtype=np.uint32))
