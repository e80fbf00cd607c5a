"""Resource limits of one sandboxed child process."""

from __future__ import annotations

import os
from dataclasses import dataclass


@dataclass(frozen=True)
class SandboxLimits:
    """Limits applied to the child that runs submitted Python.

    Attributes:
        cpu_seconds: CPU time of the child over its whole life (``RLIMIT_CPU``; SIGXCPU at the soft
            limit, SIGKILL 2 s later) [s]. Rounded up to whole seconds by the kernel interface.
        memory_bytes: Address space of the child (``RLIMIT_AS``); allocations beyond it raise
            ``MemoryError`` [B].
        file_bytes: Largest file the child may write (``RLIMIT_FSIZE``) [B].
        max_processes: Processes and threads the child's uid may have (``RLIMIT_NPROC``); 0 forbids
            fork and thread creation (compile MuJoCo models with ``usethread=False``). Enforced by
            the kernel only for an unprivileged uid (see the package docstring).
        call_timeout_s: Wall-clock cap of one call; on expiry the child is killed [s].
        startup_timeout_s: Wall-clock cap of the import of the submitted module [s].
        max_output_bytes: Bytes of the child's stdout and stderr kept (the last ones); the rest is
            dropped, which is not an error [B].
        network: Allow network access. False puts the child in a new network namespace (root only)
            and blocks socket creation with an audit hook (always).
        max_reply_bytes: Largest reply (encoded return value) accepted from the child; larger
            replies fault with ``sandbox.output_too_large`` [B].
        max_output_total_bytes: Total stdout and stderr a child may write over its life; a child
            flooding past it is killed with ``sandbox.output_flood`` (log flooding is a denial of
            service on the verifier) [B].
        unix_socket: Absolute path of the one Unix-domain socket the child may create a socket for and
            connect to (e.g. a metered session's server); every other socket operation stays refused.
            The caller makes the socket connectable by the child's uid.
        reply_spin_s: How long the parent polls for a reply before it sleeps in ``select`` [s]. A
            reply that arrives while the parent polls needs no wake-up, which on a virtual machine
            costs more than a short call itself. The poll yields the CPU between reads, so a child or
            another worker that needs the parent's CPU gets it (08 full verification: 2 s faster with
            one worker, within 1 % with two on two cores). 0 always sleeps.
        wake_poll_s: How long a child told by ``Sandbox.wake`` that a call follows polls for it instead
            of sleeping [s] (its CPU, charged to it; ``Sandbox.wake_poll_s`` sums the caller's side of
            it). A sleeping child's wake-up costs 0.03-0.08 ms on a virtual machine; the caller wakes
            it one physics step ahead, so the wake-up overlaps that step. 0 (the default) turns
            ``wake`` off; ``wake_poll_for`` turns it on only where CPUs are spare, because a polling
            child takes CPU from whatever else runs (08 with two workers on two cores: 26 s, not 22 s).
    """

    cpu_seconds: float = 120.0
    memory_bytes: int = 2 << 30
    file_bytes: int = 16 << 20
    max_processes: int = 0
    call_timeout_s: float = 30.0
    startup_timeout_s: float = 30.0
    max_output_bytes: int = 1 << 20
    network: bool = False
    max_reply_bytes: int = 256 << 20
    max_output_total_bytes: int = 32 << 20
    reply_spin_s: float = 2e-3
    wake_poll_s: float = 0.0
    unix_socket: str | None = None

    def __post_init__(self) -> None:
        for name in ("cpu_seconds", "call_timeout_s", "startup_timeout_s"):
            if not getattr(self, name) > 0:
                raise ValueError(f"SandboxLimits.{name} must be > 0, got {getattr(self, name)}")
        for name in (
            "memory_bytes",
            "file_bytes",
            "max_output_bytes",
            "max_reply_bytes",
            "max_output_total_bytes",
        ):
            if getattr(self, name) <= 0:
                raise ValueError(f"SandboxLimits.{name} must be > 0, got {getattr(self, name)}")
        if not 0.0 <= self.reply_spin_s <= 0.01:
            raise ValueError(f"SandboxLimits.reply_spin_s must be in [0, 0.01] s, got {self.reply_spin_s}")
        if not 0.0 <= self.wake_poll_s <= 0.01:
            raise ValueError(f"SandboxLimits.wake_poll_s must be in [0, 0.01] s, got {self.wake_poll_s}")
        if self.max_processes < 0:
            raise ValueError(f"SandboxLimits.max_processes must be >= 0, got {self.max_processes}")


WAKE_POLL_S = 5e-4
"""``wake_poll_s`` where CPUs are spare: a 50 Hz period's last physics step plus the caller's own work
before the call is 0.05-0.2 ms in the 08 scenes."""


def wake_poll_for(workers: int) -> float:
    """``wake_poll_s`` for a verification running ``workers`` processes that each drive one sandboxed
    policy: ``WAKE_POLL_S`` when every worker and its policy can have a CPU of their own and the CPUs
    are not already contended (``/proc/pressure/cpu`` "some" over the last 10 s below 5 %, or, where
    the kernel has no pressure information, a 1-minute load below the CPUs left over), else 0."""
    cpus = len(os.sched_getaffinity(0))
    if 2 * workers > cpus:
        return 0.0
    try:
        with open("/proc/pressure/cpu") as f:
            some = f.readline().split()
        contended = float(some[1].split("=")[1]) > 5.0
    except (OSError, IndexError, ValueError):
        contended = os.getloadavg()[0] > cpus - 2 * workers + 1
    return 0.0 if contended else WAKE_POLL_S
