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

LAYERS = ("netns", "uid_drop", "no_new_privs", "nproc")
"""Kernel layers, in the order the child establishes them: own network namespace, uid/gid drop to
``nobody``, ``PR_SET_NO_NEW_PRIVS``, ``RLIMIT_NPROC`` enforced (non-root uid)."""


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
