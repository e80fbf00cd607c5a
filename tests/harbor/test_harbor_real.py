"""The export checked by the real ``harbor`` 0.25 package (Python >= 3.12, side venv ``make
harbor-venv`` or ``RLE_HARBOR_PYTHON``): for every implemented task, ``TaskConfig`` and ``Task`` load,
``harbor lint`` passes (all rules once the base image is pinned by digest), Harbor refuses to resolve
the verifier environment without ``RLE_SECRET``, and the per-phase network plan is public for setup and
offline for the agent and verifier phases. Skipped, with the reason, when no such interpreter exists.

Every task goes through one exporter and one template, so the reduced form (``make test``) checks one
task per family (harbor lints a task in about 3 s; all 42 three times took 7 minutes);
``RLE_FULL_BATTERY=1`` checks every implemented task."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
from pathlib import Path

import pytest

from rle_design.paths import REPO_ROOT

CHECK = r"""
import json, os, sys
from harbor.models.task.config import TaskConfig
from harbor.models.task.task import Task
from harbor.models.trial.config import AgentConfig, EnvironmentConfig, VerifierConfig
from harbor.models.task.config import VerifierEnvironmentMode
from harbor.models.task.verifier_mode import resolve_effective_verifier_env_config
from harbor.trial.network_policy import resolve_trial_network_plan
from harbor.utils.env import resolve_env_vars

out = {}
for task_dir in sys.argv[1:]:
    task = Task(task_dir)
    cfg = TaskConfig.model_validate_toml(open(os.path.join(task_dir, "task.toml")).read())
    os.environ.pop("RLE_SECRET", None)
    try:
        resolve_env_vars(cfg.verifier.env)
        refused = None
    except ValueError as exc:
        refused = str(exc)
    plan = resolve_trial_network_plan(
        cfg, AgentConfig(), EnvironmentConfig(), VerifierConfig(), None,
        verifier_mode=VerifierEnvironmentMode.SEPARATE,
    )
    out[task.name] = {
        "mode": cfg.verifier.environment_mode.value,
        "resources": [cfg.environment.cpus, cfg.environment.memory_mb, cfg.environment.gpus],
        "verifier_gpus": resolve_effective_verifier_env_config(cfg, None).gpus,
        "refused": refused,
        "network": {
            "agent_setup": plan.agent_env_baseline.network_mode.value,
            "agent": plan.agent_phase.network_mode.value,
            "verifier": plan.verifier_phase.network_mode.value,
        },
    }
print(json.dumps(out))
"""


def _harbor_python() -> Path:
    path = Path(os.environ.get("RLE_HARBOR_PYTHON") or REPO_ROOT / ".venv-harbor" / "bin" / "python")
    if not path.exists():
        pytest.skip(
            f"no Harbor interpreter at {path}: harbor 0.25 needs Python >= 3.12 (run `make harbor-venv` "
            "or set RLE_HARBOR_PYTHON)"
        )
    probe = subprocess.run([str(path), "-c", "import harbor"], capture_output=True, text=True)
    if probe.returncode != 0:
        pytest.skip(f"{path} cannot import harbor: {probe.stderr.strip().splitlines()[-1:]}")
    return path


FULL = os.environ.get("RLE_FULL_BATTERY") == "1"


def _checked_ids() -> list[str]:
    """Every task of the shared export (``conftest.exported_specs``) with RLE_FULL_BATTERY=1; otherwise
    the first of each family."""
    from rle_tasks.core.export.harbor.export import not_exportable
    from rle_tasks.core.registry import all_tasks

    tasks = [t for t in all_tasks() if t.implemented and not not_exportable(t) and not t.harbor_data]
    return [t.id for t in tasks] if FULL else list({t.family: t.id for t in reversed(tasks)}.values())


@pytest.fixture(scope="module")
def checked(exported):
    """The exported task directories these checks run on."""
    return {name: path for name, path in exported.items() if name in _checked_ids()}


@pytest.fixture(scope="module")
def pinned_export(tmp_path_factory):
    """The first checked task (every one with RLE_FULL_BATTERY=1), exported with a digest-pinned base
    image (the form lint asks for); the others share its image template."""
    from rle_tasks.core.export.harbor.export import export_harbor

    out = tmp_path_factory.mktemp("pinned")
    mp = pytest.MonkeyPatch()
    mp.setenv("RLE_HARBOR_BASE_IMAGE", "python:3.11-slim-bookworm@sha256:" + "ab" * 32)
    try:
        return {p.name: p for p in export_harbor(out, _checked_ids() if FULL else _checked_ids()[:1])}
    finally:
        mp.undo()


def test_harbor_loads_the_tasks_and_plans_the_network(checked):
    python = _harbor_python()
    from rle_tasks.core.registry import get_task

    assert checked and len(checked) == len(_checked_ids())
    proc = subprocess.run(
        [str(python), "-c", CHECK, *map(str, checked.values())], capture_output=True, text=True, timeout=600
    )
    assert proc.returncode == 0, proc.stderr
    result = json.loads(proc.stdout.strip().splitlines()[-1])
    for spec in map(get_task, _checked_ids()):
        got = result[f"rle-bench/{spec.id}"]
        assert got["mode"] == "separate"
        assert got["resources"] == [spec.budget.cpus, spec.budget.memory_mb, spec.budget.gpus]
        assert got["verifier_gpus"] == 0  # the separate verifier container asks for no GPU
        assert got["refused"] == "Environment variable 'RLE_SECRET' not found in host environment"
        assert got["network"] == {"agent_setup": "public", "agent": "no-network", "verifier": "no-network"}


def test_harbor_lint_passes(checked, pinned_export):
    compose = (
        subprocess.run(["docker", "compose", "version"], capture_output=True)
        if shutil.which("docker")
        else None
    )
    if compose is None or compose.returncode != 0:
        pytest.skip(
            "harbor lint reads the exported compose files with the Docker CLI and its Compose plugin, which this "
            "machine lacks (`make harbor-venv` installs the plugin where a docker CLI exists)"
        )
    python = _harbor_python()
    harbor = [str(python), "-m", "harbor.cli.main"]
    if subprocess.run([*harbor, "--help"], capture_output=True).returncode != 0:
        harbor = [str(Path(python).parent / "harbor")]
    # Harbor's lint walks every file of a task (about 4 s a task). The default rules and the pinned
    # export run on one task (every one with RLE_FULL_BATTERY=1); on the others their results follow
    # from the run of all rules below, whose only finding, the unpinned base image, is one the
    # default rules leave out and the digest removes (the tasks share one image template).
    some = list(map(str, checked.values()))[: None if FULL else 1]
    default = subprocess.run([*harbor, "lint", *some], capture_output=True, text=True)
    assert default.returncode == 0, default.stdout + default.stderr
    every = subprocess.run(
        [*harbor, "lint", "--select", "ALL", *map(str, pinned_export.values())],
        capture_output=True,
        text=True,
    )
    assert every.returncode == 0, every.stdout + every.stderr
    # without a digest, the only finding of all rules is the unpinned base image of the two images
    unpinned = subprocess.run(
        [*harbor, "lint", "--select", "ALL", "--json", *map(str, checked.values())],
        capture_output=True,
        text=True,
    )
    rules = {f["rule"] for f in json.loads(unpinned.stdout)}
    assert rules == {"unpinned-image"}
