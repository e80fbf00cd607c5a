"""The policy socket protocol (family 05): how an evaluator asks a served policy for actions.

It lives in the toolkit so that a sandboxed ``solution.py`` can import it (``rle_tasks`` is not
importable there); ``serve`` is the policy side, ``PolicyServer`` the evaluator side.

The evaluator listens on a Unix-domain socket; the served policy (``solution.py`` in the sandbox,
which may connect to that one socket and nothing else) connects and answers requests until the
evaluator says goodbye. Every message is one frame::

    b"RLP1" | uint32 header length | uint32 payload length | header (UTF-8 JSON) | payload

(lengths big-endian). The header names the message ``type`` and describes each array in the payload
(``name``, ``dtype``, ``shape``), concatenated in order, C-contiguous, little-endian.

Messages:

* ``act`` (evaluator -> policy): ``instruction`` (the task's language), ``episode`` and ``step``
  (ints), arrays ``views`` uint8 (2, 128, 128, 3) (agent view and wrist view, upright) and
  ``state`` float32 (d,) (LIBERO d = 8: end-effector position, axis-angle, two finger positions;
  the bimanual stand-in d = 16);
* ``actions`` (policy -> evaluator): array ``actions`` float32 (k, a), 1 <= k <= 64, a = 7 (LIBERO:
  delta end-effector pose and gripper, in [-1, 1]) or 14 (stand-in joint targets); all finite;
* ``bye`` (evaluator -> policy): no more requests; the policy returns.

The evaluator executes a reply's actions in order, then asks again. ``PolicyServer.act`` checks a
reply before it is used: a malformed frame, a wrong shape or dtype, a chunk outside 1..64, a
non-finite action or a reply later than the per-request limit is a ``ProtocolError`` with its own
code (``protocol.*``).
"""

from __future__ import annotations

import contextlib
import json
import os
import socket
import struct
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from rle_design.errors import RleError
from rle_design.excerpt import excerpt

MAGIC = b"RLP1"
VIEW_SHAPE = (2, 128, 128, 3)
MAX_CHUNK = 64
MAX_FRAME_BYTES = 4 << 20
"""Largest frame either side accepts [B]: a request is ~98 KB, a full 64 x 14 reply 3.6 KB."""
DIMS = {"libero": (8, 7), "standin": (16, 14)}
"""(state, action) dimensions per environment."""
_HEAD = struct.Struct(">4sII")

__all__ = [
    "DIMS",
    "MAX_CHUNK",
    "VIEW_SHAPE",
    "PolicyServer",
    "ProtocolError",
    "Request",
    "recv_frame",
    "send_frame",
    "serve",
]


class ProtocolError(RleError):
    """A frame or message that breaks the protocol; ``code`` is ``protocol.<what>``."""

    def __init__(self, what: str, message: str) -> None:
        super().__init__(message, code=f"protocol.{what}")


@dataclass(frozen=True)
class Request:
    """One ``act`` request.

    Attributes:
        instruction: The task's language instruction.
        views: uint8 (2, 128, 128, 3): agent view, wrist view.
        state: float32 (d,) robot state.
        episode: Episode index within the evaluation.
        step: Environment step at which the request is made.
    """

    instruction: str
    views: np.ndarray
    state: np.ndarray
    episode: int = 0
    step: int = 0


def _recv_exact(sock: socket.socket, n: int, deadline: float | None) -> bytes:
    buf = bytearray()
    while len(buf) < n:
        if deadline is not None:
            left = deadline - time.monotonic()
            if left <= 0:
                raise ProtocolError("timeout", f"no complete frame within the time limit ({len(buf)}/{n} B)")
            sock.settimeout(left)
        try:
            chunk = sock.recv(min(n - len(buf), 1 << 20))
        except TimeoutError:
            raise ProtocolError(
                "timeout", f"no complete frame within the time limit ({len(buf)}/{n} B)"
            ) from None
        if not chunk:
            raise ProtocolError("closed", "the peer closed the connection")
        buf += chunk
    return bytes(buf)


