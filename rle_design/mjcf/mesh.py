"""Mesh analysis with trimesh, manifold3d and CoACD: mass properties, booleans, wall thickness, hulls.

Also the cheap format check the loader applies to untrusted mesh bytes (``check_mesh_bytes``), which
reads face counts from headers without building a mesh. trimesh, manifold3d and coacd are imported
inside the functions that need them.

All lengths are in the mesh's units, taken as metres; densities in kg/m^3.
"""

from __future__ import annotations

import struct
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Literal

import numpy as np

from rle_design.errors import MjcfError
from rle_design.mjcf.contract import Finding

if TYPE_CHECKING:
    import trimesh

__all__ = [
    "MeshProperties",
    "as_trimesh",
    "WallThickness",
    "boolean",
    "check_mesh_bytes",
    "collision_hulls",
    "compare_inertial",
    "mesh_properties",
    "min_wall_thickness",
]

_MAGIC = {
    b"PK\x03\x04": "a ZIP archive",
    b"\x89PNG": "a PNG image",
    b"%PDF": "a PDF document",
    b"\x7fELF": "an ELF executable",
    b"\x1f\x8b": "a gzip archive",
}
_CONTENT_TYPES = {"model/stl": ".stl", "model/obj": ".obj", "model/vnd.mujoco.msh": ".msh"}


def _looks_like(data: bytes) -> str:
    for magic, what in _MAGIC.items():
        if data.startswith(magic):
            return f" (its bytes look like {what})"
    return ""


def check_mesh_bytes(data: bytes, name: str, content_type: str | None, max_faces: int) -> int:
    """Check that ``data`` is the mesh format its name claims and count its faces cheaply.

    Binary STL: the header count must match the size (84 + 50 n bytes); ASCII STL is refused (MuJoCo
    reads binary STL only, and at most 200,000 STL faces: its own compile error names the file). OBJ: no NUL bytes, at least one ``v`` line; faces bounded below by the ``f`` line count.
    MSH (MuJoCo binary): 4 int32 counts whose arrays fill the file exactly.

    Args:
        data: File bytes.
        name: File name (its extension selects the format unless ``content_type`` is given).
        content_type: MuJoCo ``content_type`` attribute, e.g. ``"model/stl"``, or None.
        max_faces: Largest accepted face count.

    Returns:
        Number of faces (triangles for STL/MSH, face lines for OBJ).

    Raises:
        MjcfError: ``mesh.invalid`` (wrong or unsupported format), ``mesh.too_many_faces``.
    """
    suffix = _CONTENT_TYPES.get(content_type or "", Path(name).suffix.lower())
    hint = _looks_like(data)
    if suffix == ".stl":
        n = struct.unpack("<I", data[80:84])[0] if len(data) >= 84 else -1
        if n >= 0 and len(data) == 84 + 50 * n:
            faces = n
        elif data.lstrip()[:5].lower() == b"solid":
            raise MjcfError(
                "ASCII STL is not supported by MuJoCo; save the mesh as binary STL", code="mesh.invalid"
            )
        elif n < 0:
            raise MjcfError(
                f"not a valid binary STL: {len(data)} bytes, header needs 84{hint}", code="mesh.invalid"
            )
        else:
            raise MjcfError(
                f"not a valid binary STL: {len(data)} bytes, but the header claims {n} faces (84 + 50 x {n} = "
                f"{84 + 50 * n} bytes){hint}",
                code="mesh.invalid",
            )
    elif suffix == ".obj":
        if b"\x00" in data:
            raise MjcfError(f"not a valid OBJ: binary data in a text format{hint}", code="mesh.invalid")
        if not (data.startswith(b"v ") or b"\nv " in data):
            raise MjcfError("not a valid OBJ: no vertex ('v') line", code="mesh.invalid")
        faces = data.count(b"\nf ") + int(data.startswith(b"f "))
    elif suffix == ".msh":
        if len(data) < 16:
            raise MjcfError(f"not a valid MSH: {len(data)} bytes, header needs 16{hint}", code="mesh.invalid")
        nv, nn, nt, nf = struct.unpack("<4i", data[:16])
        expected = 16 + 4 * (3 * nv + 3 * nn + 2 * nt + 3 * nf)
        if min(nv, nn, nt, nf) < 0 or expected != len(data):
            raise MjcfError(
                f"not a valid MSH: header counts ({nv}, {nn}, {nt}, {nf}) need {expected} bytes, file has "
                f"{len(data)}{hint}",
                code="mesh.invalid",
            )
        faces = nf
    else:
        raise MjcfError(
            f"unsupported mesh format '{suffix or content_type}'; supported: .msh, .obj, .stl",
            code="mesh.invalid",
        )
    if faces > max_faces:
        raise MjcfError(f"mesh has {faces} faces, limit {max_faces}", code="mesh.too_many_faces")
    return faces


