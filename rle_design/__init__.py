"""RLE-Bench design and verification toolkit: MJCF, meshes, kinematics, stability, sensors, sandbox."""

from rle_design.errors import (
    CatalogError,
    MissingElement,
    MjcfError,
    RleError,
    UnsafeArtifact,
)

__all__ = ["CatalogError", "MissingElement", "MjcfError", "RleError", "UnsafeArtifact"]
