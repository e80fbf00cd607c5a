"""``Sandbox``: a submitted Python module served from a constrained child process."""

from __future__ import annotations

import atexit
import contextlib
import json
import os
import shutil
import signal
import subprocess
import sys
import threading
import time
import weakref
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from rle_design.errors import RleError
from rle_design.excerpt import excerpt
from rle_design.sandbox import codec
from rle_design.sandbox.channel import CHUNK, ChildGone, Expired, fill, read_exact, write_all
from rle_design.sandbox.checks import check_output
from rle_design.sandbox.death import death_cause, reap
from rle_design.sandbox.faults import FAULT_CODES, ParticipantFault
from rle_design.sandbox.isolation import child_env, drop_ids, make_workdir
from rle_design.sandbox.limits import SandboxLimits

_BOOTSTRAP = Path(__file__).with_name("_bootstrap.py")
_LANDLOCK = Path(__file__).with_name("_landlock.py").resolve()
_LIVE: weakref.WeakSet[Sandbox] = weakref.WeakSet()
_WAKE = b"".join(bytes(p) for p in codec.encode_frame({"op": "wake"}))
_WAKE_POLL_TOTAL = [0.0]


def wake_poll_total_s() -> float:
    """Time the children of this process polled after ``Sandbox.wake`` so far, bounded on the caller's
    side [s]: CPU charged to the submissions that is the platform's (benchmarks subtract it)."""
    return _WAKE_POLL_TOTAL[0]


