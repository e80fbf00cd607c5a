"""Every hostile or broken submission yields its own fault code while the test process goes on."""

from __future__ import annotations

import os
import time
from pathlib import Path

import numpy as np
import pytest

from rle_design.sandbox import ParticipantFault, Sandbox, SandboxLimits

FAST = SandboxLimits(call_timeout_s=2.0, startup_timeout_s=10.0, cpu_seconds=30.0)

HOSTILE = """
import os, socket, sys, time
import numpy as np

def spin():
    while True:
        pass

def busy():
    x = 0
    while True:
        x = x

def nap(seconds):
    time.sleep(seconds)
    return seconds

def hog():
    return np.ones(8 << 30)  # 64 GB of float64

def fork_bomb():
    while True:
        os.fork()

def secret():
    return os.environ.get("RLE_SECRET")

def write_outside(path):
    with open(path, "w") as f:
        f.write("pwned")
    return "written"

def write_inside():
    with open("notes.txt", "w") as f:
        f.write("mine")
    return open("notes.txt").read()

def connect():
    s = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
    s.connect(("127.0.0.1", 9))
    return "connected"

def swallow_socket():
    try:
        socket.socket()
    except PermissionError:
        pass
    return "fine"

def nan():
    return np.array([1.0, float("nan"), 2.0])

def wrong_shape():
    return np.zeros(6)

def string():
    return "not an array"

def hard_exit():
    os._exit(3)

def soft_exit():
    sys.exit(0)

def fail():
    raise ZeroDivisionError("the submitted code divided by zero")

def shout():
    chunk = "x" * 1023 + "\\n"
    for _ in range(10 * 1024):
        sys.stdout.write(chunk)
    return "done"

def kill_parent():
    os.kill(os.getppid(), 9)
    return "parent killed"

def parent_environ():
    return open(f"/proc/{os.getppid()}/environ", "rb").read().decode(errors="replace")

def own_status():
    return open("/proc/self/status").read()[:5]

def big_reply():
    return np.zeros(1 << 20)

def segfault():
    import ctypes
    ctypes.string_at(0)

def ok():
    return 1.5
"""


@pytest.fixture(scope="module")
def hostile(tmp_path_factory) -> Path:
    path = tmp_path_factory.mktemp("hostile") / "hostile.py"
    path.write_text(HOSTILE)
    return path


def _fault(path: Path, fn: str, *args, limits: SandboxLimits = FAST, **kw) -> ParticipantFault:
    with Sandbox(path, limits=limits) as box, pytest.raises(ParticipantFault) as info:
        box.call(fn, *args, **kw)
    return info.value


def test_infinite_loop_times_out_and_the_sandbox_is_dead(hostile):
    with Sandbox(hostile, limits=FAST) as box:
        t0 = time.monotonic()
        with pytest.raises(ParticipantFault) as info:
            box.call("spin", timeout=1.0)
        assert time.monotonic() - t0 < 3.0
        assert info.value.code == "sandbox.timeout"
        assert info.value.message == "submission.spin(): no reply within 1 s; the child was killed"
        assert not box.alive
        with pytest.raises(ParticipantFault) as again:
            box.call("ok")
        assert again.value.code == "sandbox.dead"
        assert again.value.message == "submission.ok(): the sandbox is dead (timed out after 1 s)"


def test_busy_loop_hits_the_cpu_limit(hostile):
    fault = _fault(hostile, "busy", limits=SandboxLimits(cpu_seconds=1.0, call_timeout_s=10.0))
    assert fault.code == "sandbox.cpu"
    assert fault.message.startswith("submission.busy(): CPU-time limit of 1 s used up")


def test_sleep_past_the_cap_times_out(hostile):
    with Sandbox(hostile, limits=FAST) as box:
        assert box.call("nap", 0.01) == 0.01
        with pytest.raises(ParticipantFault) as info:
            box.call("nap", 5.0, timeout=0.5)
    assert info.value.code == "sandbox.timeout"


def test_64_gb_allocation_is_a_memory_fault_and_the_child_survives(hostile):
    with Sandbox(hostile, limits=FAST) as box:
        with pytest.raises(ParticipantFault) as info:
            box.call("hog")
        assert info.value.code == "sandbox.memory"
        assert info.value.message.startswith("submission.hog(): «MemoryError")
        assert box.call("ok") == 1.5


