"""The policy socket protocol, pinned by a test client: frames, checks, and a served solution driving
a LIBERO episode through the sandbox and the side environment."""

import socket
import struct
import threading

import numpy as np
import pytest

from rle_design.policy_socket import (
    MAX_CHUNK,
    VIEW_SHAPE,
    PolicyServer,
    ProtocolError,
    Request,
    recv_frame,
    send_frame,
    serve,
)

REQ = Request(
    "put the bowl on the plate", np.zeros(VIEW_SHAPE, np.uint8), np.arange(8, dtype=np.float32), 3, 40
)


def _served(tmp_path, policy, **kw):
    """A PolicyServer with ``serve(policy)`` connected from a thread (as a solution would)."""
    server = PolicyServer(tmp_path / "p.sock", **kw)
    result = {}

    def run():
        try:
            result["n"] = serve(tmp_path / "p.sock", policy)
        except ProtocolError as exc:
            result["error"] = exc.code

    t = threading.Thread(target=run, daemon=True)
    t.start()
    server.accept(5.0)
    return server, t, result


def test_a_request_reaches_the_policy_and_its_chunk_comes_back(tmp_path):
    seen = []

    def policy(req):
        seen.append(req)
        return np.full((5, 7), 0.25)

    server, t, result = _served(tmp_path, policy)
    with server:
        chunk = server.act(REQ)
    t.join(5.0)
    assert chunk.shape == (5, 7) and chunk.dtype == np.float32 and np.all(chunk == 0.25)
    (got,) = seen
    assert got.instruction == REQ.instruction and (got.episode, got.step) == (3, 40)
    assert got.views.shape == VIEW_SHAPE and got.views.dtype == np.uint8
    assert np.array_equal(got.state, REQ.state) and got.state.dtype == np.float32
    assert result == {"n": 1}  # the policy returned after 'bye'


@pytest.mark.parametrize(
    "actions, code",
    [
        (np.zeros((0, 7)), "protocol.chunk_size"),
        (np.zeros((MAX_CHUNK + 1, 7)), "protocol.chunk_size"),
        (np.zeros((4, 6)), "protocol.shape"),
        (np.array([[0.0] * 6 + [np.nan]]), "protocol.non_finite"),
    ],
)
def test_a_bad_reply_is_refused_by_name(tmp_path, actions, code):
    server = PolicyServer(tmp_path / "p.sock")
    client = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    client.connect(str(tmp_path / "p.sock"))
    server.accept(5.0)
    with server, client:
        send_frame(client, "actions", {"actions": actions})  # a hand-written reply, ahead of the request
        with pytest.raises(ProtocolError) as exc:
            server.act(REQ)
    assert exc.value.code == code


def test_a_slow_policy_times_out_and_garbage_is_a_frame_error(tmp_path):
    server = PolicyServer(tmp_path / "p.sock", request_timeout_s=0.2)
    client = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    client.connect(str(tmp_path / "p.sock"))
    server.accept(5.0)
    with server, client:
        with pytest.raises(ProtocolError, match="time limit") as exc:
            server.act(REQ)
        assert exc.value.code == "protocol.timeout"
        client.sendall(b"HTTP" + struct.pack(">II", 2, 0) + b"{}")
        with pytest.raises(ProtocolError) as exc:
            recv_frame(server._conn, 1.0)
        assert exc.value.code == "protocol.frame"


def test_a_frame_beyond_the_size_limit_is_refused_before_it_is_read(tmp_path):
    a, b = socket.socketpair()
    with a, b:
        a.sendall(b"RLP1" + struct.pack(">II", 10, 64 << 20))
        with pytest.raises(ProtocolError) as exc:
            recv_frame(b, 1.0)
    assert exc.value.code == "protocol.too_large"


SOLUTION = """
import numpy as np
from rle_design.policy_socket import serve as _serve

def serve(socket_path):
    # a constant chunk: hold still with the gripper open
    return _serve(socket_path, lambda req: np.tile(np.array([0, 0, 0, 0, 0, 0, -1.0], np.float32), ({k}, 1)))
"""


def test_a_served_solution_drives_a_libero_episode_through_the_sandbox(tmp_path, libero10_task0_rendered):
    from rle_tasks.envs.libero.client import run_episode, serving

    sol = tmp_path / "sol"
    sol.mkdir()
    (sol / "solution.py").write_text(SOLUTION.format(k=4))
    with serving(sol) as policy:
        res = run_episode(libero10_task0_rendered, policy, init_index=0, max_steps=10)
        assert policy.requests == 3  # chunks of 4 actions: steps 0, 4, 8
    assert res.steps == 10 and res.requests == 3 and not res.success and res.fault == ""


@pytest.mark.usefixtures("libero_side_env")
def test_a_solution_that_never_connects_is_named(tmp_path):
    from rle_tasks.envs.libero import client

    sol = tmp_path / "sol"
    sol.mkdir()
    (sol / "solution.py").write_text("def serve(socket_path):\n    raise RuntimeError('no checkpoint')\n")
    with pytest.raises(ProtocolError) as exc, client.serving(sol):
        pass
    assert exc.value.code == "protocol.no_policy" and "no checkpoint" in exc.value.message
    assert "its process ended" in exc.value.message
