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

The ledger file is written outside the workspace (``<workspace>.ledger/<attempt>.jsonl`` unless
``ledger_dir`` says otherwise), so the agent cannot reach it through the workspace; the key, the
secret and hidden seeds are never written anywhere in the workspace. ``rle dev`` keeps serving in the
foreground until a client calls ``seal()`` or the command is interrupted (Ctrl-C seals the ledger).

Attempts: every session belongs to one attempt, an id the operator issues (``--attempt``; a Harbor
trial's id) or, without one, derived from the workspace's path (``default_attempt``). The attempt is
recorded in the ledger's open record and mixed into the session's hidden scenes
(``Secret.for_attempt``); a metered attempt has one session: its ledger ``<attempt>.jsonl`` is created
once, and a second ``rle dev`` of the same attempt is refused (``ledger.attempt_used``). An operator
gives each attempt a fresh id and a ledger directory the agent cannot write, and verifies with
``rle verify --attempt ID`` so that a ledger of any other attempt is refused (``ledger.wrong_attempt``).
"""

from __future__ import annotations

import hashlib
import hmac
import os
import signal
import tempfile
import threading
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from rle_design.errors import RleError
from rle_design.ledger import LedgerServer, MeteredEnv, SceneSet, record_session
from rle_tasks.core.runtime.devservice import ADDRESS_FUNCTION
from rle_tasks.core.runtime.secrets import Secret, load_secret, using_secret
from rle_tasks.core.task import TaskSpec, privileged_dev

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

import hashlib
import tempfile
import warnings
from pathlib import Path

with warnings.catch_warnings():  # the simulator runs in the server: this process's BLAS kernels do not matter
    warnings.simplefilter("ignore", RuntimeWarning)
    import rle_design  # noqa: F401
{address_function}

def connect():
    """A new connection to the ledger server (the session persists across connections)."""
    from rle_design.ledger import LedgerClient

    return LedgerClient(_address())
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
        attempt: The attempt the session belongs to.
        environment: ``"metered"`` (a ledger server of ``MeteredEnv``/``SceneSet``), ``"served"`` (a
            family's own server) or ``""`` (no development server).
    """

    task_id: str
    workspace: Path
    files: tuple[str, ...]
    server: LedgerServer | None = None
    ledger_path: Path | None = None
    attempt: str = ""
    environment: str = ""

    def close(self) -> None:
        """Seal the ledger and stop the server, if one runs."""
        if self.server is not None:
            self.server.stop()


def ledger_key(secret: Secret, task_id: str) -> bytes:
    """Ledger HMAC key of ``task_id``: HMAC-SHA256(secret, label | task_id) [32 bytes]."""
    return hmac.digest(secret.key, LEDGER_LABEL + b"|" + task_id.encode(), hashlib.sha256)


def record_solution(
    env,
    play: Callable,
    ledger: Path,
    secret: Secret,
    task_id: str,
    budget: int | None,
    wall_time_s: float | None = None,
) -> Path:
    """A shipped solution's session: ``play(client)`` on ``env`` served under ``task_id``'s ledger key of
    ``secret``, in its attempt, with the card's ``budget`` and ``wall_time_s`` [s]; returns the sealed
    ``ledger`` (``rle_design.ledger.record_session``)."""
    return record_session(
        env,
        play,
        ledger,
        key=ledger_key(secret, task_id),
        task_id=task_id,
        budget=budget,
        wall_time_s=wall_time_s,
        attempt=secret.attempt,
    )


def _socket_path(workspace: Path) -> Path:
    path = workspace / ".rle" / "ledger.sock"
    if len(str(path)) <= 100:
        path.parent.mkdir(exist_ok=True)
        return path
    digest = hashlib.sha256(str(workspace).encode()).hexdigest()[:16]
    return Path(tempfile.gettempdir()) / f"rle-ledger-{digest}.sock"


def default_attempt(workspace: Path) -> str:
    """The attempt of a workspace laid out without ``--attempt``: ``ws-`` and 16 hex digits of its path."""
    return "ws-" + hashlib.sha256(str(Path(workspace).resolve()).encode()).hexdigest()[:16]


def attempt_ledger(ledger_dir: Path, attempt: str) -> Path:
    """The one ledger of a metered attempt; refused when the attempt already had its session.

    Raises:
        RleError: ``ledger.attempt_used``.
    """
    ledger_dir.mkdir(parents=True, exist_ok=True)
    path = ledger_dir / f"{attempt}.jsonl"
    if path.exists():
        raise RleError(
            f"attempt '{attempt}' has had its session already (ledger {path}); a task allows one session per "
            "attempt. Submit that ledger, or start a new attempt (a fresh workspace, or --attempt with a new id "
            "issued by the operator)",
            code="ledger.attempt_used",
            path=str(path),
        )
    return path


def _next_ledger(ledger_dir: Path, attempt: str) -> Path:
    """A served session's ledger: several processes of one attempt share its budget."""
    ledger_dir.mkdir(parents=True, exist_ok=True)
    n = 1
    while (ledger_dir / f"{attempt}-session-{n:03d}.jsonl").exists():
        n += 1
    return ledger_dir / f"{attempt}-session-{n:03d}.jsonl"


def layout_workspace(
    spec: TaskSpec,
    workspace: Path,
    serve: bool = True,
    *,
    secret: Secret | None = None,
    ledger_dir: Path | None = None,
    attempt: str | None = None,
    socket_mode: int | None = None,
    privileged: bool = False,
) -> DevWorkspace:
    """Lay out the workspace of ``spec`` and start its ledger server when metered and ``serve``.

    ``attempt`` (default: ``default_attempt(workspace)``) binds the session's hidden scenes and its
    ledger (module docstring). ``socket_mode`` opens the socket to other uids (a Harbor sidecar
    serving the agent's container through a shared volume; the default lets only this uid connect).
    ``privileged`` serves privileged observations for an operator's oracle trial (tasks with
    ``privileged_oracle`` only); the session's ledger records it and verifiers name it.

    Raises:
        RleError: ``task.not_implemented`` for a registered task without an implementation,
            ``ledger.attempt_used`` when the attempt has had its metered session,
            ``attempt.invalid`` for a malformed attempt id.
    """
    if not spec.implemented:
        raise RleError(
            f"task '{spec.id}' is registered but not implemented yet: it has no development environment. "
            "See `rle tasks` for the implemented ones",
            code="task.not_implemented",
        )
    if privileged and not spec.privileged_oracle:
        raise RleError(
            f"task '{spec.id}' has no privileged development environment (no oracle needs one)",
            code="task.no_privileged",
        )
    workspace = Path(workspace).resolve()
    attempt = default_attempt(workspace) if attempt is None else attempt
    bound = (secret if secret is not None else load_secret()).for_attempt(attempt)
    ledgers = ledger_dir or workspace.with_name(workspace.name + ".ledger")
    if serve and (ledgers / f"{attempt}.jsonl").exists():
        attempt_ledger(ledgers, attempt)  # refuses before anything is laid out or served
    workspace.mkdir(parents=True, exist_ok=True)
    (workspace / "instruction.md").write_text(spec.instruction.rstrip() + "\n")
    with using_secret(bound), privileged_dev(privileged):
        env = spec.make_dev_env(workspace) if spec.make_dev_env is not None else None
    ws = DevWorkspace(spec.id, workspace, (), attempt=attempt)
    if isinstance(env, (MeteredEnv, SceneSet)):
        ws.environment = "metered"
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
                address_function=ADDRESS_FUNCTION,
                sessions=sessions,
            )
        )
        if serve:
            ws.ledger_path = attempt_ledger(ledgers, attempt)
            key = ledger_key(bound, spec.id)
            ws.server = LedgerServer(
                env,
                key=key,
                ledger_path=ws.ledger_path,
                socket_path=socket_path,
                task_id=spec.id,
                budget=spec.budget.steps,
                wall_time_s=spec.budget.wall_time_s,
                attempt=attempt,
                socket_mode=socket_mode,
                meta={"privileged": True} if privileged else None,
            )
            del key
            ws.server.start()
    elif env is not None and callable(getattr(env, "start", None)):
        ws.environment = "served"
    if ws.environment == "served" and serve:
        # a served environment of the family's own (renders, evaluations): same key, ledger and socket
        ws.ledger_path = _next_ledger(ledgers, attempt)
        key = ledger_key(bound, spec.id)
        env.start(
            key=key,
            ledger_path=ws.ledger_path,
            socket_path=_socket_path(workspace),
            attempt=attempt,
            socket_mode=socket_mode,
        )
        del key
        ws.server = env
    ws.files = tuple(sorted(str(p.relative_to(workspace)) for p in workspace.rglob("*") if p.is_file()))
    return ws