class Sandbox:
    """Runs the functions of one submitted module in a child process.

    Use as a context manager; ``call`` raises ``ParticipantFault`` for every fault of the submitted
    code and never hangs past its timeout. Not thread-safe: one caller at a time.

    Args:
        module_path: The submitted ``.py`` file. The contents of its directory are copied into a
            fresh working directory the child may read and write.
        limits: Resource limits.
        workdir_files: Extra files copied into the working directory, ``{relative name: source}``.
        name: Module name in the child, used in fault messages.
        interpreter: Python of the child (default: this one), e.g. that of a side virtual environment
            whose packages this one cannot import; it needs numpy for the wire format.
    """

    def __init__(
        self,
        module_path: Path,
        *,
        limits: SandboxLimits = SandboxLimits(),  # noqa: B008 - frozen dataclass
        workdir_files: Mapping[str, Path] = {},  # noqa: B006 - read only
        name: str = "submission",
        interpreter: str | Path | None = None,
    ) -> None:
        if not name.isidentifier():
            raise ValueError(f"sandbox module name must be an identifier, got {name!r}")
        self.module_path = Path(module_path)
        self.limits = limits
        self.name = name
        self.interpreter = str(interpreter) if interpreter is not None else sys.executable
        self.layers: dict[str, bool] = {}
        self._workdir_files = dict(workdir_files)
        self._proc: subprocess.Popen | None = None
        self._workdir: Path | None = None
        self._req_w = self._rep_r = -1
        self._death: str | None = None
        self._out = bytearray()
        self._pending = bytearray()  # reply bytes read past the frame being parsed
        self._out_lock = threading.Lock()
        self._drain: threading.Thread | None = None
        self._flooded = False
        self._cpu_s = 0.0
        self._woken_at: float | None = None
        self.wake_poll_s = 0.0  # caller-side bound of the child's polls after wake() [s]

    # -- lifecycle -----------------------------------------------------------------------------------
    def __enter__(self) -> Sandbox:
        self.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    @property
    def workdir(self) -> Path | None:
        """The child's working directory (None before ``start`` and after ``close``)."""
        return self._workdir

    @property
    def alive(self) -> bool:
        """True while the child runs and can serve calls."""
        return self._proc is not None and self._death is None and self._proc.poll() is None

    @property
    def cpu_time_s(self) -> float:
        """CPU time the child used (user + system) [s]: live while it runs (from ``/proc``), final
        once it is reaped; 0 when unknown (never started, or reaped by someone else)."""
        proc = self._proc
        if proc is not None and proc.returncode is None:
            try:
                fields = Path(f"/proc/{proc.pid}/stat").read_text().rsplit(")", 1)[1].split()
                return max(self._cpu_s, (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK"))
            except (OSError, IndexError, ValueError):
                pass
        return self._cpu_s

    @property
    def stdout_tail(self) -> str:
        """The last ``limits.max_output_bytes`` of the child's stdout and stderr (merged)."""
        with self._out_lock:
            return self._out.decode("utf-8", errors="replace")

    def start(self) -> None:
        """Create the working directory, start the child and import the module in it.

        Raises:
            ParticipantFault: ``sandbox.import_error`` (or the code of the death) when the import fails.
            RleError: ``sandbox.setup`` when the isolation itself cannot be established, or the
                interpreter is not an executable (our fault).
        """
        if self._proc is not None:
            return
        if not self.module_path.is_file():
            raise ParticipantFault(
                "sandbox.import_error", f"{self.name}: module file {self.module_path.name} does not exist"
            )
        if not os.access(self.interpreter, os.X_OK):
            raise RleError(
                f"sandbox interpreter {self.interpreter} is not an executable", code="sandbox.setup"
            )
        ids = drop_ids()
        self._workdir = make_workdir(self.module_path.parent, self._workdir_files, ids)
        req_r, self._req_w = os.pipe()
        self._rep_r, rep_w = os.pipe()
        lim = self.limits
        config = {
            "codec": str(Path(codec.__file__).resolve()),
            "landlock_module": str(_LANDLOCK),
            "workdir": str(self._workdir),
            "module_file": str(self._workdir / self.module_path.name),
            "module_name": self.name,
            "rfd": req_r,
            "wfd": rep_w,
            "unshare_net": ids is not None and not lim.network,
            "network": lim.network,
            "unix_socket": lim.unix_socket,
            "uid": ids[0] if ids else None,
            "gid": ids[1] if ids else None,
            "cpu_seconds": lim.cpu_seconds,
            "memory_bytes": lim.memory_bytes,
            "file_bytes": lim.file_bytes,
            "max_processes": lim.max_processes,
            "max_reply_bytes": lim.max_reply_bytes,
            "wake_poll_s": lim.wake_poll_s,
        }
        try:
            self._proc = subprocess.Popen(
                [self.interpreter, "-I", "-B", str(_BOOTSTRAP), json.dumps(config)],
                stdin=subprocess.DEVNULL,
                stdout=subprocess.PIPE,
                stderr=subprocess.STDOUT,
                pass_fds=(req_r, rep_w),
                start_new_session=True,
                cwd=self._workdir,
                env=child_env(self._workdir),
            )
        finally:
            os.close(req_r)
            os.close(rep_w)
        os.set_blocking(self._req_w, False)
        os.set_blocking(self._rep_r, False)
        self._pending.clear()
        self._woken_at = None
        _LIVE.add(self)
        self._drain = threading.Thread(
            target=self._drain_output, name=f"sandbox-{self.name}-out", daemon=True
        )
        self._drain.start()
        where = f"{self.name} (import of {self.module_path.name})"
        meta, _ = self._exchange(None, None, lim.startup_timeout_s, where)
        self.layers = (
            {k: bool(v) for k, v in meta.get("layers", {}).items()} if isinstance(meta, dict) else {}
        )

    def close(self) -> None:
        """Kill the child's whole process group and remove the working directory. Idempotent."""
        proc, self._proc = self._proc, None
        if proc is not None:
            if self._death is None:
                self._death = "closed"
            self._kill(proc)
        for fd in (self._req_w, self._rep_r):
            if fd >= 0:
                os.close(fd)
        self._req_w = self._rep_r = -1
        if self._drain is not None:
            self._drain.join(timeout=2.0)
            self._drain = None
        if self._workdir is not None:
            shutil.rmtree(self._workdir, ignore_errors=True)
            self._workdir = None
        _LIVE.discard(self)

    def __del__(self) -> None:
        if getattr(self, "_proc", None) is not None:
            self.close()

    # -- calls ---------------------------------------------------------------------------------------
    def call(
        self,
        function: str,
        *args: Any,
        timeout: float | None = None,
        shape: tuple | None = None,
        finite: bool = True,
    ) -> Any:
        """Call ``function(*args)`` in the child and return its checked result.

        Args:
            function: Name of a module-level callable.
            *args: Values of the wire format (None, bool, int, float, str, list, tuple, dict, ndarray).
            timeout: Wall-clock cap of this call [s]; default ``limits.call_timeout_s``.
            shape: Expected array shape (``None``/``-1`` entries match any size); lists are converted.
            finite: Fault on NaN or infinity anywhere in the result.

        Raises:
            ParticipantFault: any fault of the submitted code (see ``FAULT_CODES``).
        """
        where = f"{self.name}.{function}()"
        value = self._request({"op": "call", "fn": function}, list(args), timeout, where)
        return check_output(value, shape=shape, finite=finite, where=where)

    def wake(self) -> None:
        """Tell a live child that a call follows shortly (one-way, no reply, never raises): it polls for
        the call for up to ``limits.wake_poll_s`` instead of sleeping, so its wake-up overlaps what the
        caller still does (the last physics step of a control period). A no-op when ``wake_poll_s`` is
        0, before ``start`` and after the child died (the next call reports that)."""
        if self._proc is None or self._death is not None or not self.limits.wake_poll_s:
            return
        try:
            os.write(self._req_w, _WAKE)  # a frame below PIPE_BUF: written whole or not at all
        except OSError:  # full pipe (BlockingIOError) or gone: the next call tells
            return
        self._woken_at = time.monotonic()

    def has(self, function: str) -> bool:
        """True if the module defines a callable ``function``."""
        return bool(
            self._request({"op": "has", "fn": function}, None, None, f"{self.name}.has({function!r})")
        )

    def _request(self, meta: dict, value: Any, timeout: float | None, where: str) -> Any:
        if self._proc is None and self._death is None:
            self.start()
        if self._death is not None:
            raise ParticipantFault("sandbox.dead", f"{where}: the sandbox is dead ({self._death})")
        try:
            parts = codec.encode_frame(meta, value)
        except codec.CodecError as exc:
            raise RleError(f"{where}: cannot send argument: {exc}", code="sandbox.bad_argument") from None
        if self._woken_at is not None:  # the child polled from wake() until now, at most wake_poll_s
            polled = min(time.monotonic() - self._woken_at, self.limits.wake_poll_s)
            self.wake_poll_s += polled
            _WAKE_POLL_TOTAL[0] += polled
            self._woken_at = None
        _, result = self._exchange(parts, meta, timeout or self.limits.call_timeout_s, where)
        return result

    def _exchange(
        self, parts: list | None, meta: dict | None, timeout: float, where: str
    ) -> tuple[dict, Any]:
        deadline = time.monotonic() + timeout
        try:
            if parts is not None:
                write_all(self._req_w, parts, deadline)
            pending, size = self._pending, codec.PREFIX.size
            spin_s = self.limits.reply_spin_s
            while len(pending) < size:
                fill(self._rep_r, pending, deadline, spin_s)
            n_header, n_payload = codec.parse_prefix(bytes(pending[:size]))
            if n_header + n_payload > self.limits.max_reply_bytes:
                self._die(f"reply of {n_header + n_payload} bytes exceeds the cap")
                raise ParticipantFault(
                    "sandbox.output_too_large",
                    f"{where}: reply of {n_header + n_payload} bytes exceeds the cap of "
                    f"{self.limits.max_reply_bytes} bytes",
                )
            end = size + n_header + n_payload
            if end <= CHUNK:  # a small frame: one read usually brought all of it
                while len(pending) < end:
                    fill(self._rep_r, pending, deadline, spin_s)
                header, payload = bytes(pending[size : size + n_header]), pending[size + n_header : end]
                del pending[:end]
            else:
                del pending[:size]
                header = bytes(read_exact(self._rep_r, pending, n_header, deadline, spin_s))
                payload = read_exact(self._rep_r, pending, n_payload, deadline, spin_s)
            reply, value = codec.decode_frame(header, payload)
        except Expired:
            self._die(f"timed out after {timeout:g} s")
            raise ParticipantFault(
                "sandbox.timeout", f"{where}: no reply within {timeout:g} s; the child was killed"
            ) from None
        except ChildGone:
            raise self._death_fault(where) from None
        except codec.CodecError as exc:
            self._die("malformed reply")
            raise ParticipantFault(
                "sandbox.bad_type", f"{where}: malformed reply from the child: {excerpt(exc)}"
            ) from None
        if reply.get("ok") is True:
            return reply, value
        # everything the child sends is participant text: only a marked excerpt reaches a message
        code, message = reply.get("code"), excerpt(reply.get("message", ""))
        detail = str(reply.get("detail", ""))
        if code == "internal":
            self._die("isolation failed")
            raise RleError(f"{where}: sandbox isolation failed: {message}", code="sandbox.setup")
        if code not in FAULT_CODES:
            code, message = "sandbox.bad_type", f"malformed fault reply (code {excerpt(code, 20)})"
        if meta is None or code == "sandbox.exit":  # import failures and exits end the child
            self._die(f"{code}: {message}")
        raise ParticipantFault(code, f"{where}: {message}", detail)

    def _drain_output(self) -> None:
        proc, cap = self._proc, self.limits.max_output_bytes
        if proc is None or proc.stdout is None:
            return
        fd = proc.stdout.fileno()
        total = 0
        while True:
            try:
                chunk = os.read(fd, 1 << 16)
            except OSError:
                break
            if not chunk:
                break
            total += len(chunk)
            if total > self.limits.max_output_total_bytes and not self._flooded:
                self._flooded = True
                with contextlib.suppress(ProcessLookupError, PermissionError):
                    os.killpg(proc.pid, signal.SIGKILL)
            with self._out_lock:
                self._out += chunk
                if len(self._out) > cap:
                    del self._out[: len(self._out) - cap]
        proc.stdout.close()

    # -- death ---------------------------------------------------------------------------------------
    def _kill(self, proc: subprocess.Popen) -> tuple[int, float]:
        with contextlib.suppress(ProcessLookupError, PermissionError):
            os.killpg(proc.pid, signal.SIGKILL)
        return self._reap(proc, 5.0)

    def _reap(self, proc: subprocess.Popen, wait_s: float) -> tuple[int, float]:
        """``death.reap``; the CPU time of a child reaped now becomes ``cpu_time_s``."""
        fresh = proc.returncode is None
        rc, cpu = reap(proc, wait_s)
        if fresh and hasattr(proc, "_rle_cpu"):
            self._cpu_s = cpu
        return rc, cpu

    def _die(self, reason: str) -> None:
        if self._death is None:
            self._death = reason
        if self._proc is not None:
            self._kill(self._proc)

    def _death_fault(self, where: str) -> ParticipantFault:
        proc = self._proc
        rc, cpu = self._reap(proc, 2.0) if proc is not None else (-signal.SIGKILL, 0.0)
        code, text = death_cause(rc, cpu, self.limits, self._flooded)
        self._die(f"{code}: {text}")
        return ParticipantFault(code, f"{where}: {text}", self.stdout_tail[-4000:])


@atexit.register
def _close_all() -> None:
    for box in list(_LIVE):
        box.close()
