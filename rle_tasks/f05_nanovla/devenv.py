"""Development workspace of the family-05 tasks: the demonstrations, ``libero_client.py`` (or
``standin_client.py`` on the RoboTwin stand-in tracks) and the served evaluation client.

``make_dev_env`` links the read-only demonstration dataset into the workspace (``demos/``), writes the
client and returns a ``ServedSession`` (``rle_tasks.core.runtime.devservice``) that ``rle dev`` starts with the
ledger key. The session process holds LIBERO and the ledger key; the agent's client sends it
``evaluate`` requests naming a directory of the workspace (``solution.py`` and the ``ckpt.pt`` the
agent trained there). The server serves that recipe in the project sandbox, runs the requested
official initial states and charges one episode each of the card's 20,000 (``DevelopmentClient``).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from rle_design.errors import RleError
from rle_design.ledger.records import LedgerError
from rle_tasks.core.runtime.devservice import CLIENT_ADDRESS, ServedSession

MAX_REQUEST_EPISODES = 500
"""Episodes one ``evaluate`` request may ask for (the size of the evaluation set)."""

_CLIENT = '''"""Evaluation client of {task_id} (written by `rle dev`; episodes of clean LIBERO-10).

    from libero_client import connect
    with connect() as dev:
        results = dev.evaluate("submission", [(0, 0), (3, 7)])  # charged: one episode each
        results = dev.evaluate("submission", [(0, 1)], max_steps=100)  # a shorter horizon
        dev.info()                                              # free: episodes used and left

