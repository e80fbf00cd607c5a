"""``rle dev``: lay out an agent workspace and start the metered development environment.

The workspace receives ``instruction.md`` (the task's instruction I), whatever the family's
``make_dev_env(workspace)`` writes, and, for tasks with a metered environment, ``client.py``. A
family declares a metered environment by returning a ``rle_design.ledger.MeteredEnv`` from
``make_dev_env`` (or a served environment of its own: an object with ``start(key=, ledger_path=,
socket_path=)``, ``stop()``, ``wait()`` and ``socket_path``, started with the same key and paths); the ledger server is then started with the key derived from the verifier secret
(``ledger_key``), listening on ``<workspace>/.rle/ledger.sock``. The agent connects with::

    from client import connect
    with connect() as env:
        obs = env.reset()          # one step of the budget
        obs = env.step(action)     # one step: ctrl applied for n_substeps physics steps
        env.observe(); env.info()  # free

The ledger file is written outside the workspace (``<workspace>.ledger/session-NNN.jsonl`` unless
``ledger_dir`` says otherwise), so the agent cannot reach it through the workspace; the key, the
secret and hidden seeds are never written anywhere in the workspace. ``rle dev`` keeps serving in the
foreground until a client calls ``seal()`` or the command is interrupted (Ctrl-C seals the ledger).
"""

from __future__ import annotations

import hashlib
import hmac
import tempfile
from dataclasses import dataclass
from pathlib import Path

from rle_design.errors import RleError
from rle_design.ledger import LedgerServer, MeteredEnv, SceneSet
from rle_tasks.core.secrets import Secret, load_secret
from rle_tasks.core.task import TaskSpec

LEDGER_LABEL = b"rle-bench ledger key v1"
_CLIENT = '''"""Metered development environment of task {task_id} (written by `rle dev`).

    from client import connect
    with connect() as env:
        obs = env.reset()          # costs one step of the budget
        obs = env.step(action)     # costs one step: an action of {nu} values, held for {n_substeps} physics steps
        obs = env.observe()        # free: {observation}{extra}
        env.info()                 # free: steps_used, budget and model dimensions

Budget: {budget}. Resets and executed actions are recorded in a sealed ledger kept by the server
outside this workspace; call env.seal() only when you are done (it ends the session).{sessions}
"""

ADDRESS = {address!r}


def connect():
    """A new connection to the ledger server (the session persists across connections)."""
    from rle_design.ledger import LedgerClient

    return LedgerClient(ADDRESS)
'''


@dataclass
class DevWorkspace:
    """A laid-out workspace and, when metered, its running ledger server.

    Attributes:
        task_id: The task.
        workspace: The agent's workspace directory.
        files: Paths written into the workspace, relative to it, sorted.
        server: The ledger server (None when the task is not metered or ``serve=False``).
        ledger_path: The ledger the server writes (outside the workspace), or None.
    """

    task_id: str
    workspace: Path
    files: tuple[str, ...]
    server: LedgerServer | None = None
    ledger_path: Path | None = None

    def close(self) -> None:
        """Seal the ledger and stop the server, if one runs."""
        if self.server is not None:
            self.server.stop()


def ledger_key(secret: Secret, task_id: str) -> bytes:
    """Ledger HMAC key of ``task_id``: HMAC-SHA256(secret, label | task_id) [32 bytes]."""
    return hmac.digest(secret.key, LEDGER_LABEL + b"|" + task_id.encode(), hashlib.sha256)


def _socket_path(workspace: Path) -> Path:
    path = workspace / ".rle" / "ledger.sock"
    if len(str(path)) <= 100:
        path.parent.mkdir(exist_ok=True)
        return path
    digest = hashlib.sha256(str(workspace).encode()).hexdigest()[:16]
    return Path(tempfile.gettempdir()) / f"rle-ledger-{digest}.sock"


def _next_ledger(ledger_dir: Path) -> Path:
    ledger_dir.mkdir(parents=True, exist_ok=True)
    n = 1 + sum(1 for _ in ledger_dir.glob("session-*.jsonl"))
    while (ledger_dir / f"session-{n:03d}.jsonl").exists():
        n += 1
    return ledger_dir / f"session-{n:03d}.jsonl"


