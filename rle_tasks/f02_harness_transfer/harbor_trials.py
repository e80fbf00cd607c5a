"""The second stage of a family-02 Harbor job: the card's five fresh agents as Harbor trials.

``rle transfer-trials GROUP SUBMISSION --agent AGENT [--model MODEL]`` (or ``python -m
rle_tasks.f02_harness_transfer.harbor_trials``), after the development trial of ``GROUP`` left its
``agent_harness/`` in ``SUBMISSION`` (the trial's ``artifacts/`` folder, or any directory holding it):

1. exports the five fresh-agent tasks ``GROUP-fresh-0`` .. ``-4`` (``fresh.stage_task``) with the
   harness built into their images; each has the development sidecar of a metered task, serving one
   unseen kitchen drawn from ``RLE_SECRET`` and the trial's attempt, and a workspace holding only the
   harness, the held-out task's instruction and the client;
2. runs each as a Harbor trial with the operator's agent (Docker's compose environment); the oracle
   agent is the scripted fresh agent (``public/fresh_agent.py``), the test double the verifier itself
   uses;
3. writes the group's report (``GROUP.json``: the mean of the five rewards, a failed trial counting 0),
   which ``rle index`` takes like the verifier's own.

``RLE_SECRET`` must be set (private) on the host, as for every exported task.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

from rle_design.errors import RleError

from .constants import TRIALS
from .fresh import HARNESS_DIR, group_report, stage_task
from .groups import GROUPS
from .transfer import FRESH_AGENT

SOLVE_SH = """#!/usr/bin/env bash
# Oracle of a fresh-agent task: the scripted fresh agent (the verifier's test double) reads
# agent_harness/MANUAL.md and calls the harness's entry point once with the metered client.
set -euo pipefail
cd /workspace
cp /solution/fresh_agent.py /workspace/fresh_agent.py
PYTHONPATH="/workspace${PYTHONPATH:+:$PYTHONPATH}" exec python3 -c \\
  'import json, fresh_agent; print(json.dumps(fresh_agent.run()))'