@dataclass(frozen=True)
class MeshProperties:
    """Mass properties of a solid mesh of uniform density.

    Attributes:
        watertight: Closed, consistently wound surface (volume and inertia are meaningful only then).
        volume: Enclosed volume [m^3].
        mass: density x volume [kg].
        com: Centre of mass in the mesh frame [m].
        inertia: Inertia tensor about the centre of mass, mesh-frame axes [kg m^2].
        bounds: (min corner, max corner) of the axis-aligned bounding box [m].
    """

    watertight: bool
    volume: float
    mass: float
    com: tuple[float, float, float]
    inertia: tuple[tuple[float, float, float], ...]
    bounds: tuple[tuple[float, float, float], tuple[float, float, float]]


def as_trimesh(mesh_or_path) -> trimesh.Trimesh:
    import trimesh

    if isinstance(mesh_or_path, trimesh.Trimesh):
        return mesh_or_path
    loaded = trimesh.load(str(mesh_or_path), force="mesh")
    if not isinstance(loaded, trimesh.Trimesh) or len(loaded.faces) == 0:
        raise MjcfError(
            f"'{mesh_or_path}' holds no triangle mesh", code="mesh.invalid", path=str(mesh_or_path)
        )
    return loaded


def mesh_properties(mesh_or_path, density: float) -> MeshProperties:
    """Volume, mass, centre of mass, inertia about the COM and bounds of a uniform solid.

    Args:
        mesh_or_path: ``trimesh.Trimesh`` or a mesh file path.
        density: Material density [kg/m^3].
    """
    mesh = as_trimesh(mesh_or_path).copy()
    mesh.density = float(density)
    tup = lambda v: tuple(float(x) for x in v)  # noqa: E731
    return MeshProperties(
        watertight=bool(mesh.is_watertight),
        volume=float(mesh.volume),
        mass=float(mesh.mass),
        com=tup(mesh.center_mass),
        inertia=tuple(tup(r) for r in mesh.moment_inertia),
        bounds=(tup(mesh.bounds[0]), tup(mesh.bounds[1])),
    )


def compare_inertial(
    declared_mass: float,
    declared_com,
    declared_inertia,
    props: MeshProperties,
    rtol: float = 0.05,
    name: str = "body",
) -> list[Finding]:
    """Compare a declared ``<inertial>`` with the mesh's mass properties.

    Args:
        declared_mass: Declared mass [kg].
        declared_com: Declared centre of mass in the mesh frame [m] (3,).
        declared_inertia: Declared inertia about the COM: diagonal (3,) or full (3, 3) [kg m^2].
        props: Computed properties (``mesh_properties``).
        rtol: Relative tolerance; the COM is compared against ``rtol`` x the bounding-box diagonal.
        name: Element name used in messages.

    Returns:
        Findings ``inertial.mass_mismatch``, ``inertial.com_mismatch``, ``inertial.inertia_mismatch``,
        each message carrying the declared and the computed numbers.
    """
    out: list[Finding] = []
    if abs(declared_mass - props.mass) > rtol * abs(props.mass):
        out.append(
            Finding(
                "inertial.mass_mismatch",
                f"'{name}': declared mass {declared_mass:.6g} kg != mesh mass {props.mass:.6g} kg "
                f"(rtol {rtol:g})",
            )
        )
    diag = float(np.linalg.norm(np.subtract(props.bounds[1], props.bounds[0])))
    com_err = float(np.linalg.norm(np.subtract(declared_com, props.com)))
    if com_err > rtol * diag:
        out.append(
            Finding(
                "inertial.com_mismatch",
                f"'{name}': declared COM {np.round(declared_com, 6).tolist()} m != mesh COM "
                f"{np.round(props.com, 6).tolist()} m (off by {com_err:.4g} m)",
            )
        )
    inertia = np.asarray(declared_inertia, dtype=float)
    inertia = np.diag(inertia) if inertia.shape == (3,) else inertia
    ref = np.asarray(props.inertia)
    if np.linalg.norm(inertia - ref) > rtol * np.linalg.norm(ref):
        out.append(
            Finding(
                "inertial.inertia_mismatch",
                f"'{name}': declared inertia diag {np.diag(inertia).round(9).tolist()} kg m^2 != mesh "
                f"inertia diag {np.diag(ref).round(9).tolist()} kg m^2",
            )
        )
    return out


