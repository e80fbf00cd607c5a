"""Happy path: arrays in and out, latency, working directory, environment, isolation layers, codec."""

from __future__ import annotations

import json
import os
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from rle_design.errors import RleError
from rle_design.sandbox import Sandbox, SandboxLimits, codec, landlock_abi, wake_poll_for
from rle_design.sandbox.limits import WAKE_POLL_S

POLICY = """
import os
import numpy as np

GAIN = np.loadtxt("gain.txt")

def act(obs):
    return -GAIN * obs

def echo(value):
    return value

def where():
    return {"cwd": os.getcwd(), "home": os.environ["HOME"], "env": sorted(os.environ), "uid": os.getuid()}

def read_extra():
    return open("data/extra.txt").read()

def interpreter():
    import sys
    return sys.executable
"""


@pytest.fixture()
def policy(tmp_path) -> Path:
    (tmp_path / "policy.py").write_text(POLICY)
    (tmp_path / "gain.txt").write_text("2.0\n")
    extra = tmp_path / "extra_src.txt"
    extra.write_text("extra data")
    return tmp_path / "policy.py"


def test_array_in_array_out_and_round_trip_latency(policy):
    obs = np.linspace(-1.0, 1.0, 7)
    with Sandbox(policy, limits=SandboxLimits(call_timeout_s=5.0)) as box:
        np.testing.assert_array_equal(box.call("act", obs, shape=(7,)), -2.0 * obs)
        times = np.empty(1000)
        for i in range(1000):
            t0 = time.perf_counter()
            box.call("act", obs, shape=(7,))
            times[i] = time.perf_counter() - t0
    median_ms = float(np.median(times)) * 1e3
    print(f"sandbox round trip: median {median_ms:.3f} ms, p99 {np.percentile(times, 99) * 1e3:.3f} ms")
    assert median_ms < 1.0


def test_values_of_every_wire_type_round_trip(policy):
    value = {
        "none": None,
        "flags": [True, False],
        "int": -(2**40),
        "float": 0.1,
        "text": "ünïcode",
        "nested": {"t": (1, 2.5, "x")},
        "f32": np.arange(6, dtype=np.float32).reshape(2, 3),
        "i64": np.array([[1], [2]], dtype=np.int64),
        "bool": np.array([True, False]),
        "empty": np.zeros((0, 3)),
        "scalar": np.float64(3.25),
    }
    with Sandbox(policy) as box:
        back = box.call("echo", value)
    assert back["none"] is None and back["flags"] == [True, False] and back["int"] == -(2**40)
    assert back["float"] == 0.1 and back["text"] == "ünïcode" and back["nested"] == {"t": [1, 2.5, "x"]}
    for key in ("f32", "i64", "bool", "empty"):
        assert back[key].dtype == value[key].dtype and back[key].shape == value[key].shape
        np.testing.assert_array_equal(back[key], value[key])
    assert back["scalar"] == 3.25 and isinstance(back["scalar"], float)


def test_working_directory_environment_and_extra_files(policy, monkeypatch):
    monkeypatch.setenv("RLE_SECRET", "s3cr3t")
    monkeypatch.setenv("AWS_SECRET_ACCESS_KEY", "nope")
    extra = {"data/extra.txt": policy.parent / "extra_src.txt"}
    with Sandbox(policy, workdir_files=extra) as box:
        info = box.call("where")
        assert info["cwd"] == str(box.workdir) and info["home"] == str(box.workdir)
        assert box.call("read_extra") == "extra data"
        workdir = box.workdir
    assert not workdir.exists()  # removed on close
    assert "RLE_SECRET" not in info["env"] and "AWS_SECRET_ACCESS_KEY" not in info["env"]
    assert set(info["env"]) <= {
        "PATH", "LANG", "LC_ALL", "TZ", "MUJOCO_GL", "PYOPENGL_PLATFORM", "HOME", "TMPDIR",
        "PYTHONDONTWRITEBYTECODE", "MPLCONFIGDIR", "OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS",
        "MKL_NUM_THREADS", "NUMEXPR_NUM_THREADS", "LC_CTYPE",
    }  # fmt: skip
    if os.geteuid() == 0:
        assert info["uid"] != 0


@pytest.mark.skipif(os.geteuid() != 0, reason="kernel isolation layers need root")
def test_kernel_layers_are_active_as_root(policy):
    # unshare(CLONE_NEWNET) needs CAP_SYS_ADMIN (bit 21 of the effective set), which a default Docker
    # container lacks; without it the layer is off and reported, the others hold.
    status = Path("/proc/self/status").read_text().splitlines()
    cap_eff = int(next(ln for ln in status if ln.startswith("CapEff:")).split()[1], 16)
    sys_admin = bool(cap_eff >> 21 & 1)
    with Sandbox(policy) as box:
        assert box.layers == {
            "netns": sys_admin,
            "uid_drop": True,
            "no_new_privs": True,
            "landlock": landlock_abi() > 0,
            "nproc": True,
        }


def test_close_kills_the_process_group(policy):
    box = Sandbox(policy)
    box.start()
    pid = box._proc.pid
    box.close()
    with pytest.raises(ProcessLookupError):
        os.kill(pid, 0)
    assert not box.alive