"""


def harness_of(submission: Path) -> Path:
    """``submission/agent_harness`` (or ``submission`` itself when it is the harness).

    Raises:
        RleError: ``f02.no_manual`` when there is no ``MANUAL.md``.
    """
    harness = submission / HARNESS_DIR if (submission / HARNESS_DIR).is_dir() else submission
    manual = harness / "MANUAL.md"
    if manual.is_symlink() or not manual.is_file():
        raise RleError(
            f"{harness} holds no MANUAL.md: a fresh agent has no manual (the group scores 0)",
            code="f02.no_manual",
        )
    return harness


def export_fresh(group_id: str, harness: Path, out: Path, trials: int = TRIALS) -> list[Path]:
    """The fresh-agent task directories of ``group_id`` under ``out``, each with the scripted fresh
    agent as its oracle."""
    from rle_tasks.core.export.harbor.export import export_harbor

    specs = [stage_task(f"{group_id}-fresh-{k}", harness=harness) for k in range(trials)]
    dirs = export_harbor(out, specs)
    for task_dir in dirs:
        sol = task_dir / "solution"
        sol.mkdir(exist_ok=True)
        shutil.copyfile(FRESH_AGENT, sol / "fresh_agent.py")
        (sol / "solve.sh").write_text(SOLVE_SH)
        (sol / "solve.sh").chmod(0o755)
        readme = task_dir / "README.md"
        readme.write_text(
            readme.read_text().replace(
                "This task ships no reference solution, so the oracle agent has nothing to submit.",
                "Harbor's oracle agent is the scripted fresh agent (`solution/fresh_agent.py`, the verifier's "
                "test double): it reads `agent_harness/MANUAL.md` and calls the harness's entry point once. "
                "Its reward is what the group verifier would credit this agent with for this kitchen.",
            )
        )
    return dirs


def run_trial(
    task_dir: Path, jobs: Path, harbor: str, agent: str, model: str | None, extra: list[str]
) -> float | None:
    """One Harbor trial of ``task_dir``; its reward (None when the trial produced none)."""
    from rle_tasks.core.export.harbor.results import read_job

    before = set(jobs.glob("*")) if jobs.exists() else set()
    cmd = [harbor, "run", "-p", str(task_dir), "-a", agent, "-e", "docker", "-n", "1", "-y", "-o", str(jobs)]
    if model:
        cmd += ["-m", model]
    subprocess.run(cmd + extra, env={**os.environ, "LITELLM_LOCAL_MODEL_COST_MAP": "True"}, check=False)
    new = sorted(set(jobs.glob("*")) - before)
    if not new:
        return None
    try:
        records = read_job(new[-1])
    except RleError:
        return None
    return records[0].reward if records else None


def add_parser(sub) -> None:
    s = sub.add_parser("transfer-trials", help="family 02: a group's five fresh agents as Harbor trials")
    s.add_argument("group", help="e.g. 02-group-01")
    s.add_argument("submission", help="directory holding agent_harness/ (a development trial's artifacts)")
    s.add_argument(
        "--agent", required=True, help="Harbor agent of the fresh trials (oracle: the scripted one)"
    )
    s.add_argument("--model", default=None, help="the agent's model (harbor run -m)")
    s.add_argument("--out", default="out/transfer-trials")
    s.add_argument("--trials", type=int, default=TRIALS, help=f"fresh agents to run (card: {TRIALS})")
    s.add_argument("--harbor", default=shutil.which("harbor") or ".venv-harbor/bin/harbor")
    s.add_argument(
        "--local",
        action="store_true",
        help="a Docker host without Harbor's egress-control sidecar (docs/harbor.md): agent and verifier "
        "phases with network_mode public, no GPU, at most this machine's CPUs",
    )
    s.add_argument(
        "--harbor-arg",
        action="append",
        default=[],
        metavar="ARG",
        help="passed to harbor run (repeat: --harbor-arg=--override-cpus --harbor-arg=2)",
    )
    s.set_defaults(fn=run)


def run(args: argparse.Namespace) -> int:
    """``rle transfer-trials`` (module docstring)."""
    if args.group not in {g.task_id for g in GROUPS}:
        print(
            f"rle transfer-trials: unknown group {args.group!r} (02-group-01 .. 02-group-15)", file=sys.stderr
        )
        return 2
    if not os.environ.get("RLE_SECRET"):
        print(
            "rle transfer-trials: RLE_SECRET is not set: the fresh agents' kitchens and keys come from a private "
            "secret (export RLE_SECRET=...)",
            file=sys.stderr,
        )
        return 2
    if not 1 <= args.trials <= TRIALS:
        print(f"rle transfer-trials: --trials must be 1..{TRIALS}", file=sys.stderr)
        return 2
    out = Path(args.out)
    try:
        harness = harness_of(Path(args.submission))
        dirs = export_fresh(args.group, harness, out / "tasks", args.trials)
    except RleError as exc:
        print(f"rle transfer-trials: error [{exc.code}]: {exc}", file=sys.stderr)
        return 2
    extra = list(args.harbor_arg)
    if args.local:
        for task_dir in dirs:
            toml = task_dir / "task.toml"
            toml.write_text(
                toml.read_text().replace('network_mode = "no-network"', 'network_mode = "public"')
            )
        extra += ["--override-gpus", "0", "--override-cpus", str(min(os.cpu_count() or 1, 2))]
    rewards: list[float | None] = []
    for k, task_dir in enumerate(dirs):
        t0 = time.monotonic()
        print(f"fresh agent {k + 1}/{len(dirs)}: {task_dir.name} ({args.agent}) ...", flush=True)
        reward = run_trial(task_dir, out / "jobs", args.harbor, args.agent, args.model, extra)
        rewards.append(reward)
        shown = "no reward" if reward is None else f"s_trial {reward:.3f}"
        print(f"  {shown} in {time.monotonic() - t0:.0f} s", flush=True)
    group = next(g for g in GROUPS if g.task_id == args.group)
    report = group_report(group, rewards, [d.name for d in dirs]).replace(secret="private")
    path = report.write(out / f"{args.group}.json")
    print(f"{args.group}: {report.score:.3f} ({report.checkpoints[0].message}); report {path}")
    print(json.dumps({"group": args.group, "rewards": rewards}))
    return 0


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m rle_tasks.f02_harness_transfer.harbor_trials")
    add_parser(parser.add_subparsers(dest="command", required=True))
    args = parser.parse_args(["transfer-trials", *(sys.argv[1:] if argv is None else argv)])
    return args.fn(args)


if __name__ == "__main__":
    sys.exit(main())