def _to_manifold(mesh: trimesh.Trimesh):
    import manifold3d

    m = manifold3d.Manifold(
        manifold3d.Mesh64(
            vert_properties=np.ascontiguousarray(mesh.vertices, dtype=np.float64),
            tri_verts=np.ascontiguousarray(mesh.faces, dtype=np.uint64),
        )
    )
    if m.status() != manifold3d.Error.NoError:
        raise MjcfError(f"mesh is not a closed manifold ({m.status()})", code="mesh.not_manifold")
    return m


def boolean(a: trimesh.Trimesh, b: trimesh.Trimesh, op: Literal["union", "difference", "intersection"]):
    """Exact boolean of two closed meshes with manifold3d; returns a ``trimesh.Trimesh``."""
    import trimesh

    ma, mb = _to_manifold(a), _to_manifold(b)
    ops = {"union": lambda: ma + mb, "difference": lambda: ma - mb, "intersection": lambda: ma ^ mb}
    if op not in ops:
        raise MjcfError(f"boolean op '{op}' does not exist. Available: {', '.join(ops)}", code="mesh.bad_op")
    out = ops[op]().to_mesh64()
    return trimesh.Trimesh(
        vertices=np.asarray(out.vert_properties)[:, :3], faces=np.asarray(out.tri_verts, dtype=np.int64)
    )


@dataclass(frozen=True)
class WallThickness:
    """Wall thickness sampled by inward rays.

    Attributes:
        minimum: Smallest sampled thickness [m].
        p05: 5th percentile of the sampled thickness [m].
        n_samples: Rays that hit the far side (rays that miss are dropped).
    """

    minimum: float
    p05: float
    n_samples: int


def min_wall_thickness(mesh: trimesh.Trimesh, n_samples: int = 2000, seed: int = 0) -> WallThickness:
    """Wall thickness by ray casting: from ``n_samples`` area-uniform surface points (seeded), a ray
    along the inward normal (-n, started 1e-9 m inside) to the first hit on the far surface.

    Error of the method: for walls with parallel faces the ray length is the thickness exactly (to
    floating point); where the opposite face is inclined by angle a the ray overestimates by 1/cos(a);
    near the end of a thin feature the ray may run lengthwise and overestimate. A thin region of area
    fraction f is missed with probability (1 - f)^n_samples, so small thin spots need more samples.

    Args:
        mesh: Closed, outward-oriented mesh [m].
        n_samples: Number of surface samples.
        seed: Sampling seed.
    """
    import trimesh

    points, face_idx = trimesh.sample.sample_surface(mesh, int(n_samples), seed=int(seed))
    normals = mesh.face_normals[face_idx]
    eps = 1e-9 * max(1.0, float(mesh.scale))
    origins = points - normals * eps
    locations, ray_idx, _ = mesh.ray.intersects_location(origins, -normals, multiple_hits=False)
    if len(ray_idx) == 0:
        raise MjcfError("no inward ray hit the far surface: is the mesh closed?", code="mesh.not_manifold")
    dist = np.linalg.norm(locations - origins[ray_idx], axis=1) + eps
    return WallThickness(float(dist.min()), float(np.percentile(dist, 5)), int(len(dist)))


def collision_hulls(
    mesh: trimesh.Trimesh,
    threshold: float = 0.1,
    max_convex_hull: int = 16,
    seed: int = 0,
    resolution: int = 1000,
    mcts_iterations: int = 60,
) -> list[trimesh.Trimesh]:
    """Approximate convex decomposition with CoACD (defaults tuned for seconds, not quality).

    Args:
        mesh: Closed mesh [m].
        threshold: CoACD concavity threshold (smaller: more, tighter pieces).
        max_convex_hull: Most pieces (-1: no limit).
        seed: CoACD random seed.
        resolution: Surface sampling resolution of the concavity metric.
        mcts_iterations: Search iterations per cut.

    Returns:
        Convex pieces as ``trimesh.Trimesh``.
    """
    import coacd
    import trimesh

    coacd.set_log_level("error")
    parts = coacd.run_coacd(
        coacd.Mesh(np.asarray(mesh.vertices, dtype=float), np.asarray(mesh.faces, dtype=int)),
        threshold=threshold,
        max_convex_hull=max_convex_hull,
        resolution=resolution,
        mcts_iterations=mcts_iterations,
        seed=seed,
    )
    return [trimesh.Trimesh(vertices=v, faces=f) for v, f in parts]
