"""RLE-Bench design and verification toolkit: MJCF, meshes, kinematics, stability, sensors, sandbox."""

import os as _os

# Offscreen rendering on CPU: MuJoCo reads MUJOCO_GL when it is first imported, so set it before that.
_os.environ.setdefault("MUJOCO_GL", "egl")
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
