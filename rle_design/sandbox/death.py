"""How a sandbox child ends: reaping it with the CPU time it used,
and naming the cause of an unexpected death (``sandbox.cpu``, ``sandbox.crash``, ``sandbox.exit``,
``sandbox.output_flood``)."""

from __future__ import annotations

import contextlib
import os
import signal
import subprocess
import time

from rle_design.sandbox.limits import SandboxLimits


def reap(proc: subprocess.Popen, wait_s: float) -> tuple[int, float]:
    """Wait up to ``wait_s`` for the child (then SIGKILL its group and keep waiting); (exit code, CPU
    seconds it and its reaped children used). A child reaped before answers from its record."""
    if proc.returncode is not None:
        return proc.returncode, getattr(proc, "_rle_cpu", 0.0)
    deadline = time.monotonic() + wait_s
    while True:
        try:
            pid, status, usage = os.wait4(proc.pid, os.WNOHANG)
        except ChildProcessError:
            proc.returncode = proc.returncode if proc.returncode is not None else -signal.SIGKILL
            return proc.returncode, 0.0
        if pid:
            proc.returncode = os.waitstatus_to_exitcode(status)
            proc._rle_cpu = usage.ru_utime + usage.ru_stime  # type: ignore[attr-defined]
            return proc.returncode, proc._rle_cpu  # type: ignore[attr-defined]
        if time.monotonic() > deadline:
            with contextlib.suppress(ProcessLookupError, PermissionError):
                os.killpg(proc.pid, signal.SIGKILL)
            deadline = time.monotonic() + 5.0
        time.sleep(0.002)


def death_cause(rc: int, cpu_s: float, limits: SandboxLimits, flooded: bool) -> tuple[str, str]:
    """(fault code, text) of a child that died with exit code ``rc`` after ``cpu_s`` of CPU."""
    cpu_limit = int(limits.cpu_seconds + 0.999)
    if flooded:
        return (
            "sandbox.output_flood",
            f"wrote more than {limits.max_output_total_bytes} bytes to stdout/stderr and was killed",
        )
    if rc == -signal.SIGXCPU or (rc == -signal.SIGKILL and cpu_s >= cpu_limit):
        return "sandbox.cpu", f"CPU-time limit of {cpu_limit} s used up ({cpu_s:.1f} s)"
    if rc < 0:
        return "sandbox.crash", f"the child was killed by signal {signal_name(-rc)}"
    return "sandbox.exit", f"the child exited with status {rc}"


def signal_name(num: int) -> str:
    """``SIGSEGV`` for 11; the number itself where it names no signal."""
    try:
        return signal.Signals(num).name
    except ValueError:
        return str(num)
