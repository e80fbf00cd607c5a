"""RLE-Bench design and verification toolkit: MJCF, meshes, kinematics, stability, sensors, sandbox."""

import os as _os


def _default_gl_backend(find=None) -> str:
    """EGL when libEGL is present, else OSMesa when libOSMesa is, else EGL (whose error names the fix)."""
    import ctypes.util

    find = find or ctypes.util.find_library
    return "osmesa" if not find("EGL") and find("OSMesa") else "egl"


# Offscreen rendering on CPU: MuJoCo reads MUJOCO_GL when it is first imported, so set it before that.
if "MUJOCO_GL" not in _os.environ:
    _os.environ["MUJOCO_GL"] = _default_gl_backend()
_os.environ.setdefault("PYOPENGL_PLATFORM", _os.environ["MUJOCO_GL"])

# ruff: noqa: E402

from rle_design.errors import (
    CatalogError,
    MissingElement,
    MjcfError,
    RleError,
    UnsafeArtifact,
)

__all__ = ["CatalogError", "MissingElement", "MjcfError", "RleError", "UnsafeArtifact"]
