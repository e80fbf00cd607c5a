"""An exported task's development environment as a Harbor sidecar: ``python -m rle_tasks.core.export.harbor.sidecar``.

Tasks whose development environment is metered or served (families 01, 02, 03, 06) cannot run it in
the agent's container: its server holds the ledger key derived from the verifier secret. Their
exported ``environment/docker-compose.yaml`` adds a service ``dev`` beside the agent's ``main``:

- ``serve TASK`` (the service's command): draws a fresh attempt id (``harbor-`` and 16 hex digits),
  lays out the workspace in the volume both services mount at ``/workspace`` (owned by the agent's
  uid) and serves the same server as ``rle dev`` (``rle_tasks.core.runtime.devenv.layout_workspace``) on
  ``/workspace/.rle/ledger.sock``, open to the agent's uid, in that attempt. The key, the secret, the
  hidden scenes and the ledger (``/rle-ledger``, root-only) stay in the sidecar's own filesystem.
  The service is healthy once the socket exists, and the agent starts only then. With
  ``RLE_ORACLE_PRIVILEGED=1`` on the host (an operator's oracle trial) a task with a privileged
  oracle serves privileged observations; its ledger records it (``ledger.privileged``).
- ``seal`` (Harbor's ``[[verifier.collect]]`` hook, after the agent phase): asks the server to seal,
  waits for the seal, and leaves ``/rle-ledger/ledger.jsonl`` (the attempt's ledger) and
  ``/rle-ledger/attempt`` for Harbor to collect as an artifact of the service (``[[artifacts]]``).
  The separate verifier reads both there (``harbor.reward --sidecar``): the ledger the agent's
  container never could write, verified as the attempt the sidecar drew.
"""

from __future__ import annotations

import argparse
import json
import os
import secrets
import shutil
import sys
import time
from pathlib import Path

LEDGER_DIR = Path("/rle-ledger")
"""Where the sidecar keeps its ledgers (collected by Harbor as an artifact of the service)."""
WORKSPACE = Path("/workspace")
"""The agent's workspace: the volume both services mount."""
LEDGER_FILE = "ledger.jsonl"
ATTEMPT_FILE = "attempt"
ORACLE_ENV = "RLE_ORACLE_PRIVILEGED"
"""Host variable of an operator's oracle trial: ``1`` makes the sidecar of a task with a privileged
oracle (``TaskSpec.privileged_oracle``) serve privileged observations, and lets the verifier's reward
count such a session (``harbor.reward``). The agent's container never reads it."""
AGENT_UID = 1000
"""The agent user's uid in the exported agent image (``harbor.images.AGENT_USER``)."""


def _chown_tree(root: Path, uid: int) -> None:
    for path in [root, *root.rglob("*")]:
        if path.name == ".rle" or ".rle" in path.relative_to(root).parts:
            continue  # the socket's directory stays the server's
        os.lchown(path, uid, uid)


def serve(task_id: str, workspace: Path = WORKSPACE, ledger_dir: Path = LEDGER_DIR) -> int:
    """Serve ``task_id``'s development environment in a fresh attempt until sealed or signalled."""
    from rle_tasks.core.runtime.devenv import make_workspace

    if not os.environ.get("RLE_SECRET") and os.environ.get("RLE_ALLOW_PUBLIC_KEY") != "1":
        print(
            "rle-bench sidecar: RLE_SECRET is not set on the host that runs harbor: the development server "
            "would meter under the public key, and no session of it could score (RLE_ALLOW_PUBLIC_KEY=1 "
            "serves a smoke test with the public key)",
            file=sys.stderr,
        )
        return 2
    from rle_tasks.core.registry import get_task

    privileged = os.environ.get(ORACLE_ENV) == "1"
    if privileged and not get_task(task_id).privileged_oracle:
        print(f"rle-bench sidecar: {ORACLE_ENV}=1 ignored: {task_id} has no privileged oracle", flush=True)
        privileged = False
    elif privileged:
        print(
            f"rle-bench sidecar: {ORACLE_ENV}=1: serving PRIVILEGED observations for an oracle trial; the "
            "ledger records it and the verifier names it (ledger.privileged)",
            flush=True,
        )
    attempt = "harbor-" + secrets.token_hex(8)
    ledger_dir.mkdir(mode=0o700, parents=True, exist_ok=True)
    (ledger_dir / ATTEMPT_FILE).write_text(attempt + "\n")
    ws = make_workspace(
        task_id,
        workspace,
        attempt=attempt,
        ledger_dir=ledger_dir,
        socket_mode=0o666,
        prepare=lambda path: _chown_tree(path, AGENT_UID),
        privileged=privileged,
    )
    print(f"rle-bench sidecar: attempt {attempt}, session ended; ledger {ws.ledger_path}", flush=True)
    return 0


def _sealed(path: Path) -> bool:
    try:
        last = path.read_bytes().rstrip(b"\n").rsplit(b"\n", 1)[-1]
        return json.loads(last).get("kind") == "seal"
    except (OSError, ValueError, AttributeError):
        return False


def seal(workspace: Path = WORKSPACE, ledger_dir: Path = LEDGER_DIR, timeout_s: float = 60.0) -> int:
    """Seal the session (if the agent did not) and leave the attempt's ledger at ``ledger.jsonl``."""
    from rle_design.ledger import LedgerClient, LedgerError

    attempt = (ledger_dir / ATTEMPT_FILE).read_text().strip()
    sessions = sorted(ledger_dir.glob(f"{attempt}*.jsonl"))
    if not sessions:
        print(f"rle-bench sidecar: attempt {attempt} has no ledger", file=sys.stderr)
        return 1
    if not all(_sealed(p) for p in sessions):
        try:
            with LedgerClient(workspace / ".rle" / "ledger.sock") as client:
                client.seal()
        except LedgerError as exc:  # the server is gone already (it seals when it stops)
            print(f"rle-bench sidecar: {exc.code}: {exc}", file=sys.stderr)
        deadline = time.monotonic() + timeout_s
        while not all(_sealed(p) for p in sessions) and time.monotonic() < deadline:
            time.sleep(0.2)
    shutil.copyfile(sessions[-1], ledger_dir / LEDGER_FILE)
    for path in ledger_dir.iterdir():
        path.chmod(0o644)  # Harbor copies them out as the container's user
    print(f"rle-bench sidecar: {sessions[-1].name} -> {LEDGER_FILE} (sealed: {_sealed(sessions[-1])})")
    return 0


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m rle_tasks.core.export.harbor.sidecar")
    sub = parser.add_subparsers(dest="command", required=True)
    s = sub.add_parser("serve", help="serve the task's development environment (the service's command)")
    s.add_argument("task")
    s2 = sub.add_parser("seal", help="seal the session and leave its ledger for collection")
    for p in (s, s2):
        p.add_argument("--workspace", default=str(WORKSPACE), help="the agent's workspace (a shared volume)")
        p.add_argument("--ledger-dir", default=str(LEDGER_DIR), help="where the ledgers are kept")
    args = parser.parse_args(argv)
    if args.command == "serve":
        return serve(args.task, Path(args.workspace), Path(args.ledger_dir))
    return seal(Path(args.workspace), Path(args.ledger_dir))


if __name__ == "__main__":
    sys.exit(main())
