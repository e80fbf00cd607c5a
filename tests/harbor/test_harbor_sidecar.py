"""Exported tasks with a development server: the server runs in the sidecar ``dev``, the verifier scores
its session as its attempt, and the oracles of families 01 and 03 play through it (03's only in a
privileged session the operator asked for).

The sidecar's commands run here as processes (no Docker): ``serve`` in a workspace and ledger
directory of the test's own, a client that connects as the agent's would, ``seal`` as Harbor's collect
hook runs it; ``harbor.reward --sidecar`` with a stand-in ``rle`` that records what it was asked.
"""

from __future__ import annotations

import importlib.util
import json
import os
import stat
import subprocess
import sys
import time
import tomllib
from pathlib import Path

import pytest
import yaml

from rle_design.ledger import Limits, check_ledger
from rle_design.paths import REPO_ROOT
from rle_tasks.core.export.harbor.export import export_harbor
from rle_tasks.core.runtime.devenv import ledger_key
from rle_tasks.core.runtime.secrets import Secret

SECRET = "sidecar-test-secret"


@pytest.fixture(scope="module")
def exported(tmp_path_factory):
    out = tmp_path_factory.mktemp("export")
    dirs = export_harbor(out, ["01-open-fridge-l3", "03-cantilever", "03-tower", "09-gello"])
    return {d.name: d for d in dirs}


def test_a_metered_task_runs_its_server_in_the_sidecar(exported):
    task = exported["01-open-fridge-l3"]
    compose = yaml.safe_load((task / "environment" / "docker-compose.yaml").read_text())
    main, dev = compose["services"]["main"], compose["services"]["dev"]
    assert main["depends_on"] == {"dev": {"condition": "service_healthy"}}
    assert main["volumes"] == dev["volumes"] == ["workspace:/workspace"]
    assert dev["build"] == {"context": "./dev"} and "RLE_SECRET" in dev["environment"]
    assert "/workspace/.rle/ledger.sock" in " ".join(dev["healthcheck"]["test"])
    assert (task / "environment" / "dev" / "rle-bench" / "rle_tasks").is_dir()  # the server's code
    assert not (task / "environment" / "workspace" / ".rle").exists()
    assert (task / "environment" / ".dockerignore").read_text() == "dev/\n"  # not in the agent's image
    cfg = tomllib.loads((task / "task.toml").read_text())
    assert cfg["verifier"]["collect"] == [
        {
            "service": "dev",
            "command": "python3 -m rle_tasks.core.export.harbor.sidecar seal",
            "timeout_sec": 120,
        }
    ]
    assert cfg["artifacts"] == [{"source": "/rle-ledger", "service": "dev"}]
    assert '--sidecar "/rle-ledger"' in (task / "tests" / "test.sh").read_text()
    client = (task / "environment" / "workspace" / "client.py").read_text()
    assert 'path = ws / ".rle" / "ledger.sock"' in client and "/tmp/" not in client.split("def _address")[0]
    assert "development sidecar" in (task / "README.md").read_text()
    instruction = (task / "instruction.md").read_text()
    assert "already runs beside your container" in instruction and "need not copy a ledger" in instruction


def test_the_oracle_of_family_01_plays_through_the_sidecar(exported):
    sol = exported["01-open-fridge-l3"] / "solution"
    assert not (sol / "reference").exists()  # no copied ledger: it would not count
    assert "python3 /solution/oracle.py" in (sol / "solve.sh").read_text()
    oracle = (sol / "oracle.py").read_text()
    assert "from client import connect" in oracle and "play(env, 'OpenFridge', level=3)" in oracle
    programs = {p.name: p.read_text() for p in (sol / "agents").glob("*.py")}
    assert "open_fridge.py" in programs and "trial.py" not in programs
    assert not any("rle_tasks" in text for text in programs.values())  # the agent's image has none
    assert "plays the reference program" in (exported["01-open-fridge-l3"] / "README.md").read_text()


def test_a_ledger_task_whose_reference_reads_privileged_state_plays_only_with_the_operators_consent(exported):
    task = exported["03-cantilever"]
    compose = yaml.safe_load((task / "environment" / "docker-compose.yaml").read_text())
    assert compose["services"]["dev"]["environment"]["RLE_ORACLE_PRIVILEGED"] == "${RLE_ORACLE_PRIVILEGED:-0}"
    assert "RLE_ORACLE_PRIVILEGED" not in str(compose["services"]["main"])  # never the agent's
    cfg = tomllib.loads((task / "task.toml").read_text())
    assert cfg["verifier"]["env"]["RLE_ORACLE_PRIVILEGED"] == "${RLE_ORACLE_PRIVILEGED:-0}"
    assert "RLE_ORACLE_PRIVILEGED" not in str(cfg.get("agent", {})) + str(cfg.get("environment", {}))
    sol = task / "solution"
    assert (
        not (sol / "reference").exists() and "python3 /solution/oracle.py" in (sol / "solve.sh").read_text()
    )
    oracle = (sol / "oracle.py").read_text()
    assert "harmonic_cantilever(env.step, obs, edge_x=0.45" in oracle and "scale=0.93" in oracle
    assert "rle_tasks" not in (sol / "agents.py").read_text()
    readme = (task / "README.md").read_text()
    assert "RLE_ORACLE_PRIVILEGED=1" in readme and "ledger.privileged" in readme
    plain = exported["09-gello"]  # no development server: no sidecar
    assert not (plain / "environment" / "docker-compose.yaml").exists()
    assert "collect" not in tomllib.loads((plain / "task.toml").read_text())["verifier"]