def test_fork_bomb_cannot_fork(hostile):
    fault = _fault(hostile, "fork_bomb")
    assert fault.code == "sandbox.forbidden"
    assert fault.message == (
        "submission.fork_bomb(): «PermissionError: rle-sandbox: creating processes (fork) is not allowed in the sandbox»"
    )


def test_secret_is_not_in_the_childs_environment(hostile, monkeypatch):
    monkeypatch.setenv("RLE_SECRET", "top-secret-key")
    with Sandbox(hostile, limits=FAST) as box:
        assert box.call("secret") is None


def test_writing_outside_the_working_directory_is_forbidden(hostile, tmp_path):
    target = tmp_path / "outside.txt"
    fault = _fault(hostile, "write_outside", str(target))
    assert fault.code == "sandbox.forbidden"
    # the child's text is a participant excerpt, cut at EXCERPT_CHARS: the refused path's start is there
    assert f"«PermissionError: rle-sandbox: opening '{str(target)[:40]}" in fault.message
    assert not target.exists()


def test_writing_inside_the_working_directory_is_allowed(hostile):
    with Sandbox(hostile, limits=FAST) as box:
        assert box.call("write_inside") == "mine"
        assert (box.workdir / "notes.txt").read_text() == "mine"


def test_opening_a_socket_is_forbidden(hostile):
    fault = _fault(hostile, "connect")
    assert fault.code == "sandbox.forbidden"
    assert "network access (socket.__new__)" in fault.message


def test_a_swallowed_forbidden_error_is_still_a_fault(hostile):
    fault = _fault(hostile, "swallow_socket")
    assert fault.code == "sandbox.forbidden"
    assert fault.message.endswith("(error swallowed)»")


def test_nan_output_is_non_finite(hostile):
    fault = _fault(hostile, "nan")
    assert fault.code == "sandbox.non_finite"
    assert fault.message == "submission.nan(): output holds 1 non-finite value(s) (NaN or inf)"
    with Sandbox(hostile, limits=FAST) as box:
        assert np.isnan(box.call("nan", finite=False)[1])


def test_wrong_shape(hostile):
    fault = _fault(hostile, "wrong_shape", shape=(7,))
    assert fault.code == "sandbox.bad_shape"
    assert fault.message == "submission.wrong_shape(): expected shape (7,), got «(6,)»"


def test_string_where_an_array_is_expected(hostile):
    fault = _fault(hostile, "string", shape=(3,))
    assert fault.code == "sandbox.bad_type"
    assert fault.message == "submission.string(): expected an array of shape (3,), got str «not an array»"


def test_os_exit_reports_its_status(hostile):
    fault = _fault(hostile, "hard_exit")
    assert fault.code == "sandbox.exit"
    assert fault.message == "submission.hard_exit(): the child exited with status 3"


def test_sys_exit_mid_call(hostile):
    with Sandbox(hostile, limits=FAST) as box:
        with pytest.raises(ParticipantFault) as info:
            box.call("soft_exit")
        assert info.value.code == "sandbox.exit"
        assert info.value.message == "submission.soft_exit(): «sys.exit(0) called»"
        assert not box.alive


def test_exception_carries_the_traceback(hostile):
    fault = _fault(hostile, "fail")
    assert fault.code == "sandbox.exception"
    assert fault.message == "submission.fail(): «ZeroDivisionError: the submitted code divided by zero»"
    assert 'hostile.py", line' in fault.detail
    assert "in fail" in fault.detail


def test_module_crashing_at_import(tmp_path):
    path = tmp_path / "broken.py"
    path.write_text("import numpy\nraise RuntimeError('cannot even start')\n")
    with pytest.raises(ParticipantFault) as info, Sandbox(path, limits=FAST):
        pass
    assert info.value.code == "sandbox.import_error"
    assert info.value.message == "submission (import of broken.py): «RuntimeError: cannot even start»"
    assert 'broken.py", line 2' in info.value.detail


def test_missing_module_and_missing_function(tmp_path, hostile):
    with pytest.raises(ParticipantFault) as info:
        Sandbox(tmp_path / "absent.py").start()
    assert info.value.code == "sandbox.import_error"
    fault = _fault(hostile, "no_such_function")
    assert fault.code == "sandbox.missing_function"
    assert fault.message == "submission.no_such_function(): «no callable named 'no_such_function'»"


