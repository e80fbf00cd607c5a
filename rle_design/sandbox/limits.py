"""Resource limits of one sandboxed child process."""

from __future__ import annotations

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
        if self.max_processes < 0:
            raise ValueError(f"SandboxLimits.max_processes must be >= 0, got {self.max_processes}")
