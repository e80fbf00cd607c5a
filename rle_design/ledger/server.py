"""The ledger server: a separate process that owns the key, the ledger file and the simulator.

The agent talks to it over a Unix socket with ``LedgerClient``; messages are the sandbox's typed,
pickle-free frames (``rle_design.sandbox.codec``), so nothing the agent sends is ever unpickled by
the process that holds the key. The server seals the ledger when a client asks (``seal``), on
SIGTERM/SIGINT, or when ``LedgerServer.stop`` is called.
"""

from __future__ import annotations

import contextlib
import multiprocessing as mp
import os
import signal
from multiprocessing.connection import Connection, Listener
from pathlib import Path
from typing import Any

from rle_design.ledger.records import LedgerError
from rle_design.ledger.session import MeteredEnv, MeteredSession
from rle_design.sandbox import codec

MAX_MESSAGE_BYTES = 16 << 20


class _Stop(Exception):
    pass


def _on_signal(signum: int, frame: Any) -> None:
    raise _Stop


def die_with_parent() -> None:
    """Ask Linux to send this process SIGTERM (which seals) when its parent dies
    (``prctl(PR_SET_PDEATHSIG)``): a server whose ``rle dev`` was killed does not run on unowned."""
    import ctypes
    import sys

    if sys.platform.startswith("linux"):
        with contextlib.suppress(OSError, AttributeError):
            ctypes.CDLL(None, use_errno=True).prctl(1, signal.SIGTERM, 0, 0, 0)  # PR_SET_PDEATHSIG


def encode(meta: dict[str, Any], value: Any = None) -> bytes:
    """One frame as bytes."""
    return b"".join(bytes(p) for p in codec.encode_frame(meta, value))


def decode(message: bytes) -> tuple[dict[str, Any], Any]:
    """(meta, value) of one frame; raises ``codec.CodecError`` when malformed."""
    if len(message) < codec.PREFIX.size:
        raise codec.CodecError("message shorter than the frame prefix")
    n_header, n_payload = codec.parse_prefix(message[: codec.PREFIX.size])
    end = codec.PREFIX.size + n_header
    if end + n_payload != len(message):
        raise codec.CodecError("frame lengths do not match the message")
    return codec.decode_frame(message[codec.PREFIX.size : end], bytearray(message[end:]))


def _handle(session: MeteredSession, meta: dict[str, Any], value: Any) -> tuple[dict[str, Any], Any]:
    op = meta.get("op")
    if op == "step":
        obs = session.step(value, defer_record=True)  # recorded right after the reply is sent
        if session.last_clipped:
            return {"ok": True, "steps_used": session.steps_used, "clipped": session.last_clipped}, obs
    elif op == "reset":
        if value is not None and not isinstance(value, dict):
            raise LedgerError("reset options must be a dict", code="ledger.bad_request")
        obs = session.reset(value)
    elif op == "observe":
        obs = session.observe()
    elif op == "info":
        return {"ok": True}, session.info()
    elif op == "query":
        if not (
            isinstance(value, dict)
            and isinstance(value.get("name"), str)
            and isinstance(value.get("args", {}), dict)
        ):
            raise LedgerError("a query is {'name': str, 'args': dict}", code="ledger.bad_request")
        return {"ok": True}, session.query(value["name"], value.get("args", {}))
    elif op == "seal":
        return {"ok": True, "steps_used": session.steps_used}, session.seal()
    else:
        raise LedgerError(
            f"unknown operation {op!r}. Operations: reset, step, observe, info, query, seal",
            code="ledger.bad_request",
        )
    return {"ok": True, "steps_used": session.steps_used}, obs


def _serve_connection(session: MeteredSession, conn: Connection) -> None:
    while not session.sealed:
        try:
            message = conn.recv_bytes(MAX_MESSAGE_BYTES)
        except (EOFError, OSError):
            return
        try:
            meta, value = decode(message)
            reply = encode(*_handle(session, meta, value))
        except LedgerError as exc:
            reply = encode({"ok": False, "code": exc.code, "message": exc.message})
        except codec.CodecError as exc:
            reply = encode(
                {"ok": False, "code": "ledger.bad_request", "message": f"malformed request: {exc}"}
            )
        except Exception as exc:  # noqa: BLE001 - a server-side bug (e.g. an observer) must not end the session
            text = f"server error: {type(exc).__name__}: {exc}"
            reply = encode({"ok": False, "code": "ledger.internal", "message": text})
        try:
            conn.send_bytes(reply)
        except OSError:
            return
        finally:
            session.commit(force=False)