def make_workspace(
    task_id: str,
    workspace: Path,
    serve: bool = True,
    *,
    wait: bool = True,
    attempt: str | None = None,
    ledger_dir: Path | None = None,
    socket_mode: int | None = None,
    prepare: Callable[[Path], None] | None = None,
    privileged: bool = False,
) -> DevWorkspace:
    """``rle dev TASK --workspace DIR [--attempt ID]``: lay out the workspace and serve its environment.

    With a metered environment and ``serve``, prints how to connect and, with ``wait``, blocks until
    a client seals the session; Ctrl-C or SIGTERM (also of a background ``rle dev &``) seals the
    ledger and stops the server. ``ledger_dir`` and ``socket_mode`` as for ``layout_workspace``;
    ``prepare(workspace)`` runs once the workspace is laid out and served (a Harbor sidecar hands it
    to the agent's uid); ``privileged`` as for ``layout_workspace``.

    Raises:
        RleError: ``task.unknown``, ``task.not_implemented``, ``ledger.attempt_used``,
            ``attempt.invalid`` (the CLI exits with status 2).
    """
    from rle_tasks.core.registry import get_task

    ws = layout_workspace(
        get_task(task_id),
        workspace,
        serve,
        attempt=attempt,
        ledger_dir=ledger_dir,
        socket_mode=socket_mode,
        privileged=privileged,
    )
    if prepare is not None:
        prepare(ws.workspace)
    tops: dict[str, int] = {}
    for f in ws.files:
        top = f.split("/", 1)[0]
        tops[top] = tops.get(top, 0) + 1
    shown = ", ".join(f"{t}/ ({n} files)" if n > 1 or "/" in t else t for t, n in sorted(tops.items()))
    if ws.server is not None:
        print(
            f"rle dev serves in the foreground (process {os.getpid()}): run it in its own terminal or with `&`"
        )
    print(f"workspace {ws.workspace} laid out for {task_id} (attempt {ws.attempt}): {shown or '(no files)'}")
    if ws.server is not None:
        print(
            f"Metered environment listening on {ws.server.socket_path}; connect with "
            f"`from {getattr(ws.server, 'client', 'client')} import connect` in the workspace. Ledger: {ws.ledger_path}. "
            f"Ctrl-C, `kill {os.getpid()}` or a client's seal() seals the ledger and stops the server.",
            flush=True,
        )
        if wait:
            main = threading.current_thread() is threading.main_thread()  # signals reach the main thread only
            sigs = (signal.SIGTERM, signal.SIGINT) if main else ()
            old = {sig: signal.signal(sig, _interrupt) for sig in sigs}
            try:
                ws.server.wait()
            except KeyboardInterrupt:
                ws.close()
                print(f"ledger sealed: {ws.ledger_path}", flush=True)
            finally:
                for sig, handler in old.items():
                    signal.signal(sig, handler)
    return ws


def _interrupt(signum: int, frame: object) -> None:
    raise KeyboardInterrupt