def layout_workspace(
    spec: TaskSpec,
    workspace: Path,
    serve: bool = True,
    *,
    secret: Secret | None = None,
    ledger_dir: Path | None = None,
) -> DevWorkspace:
    """Lay out the workspace of ``spec`` and start its ledger server when metered and ``serve``.

    Raises:
        RleError: ``task.not_implemented`` for a registered task without an implementation.
    """
    if not spec.implemented:
        raise RleError(
            f"task '{spec.id}' is registered but not implemented yet: it has no development environment. "
            "See `rle tasks` for the implemented ones",
            code="task.not_implemented",
        )
    workspace = Path(workspace).resolve()
    workspace.mkdir(parents=True, exist_ok=True)
    (workspace / "instruction.md").write_text(spec.instruction.rstrip() + "\n")
    env = spec.make_dev_env(workspace) if spec.make_dev_env is not None else None
    ws = DevWorkspace(spec.id, workspace, ())
    if isinstance(env, (MeteredEnv, SceneSet)):
        if isinstance(env, SceneSet):
            nu = env.action_size()
            sessions = "\n\n" + env.session_doc()
        else:
            from mujoco import MjModel

            nu = env.action_size(MjModel.from_xml_string(env.xml))
            sessions = ""
        socket_path = _socket_path(workspace)
        extra = "".join(f", {name}" for name, _ in getattr(env, "observers", ()))
        budget = (
            f"{spec.budget.steps} charged steps" if spec.budget.steps is not None else "unmetered (unlimited)"
        )
        (workspace / "client.py").write_text(
            _CLIENT.format(
                task_id=spec.id,
                nu=nu,
                n_substeps=env.n_substeps,
                observation=env.observation_doc,
                extra=extra,
                budget=budget,
                address=str(socket_path),
                sessions=sessions,
            )
        )
        if serve:
            ws.ledger_path = _next_ledger(ledger_dir or workspace.with_name(workspace.name + ".ledger"))
            key = ledger_key(secret if secret is not None else load_secret(), spec.id)
            ws.server = LedgerServer(
                env,
                key=key,
                ledger_path=ws.ledger_path,
                socket_path=socket_path,
                task_id=spec.id,
                budget=spec.budget.steps,
                wall_time_s=spec.budget.wall_time_s,
            )
            del key
            ws.server.start()
    elif serve and env is not None and callable(getattr(env, "start", None)):
        # a served environment of the family's own (renders, evaluations): same key, ledger and socket
        ws.ledger_path = _next_ledger(ledger_dir or workspace.with_name(workspace.name + ".ledger"))
        key = ledger_key(secret if secret is not None else load_secret(), spec.id)
        env.start(key=key, ledger_path=ws.ledger_path, socket_path=_socket_path(workspace))
        del key
        ws.server = env
    ws.files = tuple(sorted(str(p.relative_to(workspace)) for p in workspace.rglob("*") if p.is_file()))
    return ws


def make_workspace(task_id: str, workspace: Path, serve: bool = True, *, wait: bool = True) -> DevWorkspace:
    """``rle dev TASK --workspace DIR``: lay out the workspace and serve its metered environment.

    With a metered environment and ``serve``, prints how to connect and, with ``wait``, blocks until
    a client seals the session; Ctrl-C (KeyboardInterrupt) seals the ledger and stops the server.

    Raises:
        RleError: ``task.unknown`` or ``task.not_implemented`` (the CLI exits with status 2).
    """
    from rle_tasks.core.registry import get_task

    ws = layout_workspace(get_task(task_id), workspace, serve)
    tops: dict[str, int] = {}
    for f in ws.files:
        top = f.split("/", 1)[0]
        tops[top] = tops.get(top, 0) + 1
    shown = ", ".join(f"{t}/ ({n} files)" if n > 1 or "/" in t else t for t, n in sorted(tops.items()))
    print(f"workspace {ws.workspace} laid out for {task_id}: {shown or '(no files)'}")
    if ws.server is not None:
        print(
            f"metered environment listening on {ws.server.socket_path}; connect with "
            f"`from client import connect` in the workspace. Ledger: {ws.ledger_path}. "
            "Ctrl-C seals the ledger and stops the server.",
            flush=True,
        )
        if wait:
            try:
                ws.server.wait()
            except KeyboardInterrupt:
                ws.close()
                print(f"ledger sealed: {ws.ledger_path}")
    return ws
