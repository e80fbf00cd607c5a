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

__all__ = ["CatalogError", "MissingElement", "MjcfError", "RleError", "UnsafeArtifact"]
