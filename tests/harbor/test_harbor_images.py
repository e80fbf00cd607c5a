"""The exported images, built and run: the toolkit imports in the agent's image (pinocchio needs
libgomp1) and the verifier package does not exist there; the verifier's image imports the verifier.

Needs a running Docker daemon and the base image (``scripts/harbor_e2e_setup.sh`` provides both on
this machine kind); skipped with its reason otherwise. Image layers are shared between the two images
and cached by Docker, so only a first build is long.
"""

from __future__ import annotations

import json
import shutil
import subprocess
from pathlib import Path

import pytest

from rle_tasks.core.export.harbor.export import export_harbor
from rle_tasks.core.export.harbor.images import base_image


def _docker_ready() -> str | None:
    if shutil.which("docker") is None:
        return "no docker CLI"
    if subprocess.run(["docker", "info"], capture_output=True).returncode != 0:
        return "no running Docker daemon (scripts/harbor_e2e_setup.sh starts one)"
    if subprocess.run(["docker", "image", "inspect", base_image()], capture_output=True).returncode != 0:
        return f"no base image {base_image()} (scripts/harbor_e2e_setup.sh builds it)"
    return None


pytestmark = pytest.mark.skipif(_docker_ready() is not None, reason=str(_docker_ready()))


def _build(context, tag: str) -> None:
    done = subprocess.run(["docker", "build", "-q", "-t", tag, str(context)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr[-3000:]


def _run(tag: str, code: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        ["docker", "run", "--rm", tag, "python3", "-c", code], capture_output=True, text=True
    )


def test_agent_and_verifier_images_import_what_they_must(tmp_path):
    (task,) = export_harbor(tmp_path, ["09-gello"])
    _build(task / "environment", "rle-test-agent:09")
    _build(task / "tests", "rle-test-verifier:09")
    try:
        agent = _run("rle-test-agent:09", "import rle_design.kinematics, pinocchio; print('ok')")
        assert agent.returncode == 0 and agent.stdout.strip().endswith("ok"), agent.stderr[-2000:]
        hidden = _run("rle-test-agent:09", "import rle_tasks")
        assert hidden.returncode != 0 and "No module named 'rle_tasks'" in hidden.stderr
        verifier = _run(
            "rle-test-verifier:09",
            "import rle_tasks.core.export.harbor.reward, rle_tasks.f09_gello.verifier, pinocchio; print('ok')",
        )
        assert verifier.returncode == 0 and verifier.stdout.strip().endswith("ok"), verifier.stderr[-2000:]
        probe = _run("rle-test-verifier:09", SANDBOX_PROBE)
        assert probe.returncode == 0, probe.stderr[-2000:]
        seen = json.loads(probe.stdout.strip().splitlines()[-1])
        assert seen["read"] == seen["list"] == "PermissionError", seen  # Landlock: EACCES on the package
        assert seen["import"] == "ImportError" and seen["toolkit"] == "ok", seen
        assert "/opt/rle-bench" in seen["sys_path"] or seen["editable"], (
            seen
        )  # the package is installed there
    finally:
        subprocess.run(
            ["docker", "rmi", "-f", "rle-test-agent:09", "rle-test-verifier:09"], capture_output=True
        )


SANDBOX_PROBE = (Path(__file__).parent / "sandbox_probe.py").read_text()
"""A sandboxed submission in the verifier's image (as root, as ``harbor.reward`` runs) tries to read,
list and import the verifier package, then imports the public toolkit (``sandbox_probe.py``)."""

BASE_COMPOSE = """services:
  main:
    build:
      context: .
    command: ["sh", "-c", "sleep infinity"]
"""
"""What Harbor's docker environment adds for ``main`` (its build file), for a compose run without Harbor."""

AGENT_CHECK = r"""
import glob, json, os
out = {"uid": os.getuid(), "rle_env": sorted(k for k in os.environ if k.startswith("RLE_"))}
leaks = []
for path in glob.glob("/proc/[0-9]*/environ"):
    try:
        if b"isolation-check-secret" in open(path, "rb").read():
            leaks.append(path)
    except OSError:
        pass
out["environ_leaks"] = leaks
out["ledger_dir_visible"] = os.path.exists("/rle-ledger")
import sys
sys.path.insert(0, "/workspace")
{use}
print(json.dumps(out))
"""
METERED_USE = """
from client import connect
with connect() as env:
    env.reset()
    env.step([0.0] * env.info()["action_size"])
    out["charged"] = env.info()["steps_used"]
    env.seal()
"""
POSE_USE = """
from pose_client import connect
with connect() as dev:
    assert dev.frames(0, n=1)  # labelled frames of a public seed: free
    out["charged"] = dev.info()["evaluations_used"]
    dev.seal()
"""
STANDIN_USE = """
from standin_client import connect
with connect() as dev:
    out["charged"] = dev.info()["episodes_used"]  # evaluations are charged; none was asked for
    dev.seal()
"""
USES = {"03-cantilever": (METERED_USE, 2), "01-open-fridge-l3": (METERED_USE, 2), "02-group-01": (METERED_USE, 2),
        "06-pose-b-rgbd": (POSE_USE, 0), "05-robotwin-open": (STANDIN_USE, 0)}  # fmt: skip
"""How the agent's user uses each task's development client in the check, and what it is charged."""


@pytest.mark.parametrize("task_id", sorted(USES))
def test_the_agents_container_reaches_the_sidecar_and_not_its_secrets(tmp_path, task_id):
    """In the built environment: the agent's user connects, resets, steps and seals through the
    workspace's client; no RLE_ variable, no process environment and no /rle-ledger of the sidecar is
    visible from ``main``; the sidecar holds the sealed ledger of its attempt."""
    import json
    import os

    from rle_tasks.core.export.harbor.export import not_exportable
    from rle_tasks.core.registry import get_task

    if why := not_exportable(get_task(task_id)):
        pytest.skip(f"{task_id} is not exported here: {why}")
    (task,) = export_harbor(tmp_path, [task_id])
    env_dir = task / "environment"
    (env_dir / "base-compose.yaml").write_text(BASE_COMPOSE)
    project = f"rle-iso-{task_id}".replace(".", "-")
    compose = ["docker", "compose", "--project-name", project, "--project-directory", str(env_dir),
               "-f", str(env_dir / "base-compose.yaml"), "-f", str(env_dir / "docker-compose.yaml")]  # fmt: skip
    env = {**os.environ, "RLE_SECRET": "isolation-check-secret-123"}
    try:
        up = subprocess.run(
            [*compose, "up", "-d", "--build", "--wait"], capture_output=True, text=True, env=env
        )
        assert up.returncode == 0, up.stderr[-3000:]
        agent = subprocess.run(
            [
                *compose,
                "exec",
                "-T",
                "-u",
                "1000",
                "main",
                "python3",
                "-c",
                AGENT_CHECK.replace("{use}", USES[task_id][0]),
            ],
            capture_output=True,
            text=True,
            env=env,
        )
        assert agent.returncode == 0, agent.stderr[-3000:]
        seen = json.loads(agent.stdout.strip().splitlines()[-1])
        public = sorted(d.env for d in get_task(task_id).harbor_data)  # where a built dataset lies
        assert seen["uid"] == 1000 and seen["rle_env"] == public and seen["environ_leaks"] == []
        assert not seen["ledger_dir_visible"] and seen["charged"] == USES[task_id][1]
        sealed = subprocess.run(
            [*compose, "exec", "-T", "dev", "python3", "-m", "rle_tasks.core.export.harbor.sidecar", "seal"],
            capture_output=True,
            text=True,
            env=env,
        )
        assert sealed.returncode == 0 and "(sealed: True)" in sealed.stdout, sealed.stdout + sealed.stderr
    finally:
        subprocess.run([*compose, "down", "-v", "--rmi", "local"], capture_output=True, env=env)
