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


def _blas_core(cpuinfo: str = "/proc/cpuinfo") -> str | None:
    """The OpenBLAS kernel family every x86-64 machine with AVX2 and FMA runs: ``Haswell``; else None.

    OpenBLAS picks its kernels per CPU, and kernels of another vector width (AVX-512 on SkylakeX) round
    a matrix product differently; a controller's solves feed those bits into contact physics, which
    amplifies them, so a ledger replayed on two machines would end in different states. One kernel
    family everywhere keeps a verifier's report the same across machines.
    """
    try:
        with open(cpuinfo) as f:
            for line in f:
                if line.startswith("flags"):
                    flags = set(line.split(":", 1)[1].split())
                    return "Haswell" if {"avx2", "fma"} <= flags else None
    except OSError:
        return None
    return None


# OpenBLAS reads OPENBLAS_CORETYPE when numpy first loads it, so set it before that.
if "OPENBLAS_CORETYPE" not in _os.environ and (_core := _blas_core()):
    _os.environ["OPENBLAS_CORETYPE"] = _core
    import sys as _sys

    if "numpy" in _sys.modules:
        import warnings as _warnings

        _warnings.warn(
            "numpy was imported before rle_design, so OpenBLAS kept its own kernels: ledger replays "
            "may differ from other machines (import rle_design first)",
            RuntimeWarning,
            stacklevel=2,
        )

# ruff: noqa: E402

from rle_design.errors import (
    CatalogError,
    MissingElement,
    MjcfError,
    RleError,
    UnsafeArtifact,
)

__all__ = [
    "MJ_ASSET_CACHE_BYTES",
    "CatalogError",
    "MissingElement",
    "MjcfError",
    "RleError",
    "UnsafeArtifact",
    "widen_mujoco_asset_cache",
]

MJ_ASSET_CACHE_BYTES = 2 << 30
"""Capacity of MuJoCo's process-wide asset cache [bytes] that ``widen_mujoco_asset_cache`` sets (only
what a process loads is held)."""


def widen_mujoco_asset_cache(capacity: int = MJ_ASSET_CACHE_BYTES) -> None:
    """Raise MuJoCo's asset cache (500 MiB by default) to ``capacity`` bytes.

    The cache holds processed meshes across compiles. A process that builds several families' models
    fills the default: a kitchen scene's meshes take 115 MB of it, the G1's 147 MB, the object
    catalogue's 262 MB, and an evicted mesh is reloaded and processed again at the next compile (the
    kitchen task tests after the catalogue's, one process: 443 s with the default, 45 s widened). A
    process without MuJoCo (an exported task's reward step) has no cache to widen.
    """
    try:
        import mujoco
    except ImportError:
        return

    cache = mujoco.mj_getCache()
    if mujoco.mj_getCacheCapacity(cache) < capacity:
        mujoco.mj_setCacheCapacity(cache, capacity)
