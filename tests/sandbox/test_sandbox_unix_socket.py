"""A sandboxed child may reach one named Unix socket (a metered session's server) and nothing else."""

from __future__ import annotations

import os
import shutil
import sys
import tempfile
from pathlib import Path

import pytest

from rle_design.ledger import LedgerServer, verify_ledger
from rle_design.sandbox import ParticipantFault, Sandbox, SandboxLimits

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "ledger"))
from test_scene_sessions import KEY, Sliders  # noqa: E402

AGENT = """
import socket

def drive(address):
    from rle_design.ledger import LedgerClient

    with LedgerClient(address) as c:
        c.reset(evaluation=True)
        obs = c.step([100.0])
        return [float(obs["qpos"][0]), int(c.info()["steps_used"])]

def other_socket(address):
    s = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    s.connect(address)

def inet_socket():
    socket.socket(socket.AF_INET, socket.SOCK_STREAM)
"""


@pytest.fixture()
def served(tmp_path):
    sock_dir = Path(tempfile.mkdtemp(prefix="rle-sock-"))  # every ancestor searchable by the child's uid
    server = LedgerServer(
        Sliders(),
        key=KEY,
        ledger_path=tmp_path / "l.jsonl",
        socket_path=sock_dir / "s.sock",
        task_id="t",
        budget=10,
    )
    server.start()
    os.chmod(sock_dir, 0o711)
    os.chmod(server.socket_path, 0o666)  # the child may run as an unprivileged uid
    yield server
    server.stop()
    shutil.rmtree(sock_dir, ignore_errors=True)


def _sandbox(tmp_path: Path, socket_path: Path) -> Sandbox:
    mod = tmp_path / "agent" / "agent.py"
    mod.parent.mkdir()
    mod.write_text(AGENT)
    return Sandbox(
        mod, limits=SandboxLimits(call_timeout_s=60.0, startup_timeout_s=30.0, unix_socket=str(socket_path))
    )


def test_child_drives_the_session_through_the_allowed_socket(tmp_path, served):
    with _sandbox(tmp_path, served.socket_path) as box:
        x, steps = box.call("drive", str(served.socket_path))
    assert x > 0 and steps == 2
    served.stop()
    assert verify_ledger(tmp_path / "l.jsonl", KEY, "t").valid


def test_every_other_socket_stays_refused(tmp_path, served):
    with _sandbox(tmp_path, served.socket_path) as box:
        with pytest.raises(ParticipantFault) as exc:
            box.call("other_socket", str(tmp_path / "elsewhere.sock"))
        assert "network access (socket.connect)" in exc.value.message
    (tmp_path / "b").mkdir()
    with _sandbox(tmp_path / "b", served.socket_path) as box:
        with pytest.raises(ParticipantFault) as exc:
            box.call("inet_socket")
        assert "network access (socket.__new__)" in exc.value.message
