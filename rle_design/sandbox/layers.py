"""Which isolation layers a sandboxed child gets in the current environment.

The kernel layers depend on the parent's privileges: a root parent with CAP_SYS_ADMIN gets all of
them; a default Docker container (no CAP_SYS_ADMIN) gets no network namespace; a non-root parent gets
neither the network namespace nor the uid drop. ``probe_layers`` starts one child on an empty module,
through the same bootstrap as every sandbox, and returns the layers it established.
"""

from __future__ import annotations

import functools
import tempfile
from pathlib import Path

LAYERS = ("netns", "uid_drop", "no_new_privs", "landlock", "nproc")
"""Kernel layers, in the order the child establishes them: own network namespace, uid/gid drop to
``nobody``, ``PR_SET_NO_NEW_PRIVS``, a Landlock domain (file access limited to the interpreter's
library trees read-only and the working directory; no TCP; no signals out; Linux >= 5.13, any uid),
``RLIMIT_NPROC`` enforced (non-root uid)."""


@functools.cache
def landlock_abi() -> int:
    """The kernel's Landlock ABI version, 0 when Landlock is absent or disabled (or not Linux)."""
    import ctypes

    try:
        libc = ctypes.CDLL(None, use_errno=True)
        libc.syscall.restype = ctypes.c_long
        abi = libc.syscall(ctypes.c_long(444), None, ctypes.c_size_t(0), ctypes.c_uint32(1))
    except (OSError, AttributeError):
        return 0
    return max(0, int(abi))


@functools.cache
def probe_layers() -> dict[str, bool]:
    """``{layer: active}`` for a child started now by this process (cached per process).

    Raises:
        RleError: ``sandbox.setup`` when no child can be started at all.
    """
    from rle_design.sandbox.limits import SandboxLimits
    from rle_design.sandbox.process import Sandbox

    with tempfile.TemporaryDirectory(prefix="rle-probe-") as tmp:
        module = Path(tmp) / "probe.py"
        module.write_text("")
        with Sandbox(module, limits=SandboxLimits(startup_timeout_s=30.0), name="probe") as box:
            return {name: bool(box.layers.get(name, False)) for name in LAYERS}
