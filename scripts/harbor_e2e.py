"""Real Harbor trials of exported tasks, one per family: ``make harbor-e2e`` (not part of ``make test``).

Exports the tasks (``rle export harbor``), runs each as a Harbor trial with the oracle agent, Docker's
compose environment and a private secret (``RLE_SECRET``, drawn when unset), and checks each reward
against what it must get (``expected``: the same verification run here on the shipped reference with
the same secret, the golden score where the oracle plays through the development sidecar, 0 where the
README says it cannot) within ``TOLERANCE``. Prints a table (reward, expected, trial time) and exits 1
when a trial errs or misses.

Needs Docker with Compose v2 and the base image (``scripts/harbor_e2e_setup.sh`` prepares this machine
kind) and the Harbor side environment (``make harbor-venv``). Local Docker has no egress-control
sidecar, so the exported ``no-network`` phases run with ``network_mode = "public"`` here; resources
are capped to this machine (``--override-cpus``) and no GPU is asked for (``--override-gpus 0``).

Usage: ``python scripts/harbor_e2e.py [TASK ...] [--out DIR]``.
"""

from __future__ import annotations

import argparse
import json
import os
import secrets
import subprocess
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
TASKS = (
    "01-open-fridge-l3",
    "02-group-01",
    "03-cantilever",
    "04-fight",
    "05-robotwin-open",
    "06-pose-b-rgbd",
    "07-bin-clearing",
    "08-mobile-base",
    "09-gello",
)
"""One task of every family (05's images hold its dataset: `make standin-demos` first)."""
QUICK = ("05-",)
"""Tasks verified on their quick episodes (``RLE_VERIFY_QUICK=1``; here and in the trial): 05 trains the
recipe in full, then runs 12 episodes instead of 300."""
TOLERANCE = 0.05
"""|reward - expected| allowed (the issue's bound; a played session is recorded afresh, and OpenBLAS
kernels may differ between the image and this machine)."""


def quick(task_id: str) -> bool:
    return task_id.startswith(QUICK)


def expected(task_dir: Path, secret: str) -> tuple[float | None, str]:
    """The reward an oracle trial must get, and why: 0 where the README says the oracle cannot play
    through the development sidecar; the golden score where the oracle plays the reference program
    (its session is recorded afresh in the trial); else the same verification run here, the shipped
    reference with the same secret (a trial scores as the verifier does locally)."""
    import tempfile

    from rle_tasks.core.registry import get_task
    from rle_tasks.core.runtime.secrets import Secret
    from rle_tasks.core.solutions import declaration, materialise
    from rle_tasks.core.task import VerifyContext

    spec = get_task(task_dir.name)
    if "reference" not in spec.solutions:
        return None, "no reference"
    if "scores **0**" in (task_dir / "README.md").read_text():
        return 0.0, "README: the oracle cannot play"
    if (task_dir / "solution" / "oracle.py").is_file():
        return declaration(spec).get("reference").quick_score, "golden (the oracle plays)"
    with tempfile.TemporaryDirectory() as tmp:
        ref = materialise(spec, "reference", dest=Path(tmp) / "reference")
        ctx = VerifyContext(
            secret=Secret(secret.encode(), public=False),
            jobs=min(os.cpu_count() or 1, 2),
            quick=quick(spec.id),
        )
        return spec.verify(ref, ctx).score, "rle verify here, same secret" + (", quick" if ctx.quick else "")


def run_trial(task_dir: Path, jobs: Path, harbor: Path, env: dict[str, str]) -> tuple[dict, float, str]:
    """(reward dict or {}, seconds, job log tail) of one oracle trial."""
    text = (
        (task_dir / "task.toml").read_text().replace('network_mode = "no-network"', 'network_mode = "public"')
    )
    (task_dir / "task.toml").write_text(text)
    before = set(jobs.glob("*")) if jobs.exists() else set()
    t0 = time.monotonic()
    cmd = [str(harbor), "run", "-p", str(task_dir), "-a", "oracle", "-e", "docker", "-n", "1", "-y",
           "--override-gpus", "0", "--override-cpus", str(min(os.cpu_count() or 1, 2)), "-o", str(jobs)]  # fmt: skip
    proc = subprocess.run(cmd, env=env, capture_output=True, text=True)
    seconds = time.monotonic() - t0
    new = sorted(set(jobs.glob("*")) - before)
    rewards = list(new[-1].glob(f"{task_dir.name}__*/verifier/reward.json")) if new else []
    reward = json.loads(rewards[0].read_text()) if rewards else {}
    return reward, seconds, (proc.stdout + proc.stderr)[-2000:]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("tasks", nargs="*", default=list(TASKS))
    parser.add_argument("--out", default=str(REPO / "out" / "harbor-e2e"))
    args = parser.parse_args(argv)
    out = Path(args.out)
    harbor = REPO / ".venv-harbor" / "bin" / "harbor"
    if not harbor.is_file():
        print("no Harbor side environment: run `make harbor-venv`", file=sys.stderr)
        return 2
    from rle_tasks.core.export.harbor.export import export_harbor

    dirs = export_harbor(out / "tasks", args.tasks)
    env = {**os.environ, "LITELLM_LOCAL_MODEL_COST_MAP": "True"}
    env.setdefault("RLE_SECRET", secrets.token_hex(32))  # private: never the public key
    env["RLE_ORACLE_PRIVILEGED"] = "1"  # oracle trials: a privileged oracle (03-cantilever) may play
    failed = 0
    print(f"{'task':<20} {'reward':>8} {'expected':>9} {'time':>7}  verdict (expected from)", flush=True)
    for task_dir in dirs:
        trial_env = {**env, "RLE_VERIFY_QUICK": "1" if quick(task_dir.name) else "0"}
        reward, seconds, tail = run_trial(task_dir, out / "jobs", harbor, trial_env)
        want, why = expected(task_dir, env["RLE_SECRET"])
        got = reward.get("reward")
        ok = (
            got is not None
            and reward.get("secret_private") == 1.0
            and bool(reward.get("partial")) == quick(task_dir.name)
            and (want is None or abs(got - want) <= TOLERANCE)
        )
        failed += not ok
        shown = "error" if got is None else f"{got:.3f}"
        print(f"{task_dir.name:<20} {shown:>8} {'-' if want is None else f'{want:.3f}':>9} {seconds:>6.0f}s  "
              f"{'ok' if ok else 'FAIL'} ({why})", flush=True)  # fmt: skip
        if got is None:
            print(tail, file=sys.stderr)
    print(
        f"job directories: {out / 'jobs'} (`rle index --allow-privileged --allow-partial {out / 'jobs'}/*` "
        "reads them: an oracle's privileged sessions and quick rewards are refused otherwise)"
    )
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