`evaluate(directory, episodes)` serves `directory/solution.py` (relative to this workspace; it loads
the `ckpt.pt` you trained there) exactly as the verifier will, and runs the (LIBERO-10 task,
official initial state) pairs: task 0-9, state 0-49. Each result: init_index, success, steps,
requests, fault. Budget: {budget} episodes per attempt (restarting the server does not reset it),
each recorded with the sha256 of the directory it ran in a sealed ledger outside this workspace;
dev.seal() ends the session.
"""

import hashlib
import tempfile
from multiprocessing.connection import Client
from pathlib import Path

import warnings

with warnings.catch_warnings():  # the simulator runs in the server: this process's BLAS kernels do not matter
    warnings.simplefilter("ignore", RuntimeWarning)
    from rle_design.ledger.server import decode, encode
{address}

class DevClient(_Connection):
    def evaluate(self, directory, episodes, max_steps=None):
        pairs = [[int(t), int(i)] for t, i in episodes]
        return self._request("evaluate", {{"dir": str(directory), "episodes": pairs, "max_steps": max_steps}})


def connect():
    return DevClient()
'''

_STANDIN_DOC = '''"""Evaluation client of {task_id} (written by `rle dev`; episodes of the bimanual stand-in's clean scenes).

    from standin_client import connect
    with connect() as dev:
        results = dev.evaluate("submission", [(0, 5), (2, 17)])  # charged: one episode each
        results = dev.evaluate("submission", [(1, 3)], max_steps=60)  # a shorter horizon
        dev.info()                                              # free: episodes used and left

`evaluate(directory, episodes)` serves `directory/solution.py` (relative to this workspace; it loads
the `ckpt.pt` you trained there) exactly as the verifier will, and runs the (task, layout seed)
pairs: task 0-2, layout seed 0-999999 (the demonstrations used seeds from 0). Each result:
init_index (the layout seed), success, steps, requests, fault. Budget: {budget} episodes, recorded
in a sealed ledger outside this workspace.
"""
'''
STANDIN_SEED_LIMIT = 1_000_000
"""Layout seeds a development request may name (evaluation seeds are drawn above it)."""


class _Session:
    """One development session: ``evaluate``, ``info``, ``seal`` (``rle_tasks.core.runtime.devservice``)."""

    def __init__(self, workspace: Path, client, standin: bool = False) -> None:
        self.workspace = workspace.resolve()
        self.client = client
        self.standin = standin
        self.sealed = False

    def handle(self, meta: dict[str, Any], value: Any) -> tuple[dict[str, Any], Any]:
        import dataclasses

        op = meta.get("op")
        args = value if isinstance(value, dict) else {}
        if op == "evaluate":
            directory = (self.workspace / str(args.get("dir", "submission"))).resolve()
            if not directory.is_relative_to(self.workspace) or not (directory / "solution.py").is_file():
                raise LedgerError(
                    f"{args.get('dir')!r} is not a directory of the workspace holding solution.py",
                    code="f05.dev_dir",
                )
            try:
                episodes = [(int(t), int(i)) for t, i in args.get("episodes", [])]
            except (TypeError, ValueError):
                raise LedgerError(
                    "episodes must be (task, initial state) pairs", code="ledger.bad_request"
                ) from None
            tasks, inits, what = (
                (3, STANDIN_SEED_LIMIT, "task 0-2 and layout seed 0-999999")
                if self.standin
                else (10, 50, "task 0-9 and initial state 0-49")
            )
            bad = [(t, i) for t, i in episodes if not (0 <= t < tasks and 0 <= i < inits)]
            if bad or not 1 <= len(episodes) <= MAX_REQUEST_EPISODES:
                raise LedgerError(
                    f"1..{MAX_REQUEST_EPISODES} pairs of {what}; refused: {bad[:5]}",
                    code="ledger.bad_request",
                )
            steps = args.get("max_steps")
            try:
                results = self.client.evaluate(
                    directory, episodes, max_steps=None if steps is None else int(steps)
                )
            except RleError as exc:
                raise LedgerError(exc.message, code=exc.code) from None
            return {"ok": True}, [dataclasses.asdict(r) for r in results]
        if op == "info":
            return {"ok": True}, self.client.info()
        if op == "seal":
            self.seal()
            return {"ok": True}, {"episodes_used": self.client.used}
        raise LedgerError(
            f"unknown operation {op!r}. Operations: evaluate, info, seal", code="ledger.bad_request"
        )

    def seal(self) -> None:
        if not self.sealed:
            self.client.close()
        self.sealed = True


def open_session(
    *, key: bytes | None, ledger_path: Path | None, workspace: str, task_id: str, attempt: str = ""
) -> _Session:
    """The session of one development server (``rle_tasks.core.runtime.devservice`` factory)."""
    import tempfile

    from rle_tasks.envs.libero.dev import DevelopmentClient

    if key is None or ledger_path is None:  # a rehearsal without a key: a throwaway ledger
        key, ledger_path = (
            b"rehearsal-key-not-secret",
            Path(tempfile.mkdtemp(prefix="rle-f05dev-")) / "dev.jsonl",
        )
    standin = task_id.startswith("05-robotwin")
    client = DevelopmentClient(
        ledger_path, key, task_id=task_id, env="standin" if standin else "libero", attempt=attempt
    )
    return _Session(Path(workspace), client, standin=standin)


def make_dev_env(workspace: Path, task_id: str = "05-libero-open") -> ServedSession:
    """Link the demonstrations, write ``libero_client.py``; return the (not yet started) server.

    Raises:
        RleError: ``f05.no_dataset`` when the demonstration dataset is not built.
    """
    from rle_tasks.envs.libero.dev import DEV_EPISODE_BUDGET
    from rle_tasks.f05_nanovla.datasets import dataset_dir

    ws = Path(workspace)
    ws.mkdir(parents=True, exist_ok=True)
    standin = task_id.startswith("05-robotwin")
    demos = dataset_dir(task_id)
    if not (demos / "manifest.sha256").is_file():
        target = "standin-demos" if standin else "libero-demos"
        raise RleError(
            f"the demonstration dataset is not built at {demos}: build it with `make {target}`",
            code="f05.no_dataset",
        )
    link = ws / "demos"
    if link.is_symlink() or link.exists():
        link.unlink()
    link.symlink_to(demos, target_is_directory=True)
    (ws / "submission").mkdir(exist_ok=True)
    text = _CLIENT
    if standin:
        text = _STANDIN_DOC + text[text.index("\nimport hashlib") :]
    (ws / ("standin_client.py" if standin else "libero_client.py")).write_text(
        text.format(budget=f"{DEV_EPISODE_BUDGET:,}", address=CLIENT_ADDRESS, task_id=task_id)
    )
    return ServedSession(
        "rle_tasks.f05_nanovla.devenv:open_session",
        {"workspace": str(ws), "task_id": task_id},
        name=f"rle-dev-{task_id}",
        client="standin_client" if standin else "libero_client",
    )
