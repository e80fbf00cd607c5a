"""Printed PLA shells of the GELLO leaders, built with manifold3d and measured with trimesh.

Every printed part is a closed hollow shell (outer solid minus an inner solid offset by the wall
thickness), the way a slicer prints a part with walls and zero infill. Its mass is the shell volume
times the PLA density of the materials catalog; inertia is the exact polyhedral inertia of the shell.
"""

from __future__ import annotations

from dataclasses import dataclass

import manifold3d
import numpy as np
import trimesh

SEGMENTS = 20
"""Circular segments of printed tubes (keeps each STL a few kB)."""


@dataclass(frozen=True)
class ShellPart:
    """A printed part with its mass properties in the part's (body) frame.

    Attributes:
        mesh: Watertight triangle mesh [m].
        mass: Shell mass [kg].
        com: Centre of mass [m].
        inertia: Inertia tensor about the centre of mass [kg m^2].
    """

    mesh: trimesh.Trimesh
    mass: float
    com: np.ndarray
    inertia: np.ndarray


def _to_trimesh(solid: manifold3d.Manifold) -> trimesh.Trimesh:
    m = solid.to_mesh()
    return trimesh.Trimesh(
        vertices=np.asarray(m.vert_properties)[:, :3], faces=np.asarray(m.tri_verts), process=True
    )


def _align_z(direction: np.ndarray) -> np.ndarray:
    """4x4 rotation taking +z to ``direction``."""
    d = direction / np.linalg.norm(direction)
    return trimesh.geometry.align_vectors([0.0, 0.0, 1.0], d)


def tube(start: np.ndarray, end: np.ndarray, radius: float, wall: float) -> manifold3d.Manifold:
    """Closed hollow cylinder from ``start`` to ``end`` with end caps of thickness ``wall`` [m]."""
    start, end = np.asarray(start, float), np.asarray(end, float)
    length = float(np.linalg.norm(end - start))
    outer = manifold3d.Manifold.cylinder(length + 2 * wall, radius, radius, SEGMENTS).translate([0, 0, -wall])
    inner = manifold3d.Manifold.cylinder(length, radius - wall, radius - wall, SEGMENTS)
    shell = outer - inner
    t = _align_z(end - start)
    t[:3, 3] = start
    return shell.transform(t[:3, :])


def box_shell(center: np.ndarray, size: np.ndarray, wall: float) -> manifold3d.Manifold:
    """Closed hollow box of outer ``size`` centred at ``center`` [m]."""
    size = np.asarray(size, float)
    outer = manifold3d.Manifold.cube(size.tolist(), center=True)
    inner = manifold3d.Manifold.cube((size - 2 * wall).tolist(), center=True)
    return (outer - inner).translate(np.asarray(center, float).tolist())


def measure(solid: manifold3d.Manifold, density: float) -> ShellPart:
    """Mass properties of a solid of uniform ``density`` [kg/m^3]."""
    mesh = _to_trimesh(solid)
    mesh.density = density
    return ShellPart(
        mesh=mesh,
        mass=float(mesh.mass),
        com=np.asarray(mesh.center_mass, float),
        inertia=np.asarray(mesh.moment_inertia, float),
    )


def box_inertia(mass: float, size: np.ndarray) -> np.ndarray:
    """Inertia of a solid box about its centre [kg m^2]."""
    x, y, z = np.asarray(size, float)
    return mass / 12.0 * np.diag([y * y + z * z, x * x + z * z, x * x + y * y])


def combine(parts: list[tuple[float, np.ndarray, np.ndarray]]) -> tuple[float, np.ndarray, np.ndarray]:
    """Combine ``(mass, com, inertia_about_com)`` items into one rigid body (parallel-axis theorem)."""
    mass = sum(m for m, _, _ in parts)
    com = sum(m * np.asarray(c) for m, c, _ in parts) / mass
    inertia = np.zeros((3, 3))
    for m, c, i in parts:
        d = np.asarray(c) - com
        inertia += i + m * (d @ d * np.eye(3) - np.outer(d, d))
    return float(mass), com, inertia
