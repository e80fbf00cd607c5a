"""Harbor export: task.toml fields (tomllib), files and scripts, reference solution, errors."""

import dataclasses
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import tomllib
from pathlib import Path

import pytest

from rle_design.errors import RleError
from rle_tasks.core.export.harbor.export import export_harbor
from rle_tasks.core.registry import get_task
from rle_tasks.core.report import Checkpoint, VerifierReport, artifact_sha256
from rle_tasks.core.task import ArtifactContract, Budget, TaskSpec

# Harbor's package-name rule (harbor.constants.ORG_NAME_PATTERN in 0.25).
ORG_NAME = re.compile(r"^[a-zA-Z0-9][a-zA-Z0-9._-]*/[a-zA-Z0-9][a-zA-Z0-9._-]*$")


def _verify(directory, ctx):  # pragma: no cover - never called by the export
    raise AssertionError("export must not run the verifier")


FAKE_FAMILY = "harbor_fake_family"
_DECLARATION = """
from rle_tasks.core.solutions import Solution, SolutionSet

SOLUTIONS = SolutionSet(
    package="harbor_fake_family",
    solutions=(
        Solution("reference", sha256="{sha}", quick_score=0.0, files=((".", "solutions/reference"),)),
        Solution("baseline/box", sha256="{sha}", quick_score=0.0, base="reference"),
    ),
)
"""


@pytest.fixture
def spec(tmp_path, monkeypatch):
    """A task whose solutions are declared by a small family package in ``tmp_path``."""
    pkg = tmp_path / "pkgs" / FAKE_FAMILY
    ref = pkg / "solutions" / "reference"
    ref.mkdir(parents=True)
    (pkg / "__init__.py").write_text("")
    (ref / "base.xml").write_text("<mujoco/>\n")
    (pkg / "solutions" / "__init__.py").write_text(_DECLARATION.format(sha=artifact_sha256(ref)))
    monkeypatch.syspath_prepend(str(tmp_path / "pkgs"))
    yield TaskSpec(
        id="08-mobile-base",
        family=8,
        title='Universal mobile-manipulator base ("test" spec)',
        instruction="Design a base.\n",
        budget=Budget(
            wall_time_s=7200.0, cpus=4, gpus=0, memory_mb=8192, steps=5000, verifier_timeout_s=1800.0
        ),
        contract=ArtifactContract(
            required=("base.xml",), optional=("meshes/*.stl",), description="One MJCF."
        ),
        verify=_verify,
        solutions=("reference", "baseline/box"),
        solutions_module=f"{FAKE_FAMILY}.solutions",
    )
    for name in [m for m in sys.modules if m.startswith(FAKE_FAMILY)]:
        del sys.modules[name]


def test_task_toml_fields(tmp_path, spec):
    (task_dir,) = export_harbor(tmp_path / "out", [spec])
    assert task_dir == tmp_path / "out" / "08-mobile-base"
    cfg = tomllib.loads((task_dir / "task.toml").read_text())
    assert cfg["schema_version"] == "1.4"
    assert cfg["task"]["name"] == "rle-bench/08-mobile-base" and ORG_NAME.match(cfg["task"]["name"])
    assert cfg["task"]["description"] == 'Universal mobile-manipulator base ("test" spec)'
    # never root (harbor lint root-agent); offline while working
    assert cfg["agent"] == {"timeout_sec": 7200, "user": "agent", "network_mode": "no-network"}
    assert cfg["verifier"]["network_mode"] == "no-network"
    assert cfg["verifier"]["timeout_sec"] == 1800
    assert cfg["verifier"]["environment_mode"] == "separate"
    assert cfg["verifier"]["env"] == {
        "RLE_SECRET": "${RLE_SECRET}",
        "RLE_ALLOW_PUBLIC_KEY": "${RLE_ALLOW_PUBLIC_KEY:-0}",
        "RLE_ORACLE_PRIVILEGED": "${RLE_ORACLE_PRIVILEGED:-0}",
        "RLE_VERIFY_QUICK": "${RLE_VERIFY_QUICK:-0}",
    }
    venv = cfg["verifier"]["environment"]
    assert (venv["cpus"], venv["memory_mb"], venv["gpus"]) == (
        4,
        8192,
        0,
    )  # CPU-only, whatever the agent gets
    env = cfg["environment"]
    assert (env["cpus"], env["memory_mb"], env["gpus"]) == (4, 8192, 0)
    assert env["network_mode"] == "public"  # container start and agent setup only
    assert cfg["metadata"]["required_artifacts"] == ["base.xml"]
    assert cfg["metadata"]["interaction_steps"] == 5000
    assert set(cfg) == {"schema_version", "task", "metadata", "agent", "verifier", "environment"}


