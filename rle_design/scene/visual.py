"""Physics-only models: visual meshes dropped before compiling.

A catalog arm's visual meshes hold most of its vertices (the Panda's: ~0.3 M of them), and compiling
them costs ~0.5 s the first time in a process. A model used only for physics or planning does not
need them. A visual-only geom (``contype = conaffinity = 0``) is dropped only where its body states
its own inertia, so masses, inertias and collisions are unchanged (a body without ``<inertial>``
takes its inertia from its geoms, visual ones included).
"""

from __future__ import annotations

import mujoco

__all__ = ["drop_visual_meshes"]


def drop_visual_meshes(spec: mujoco.MjSpec, prefix: str = "") -> int:
    """Delete the visual-only mesh geoms of bodies named ``prefix...`` that state their inertia, and the
    meshes no geom uses any more; returns the number of geoms deleted."""
    mesh = mujoco.mjtGeom.mjGEOM_MESH
    dropped = 0
    for g in list(spec.geoms):
        body = g.parent
        if (
            g.type == mesh
            and g.contype == 0
            and g.conaffinity == 0
            and body.name.startswith(prefix)
            and body.explicitinertial
        ):
            spec.delete(g)
            dropped += 1
    used = {g.meshname for g in spec.geoms if g.type == mesh}
    for m in list(spec.meshes):
        if m.name not in used:
            spec.delete(m)
    return dropped