def send_frame(sock: socket.socket, kind: str, arrays: dict[str, np.ndarray] | None = None, **fields) -> None:
    """Send one message: ``kind`` with JSON ``fields`` and ``arrays`` (name -> array)."""
    specs, parts = [], []
    for name, a in (arrays or {}).items():
        a = np.ascontiguousarray(a)
        le = a.astype(a.dtype.newbyteorder("<"), copy=False)
        specs.append({"name": name, "dtype": a.dtype.str.lstrip("<>|="), "shape": list(a.shape)})
        parts.append(le.tobytes())
    header = json.dumps({"type": kind, **fields, "arrays": specs}).encode()
    payload = b"".join(parts)
    sock.sendall(_HEAD.pack(MAGIC, len(header), len(payload)) + header + payload)


def recv_frame(
    sock: socket.socket, timeout_s: float | None = None, max_bytes: int = MAX_FRAME_BYTES
) -> tuple[dict, dict[str, np.ndarray]]:
    """Receive one message: ``(header, arrays)``; raises ``ProtocolError`` on anything malformed."""
    deadline = None if timeout_s is None else time.monotonic() + timeout_s
    magic, hlen, plen = _HEAD.unpack(_recv_exact(sock, _HEAD.size, deadline))
    if magic != MAGIC:
        raise ProtocolError("frame", f"frame starts with {excerpt(magic, 20)}, not {MAGIC!r}")
    if hlen + plen > max_bytes:
        raise ProtocolError("too_large", f"frame of {hlen + plen} B exceeds {max_bytes} B")
    try:
        header = json.loads(_recv_exact(sock, hlen, deadline))
    except (UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise ProtocolError("frame", f"header is not UTF-8 JSON: {excerpt(exc)}") from None
    payload = _recv_exact(sock, plen, deadline)
    if not isinstance(header, dict) or not isinstance(header.get("type"), str):
        raise ProtocolError("frame", "header must be a JSON object with a string 'type'")
    arrays, offset = {}, 0
    for spec in header.get("arrays", []):
        try:
            dtype = np.dtype(str(spec["dtype"])).newbyteorder("<")
            shape = tuple(int(s) for s in spec["shape"])
            if dtype.kind not in "uif" or any(s < 0 for s in shape):
                raise ValueError(f"dtype {dtype} / shape {shape}")
            n = int(np.prod(shape, dtype=np.int64)) * dtype.itemsize
        except (KeyError, TypeError, ValueError) as exc:
            raise ProtocolError("frame", f"bad array description {excerpt(spec)}: {excerpt(exc)}") from None
        if offset + n > len(payload):
            raise ProtocolError("frame", f"array {excerpt(spec.get('name'), 40)} runs past the payload")
        arrays[str(spec.get("name"))] = np.frombuffer(
            payload, dtype, count=n // dtype.itemsize, offset=offset
        ).reshape(shape)
        offset += n
    if offset != len(payload):
        raise ProtocolError("frame", f"payload has {len(payload) - offset} B that no array describes")
    return header, arrays


def check_actions(actions: np.ndarray, action_dim: int) -> np.ndarray:
    """A reply's actions as float32 (k, action_dim); raises ``ProtocolError`` naming the fault."""
    a = np.asarray(actions)
    if a.ndim != 2 or a.shape[1] != action_dim:
        raise ProtocolError("shape", f"actions must have shape (k, {action_dim}), got {excerpt(a.shape, 40)}")
    if not 1 <= a.shape[0] <= MAX_CHUNK:
        raise ProtocolError(
            "chunk_size", f"a reply carries 1..{MAX_CHUNK} actions, got {excerpt(a.shape[0], 20)}"
        )
    if a.dtype.kind != "f":
        raise ProtocolError("dtype", f"actions must be floating point, got {excerpt(a.dtype, 20)}")
    if not np.all(np.isfinite(a)):
        raise ProtocolError("non_finite", "actions contain NaN or infinity")
    return a.astype(np.float32)


def serve(
    socket_path: str | os.PathLike, policy: Callable[[Request], np.ndarray], env: str = "libero"
) -> int:
    """Policy side: connect to the evaluator at ``socket_path`` and answer ``act`` requests with
    ``policy(request)`` ((k, a) actions) until ``bye``. Returns the number of requests answered.

    This is the reference implementation of the wire format; a solution may speak it itself.
    """
    state_dim, action_dim = DIMS[env]
    with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as sock:
        sock.connect(str(socket_path))
        n = 0
        while True:
            header, arrays = recv_frame(sock)
            if header["type"] == "bye":
                return n
            if header["type"] != "act":
                raise ProtocolError("type", f"unexpected message type {excerpt(header['type'], 40)}")
            req = Request(
                str(header.get("instruction", "")),
                arrays["views"],
                arrays["state"],
                int(header.get("episode", 0)),
                int(header.get("step", 0)),
            )
            if req.state.shape != (state_dim,):
                raise ProtocolError("shape", f"state must have shape ({state_dim},), got {req.state.shape}")
            send_frame(sock, "actions", {"actions": check_actions(policy(req), action_dim)})
            n += 1


class PolicyServer:
    """Evaluator side: listen on ``socket_path``, accept the served policy, ask it for actions.

    Args:
        socket_path: Where to listen (its directory must exist; the file is created).
        env: ``"libero"`` or ``"standin"`` (state and action dimensions, ``DIMS``).
        request_timeout_s: Largest time a reply may take [s].
    """

    def __init__(
        self, socket_path: str | os.PathLike, env: str = "libero", request_timeout_s: float = 10.0
    ) -> None:
        self.path = Path(socket_path)
        self.state_dim, self.action_dim = DIMS[env]
        self.request_timeout_s = request_timeout_s
        self._listener = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
        self._listener.bind(str(self.path))
        os.chmod(self.path, 0o666)  # the sandboxed policy may run as an unprivileged uid
        self._listener.listen(1)
        self._conn: socket.socket | None = None
        self.requests = 0

    def accept(self, timeout_s: float) -> None:
        """Wait for the policy to connect; ``protocol.no_policy`` when it does not within ``timeout_s``."""
        self._listener.settimeout(timeout_s)
        try:
            self._conn, _ = self._listener.accept()
        except TimeoutError:
            raise ProtocolError("no_policy", f"the policy did not connect within {timeout_s:.0f} s") from None

    def act(self, req: Request) -> np.ndarray:
        """The policy's next chunk of actions, float32 (k, a), checked."""
        if self._conn is None:
            raise ProtocolError("closed", "no policy is connected")
        views = np.asarray(req.views, np.uint8)
        state = np.asarray(req.state, np.float32)
        if views.shape != VIEW_SHAPE or state.shape != (self.state_dim,):
            raise ValueError(f"request views {views.shape} / state {state.shape} do not match the protocol")
        send_frame(
            self._conn, "act", {"views": views, "state": state},
            instruction=req.instruction, episode=int(req.episode), step=int(req.step),
        )  # fmt: skip
        header, arrays = recv_frame(self._conn, self.request_timeout_s)
        if header["type"] != "actions" or "actions" not in arrays:
            raise ProtocolError("type", f"expected an 'actions' reply, got {excerpt(header['type'], 40)}")
        self.requests += 1
        return check_actions(arrays["actions"], self.action_dim)

    def close(self) -> None:
        if self._conn is not None:
            with contextlib.suppress(OSError):
                send_frame(self._conn, "bye")
            self._conn.close()
            self._conn = None
        self._listener.close()
        self.path.unlink(missing_ok=True)

    def __enter__(self) -> PolicyServer:
        return self

    def __exit__(self, *exc) -> None:
        self.close()