def test_files_images_and_scripts(tmp_path, spec):
    (task_dir,) = export_harbor(tmp_path / "out", [spec])
    instr = (task_dir / "instruction.md").read_text()
    assert instr.startswith('# Universal mobile-manipulator base ("test" spec)\n\nDesign a base.\n')
    assert "`/logs/artifacts/`" in instr and "Required files: `base.xml`" in instr
    assert "5000 charged interaction steps" in instr

    agent_df = (task_dir / "environment" / "Dockerfile").read_text()
    assert agent_df.startswith("FROM python:3.11-slim")
    assert (
        "pip install --no-deps robosuite==1.5.2" in agent_df and "ENV PYTHONPATH=/opt/rle-bench" in agent_df
    )
    assert "libegl1" in agent_df and "libosmesa6" in agent_df
    assert (
        "useradd --create-home --uid 1000 agent" in agent_df
        and "chown -R agent /workspace /logs/artifacts" in agent_df
    )
    snap = task_dir / "environment" / "rle-bench"
    assert (snap / "rle_design" / "catalogs" / "profiles.yaml").is_file() and not (
        snap / "rle_tasks"
    ).exists()
    assert (task_dir / "environment" / "workspace" / "instruction.md").read_text() == "Design a base.\n"
    assert not list(snap.rglob("__pycache__"))

    verifier_df = (task_dir / "tests" / "Dockerfile").read_text()
    assert "COPY test.sh /tests/test.sh" in verifier_df
    assert (task_dir / "tests" / "rle-bench" / "pyproject.toml").is_file()
    test_sh = task_dir / "tests" / "test.sh"
    assert os.access(test_sh, os.X_OK)
    text = test_sh.read_text()
    assert (
        'exec python3 -m rle_tasks.core.export.harbor.reward 08-mobile-base --logs "$LOGS" --jobs "$JOBS"'
        in text
    )
    assert "JOBS=$(( $(nproc) < 4 ? $(nproc) : 4 ))" in text  # the task's CPU budget caps the workers
    assert subprocess.run(["bash", "-n", str(test_sh)], capture_output=True).returncode == 0

    solve = task_dir / "solution" / "solve.sh"
    assert os.access(solve, os.X_OK) and "cp -r /solution/reference/. /logs/artifacts/" in solve.read_text()
    assert (task_dir / "solution" / "reference" / "base.xml").read_text() == "<mujoco/>\n"


def test_reward_from_a_real_report():
    from rle_tasks.core.export.harbor.reward import reward_from_report

    checkpoints = (Checkpoint("validity", 0.25, 1.0, True), Checkpoint("reward", 0.75, 0.5, False))
    report = VerifierReport(
        "08-mobile-base", "08", "mechanical_design", score=0.625, valid=True, checkpoints=checkpoints
    )
    reward = reward_from_report(json.loads(report.to_json()), secret_private=True)
    assert reward == {"reward": 0.625, "secret_private": 1.0, "validity": 1.0, "checkpoint_reward": 0.5}


def test_base_image_can_be_pinned(tmp_path, spec, monkeypatch):
    monkeypatch.setenv("RLE_HARBOR_BASE_IMAGE", "python:3.11-slim-bookworm@sha256:" + "0" * 64)
    (task_dir,) = export_harbor(tmp_path, [spec])
    for df in ("environment/Dockerfile", "tests/Dockerfile"):
        assert (task_dir / df).read_text().startswith("FROM python:3.11-slim-bookworm@sha256:000")


def test_re_export_replaces_and_foreign_directory_is_kept(tmp_path, spec):
    out = tmp_path / "out"
    export_harbor(out, [spec])
    (out / "08-mobile-base" / "stale.txt").write_text("x")
    export_harbor(out, [spec])
    assert not (out / "08-mobile-base" / "stale.txt").exists()
    foreign = tmp_path / "o2" / "08-mobile-base"
    foreign.mkdir(parents=True)
    with pytest.raises(RleError, match="exists and is not a Harbor task directory"):
        export_harbor(tmp_path / "o2", [spec])
    assert foreign.is_dir()


def test_unimplemented_unsupported_and_unknown_ids_are_refused(tmp_path):
    with pytest.raises(RleError) as exc:
        export_harbor(tmp_path, ["04-run"])
    assert exc.value.code == "harbor.unimplemented"
    assert str(exc.value).startswith(
        "task '04-run' is registered but not implemented (no verifier), so it cannot be exported. "
        "Implemented tasks: "
    )
    unsupported = dataclasses.replace(get_task("09-gello"), harbor_unsupported="it needs a robot arm")
    with pytest.raises(RleError) as exc:
        export_harbor(tmp_path, [unsupported])
    assert exc.value.code == "harbor.unsupported"
    assert str(exc.value) == "task '09-gello' cannot be exported as a Harbor task yet: it needs a robot arm"
    with pytest.raises(RleError, match="task '01-open-fridg-l1' does not exist"):
        export_harbor(tmp_path, ["01-open-fridg-l1"])


