"""The exported images, built and run: the toolkit imports in the agent's image (pinocchio needs
libgomp1) and the verifier package does not exist there; the verifier's image imports the verifier.

Needs a running Docker daemon and the base image (``scripts/harbor_e2e_setup.sh`` provides both on
this machine kind); skipped with its reason otherwise. Image layers are shared between the two images
and cached by Docker, so only a first build is long.
"""

from __future__ import annotations

import shutil
import subprocess

import pytest

from rle_tasks.core.harbor import export_harbor
from rle_tasks.core.harbor_images import base_image


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
            "import rle_tasks.core.harbor_reward, rle_tasks.f09_gello.verifier, pinocchio; print('ok')",
        )
        assert verifier.returncode == 0 and verifier.stdout.strip().endswith("ok"), verifier.stderr[-2000:]
    finally:
        subprocess.run(
            ["docker", "rmi", "-f", "rle-test-agent:09", "rle-test-verifier:09"], capture_output=True
        )
