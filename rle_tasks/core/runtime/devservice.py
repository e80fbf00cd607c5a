"""A family's served development session: a separate process that owns what the agent may not see.

Families whose development environment is not a ``MeteredEnv`` (renderers, evaluation clients) serve
a *session* object from a spawned process; the agent's client in the workspace talks to it over a
Unix socket with the ledger's typed, pickle-free frames (``rle_design.ledger.server.encode`` /
``decode``), so the scene, the simulator and the ledger key stay in this process.

A session is built by a module-level factory ``factory(key=, ledger_path=, **kwargs)`` named as
``"package.module:function"`` (so the spawned process can import it) and has:

* ``handle(meta, value) -> (reply meta, reply value)``: one request (``meta["op"]`` names it); a
  ``LedgerError`` becomes an ``{"ok": False, "code", "message"}`` reply;
* ``sealed``: the session has ended (a ``seal`` request, usually);
* ``seal()``: close the ledger (called once more when the process is stopped; must be idempotent).

``ServedSession`` is what a family's ``make_dev_env`` returns: core ``devenv`` starts it with the
ledger key and a ledger path outside the workspace (``start(key=, ledger_path=, socket_path=)``).
"""

from __future__ import annotations

import importlib
import multiprocessing as mp
import os
import signal
from multiprocessing.connection import Connection, Listener
from pathlib import Path
from typing import Any

from rle_design.ledger.records import LedgerError
from rle_design.ledger.server import MAX_MESSAGE_BYTES, decode, die_with_parent, encode
from rle_design.sandbox import codec

STARTUP_S = 180.0
"""How long a session process may take to listen [s]."""


class _Stop(Exception):
    pass


def _on_signal(signum: int, frame: Any) -> None:
    raise _Stop


def _factory(name: str):
    module, _, attr = name.partition(":")
    return getattr(importlib.import_module(module), attr)


def serve(
    factory: str,
    kwargs: dict[str, Any],
    socket_path: str,
    key: bytes | None,
    ledger_path: str | None,
    ready: Connection | None = None,
    attempt: str = "",
    socket_mode: int | None = None,
) -> None:
    """Serve one development session until sealed or signalled (runs in the server process).

    SIGTERM, SIGINT and the death of the process that started it (``rle dev`` killed in any way)
    seal the ledger and remove the socket."""
    signal.signal(signal.SIGTERM, _on_signal)
    signal.signal(signal.SIGINT, _on_signal)
    die_with_parent()
    path = Path(ledger_path) if ledger_path else None
    session = _factory(factory)(key=key, ledger_path=path, attempt=attempt, **kwargs)
    del key
    old = os.umask(0o077)
    try:
        listener = Listener(socket_path, family="AF_UNIX")
        if socket_mode is not None:  # an agent of another uid connects (a Harbor sidecar's socket)
            os.chmod(socket_path, socket_mode)
    finally:
        os.umask(old)
    if ready is not None:
        ready.send("ready")
        ready.close()
    try:
        while not session.sealed:
            with listener.accept() as conn:
                while not session.sealed:
                    try:
                        message = conn.recv_bytes(MAX_MESSAGE_BYTES)
                    except (EOFError, OSError):
                        break
                    try:
                        reply = encode(*session.handle(*decode(message)))
                    except LedgerError as exc:
                        reply = encode({"ok": False, "code": exc.code, "message": exc.message})
                    except codec.CodecError as exc:
                        reply = encode({"ok": False, "code": "ledger.bad_request", "message": str(exc)})
                    conn.send_bytes(reply)
    except _Stop:
        pass
    finally:
        session.seal()
        listener.close()


def start(
    factory: str,
    kwargs: dict[str, Any],
    socket_path: Path,
    key: bytes | None,
    ledger_path: Path | None,
    name: str = "rle-dev",
    attempt: str = "",
    socket_mode: int | None = None,
):
    """Start ``serve`` in a spawned process and wait until it listens; returns the process."""
    ctx = mp.get_context("spawn")
    parent, child = ctx.Pipe(duplex=False)
    proc = ctx.Process(
        target=serve,
        args=(
            factory,
            kwargs,
            str(socket_path),
            key,
            str(ledger_path) if ledger_path else None,
            child,
            attempt,
            socket_mode,
        ),
        name=name,
    )
    proc.start()
    child.close()
    if not parent.poll(STARTUP_S):
        proc.terminate()
        raise LedgerError(
            f"the development server did not start within {STARTUP_S:.0f} s", code="ledger.server"
        )
    parent.recv()
    return proc


class ServedSession:
    """A family's served development environment (started by ``rle dev``).

    Args:
        factory: ``"module:function"`` building the session (module docstring).
        kwargs: Further keyword arguments of the factory (picklable).
        name: Process name.
        client: The workspace's client module (what the agent imports ``connect`` from).
    """

    def __init__(
        self, factory: str, kwargs: dict[str, Any], name: str = "rle-dev", client: str = "client"
    ) -> None:
        self.factory = factory
        self.kwargs = dict(kwargs)
        self.name = name
        self.client = client
        self.socket_path: Path | None = None
        self._proc = None

    def start(
        self,
        *,
        key: bytes,
        ledger_path: Path,
        socket_path: Path,
        attempt: str = "",
        socket_mode: int | None = None,
    ) -> None:
        self.socket_path = Path(socket_path)
        if self.socket_path.exists():
            self.socket_path.unlink()
        self._proc = start(
            self.factory, self.kwargs, self.socket_path, key, ledger_path, self.name, attempt, socket_mode
        )

    def stop(self, timeout: float = 30.0) -> None:
        """Seal the ledger (SIGTERM) and wait for the server to end."""
        if self._proc is not None and self._proc.is_alive():
            self._proc.terminate()
            self._proc.join(timeout)

    def wait(self, timeout: float | None = None) -> None:
        if self._proc is not None:
            self._proc.join(timeout)


ADDRESS_FUNCTION = """
def _address():
    # the socket beside this file (core devenv's socket path, from the client's side), so the same
    # client reaches `rle dev` and a Harbor sidecar serving the workspace's .rle/ over a shared volume
    ws = Path(__file__).resolve().parent
    path = ws / ".rle" / "ledger.sock"
    if len(str(path)) <= 100:
        return str(path)
    digest = hashlib.sha256(str(ws).encode()).hexdigest()[:16]
    return str(Path(tempfile.gettempdir()) / f"rle-ledger-{digest}.sock")
"""
"""Source of ``_address()`` in the workspace clients (it needs ``hashlib``, ``tempfile``, ``Path``)."""

CLIENT_ADDRESS = (
    ADDRESS_FUNCTION
    + """

class _Connection:
    # one connection to the development server; a context manager

    def __init__(self):
        self._conn = Client(_address(), family="AF_UNIX")

    def _request(self, op, value=None):
        self._conn.send_bytes(encode({"op": op}, value))
        meta, out = decode(self._conn.recv_bytes())
        if not meta.get("ok"):
            raise RuntimeError(f"{meta.get('code')}: {meta.get('message')}")
        return out

    def info(self):
        return self._request("info")

    def seal(self):
        return self._request("seal")

    def close(self):
        self._conn.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
"""
)
"""Source of the workspace clients' ``_address()`` (core ``devenv``'s socket path, from the client's
side) and ``_Connection`` (requests, ``info``, ``seal``, a context manager); a client module imports
``hashlib``, ``tempfile``, ``Path``, ``multiprocessing.connection.Client`` and the ledger's
``encode``/``decode`` before it and subclasses ``_Connection`` with its operations."""
