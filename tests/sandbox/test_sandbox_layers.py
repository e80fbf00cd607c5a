"""Each isolation layer on its own: the kernel layers stop a ctypes bypass of the audit hook (root),
and the audit hook works without the kernel layers (as when not running as root)."""

from __future__ import annotations

import errno
import os
from pathlib import Path

import pytest

from rle_design.sandbox import ParticipantFault, Sandbox, SandboxLimits, landlock_abi
from rle_design.sandbox import process as sandbox_process

FAST = SandboxLimits(call_timeout_s=3.0, startup_timeout_s=10.0)

BYPASS = """
import ctypes, os

libc = ctypes.CDLL(None, use_errno=True)

def _result(ret):
    return [int(ret), ctypes.get_errno()]

def raw_fork():
    pid = libc.fork()
    if pid == 0:
        libc._exit(0)
    return _result(pid)

def raw_connect():
    fd = libc.socket(2, 1, 0)  # AF_INET, SOCK_STREAM
    addr = (2).to_bytes(2, "little") + (80).to_bytes(2, "big") + bytes([1, 1, 1, 1]) + bytes(8)
    return _result(libc.connect(fd, addr, 16))

def raw_write(path):
    return _result(libc.open(path.encode(), os.O_WRONLY | os.O_CREAT, 0o644))

def raw_read(path):
    return _result(libc.open(path.encode(), os.O_RDONLY))

def raw_kill_parent():
    return _result(libc.kill(os.getppid(), 0))

def py_socket():
    import socket
    socket.socket()

def py_fork():
    os.fork()
"""


@pytest.fixture(scope="module")
def bypass(tmp_path_factory) -> Path:
    path = tmp_path_factory.mktemp("bypass") / "bypass.py"
    path.write_text(BYPASS)
    return path


root_only = pytest.mark.skipif(os.geteuid() != 0, reason="the kernel layers need a root parent")


@root_only
def test_kernel_layers_stop_a_ctypes_bypass(bypass, tmp_path):
    target = tmp_path / "pwned.txt"
    with Sandbox(bypass, limits=FAST) as box:
        assert box.call("raw_fork") == [-1, errno.EAGAIN]  # RLIMIT_NPROC = 0 for nobody
        if box.layers["landlock"] and landlock_abi() >= 4:  # TCP connect refused by the Landlock domain
            assert box.call("raw_connect") == [-1, errno.EACCES]
        elif box.layers["netns"]:  # off where the kernel refuses it (no CAP_SYS_ADMIN, as in Docker)
            assert box.call("raw_connect") == [-1, errno.ENETUNREACH]  # empty network namespace
        assert box.call("raw_write", str(target)) == [-1, errno.EACCES]  # uid nobody
        assert box.call("raw_read", "/etc/shadow")[1] in (errno.EACCES, errno.ENOENT)
        assert box.call("raw_kill_parent") == [-1, errno.EPERM]  # other uid
    assert not target.exists()


def test_audit_hook_alone_blocks_python_level_escapes(bypass, monkeypatch):
    monkeypatch.setattr(sandbox_process, "drop_ids", lambda: None)  # as if not root: no kernel layers
    with Sandbox(bypass, limits=FAST) as box:
        assert box.layers["uid_drop"] is False and box.layers["netns"] is False
        for fn, what in (
            ("py_socket", "network access (socket.__new__)"),
            ("py_fork", "creating processes (fork)"),
        ):
            with pytest.raises(ParticipantFault) as info:
                box.call(fn)
            assert info.value.code == "sandbox.forbidden"
            assert f"rle-sandbox: {what} is not allowed in the sandbox" in info.value.message


landlock_only = pytest.mark.skipif(
    landlock_abi() == 0, reason="the kernel has no Landlock (Linux < 5.13 or disabled)"
)


@landlock_only
def test_landlock_confines_reads_and_writes_for_any_uid(bypass, tmp_path, monkeypatch):
    # as if not root (no uid drop): before Landlock, the child could read every world-readable file
    monkeypatch.setattr(sandbox_process, "drop_ids", lambda: None)
    outside = tmp_path / "hidden_eval.json"
    outside.write_text("{}")
    outside.chmod(0o644)
    target = tmp_path / "pwned.txt"
    repo_file = Path(__file__).resolve().parents[2] / "rle_tasks" / "__init__.py"
    with Sandbox(bypass, limits=FAST) as box:
        assert box.layers["landlock"] and not box.layers["uid_drop"]
        assert box.call("raw_read", str(outside)) == [-1, errno.EACCES]
        assert box.call("raw_read", str(repo_file)) == [-1, errno.EACCES]  # the verifier package
        assert box.call("raw_write", str(target)) == [-1, errno.EACCES]
        assert box.call("raw_read", "/proc/self/status")[0] >= 0  # its own /proc entry stays readable
        if landlock_abi() >= 6:  # signal scoping: the parent is outside the sandbox's domain
            assert box.call("raw_kill_parent") == [-1, errno.EPERM]
    assert not target.exists()


@landlock_only
def test_landlock_keeps_the_numeric_stack_and_the_toolkit_importable(tmp_path):
    module = tmp_path / "heavy.py"
    module.write_text(
        "import numpy, scipy.linalg, mujoco, onnxruntime\n"
        "import rle_design.kinematics\n"
        "def f():\n    return float(numpy.linalg.det(numpy.eye(3)))\n"
    )
    with Sandbox(module, limits=SandboxLimits(call_timeout_s=10.0, startup_timeout_s=60.0)) as box:
        assert box.layers["landlock"] and box.call("f") == 1.0