def test_printing_10_mb_is_truncated_not_an_error(hostile):
    with Sandbox(hostile, limits=FAST) as box:
        assert box.call("shout") == "done"
        tail = box.stdout_tail
    assert 0 < len(tail) <= FAST.max_output_bytes
    assert tail.endswith("x\n")


def test_killing_the_parent_is_forbidden_and_the_parent_lives(hostile):
    fault = _fault(hostile, "kill_parent")
    assert fault.code == "sandbox.forbidden"
    assert f"sending signals to other processes (pid {os.getpid()})" in fault.message


def test_reading_the_parents_proc_entries_is_forbidden(hostile, monkeypatch):
    monkeypatch.setenv("RLE_SECRET", "top-secret-key")
    with Sandbox(hostile, limits=FAST) as box:
        assert box.call("own_status") == "Name:"
        with pytest.raises(ParticipantFault) as info:
            box.call("parent_environ")
    assert info.value.code == "sandbox.forbidden"
    assert f"reading '/proc/{os.getpid()}/environ' (another process's /proc entry)" in info.value.message


def test_reply_over_the_cap(hostile):
    limits = SandboxLimits(call_timeout_s=2.0, max_reply_bytes=1 << 20)
    with Sandbox(hostile, limits=limits) as box:
        with pytest.raises(ParticipantFault) as info:
            box.call("big_reply")
        assert info.value.code == "sandbox.output_too_large"
        assert info.value.message.startswith("submission.big_reply(): «reply of 8388")
        assert box.call("ok") == 1.5


def test_segfault_is_a_crash(hostile):
    fault = _fault(hostile, "segfault")
    assert fault.code == "sandbox.crash"
    assert fault.message == "submission.segfault(): the child was killed by signal SIGSEGV"


def test_import_that_hangs_times_out(tmp_path):
    path = tmp_path / "slow.py"
    path.write_text("import time\ntime.sleep(60)\n")
    limits = SandboxLimits(startup_timeout_s=1.0)
    t0 = time.monotonic()
    with pytest.raises(ParticipantFault) as info, Sandbox(path, limits=limits):
        pass
    assert time.monotonic() - t0 < 4.0
    assert info.value.code == "sandbox.timeout"
    assert info.value.message == "submission (import of slow.py): no reply within 1 s; the child was killed"


def test_has_reports_module_level_callables(hostile):
    with Sandbox(hostile, limits=FAST) as box:
        assert box.has("ok") and not box.has("absent") and not box.has("np.ones")


def test_importing_the_verifier_package_is_refused(tmp_path):
    from rle_design.sandbox import ParticipantFault, Sandbox

    mod = tmp_path / "evil.py"
    mod.write_text("import rle_tasks.core.report as r\nr.Checkpoint.__post_init__ = lambda self: None\n")
    box = Sandbox(mod)
    try:
        with pytest.raises(ParticipantFault) as info:
            box.start()
    finally:
        box.close()
    assert info.value.code == "sandbox.import_error"
    assert "importing the verifier package 'rle_tasks' is not allowed" in str(info.value)


def test_public_toolkit_stays_importable(tmp_path):
    from rle_design.sandbox import Sandbox

    mod = tmp_path / "ok.py"
    mod.write_text(
        "from rle_design.catalog import load_catalog\ndef n():\n    return len(load_catalog('profiles'))\n"
    )
    with Sandbox(mod) as box:
        assert box.call("n") == 5


def test_stdout_flood_is_killed_with_its_own_code(tmp_path):
    mod = tmp_path / "flood.py"
    mod.write_text(
        "import sys\ndef f():\n    for _ in range(64):\n        sys.stdout.write('x' * (1 << 20))\n    return 1\n"
    )
    box = Sandbox(mod, limits=SandboxLimits(max_output_total_bytes=8 << 20, call_timeout_s=20.0))
    try:
        with pytest.raises(ParticipantFault) as info:
            box.call("f")
    finally:
        box.close()
    assert info.value.code == "sandbox.output_flood"
    assert "wrote more than 8388608 bytes to stdout/stderr" in str(info.value)