def test_codec_refuses_object_arrays_and_unknown_tags():
    with pytest.raises(codec.CodecError, match="ndarray of dtype object"):
        codec.encode_frame({}, np.array([object()]))
    with pytest.raises(codec.CodecError, match="value of type set"):
        codec.encode_frame({}, {1, 2})
    header = json.dumps({"m": {}, "v": {"$a": [0, "|O", [1]]}, "b": [8]}).encode()
    with pytest.raises(codec.CodecError, match="dtype object is not allowed"):
        codec.decode_frame(header, bytearray(8))
    header = json.dumps({"m": {}, "v": {"__reduce__": 1}, "b": []}).encode()
    with pytest.raises(codec.CodecError, match="unknown tag in value tree"):
        codec.decode_frame(header, bytearray())
    header = json.dumps({"m": {}, "v": {"$a": [0, "<f8", [3]]}, "b": [16]}).encode()
    with pytest.raises(
        codec.CodecError, match=r"array of shape \(3,\) and dtype float64 does not match 16 bytes"
    ):
        codec.decode_frame(header, bytearray(16))


@pytest.mark.parametrize("spin_s", [0.0, 200e-6])
def test_frames_larger_than_the_pipe_and_many_buffers_round_trip(policy, spin_s):
    """Frames cross the 64 KiB pipe buffer and the read chunk in pieces; with and without polling.

    A 240 x 320 RGB-D frame is 240*320*(3 + 4) = 537,600 B, eight times the pipe capacity, and 300
    small arrays make a frame of 300 buffers written with one ``writev``.
    """
    rng = np.random.default_rng(7)
    frame = {"rgb": rng.integers(0, 255, (240, 320, 3), dtype=np.uint8), "depth": rng.random((240, 320))}
    many = [np.full(3, float(i)) for i in range(300)]
    with Sandbox(policy, limits=SandboxLimits(reply_spin_s=spin_s)) as box:
        for _ in range(3):  # the stream stays aligned frame after frame
            back = box.call("echo", frame)
            np.testing.assert_array_equal(back["rgb"], frame["rgb"])
            np.testing.assert_array_equal(back["depth"], frame["depth"])
            assert [float(a[0]) for a in box.call("echo", many)] == [float(i) for i in range(300)]
            np.testing.assert_array_equal(box.call("act", np.ones(3), shape=(3,)), -2.0 * np.ones(3))


def test_wake_makes_the_child_poll_for_the_next_call_and_changes_no_reply(policy):
    # wake() is one-way: no reply to read, the stream stays aligned, and the caller's bound of the
    # child's polls is at most wake_poll_s per wake (here 2 ms each, 5 wakes: <= 10 ms).
    limits = SandboxLimits(wake_poll_s=2e-3)
    with Sandbox(policy, limits=limits) as box:
        for k in range(5):
            box.wake()
            np.testing.assert_array_equal(box.call("act", np.full(3, k), shape=(3,)), -2.0 * np.full(3, k))
        box.wake()
        box.wake()  # two wakes in a row, then a pause longer than the poll: the child sleeps again
        time.sleep(0.01)
        np.testing.assert_array_equal(box.call("act", np.ones(3), shape=(3,)), -2.0 * np.ones(3))
        assert 0.0 < box.wake_poll_s <= 6 * 2e-3
    box.wake()  # after close: nothing to wake, no error
    idle = Sandbox(policy, limits=SandboxLimits(wake_poll_s=0.0))
    idle.wake()  # before start, and with waking turned off: a no-op
    with idle:
        idle.wake()
        assert idle.call("act", np.ones(3), shape=(3,)).shape == (3,) and idle.wake_poll_s == 0.0


def test_waking_is_only_offered_where_every_worker_and_its_child_have_a_cpu():
    cpus = len(os.sched_getaffinity(0))
    assert wake_poll_for(cpus) == 0.0  # 2 x cpus processes on cpus CPUs: a polling child steals
    assert wake_poll_for(1) in (0.0, WAKE_POLL_S) if cpus >= 2 else wake_poll_for(1) == 0.0


def test_reply_spin_is_bounded():
    with pytest.raises(ValueError, match="reply_spin_s"):
        SandboxLimits(reply_spin_s=0.5)
    with pytest.raises(ValueError, match="reply_spin_s"):
        SandboxLimits(reply_spin_s=-1e-6)
    with pytest.raises(ValueError, match="wake_poll_s"):
        SandboxLimits(wake_poll_s=0.5)


def test_child_runs_the_interpreter_it_is_given(policy, tmp_path):
    """A side environment's Python serves the module (here this one's, reached by another path)."""
    other = tmp_path / "bin" / "python"
    other.parent.mkdir()
    other.symlink_to(os.path.realpath(sys.executable))
    with Sandbox(policy, interpreter=other) as box:
        assert box.call("interpreter") == str(other)
        assert box.call("echo", 2.5) == 2.5
    missing = Sandbox(policy, interpreter=tmp_path / "none" / "python")
    with pytest.raises(RleError, match="not an executable") as err:
        missing.start()
    assert err.value.code == "sandbox.setup" and missing.workdir is None