def serve(
    env: MeteredEnv,
    *,
    key: bytes | None,
    ledger_path: Path | None,
    socket_path: Path,
    task_id: str,
    budget: int | None,
    actions_per_record: int = 16,
    wall_time_s: float | None = None,
    attempt: str = "",
    ready: Connection | None = None,
    socket_mode: int | None = None,
    meta: dict | None = None,
) -> None:
    """Serve one metered session until sealed or signalled (runs in the server process).

    ``env`` is a ``MeteredEnv``, or any definition with ``open_session(**kwargs)`` (a
    ``rle_design.ledger.SceneSet``) that returns its own session."""
    signal.signal(signal.SIGTERM, _on_signal)
    signal.signal(signal.SIGINT, _on_signal)
    die_with_parent()
    session = None
    opener = getattr(env, "open_session", None) or (lambda **kw: MeteredSession(env, **kw))
    try:
        session = opener(
            task_id=task_id,
            budget=budget,
            key=key,
            ledger_path=ledger_path,
            actions_per_record=actions_per_record,
            wall_time_s=wall_time_s,
            attempt=attempt,
            **({"meta": meta} if meta else {}),
        )
        del key
        old_umask = os.umask(0o077)
        try:
            listener = Listener(str(socket_path), family="AF_UNIX")
            if socket_mode is not None:  # an agent of another uid connects (a Harbor sidecar's socket)
                os.chmod(socket_path, socket_mode)
        finally:
            os.umask(old_umask)
    except (LedgerError, OSError) as exc:
        if ready is not None:
            ready.send(("error", getattr(exc, "code", "ledger.server"), str(exc)))
        return
    if ready is not None:
        ready.send(("ready", "", ""))
        ready.close()
    try:
        while not session.sealed:
            with listener.accept() as conn:
                _serve_connection(session, conn)
    except _Stop:
        pass
    finally:
        session.seal()
        listener.close()


class LedgerServer:
    """Starts ``serve`` in its own (spawned) process; the caller never keeps the key afterwards.

    Args:
        env: The metered environment (or a ``SceneSet``).
        key: Ledger HMAC key [bytes]; handed to the server process at start. None serves the same
            environment unmetered, without a ledger (only to measure the metering overhead).
        ledger_path: New ledger file written by the server (None when unmetered).
        socket_path: Unix socket the agent connects to (at most ~100 characters).
        task_id: Task the ledger belongs to.
        budget: Charged steps allowed, or None for unlimited.
        actions_per_record: Executed actions grouped per ledger record (see ``MeteredSession``).
        wall_time_s: Wall-clock time the session may charge steps for [s] (see ``MeteredSession``).
        attempt: The attempt the session belongs to (recorded in the ledger's open record).
        socket_mode: Permission bits of the socket (default 0600: only the server's uid connects).
        meta: Extra fields of the ledger's open record (``{"privileged": True}`` for an operator's
            oracle session).
    """

    def __init__(
        self,
        env: MeteredEnv | Any,
        *,
        key: bytes | None,
        ledger_path: Path | None,
        socket_path: Path,
        task_id: str,
        budget: int | None,
        actions_per_record: int = 16,
        wall_time_s: float | None = None,
        attempt: str = "",
        socket_mode: int | None = None,
        meta: dict | None = None,
    ) -> None:
        if len(str(socket_path)) > 100:
            raise LedgerError(
                f"socket path {socket_path} is longer than 100 characters", code="ledger.socket_path"
            )
        self.ledger_path = Path(ledger_path) if ledger_path is not None else None
        self.socket_path = Path(socket_path)
        ctx = mp.get_context("spawn")
        parent, child = ctx.Pipe(duplex=False)
        self._ready = parent
        kwargs = dict(
            key=key,
            ledger_path=self.ledger_path,
            socket_path=self.socket_path,
            task_id=task_id,
            budget=budget,
            actions_per_record=actions_per_record,
            wall_time_s=wall_time_s,
            attempt=attempt,
            socket_mode=socket_mode,
            meta=meta,
        )
        self._process = ctx.Process(
            target=serve,
            args=(env,),
            kwargs={**kwargs, "ready": child},
            name=f"rle-ledger-{task_id}",
            daemon=False,
        )
        self._child_end = child

    @property
    def alive(self) -> bool:
        return self._process.is_alive()

    def start(self, timeout: float = 120.0) -> None:
        """Start the server process and wait until it listens.

        Raises:
            LedgerError: the server could not start (model, ledger file or socket problem).
        """
        self._process.start()
        self._child_end.close()
        self._process._kwargs = {}  # type: ignore[attr-defined]  # drop our reference to the key
        if not self._ready.poll(timeout):
            self._process.kill()
            raise LedgerError(f"ledger server did not start within {timeout:g} s", code="ledger.server")
        try:
            status, code, message = self._ready.recv()
        except EOFError:
            raise LedgerError("ledger server died while starting", code="ledger.server") from None
        if status != "ready":
            self._process.join(5.0)
            raise LedgerError(message, code=code)

    def stop(self, timeout: float = 30.0) -> None:
        """Ask the server to seal and exit (SIGTERM), then wait for it."""
        if self._process.is_alive():
            self._process.terminate()
        self._process.join(timeout)
        if self._process.is_alive():
            self._process.kill()
            self._process.join(5.0)

    def wait(self, timeout: float | None = None) -> None:
        """Block until the server exits (after a client's ``seal`` or a signal)."""
        self._process.join(timeout)

    def __enter__(self) -> LedgerServer:
        self.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self.stop()
