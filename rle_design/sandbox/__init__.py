"""Running submitted Python in a constrained child process.

``Sandbox(module_path)`` starts ``python -I`` on a small trusted bootstrap that imports the submitted
module in its own temporary working directory and serves calls over two pipes. Replies cross the
channel in a typed, pickle-free format (JSON header + raw array bytes, ``codec``); the parent never
unpickles anything the child produced. Every fault of the submitted code is a ``ParticipantFault``
with a stable code (``FAULT_CODES``).

Which guarantee comes from which layer:

==========================  ==========================================  ============================
guarantee                   layer                                       when
==========================  ==========================================  ============================
no secret in the child      scrubbed environment (allowlist), own       always
                            working directory with copies only
bounded wall time           parent-side per-call/import timeout, kill   always
                            of the child's process group
bounded CPU, memory, file   RLIMIT_CPU, RLIMIT_AS, RLIMIT_FSIZE,        always (kernel)
size                        RLIMIT_CORE=0
no fork                     RLIMIT_NPROC=max_processes                  kernel: for a non-root uid
                            audit hook on os.fork/exec/spawn/system/    always (Python-level)
                            subprocess/posix_spawn/pty
no network                  new network namespace (only loopback,       root with CAP_SYS_ADMIN
                            down)                                       (kernel)
                            audit hook on every ``socket.*`` event      always (Python-level)
no writes outside workdir   uid/gid drop to nobody/nogroup, workdir     root only (kernel)
                            owned by nobody (mode 700)
                            audit hook on open-for-write, mkdir,        always (Python-level)
                            remove, rename, chmod ... outside workdir
cannot signal the parent    own session; different uid (EPERM)          kernel: root only
                            audit hook on os.kill/os.killpg             always (Python-level)
no privilege regain         prctl(PR_SET_NO_NEW_PRIVS)                  always (kernel)
no reads or writes outside  Landlock domain: read-only the interpreter, kernel: Landlock (Linux
the library trees and the   its site-packages, the public toolkit and   >= 5.13), any uid
working directory           system libraries; read-write the workdir
no TCP, no signals out      Landlock network rules (ABI >= 4) and       kernel: Landlock ABI 4 / 6
                            signal scoping (ABI >= 6)
==========================  ==========================================  ============================

The audit hook is a tripwire, not a boundary: code that loads ``ctypes`` (allowed, since libraries
such as torch need it) can call libc directly and bypass it. The kernel layers are the boundary,
and most of them need the parent to run as root (as in the evaluation container); the test
``test_kernel_layers_stop_a_ctypes_bypass`` checks them against raw libc calls. The hook also
refuses reading another process's ``/proc/<pid>/`` entries (the parent's environ).

A kernel layer the environment refuses is left off, never failed: in a default Docker container
(no CAP_SYS_ADMIN) ``unshare(CLONE_NEWNET)`` fails with EPERM, so the child has no network namespace
of its own (the container's network policy and the audit hook remain). ``Sandbox.layers`` says which
layers a child got; ``probe_layers()`` says which ones this process can establish, and verifier
reports record it (``sandbox_layers``).

Landlock confines file access for any uid: the child reads only its interpreter's trees, the public
toolkit (``rle_design``, never ``rle_tasks``), shared libraries and a few ``/proc`` and ``/sys``
entries numeric libraries probe, and writes only its working directory (``/proc/self`` is its own
entry, so the parent's environ stays out of reach). Without Landlock (older kernels, or a container
whose seccomp profile refuses the syscalls) and not running as root, the child keeps the caller's
uid: the kernel still enforces the rlimits (RLIMIT_NPROC=0 stops fork and thread creation for an
unprivileged uid), but a ctypes-level bypass could open sockets, write wherever the caller's user
can, read files the caller can read (the secret file, ``/proc/<parent>/environ`` holding
``RLE_SECRET``) and signal the parent (same uid). Run verifiers of untrusted code as root in a
container on a Landlock kernel, or keep the secret out of reach of the verifier's user.

As root: files readable only by root stay unreadable; world-writable directories (/tmp, /dev/shm)
stay writable by ``nobody`` (file size capped by RLIMIT_FSIZE); all concurrent sandboxes share the
``nobody`` uid, so RLIMIT_NPROC counts their processes together (``max_processes`` > 0 is a shared
allowance). An interpreter installed under a private directory (``/root/.pyenv``) stays importable
after the uid drop through directory descriptors opened before it (``/proc/self/fd/N`` entries on
``sys.path``), which exposes that install tree, and nothing else under the private directory, to
the child.

If the parent dies abruptly, an orphaned child exits at its next read of the closed request pipe, or
at its CPU-time limit if it is spinning.
"""

from rle_design.excerpt import excerpt, withhold
from rle_design.sandbox.faults import FAULT_CODES, ParticipantFault
from rle_design.sandbox.layers import LAYERS, landlock_abi, probe_layers
from rle_design.sandbox.limits import SandboxLimits, wake_poll_for
from rle_design.sandbox.process import Sandbox, wake_poll_total_s

__all__ = [
    "FAULT_CODES",
    "LAYERS",
    "ParticipantFault",
    "Sandbox",
    "SandboxLimits",
    "excerpt",
    "landlock_abi",
    "probe_layers",
    "wake_poll_for",
    "wake_poll_total_s",
    "withhold",
]
