"""The sandbox under Docker's default capability set: no CAP_SYS_ADMIN, so ``unshare(CLONE_NEWNET)``
fails with EPERM. The child still starts, the remaining kernel layers hold, the missing layer is
reported (``Sandbox.layers``, ``probe_layers``, the verifier report), and the submission is not blamed.

With ``capsh`` the parent really runs without the capabilities Docker withholds; without it the
refusal is simulated by a bootstrap copy whose ``unshare`` call returns EPERM.
"""

from __future__ import annotations

import errno
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from rle_design.paths import REPO_ROOT
from rle_design.sandbox import ParticipantFault, Sandbox, SandboxLimits, landlock_abi
from rle_design.sandbox import process as sandbox_process

DOCKER_DEFAULT = {
    "cap_chown", "cap_dac_override", "cap_fowner", "cap_fsetid", "cap_kill", "cap_setgid", "cap_setuid",
    "cap_setpcap", "cap_net_bind_service", "cap_net_raw", "cap_sys_chroot", "cap_mknod", "cap_audit_write",
    "cap_setfcap",
}  # fmt: skip
"""Capabilities a container gets from Docker by default (moby's oci/caps/defaults.go)."""
ALL_CAPS = [
    "cap_dac_read_search",
    "cap_linux_immutable",
    "cap_net_broadcast",
    "cap_net_admin",
    "cap_ipc_lock",
    "cap_ipc_owner",
    "cap_sys_module",
    "cap_sys_rawio",
    "cap_sys_ptrace",
    "cap_sys_pacct",
    "cap_sys_admin",
    "cap_sys_boot",
    "cap_sys_nice",
    "cap_sys_resource",
    "cap_sys_time",
    "cap_sys_tty_config",
    "cap_lease",
    "cap_audit_control",
    "cap_mac_override",
    "cap_mac_admin",
    "cap_syslog",
    "cap_wake_alarm",
    "cap_block_suspend",
    "cap_audit_read",
]
DEGRADED = {
    "netns": False,
    "uid_drop": True,
    "no_new_privs": True,
    "landlock": landlock_abi() > 0,
    "nproc": True,
}
"""Docker's default capabilities: no network namespace; Landlock needs no capability."""

PROBE = """
import errno, json, sys
from pathlib import Path
from rle_design.sandbox import ParticipantFault, Sandbox, SandboxLimits, probe_layers
from rle_tasks.core.registry import get_task
from rle_tasks.core.report import VerifierReport
from rle_tasks.core.verify import _sandbox_layers

out = {"probe": probe_layers(), "report_field": _sandbox_layers()}
with Sandbox(Path(sys.argv[1]), limits=SandboxLimits(call_timeout_s=5.0)) as box:
    out["layers"] = box.layers
    out["add"] = box.call("add", 2, 3)
    out["raw_write"] = box.call("raw_write", sys.argv[2])
    out["raw_fork"] = box.call("raw_fork")
    try:
        box.call("py_socket")
    except ParticipantFault as exc:
        out["py_socket"] = exc.code
print(json.dumps(out))
"""

SUBMISSION = """
import ctypes, os

libc = ctypes.CDLL(None, use_errno=True)

def add(a, b):
    return a + b

def raw_write(path):
    return [int(libc.open(path.encode(), os.O_WRONLY | os.O_CREAT, 0o644)), ctypes.get_errno()]

def raw_fork():
    pid = libc.fork()
    if pid == 0:
        libc._exit(0)
    return [int(pid), ctypes.get_errno()]

def py_socket():
    import socket
    socket.socket()
"""

root_only = pytest.mark.skipif(os.geteuid() != 0, reason="the kernel layers need a root parent")


@pytest.fixture
def submission(tmp_path) -> Path:
    path = tmp_path / "sub" / "submission.py"
    path.parent.mkdir()
    path.write_text(SUBMISSION)
    return path


