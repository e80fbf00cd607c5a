"""The exported ``tests/test.sh`` as an operator and an attacker see it: a private secret is required,
a verifier fault writes no reward, and code run by the verifier cannot plant or change the reward.

``test.sh`` runs with ``/logs`` redirected to a world-traversable temporary directory and a stand-in
``rle`` command first on PATH (the real verifiers take minutes). For the hostile case the stand-in runs
a real ``Sandbox`` on a submission that calls libc directly (bypassing the audit hook) to create
``reward.txt``, ``reward.json`` and a ``reward.json`` symlink in ``/logs/verifier``.
"""

from __future__ import annotations

import errno
import json
import os
import shutil
import subprocess
import sys
import tempfile
import tomllib
from pathlib import Path

import pytest

from rle_design.paths import REPO_ROOT

root_only = pytest.mark.skipif(os.geteuid() != 0, reason="test.sh runs as root in the verifier container")

REPORT = {
    "task_id": "T",
    "score": 0.25,
    "secret": "private",
    "checkpoints": [{"id": "validity", "score": 1.0}, {"id": "reward", "score": 0.5}],
}

FAKE_RLE = """#!{python}
# Stand-in for `rle verify TASK DIR --json REPORT --jobs N`.
import json, os, sys
from pathlib import Path
args = sys.argv[1:]
report_path = Path(args[args.index("--json") + 1])
Path(os.environ["FAKE_RLE_MARK"]).write_text("called")
mode = os.environ["FAKE_RLE_MODE"]
report = json.loads(os.environ["FAKE_RLE_REPORT"])
if mode == "hostile":
    from rle_design.sandbox import Sandbox
    with Sandbox(Path(os.environ["FAKE_RLE_HOSTILE"])) as box:
        report["native_metrics"] = box.call("plant", os.environ["FAKE_RLE_TARGET"])
if mode != "no_report":
    report_path.write_text(json.dumps(report))
if mode == "crash":
    raise RuntimeError("verifier bug")
sys.exit(1 if mode == "status_1" else 0)
"""

HOSTILE = """
import ctypes, os

libc = ctypes.CDLL(None, use_errno=True)

def _open(path):
    fd = libc.open(path.encode(), os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o666)
    if fd >= 0:
        libc.write(fd, b"1.0", 3)
        libc.close(fd)
    return ctypes.get_errno() if fd < 0 else 0

def plant(verifier_dir):
    out = {"txt": _open(verifier_dir + "/reward.txt"), "json": _open(verifier_dir + "/reward.json")}
    ret = libc.symlink(b"/tmp/rle-planted-reward.json", (verifier_dir + "/reward.json").encode())
    out["symlink"] = ctypes.get_errno() if ret != 0 else 0
    return out
"""


@pytest.fixture
def logs():
    """``/logs`` as Harbor leaves it before verification: artifacts and verifier directory, mode 777,
    under a directory any uid can traverse (so that only the script's own closing stops ``nobody``)."""
    base = Path(tempfile.mkdtemp(prefix="rle-harbor-logs-", dir="/tmp"))
    base.chmod(0o755)
    logs = base / "logs"
    for sub in ("", "artifacts", "verifier"):
        (logs / sub).mkdir(exist_ok=True)
        (logs / sub).chmod(0o777)
    (logs / "artifacts" / "robot.xml").write_text("<mujoco/>\n")
    yield logs
    shutil.rmtree(base, ignore_errors=True)


def _run(task_dir: Path, logs: Path, tmp_path: Path, mode: str, env: dict[str, str], report=REPORT):
    bin_dir = tmp_path / "bin"
    bin_dir.mkdir(exist_ok=True)
    (bin_dir / "rle").write_text(FAKE_RLE.format(python=sys.executable))
    (bin_dir / "rle").chmod(0o755)
    if not (bin_dir / "python3").exists():
        (bin_dir / "python3").symlink_to(sys.executable)
    (tmp_path / "hostile.py").write_text(HOSTILE)
    script = tmp_path / "test.sh"
    text = (task_dir / "tests" / "test.sh").read_text()
    script.write_text(text.replace("/logs", str(logs)))
    script.chmod(0o755)
    full_env = {
        "PATH": f"{bin_dir}:{os.environ['PATH']}",
        "PYTHONPATH": str(REPO_ROOT),
        "FAKE_RLE_MODE": mode,
        "FAKE_RLE_MARK": str(tmp_path / "called"),
        "FAKE_RLE_REPORT": json.dumps(report),
        "FAKE_RLE_HOSTILE": str(tmp_path / "hostile.py"),
        "FAKE_RLE_TARGET": str(logs / "verifier"),
        **env,
    }
    return subprocess.run(["bash", str(script)], env=full_env, capture_output=True, text=True, timeout=120)