def _client(workspace: Path):
    spec = importlib.util.spec_from_file_location("ws_client", workspace / "client.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _sidecar(*args: str, env: dict[str, str]) -> subprocess.Popen:
    return subprocess.Popen(
        [sys.executable, "-m", "rle_tasks.core.export.harbor.sidecar", *args],
        env={**os.environ, "PYTHONPATH": str(REPO_ROOT), **env},
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
    )


def test_the_sidecar_serves_an_attempt_of_its_own_and_leaves_its_sealed_ledger(tmp_path):
    ws, ledgers = tmp_path / "ws", tmp_path / "ledgers"
    where = ["--workspace", str(ws), "--ledger-dir", str(ledgers)]
    refused = _sidecar("serve", "03-cantilever", *where, env={"RLE_SECRET": "", "RLE_ALLOW_PUBLIC_KEY": "0"})
    assert refused.wait(60) == 2 and b"RLE_SECRET is not set" in refused.stdout.read()
    server = _sidecar("serve", "03-cantilever", *where, env={"RLE_SECRET": SECRET})
    try:
        sock = ws / ".rle" / "ledger.sock"
        deadline = time.monotonic() + 90
        while not sock.exists():
            assert time.monotonic() < deadline and server.poll() is None, server.stdout.read()
            time.sleep(0.1)
        assert stat.S_IMODE(sock.stat().st_mode) == 0o666  # the agent's uid connects
        with _client(ws).connect() as env:  # the workspace's own client, as the agent runs it
            obs = env.reset()
            env.step([0.0] * env.info()["action_size"])
        assert "bodies" not in obs and "sizes" not in obs  # an agent's session: no piece poses
        sealed = subprocess.run(
            [sys.executable, "-m", "rle_tasks.core.export.harbor.sidecar", "seal", *where],
            env={**os.environ, "PYTHONPATH": str(REPO_ROOT)},
            capture_output=True,
            text=True,
            timeout=120,
        )
        assert sealed.returncode == 0, sealed.stderr
        assert server.wait(60) == 0
    finally:
        if server.poll() is None:
            server.kill()
    attempt = (ledgers / "attempt").read_text().strip()
    assert attempt.startswith("harbor-") and len(attempt) == len("harbor-") + 16
    from rle_tasks.f03_physical_reasoning.task import BUDGET

    key = ledger_key(Secret(SECRET.encode(), public=False), "03-cantilever")
    limits = Limits(BUDGET.steps, BUDGET.wall_time_s)
    gate = check_ledger(ledgers / "ledger.jsonl", key, "03-cantilever", limits, attempt)
    assert gate.ok and gate.development_steps == 2 and not gate.privileged, gate.message
    assert check_ledger(ledgers / "ledger.jsonl", key, "03-cantilever", limits, "harbor-other").code == (
        "ledger.wrong_attempt"
    )


FAKE_RLE = """#!{python}
import json, sys
from pathlib import Path
args = sys.argv[1:]
artifacts = Path(args[2])
seen = {{"args": args, "ledger": (artifacts / "ledger.jsonl").read_text() if (artifacts / "ledger.jsonl").exists() else None}}
Path({mark!r}).write_text(json.dumps(seen))
Path(args[args.index("--json") + 1]).write_text(json.dumps({{"score": 0.5, "secret": "private", "checkpoints": []}}))
"""


@pytest.mark.skipif(os.geteuid() != 0, reason="the verifier runs as root in its container")
def test_the_verifier_scores_the_sidecars_session_as_its_attempt(tmp_path):
    from rle_tasks.core.export.harbor.reward import VerifierSetupError, run

    logs = tmp_path / "logs"
    for sub in ("artifacts", "verifier"):
        (logs / sub).mkdir(parents=True)
    (logs / "artifacts" / "ledger.jsonl").write_text("the agent's own ledger\n")
    sidecar = tmp_path / "rle-ledger"
    sidecar.mkdir()
    (sidecar / "ledger.jsonl").write_text("the session's ledger\n")
    (sidecar / "attempt").write_text("harbor-0123456789abcdef\n")
    bin_dir = tmp_path / "bin"
    bin_dir.mkdir()
    mark = tmp_path / "seen.json"
    (bin_dir / "rle").write_text(FAKE_RLE.format(python=sys.executable, mark=str(mark)))
    (bin_dir / "rle").chmod(0o755)
    env = {"PATH": f"{bin_dir}:{os.environ['PATH']}", "RLE_SECRET": SECRET}
    assert run("03-cantilever", logs, 1, env, sidecar) == 0
    seen = json.loads(mark.read_text())
    assert seen["ledger"] == "the session's ledger\n"
    assert seen["args"][-2:] == ["--attempt", "harbor-0123456789abcdef"]
    assert json.loads((logs / "verifier" / "reward.json").read_text())["reward"] == 0.5
    (sidecar / "attempt").unlink()  # the sidecar never ran: no reward rather than an unbound score
    with pytest.raises(VerifierSetupError, match="left no attempt"):
        run("03-cantilever", logs, 1, env, sidecar)


@pytest.mark.physics
@pytest.mark.parametrize(
    "task_id",
    [
        "03-cantilever",
        pytest.param(
            "03-tower",
            marks=pytest.mark.skipif(
                os.environ.get("RLE_FULL_BATTERY") != "1",
                reason="56 s of play: full battery only (RLE_FULL_BATTERY=1); the reduced run plays the cantilever",
            ),
        ),
    ],
)
def test_a_privileged_oracle_plays_through_the_sidecar_and_is_named(exported, tmp_path, task_id):
    """The exported oracle program, run as Harbor's oracle agent runs it, against a sidecar the operator
    started with RLE_ORACLE_PRIVILEGED=1 (public key here): the reference's score, and the report names
    the privileged session; the reward counts it only when the verifier is told (the same flag)."""
    from rle_tasks.core.export.harbor.reward import reward_from_report
    from rle_tasks.core.registry import get_task
    from rle_tasks.core.runtime.secrets import PUBLIC_KEY
    from rle_tasks.core.solutions import declaration
    from rle_tasks.core.task import VerifyContext
    from rle_tasks.core.verify import run_verify

    ws, ledgers = tmp_path / "ws", tmp_path / "ledgers"
    where = ["--workspace", str(ws), "--ledger-dir", str(ledgers)]
    env = {"RLE_SECRET": "", "RLE_ALLOW_PUBLIC_KEY": "1", "RLE_ORACLE_PRIVILEGED": "1"}
    server = _sidecar("serve", task_id, *where, env=env)
    try:
        deadline = time.monotonic() + 90
        while not (ws / ".rle" / "ledger.sock").exists():
            assert time.monotonic() < deadline and server.poll() is None, server.stdout.read()
            time.sleep(0.1)
        oracle = (exported[task_id] / "solution" / "oracle.py").read_text()
        oracle = oracle.replace(
            '"/workspace", "/solution"', f"{str(ws)!r}, {str(exported[task_id] / 'solution')!r}"
        )
        played = subprocess.run(
            [sys.executable, "-c", oracle], cwd=ws, env={**os.environ, "PYTHONPATH": str(REPO_ROOT)},
            capture_output=True, text=True, timeout=900,
        )  # fmt: skip
        assert played.returncode == 0, played.stdout[-2000:] + played.stderr[-2000:]
        assert server.wait(60) == 0
    finally:
        if server.poll() is None:
            server.kill()
    artifact = tmp_path / "artifact"
    artifact.mkdir()
    attempt = (ledgers / "attempt").read_text().strip()
    (artifact / "ledger.jsonl").write_bytes(sorted(ledgers.glob(f"{attempt}*.jsonl"))[-1].read_bytes())
    ctx = VerifyContext(secret=Secret(PUBLIC_KEY, public=True), quick=True, attempt=attempt)
    report, internal = run_verify(get_task(task_id), artifact, ctx)
    golden = declaration(get_task(task_id)).get("reference").quick_score
    assert not internal and report.score == pytest.approx(golden, abs=0.05), report.errors
    assert [e.code for e in report.errors] == ["ledger.privileged"]
    assert report.native_metrics["privileged_session"] is True
    as_dict = report.to_dict()
    assert reward_from_report(as_dict, False)["reward"] == 0.0  # an agent's verifier: nothing counts
    assert reward_from_report(as_dict, False, oracle=True)["reward"] == pytest.approx(report.score)


def test_reference_programs_that_read_only_what_agents_get_are_the_oracles_of_their_tasks(tmp_path):
    for task in export_harbor(tmp_path, ["03-balance-coins", "03-hidden-com"]):
        sol = task / "solution"
        assert sorted(p.name for p in sol.iterdir()) == ["oracle.py", "solve.sh"], task.name
        program = (sol / "oracle.py").read_text()
        assert "from client import connect" in program and "env.seal()" in program
        assert "rle_tasks" not in program and "privileged" not in program.split('"""', 2)[2]
        assert (
            'PYTHONPATH="/workspace${PYTHONPATH:+:$PYTHONPATH}" exec python3 /solution/oracle.py'
            in (sol / "solve.sh").read_text()
        )
        assert "RLE_ORACLE_PRIVILEGED" not in (task / "README.md").read_text()  # plays as an agent would