@root_only
@pytest.mark.skipif(shutil.which("capsh") is None, reason="capsh is not installed (libcap2-bin)")
def test_docker_default_capabilities(submission, tmp_path):
    target = tmp_path / "pwned.txt"
    drop = ",".join(c for c in ALL_CAPS if c not in DOCKER_DEFAULT)
    cmd = f"{sys.executable} -c '{PROBE}' {submission} {target}"
    proc = subprocess.run(
        ["capsh", f"--drop={drop}", "--", "-c", cmd],
        env={**os.environ, "PYTHONPATH": str(REPO_ROOT)},
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert proc.returncode == 0, proc.stderr
    out = json.loads(proc.stdout.strip().splitlines()[-1])
    assert out["layers"] == out["probe"] == out["report_field"] == DEGRADED
    assert out["add"] == 5
    assert out["raw_write"] == [-1, errno.EACCES]  # uid nobody still holds
    assert out["raw_fork"] == [-1, errno.EAGAIN]  # RLIMIT_NPROC still holds
    assert out["py_socket"] == "sandbox.forbidden"  # the audit hook still blocks sockets
    assert not target.exists()


@root_only
def test_simulated_unshare_refusal(submission, tmp_path, monkeypatch):
    source = sandbox_process._BOOTSTRAP.read_text()
    call = "libc.unshare(_CLONE_NEWNET) == 0"
    assert call in source
    refused = "(ctypes.set_errno(errno.EPERM) or -1) == 0"  # what the kernel answers without the cap
    bootstrap = tmp_path / "_bootstrap.py"
    bootstrap.write_text(
        source.replace(call, refused).replace("import ctypes\n", "import ctypes\nimport errno\n", 1)
    )
    monkeypatch.setattr(sandbox_process, "_BOOTSTRAP", bootstrap)
    target = tmp_path / "pwned.txt"
    with Sandbox(submission, limits=SandboxLimits(call_timeout_s=5.0)) as box:
        assert box.layers == DEGRADED
        assert box.call("add", 2, 3) == 5
        assert box.call("raw_write", str(target)) == [-1, errno.EACCES]
        with pytest.raises(ParticipantFault) as info:
            box.call("py_socket")
        assert info.value.code == "sandbox.forbidden"
    assert not target.exists()


def test_verifier_report_records_the_layers(tmp_path):
    from rle_design.sandbox import probe_layers
    from rle_tasks.core.report import VerifierReport
    from rle_tasks.core.runtime.secrets import load_secret
    from rle_tasks.core.task import TaskSpec, VerifyContext
    from rle_tasks.core.verify import run_verify

    spec = TaskSpec(
        "08-mobile-base", 8, "t", verify=lambda d, ctx: VerifierReport("08-mobile-base", "08", "")
    )
    report, internal = run_verify(spec, tmp_path, VerifyContext(secret=load_secret()))
    assert not internal and report.sandbox_layers == probe_layers()
    assert set(report.sandbox_layers) == {"netns", "uid_drop", "no_new_privs", "landlock", "nproc"}
    assert json.loads(report.to_json())["sandbox_layers"] == report.sandbox_layers


@root_only
@pytest.mark.skipif(shutil.which("capsh") is None, reason="capsh is not installed (libcap2-bin)")
def test_sandbox_suite_passes_with_docker_default_capabilities():
    """The whole sandbox suite (this test excluded) in a parent without the capabilities Docker withholds."""
    drop = ",".join(c for c in ALL_CAPS if c not in DOCKER_DEFAULT)
    here = Path(__file__).parent
    cmd = (
        f"{sys.executable} -m pytest -q -p no:cacheprovider {here} "
        "-k 'not test_sandbox_suite_passes_with_docker_default_capabilities'"
    )
    proc = subprocess.run(
        ["capsh", f"--drop={drop}", "--", "-c", cmd],
        env={**os.environ, "PYTHONPATH": str(REPO_ROOT)},
        capture_output=True,
        text=True,
        timeout=600,
        cwd=REPO_ROOT,
    )
    assert proc.returncode == 0, proc.stdout[-4000:] + proc.stderr[-2000:]
    assert " passed" in proc.stdout and " failed" not in proc.stdout