def _reward(logs: Path) -> dict | None:
    path = logs / "verifier" / "reward.json"
    return json.loads(path.read_text()) if path.is_file() else None


@pytest.fixture
def task_dir(exported):
    """A task verified from /logs/artifacts alone (the sidecar's ledger path: test_harbor_sidecar)."""
    return next(t for t in exported.values() if "--sidecar" not in (t / "tests" / "test.sh").read_text())


def test_secret_has_no_default(exported):
    for task_dir in exported.values():
        env = tomllib.loads((task_dir / "task.toml").read_text())["verifier"]["env"]
        assert env["RLE_SECRET"] == "${RLE_SECRET}"  # Harbor refuses to resolve it when unset


@root_only
def test_refuses_to_verify_without_a_private_secret(task_dir, logs, tmp_path):
    for env in ({}, {"RLE_SECRET": ""}):
        proc = _run(task_dir, logs, tmp_path, "ok", env)
        assert proc.returncode == 1, proc.stderr
        assert "RLE_SECRET is not set: an exported RLE-Bench task verifies only with a private secret" in (
            proc.stderr
        )
        assert not (tmp_path / "called").exists() and _reward(logs) is None
    # An explicit smoke test with the public key is possible, and the reward says so.
    public = {**REPORT, "secret": "public"}
    proc = _run(task_dir, logs, tmp_path, "ok", {"RLE_SECRET": "", "RLE_ALLOW_PUBLIC_KEY": "1"}, public)
    assert proc.returncode == 0, proc.stderr
    assert _reward(logs) == {"reward": 0.25, "secret_private": 0.0, "validity": 1.0, "checkpoint_reward": 0.5}


@root_only
def test_private_secret_gives_the_report_score(task_dir, logs, tmp_path):
    proc = _run(task_dir, logs, tmp_path, "ok", {"RLE_SECRET": "s3cret"})
    assert proc.returncode == 0, proc.stderr
    assert _reward(logs) == {"reward": 0.25, "secret_private": 1.0, "validity": 1.0, "checkpoint_reward": 0.5}
    assert json.loads((logs / "verifier" / "report.json").read_text())["score"] == 0.25
    # a report made with the public key under a private secret is not trusted
    proc = _run(task_dir, logs, tmp_path, "ok", {"RLE_SECRET": "s3cret"}, {**REPORT, "secret": "public"})
    assert proc.returncode == 1 and "made with the public key" in proc.stderr and _reward(logs) is None


@root_only
@pytest.mark.parametrize("mode", ["status_1", "no_report", "crash"])
def test_verifier_fault_writes_no_reward(task_dir, logs, tmp_path, mode):
    (logs / "verifier" / "reward.txt").write_text("1.0")  # stale file from an earlier run
    proc = _run(task_dir, logs, tmp_path, mode, {"RLE_SECRET": "s3cret"})
    assert (tmp_path / "called").exists()
    assert (
        not (logs / "verifier" / "reward.json").exists() and not (logs / "verifier" / "reward.txt").exists()
    )
    assert proc.returncode != 0 and "rle-bench verifier error:" in proc.stderr


@root_only
def test_hostile_submission_cannot_plant_the_reward(task_dir, logs, tmp_path):
    (logs / "verifier" / "reward.txt").write_text("1.0")  # stale, planted before verification
    proc = _run(task_dir, logs, tmp_path, "hostile", {"RLE_SECRET": "s3cret"})
    assert proc.returncode == 0, proc.stderr + proc.stdout
    assert _reward(logs) == {"reward": 0.25, "secret_private": 1.0, "validity": 1.0, "checkpoint_reward": 0.5}
    report = json.loads((logs / "verifier" / "report.json").read_text())
    # every attempt ran in the sandbox as nobody and was refused by the kernel
    assert report["native_metrics"] == {"txt": errno.EACCES, "json": errno.EACCES, "symlink": errno.EACCES}
    verifier = logs / "verifier"
    assert sorted(p.name for p in verifier.iterdir()) == ["report.json", "reward.json", "verify.log"]
    assert not (verifier / "reward.json").is_symlink()
    assert _reward(logs) == {"reward": 0.25, "secret_private": 1.0, "validity": 1.0, "checkpoint_reward": 0.5}
    assert not Path("/tmp/rle-planted-reward.json").exists()
