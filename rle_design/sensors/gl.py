"""Headless OpenGL contexts for MuJoCo offscreen rendering on CPU: EGL first, OSMesa as fallback.

MuJoCo's classic renderer needs a current OpenGL context. On a machine without a display we use EGL
(Mesa llvmpipe on CPU, or a GPU driver), and fall back to OSMesa when EGL cannot be loaded. PyOpenGL
fixes its platform once per process (``PYOPENGL_PLATFORM``); the fallback therefore drops a PyOpenGL that
failed to load and switches both variables to the other backend.
"""

from __future__ import annotations

import os
import sys
from typing import Any

from rle_design.errors import RleError

BACKENDS = ("egl", "osmesa")
_INSTALL_HINT = {
    "egl": "apt-get install libegl1 libgl1 (Mesa provides a CPU EGL driver)",
    "osmesa": "apt-get install libosmesa6",
}


class RenderError(RleError):
    """No offscreen OpenGL context could be created, or a renderer was used after ``close()``."""

    code = "render.unavailable"


def _import_backend(name: str) -> type:
    if name == "egl":
        from mujoco.egl import GLContext
    else:
        from mujoco.osmesa import GLContext
    return GLContext


def _forget_pyopengl() -> None:
    """Drop a half-initialised PyOpenGL so that a different platform can be loaded."""
    for mod in [m for m in sys.modules if m == "OpenGL" or m.startswith("OpenGL.")]:
        del sys.modules[mod]
    for mod in ("mujoco.egl", "mujoco.egl.egl_ext", "mujoco.osmesa"):
        sys.modules.pop(mod, None)


def requested_backend() -> str:
    """Backend named by ``MUJOCO_GL`` (default ``"egl"``); raises ``RenderError`` for other values."""
    name = os.environ.get("MUJOCO_GL", "egl").strip().lower() or "egl"
    if name not in BACKENDS:
        raise RenderError(
            f"MUJOCO_GL={name!r} cannot render offscreen here. Available backends: {', '.join(BACKENDS)}",
            code="render.backend",
        )
    return name


def create_context(width: int, height: int) -> tuple[Any, str]:
    """Create and make current an offscreen GL context.

    Args:
        width: Framebuffer width [px].
        height: Framebuffer height [px].

    Returns:
        ``(context, backend)`` where ``context`` has ``make_current()`` and ``free()``.

    Raises:
        RenderError: Neither EGL nor OSMesa could create a context; the message carries each
            backend's failure and the package that provides it.
    """
    first = requested_backend()
    order = [first] + [b for b in BACKENDS if b != first]
    failures: list[str] = []
    for i, name in enumerate(order):
        if i > 0:
            os.environ["PYOPENGL_PLATFORM"] = name
            os.environ["MUJOCO_GL"] = name
            _forget_pyopengl()
        try:
            cls = _import_backend(name)
            ctx = cls(width, height)
            ctx.make_current()
            return ctx, name
        except Exception as exc:  # the GL stack raises ImportError, OSError, RuntimeError, GLError ...
            failures.append(f"{name}: {type(exc).__name__}: {exc} (install: {_INSTALL_HINT[name]})")
    raise RenderError("no offscreen OpenGL context could be created; " + "; ".join(failures))


def release_current(backend: str) -> None:
    """Leave no context current in the calling thread (EGL), so that another thread can make it current:
    an EGL context is current in at most one thread. A no-op for OSMesa, whose contexts are not handed
    between threads here (``parallel_ok``)."""
    if backend == "egl":
        import mujoco.egl
        from mujoco.egl import egl_ext as EGL

        if mujoco.egl.EGL_DISPLAY is not None:
            EGL.eglMakeCurrent(
                mujoco.egl.EGL_DISPLAY, EGL.EGL_NO_SURFACE, EGL.EGL_NO_SURFACE, EGL.EGL_NO_CONTEXT
            )


def parallel_ok(backend: str) -> bool:
    """Whether contexts of ``backend`` may draw in parallel threads (EGL; not OSMesa)."""
    return backend == "egl"
