"""Cross-sections of a part seen as a beam (``strength`` loads them).

Sections. A box, cylinder or capsule is a prismatic beam along its longest axis (a cylinder's and a
capsule's axis is its own z), of constant section, so the clamp is its weakest section: circle of
radius r (A = pi r^2, I = pi r^4 / 4, c = r, torsion tau = 2 T / (pi r^3)) or rectangle b x h
(I_y = b h^3 / 12, I_z = h b^3 / 12; bending in the worst direction sigma = M sqrt((c_y / I_y)^2 +
(c_z / I_z)^2); torsion tau = T (3 a + 1.8 b) / (a^2 b^2), a >= b, Roark). Spheres and ellipsoids
are masses, not beams. A mesh part is cut into ``MESH_SECTIONS`` sections along its longest axis
(manifold3d slices; area and second moments of each by Green's theorem); each section between the
clamp and the far end carries the loads beyond it, the part's own weight in proportion.

SI units: m.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

__all__ = ["MESH_SECTIONS", "Beam", "Section", "beam_section", "mesh_sections", "polygon_section"]

_GT = mujoco.mjtGeom


@dataclass(frozen=True)
class Beam:
    """A prismatic section.

    Attributes:
        length: Full length along the axis [m].
        area: Section area [m^2].
        inertia: Smallest second moment of area [m^4] (deflection).
        bending: Worst-direction section modulus inverse, max over directions of c / I [1/m^3].
        torsion: Shear stress per unit torque [1/m^3].
        axis: Beam axis in the geom frame (unit vector).
    """

    length: float
    area: float
    inertia: float
    bending: float
    torsion: float
    axis: np.ndarray


def beam_section(geom_type: int, size: np.ndarray) -> Beam | None:
    """The beam of a box, cylinder or capsule geom of MuJoCo ``size``; None for other types."""
    t = int(geom_type)
    if t in (_GT.mjGEOM_CYLINDER, _GT.mjGEOM_CAPSULE):
        r, h = float(size[0]), float(size[1])
        length = 2 * h + (2 * r if t == _GT.mjGEOM_CAPSULE else 0.0)
        inertia = np.pi * r**4 / 4
        return Beam(length, np.pi * r**2, inertia, r / inertia, 2 / (np.pi * r**3), np.array([0.0, 0.0, 1.0]))
    if t == _GT.mjGEOM_BOX:
        half = np.asarray(size[:3], float)
        k = int(np.argmax(half))
        b, h = (2 * half[i] for i in range(3) if i != k)
        iy, iz = b * h**3 / 12, h * b**3 / 12
        a_, b_ = max(b, h), min(b, h)
        return Beam(
            2 * half[k],
            b * h,
            min(iy, iz),
            float(np.hypot((h / 2) / iy, (b / 2) / iz)),
            (3 * a_ + 1.8 * b_) / (a_**2 * b_**2),
            np.eye(3)[k],
        )
    return None


MESH_SECTIONS = 24
"""Sections a mesh part is cut into along its longest axis, the first and last at its ends [1]."""


@dataclass(frozen=True)
class Section:
    """One cross-section of a part, perpendicular to its beam axis.

    Attributes:
        s: Position along the axis from the geom frame's origin [m].
        centre: Its centroid in the geom frame [m].
        area: Area [m^2].
        inertia: Smallest principal second moment of area [m^4].
        bending: Largest over the section's points of hypot(v / I_1, u / I_2) in principal axes
            (u, v): bending stress per unit moment in the worst direction [1/m^3].
        torsion: Shear stress per unit torque, c_max / J with Saint-Venant's J = A^4 / (4 pi^2 I_p)
            (exact for a circle, low for thin sections: conservative) [1/m^3].
    """

    s: float
    centre: np.ndarray
    area: float
    inertia: float
    bending: float
    torsion: float


def _loop_moments(p: np.ndarray) -> np.ndarray:
    """(A, S_x, S_y, I_xx, I_yy, I_xy) of a closed polygon loop by Green's theorem (signed: holes,
    wound clockwise, subtract), moments about the origin."""
    x, y = p[:, 0], p[:, 1]
    x1, y1 = np.roll(x, -1), np.roll(y, -1)
    cross = x * y1 - x1 * y
    return np.array(
        [
            cross.sum() / 2,
            ((x + x1) * cross).sum() / 6,
            ((y + y1) * cross).sum() / 6,
            ((y**2 + y * y1 + y1**2) * cross).sum() / 12,
            ((x**2 + x * x1 + x1**2) * cross).sum() / 12,
            ((x * y1 + 2 * x * y + 2 * x1 * y1 + x1 * y) * cross).sum() / 24,
        ]
    )


def polygon_section(loops: list[np.ndarray]) -> tuple[float, np.ndarray, float, float, float] | None:
    """Area, centroid, smallest principal moment, worst-direction bending factor and torsion factor
    of a planar section given as closed loops (outer counter-clockwise, holes clockwise) [m]; None
    for an empty section."""
    loops = [np.asarray(p, float) for p in loops if len(p) >= 3]
    if not loops:
        return None
    a, sx, sy, ixx, iyy, ixy = sum(_loop_moments(p) for p in loops)
    if a <= 1e-14:
        return None
    cx, cy = sx / a, sy / a
    ixx, iyy, ixy = ixx - a * cy**2, iyy - a * cx**2, ixy - a * cx * cy  # about the centroid
    vals, vecs = np.linalg.eigh(np.array([[iyy, -ixy], [-ixy, ixx]]))  # inertia tensor of the plane
    vals = np.maximum(vals, 1e-30)
    pts = np.vstack(loops) - [cx, cy]
    uv = pts @ vecs  # principal coordinates; I about axis u is vals[1] (stress ~ v), about v vals[0]
    # bending about principal axis k: sigma = M v / I_u; worst direction: hypot of the two
    bend = float(np.max(np.hypot(uv[:, 1] / vals[1] if vals[1] > 0 else 0, uv[:, 0] / vals[0])))
    ip = float(vals.sum())
    j = a**4 / (4 * np.pi**2 * ip)
    tors = float(np.max(np.linalg.norm(pts, axis=1)) / j)
    return float(a), np.array([cx, cy]), float(vals.min()), bend, tors


def mesh_sections(model: mujoco.MjModel, g: int, n: int = MESH_SECTIONS, cache: dict | None = None):
    """The beam axis of mesh geom ``g`` (its oriented bounding box's longest axis, geom frame), the
    axial extent (lo, hi) [m] and ``n`` cross-sections, evenly inside it."""
    import trimesh

    from rle_design.mjcf.geom_solid import geom_manifold, geom_trimesh

    verts = np.asarray(geom_trimesh(model, g).vertices)
    to_box, extents = trimesh.bounds.oriented_bounds(verts)
    k = int(np.argmax(extents))
    axis = np.asarray(to_box[k, :3], float)
    axis /= np.linalg.norm(axis)
    u = np.cross(axis, [1.0, 0, 0] if abs(axis[0]) < 0.9 else [0, 1.0, 0])
    u /= np.linalg.norm(u)
    v = np.cross(axis, u)
    frame = np.vstack([u, v, axis])  # rows: geom frame -> (u, v, axis)
    mat = np.zeros((3, 4))
    mat[:, :3] = frame
    man = geom_manifold(model, g, cache).transform(mat)
    z = verts @ axis
    lo, hi = float(z.min()), float(z.max())
    out = []
    pad = 1e-4 * (hi - lo)  # the end sections just inside the part's faces
    for s in np.linspace(lo + pad, hi - pad, n):
        sec = polygon_section([np.asarray(p) for p in man.slice(float(s)).to_polygons()])
        if sec is None:
            continue
        area, c, inertia, bend, tors = sec
        centre = frame.T @ np.array([c[0], c[1], s])
        out.append(Section(float(s), centre, area, inertia, bend, tors))
    return axis, (lo, hi), out