def test_default_exports_every_implemented_task_that_can_be_exported(exported, tmp_path, monkeypatch):
    """The default selection is every implemented task that can be exported here, in registry order.
    The shared export (``exported``) already wrote all of them but those whose images hold a built
    dataset; only those are exported again here (a full export takes a minute on a loaded machine)."""
    from rle_tasks.core.export.harbor import export as export_module
    from rle_tasks.core.export.harbor.export import not_exportable
    from rle_tasks.core.registry import all_tasks

    implemented = [t.id for t in all_tasks() if t.implemented and not not_exportable(t)]
    assert "09-gello" in implemented and "05-robotwin-open" in {t.id for t in all_tasks() if t.implemented}
    done = {tid: path for tid, path in exported.items() if tid in implemented}
    fresh = export_module.export_task

    def export_task(spec, out, root=None):
        return done[spec.id] if spec.id in done else fresh(spec, out, root)

    monkeypatch.setattr(export_module, "export_task", export_task)
    written = export_harbor(tmp_path, None)
    assert [p.name for p in written] == implemented
    assert all((p / "task.toml").is_file() for p in written)


def test_cli_export_of_unimplemented_task_exits_2(tmp_path, capsys):
    from rle_tasks.cli import main

    assert main(["export", "harbor", str(tmp_path), "--tasks", "04-run"]) == 2
    err = capsys.readouterr().err
    assert err.startswith(
        "rle export: error [harbor.unimplemented]: task '04-run' is registered but not implemented"
    )


@pytest.mark.skipif(os.geteuid() != 0 or shutil.which("setpriv") is None, reason="needs root and setpriv")
def test_solve_sh_copies_into_an_artifacts_directory_of_another_uid(tmp_path, spec):
    """Harbor mounts /logs/artifacts owned by another uid; the oracle (not root) must still copy into it."""
    (task_dir,) = export_harbor(tmp_path / "out", [spec])
    base = Path(tempfile.mkdtemp(prefix="rle-solve-", dir="/tmp"))
    try:
        base.chmod(0o755)
        shutil.copytree(task_dir / "solution", base / "solution")
        for p in [base / "solution", *(base / "solution").rglob("*")]:
            p.chmod(0o755 if p.is_dir() else 0o644)
        artifacts = base / "logs" / "artifacts"
        artifacts.mkdir(parents=True)
        artifacts.chmod(0o777)  # root-owned, writable by all, as a mounted directory of another uid
        (base / "logs").chmod(0o755)
        script = (task_dir / "solution" / "solve.sh").read_text()
        script = script.replace("/solution/", f"{base}/solution/").replace("/logs/", f"{base}/logs/")
        proc = subprocess.run(
            ["setpriv", "--reuid=65534", "--regid=65534", "--clear-groups", "bash", "-c", script],
            capture_output=True,
            text=True,
        )
        assert proc.returncode == 0, proc.stderr
        assert (artifacts / "base.xml").read_text() == "<mujoco/>\n"
    finally:
        shutil.rmtree(base, ignore_errors=True)


def test_jobs_follow_the_cpu_budget(tmp_path, spec):
    (task_dir,) = export_harbor(tmp_path / "out", [spec])
    line = next(
        ln for ln in (task_dir / "tests" / "test.sh").read_text().splitlines() if ln.startswith("JOBS=")
    )
    for cores, expected in ((64, 4), (2, 2)):
        shell = f"nproc() {{ echo {cores}; }}; {line}; echo $JOBS"
        assert subprocess.run(["bash", "-c", shell], capture_output=True, text=True).stdout.strip() == str(
            expected
        )


SLIDER = """<mujoco><worldbody><body><joint name="x" type="slide"/><geom size="0.1" mass="1"/></body>
</worldbody><actuator><motor joint="x"/></actuator></mujoco>"""


def _metered_dev_env(workspace):
    from rle_design.ledger import MeteredEnv

    (Path(workspace) / "helpers.py").write_text("X = 1\n")
    return MeteredEnv(SLIDER, n_substeps=5)


def test_a_metered_dev_env_is_served_by_the_sidecar(tmp_path):
    """The ledger server needs a key derived from the secret: it runs in the sidecar ``dev``, and the
    workspace's client reaches it through the socket in the shared workspace."""
    spec = TaskSpec(
        "07-metered",
        7,
        "metered",
        verify=_verify,
        budget=Budget(wall_time_s=60.0, steps=100),
        make_dev_env=_metered_dev_env,
    )
    (task_dir,) = export_harbor(tmp_path / "out", [spec])
    ws = task_dir / "environment" / "workspace"
    assert sorted(p.name for p in ws.iterdir()) == ["client.py", "helpers.py", "instruction.md"]
    assert "runs beside the agent as the compose service `dev`" in (task_dir / "README.md").read_text()
    assert (task_dir / "environment" / "docker-compose.yaml").is_file()
    assert (
        "python3 -m rle_tasks.core.export.harbor.sidecar serve 07-metered"
        in (task_dir / "environment" / "dev" / "Dockerfile").read_text()
    )
