"""Child side of the sandbox: run as ``python -I -B _bootstrap.py CONFIG_JSON``.

Trusted code only until the submitted module is imported: it isolates the network (root), sets the
rlimits, drops to the unprivileged uid (root), sets no_new_privs, installs the audit hook, imports the
module and then serves requests on the two channel file descriptors. It never imports ``rle_design``
(isolated mode has no package path); the codec and the Landlock rules (``_landlock.py``) are loaded
from their files.
"""

import contextlib
import ctypes
import importlib.util
import json
import os
import resource
import select
import sys
import time
import traceback

sys.dont_write_bytecode = True
_CONFIG = json.loads(sys.argv[1])
_spec = importlib.util.spec_from_file_location("_rle_codec", _CONFIG["codec"])
codec = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(codec)
_spec = importlib.util.spec_from_file_location("_rle_landlock", _CONFIG["landlock_module"])
landlock = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(landlock)

_RFD, _WFD = _CONFIG["rfd"], _CONFIG["wfd"]
_WORKDIR = os.path.realpath(_CONFIG["workdir"])
_MARK = "rle-sandbox:"
_state = {"violation": None}
_CLONE_NEWNET = 0x40000000
_PR_SET_NO_NEW_PRIVS = 38
_WRITE_FLAGS = os.O_WRONLY | os.O_RDWR | os.O_CREAT | os.O_TRUNC | os.O_APPEND
_PROCESS_EVENTS = {
    "os.system": "os.system",
    "os.exec": "exec",
    "os.posix_spawn": "posix_spawn",
    "os.spawn": "os.spawn",
    "os.fork": "fork",
    "os.forkpty": "forkpty",
    "subprocess.Popen": "subprocess",
    "pty.spawn": "pty.spawn",
}
_PATH_EVENTS = {
    "os.mkdir",
    "os.remove",
    "os.rmdir",
    "os.chmod",
    "os.chown",
    "os.truncate",
    "os.utime",
    "os.mknod",
}
_TWO_PATH_EVENTS = {"os.rename", "os.link", "os.symlink"}


def _send(meta, value=None):
    try:
        parts = codec.encode_frame(meta, value)
    except codec.CodecError as exc:
        parts = codec.encode_frame(
            {"ok": False, "code": "sandbox.bad_type", "message": f"cannot return {exc}"}
        )
    size = codec.frame_size(parts)
    if size > _CONFIG["max_reply_bytes"]:
        msg = f"reply of {size} bytes exceeds the cap of {_CONFIG['max_reply_bytes']} bytes"
        parts = codec.encode_frame({"ok": False, "code": "sandbox.output_too_large", "message": msg})
    views = [memoryview(p).cast("B") for p in parts if len(p)]
    while views:
        k = os.writev(_WFD, views[:1024])
        while views and k >= len(views[0]):
            k -= len(views.pop(0))
        if views and k:
            views[0] = views[0][k:]


_PENDING = bytearray()  # request bytes read past the frame being parsed


def _read_exact(n):
    buf = bytearray(n)
    view, got = memoryview(buf), min(n, len(_PENDING))
    if got:
        view[:got] = _PENDING[:got]
        del _PENDING[:got]
    while got < n:
        if n - got < 65536:  # a whole small frame in one read
            chunk = os.read(_RFD, 65536)
            if not chunk:
                os._exit(0)  # parent went away
            take = min(len(chunk), n - got)
            view[got : got + take] = chunk[:take]
            _PENDING.extend(chunk[take:])
            got += take
        else:
            k = os.readv(_RFD, [view[got:]])
            if k == 0:
                os._exit(0)
            got += k
    return buf


def _receive():
    size = codec.PREFIX.size
    while len(_PENDING) < size:
        _fill()
    n_header, n_payload = codec.parse_prefix(bytes(_PENDING[:size]))
    end = size + n_header + n_payload
    if end <= 65536:  # a small frame: one read usually brought all of it
        while len(_PENDING) < end:
            _fill()
        header, payload = bytes(_PENDING[size : size + n_header]), _PENDING[size + n_header : end]
        del _PENDING[:end]
        return codec.decode_frame(header, payload)
    del _PENDING[:size]
    header = _read_exact(n_header)
    return codec.decode_frame(bytes(header), _read_exact(n_payload))


def _poll_request(limit):
    """Return when request bytes are pending or readable, or after ``limit`` seconds of polling that
    yields the CPU between polls (whoever else needs it gets it)."""
    end = time.monotonic() + limit
    while not _PENDING and not select.select([_RFD], [], [], 0)[0] and time.monotonic() < end:
        os.sched_yield()


def _fill():
    chunk = os.read(_RFD, 65536)
    if not chunk:
        os._exit(0)  # parent went away
    _PENDING.extend(chunk)


def _forbid(what):
    msg = f"{_MARK} {what} is not allowed in the sandbox"
    if _state["violation"] is None:
        _state["violation"] = msg
    raise PermissionError(msg)


def _inside(path):
    if path is None or isinstance(path, int):
        return True
    real = os.path.realpath(os.fsdecode(path))
    return real == _WORKDIR or real.startswith(_WORKDIR + os.sep) or real == os.devnull


def _other_process(path):
    """True for ``/proc/<pid>/...`` of another process (e.g. the parent's environ)."""
    real = os.path.realpath(os.fsdecode(path))
    if not real.startswith("/proc/"):
        return False
    head = real[6:].split("/", 1)[0]
    return head.isdigit() and int(head) != os.getpid()


def _allowed_socket(event, args):
    """The one Unix-domain socket of ``unix_socket``: creating an AF_UNIX socket and connecting to it."""
    path = _CONFIG.get("unix_socket")
    if not path:
        return False
    if event == "socket.__new__":
        return len(args) > 1 and args[1] == 1  # AF_UNIX
    if event == "socket.connect":
        address = args[1] if len(args) > 1 else None
        return isinstance(address, (str, bytes)) and os.fsdecode(address) == path
    return False


def _audit(event, args):
    if event == "open":
        path, mode, flags = args
        writing = (isinstance(mode, str) and any(c in mode for c in "wax+")) or (
            isinstance(flags, int) and flags & _WRITE_FLAGS
        )
        if writing and not _inside(path):
            _forbid(f"opening '{os.fsdecode(path)}' for writing (outside the working directory)")
        if not isinstance(path, int) and _other_process(path):
            _forbid(f"reading '{os.fsdecode(path)}' (another process's /proc entry)")
    elif event.startswith("socket.") and not _CONFIG["network"] and not _allowed_socket(event, args):
        _forbid(f"network access ({event})")
    elif event in _PROCESS_EVENTS:
        _forbid(f"creating processes ({_PROCESS_EVENTS[event]})")
    elif event in ("os.kill", "os.killpg"):
        pid = args[0]
        if pid not in (0, os.getpid(), -os.getpid()):
            _forbid(f"sending signals to other processes (pid {pid})")
    elif event in _PATH_EVENTS:
        if event != "os.truncate" and args[-1] is not None:
            return  # dir_fd-relative: left to the kernel layers
        if not _inside(args[0]):
            _forbid(f"{event} on '{os.fsdecode(args[0])}' (outside the working directory)")
    elif event in _TWO_PATH_EVENTS and (
        not _inside(args[1]) or (event == "os.rename" and not _inside(args[0]))
    ):
        _forbid(f"{event} to '{os.fsdecode(args[1])}' (outside the working directory)")


def _world_reachable(path):
    """True if any uid can list ``path``: every ancestor is world-searchable and it is world-readable."""
    try:
        if os.stat(path).st_mode & 5 != 5:
            return False
        parent = os.path.dirname(path)
        while parent and parent != os.path.dirname(parent):
            if not os.stat(parent).st_mode & 0o001:
                return False
            parent = os.path.dirname(parent)
    except OSError:
        return True  # absent entries are harmless
    return True


def _reroute_unreachable_paths():
    """Keep the interpreter's own library importable after the uid drop.

    An interpreter installed under a private directory (e.g. ``/root/.pyenv``) would be unreadable
    to ``nobody``. Each such ``sys.path`` directory is opened now, as root, and replaced by its
    ``/proc/self/fd/N`` alias: lookups through that descriptor start inside the directory, so only
    the library itself (public content) becomes readable, not its private ancestors.
    """
    aliases = {}
    for i, entry in enumerate(list(sys.path)):
        if entry and os.path.isdir(entry) and not _world_reachable(os.path.realpath(entry)):
            fd = os.open(entry, os.O_RDONLY | os.O_DIRECTORY)
            sys.path[i] = aliases[entry.rstrip(os.sep) + os.sep] = f"/proc/self/fd/{fd}/"
    for module in list(sys.modules.values()):  # packages imported already (ctypes, json, ...)
        path = getattr(module, "__path__", None)
        if isinstance(path, list):
            for j, p in enumerate(path):
                for old, new in aliases.items():
                    if isinstance(p, str) and p.startswith(old):
                        path[j] = new + p[len(old) :]
    sys.path_importer_cache.clear()


def _isolate():
    layers = {"netns": False, "uid_drop": False, "no_new_privs": False, "nproc": False, "landlock": False}
    libc = ctypes.CDLL(None, use_errno=True)
    # A layer the kernel refuses (unshare needs CAP_SYS_ADMIN, absent in a default Docker container;
    # setuid needs CAP_SETUID) is left off and reported, never blamed on the submission.
    if _CONFIG["unshare_net"]:
        layers["netns"] = libc.unshare(_CLONE_NEWNET) == 0
    os.chdir(_WORKDIR)
    os.umask(0o077)
    cpu = int(_CONFIG["cpu_seconds"] + 0.999)
    resource.setrlimit(resource.RLIMIT_CORE, (0, 0))
    resource.setrlimit(resource.RLIMIT_CPU, (cpu, cpu + 2))
    resource.setrlimit(resource.RLIMIT_AS, (_CONFIG["memory_bytes"],) * 2)
    resource.setrlimit(resource.RLIMIT_FSIZE, (_CONFIG["file_bytes"],) * 2)
    opened = (
        landlock.rule_paths(_WORKDIR, _CONFIG.get("readable", ())) if _CONFIG.get("landlock", True) else []
    )
    if _CONFIG["uid"] is not None:
        _reroute_unreachable_paths()
        with contextlib.suppress(PermissionError):
            os.setgroups([])
            os.setgid(_CONFIG["gid"])
            os.setuid(_CONFIG["uid"])
        layers["uid_drop"] = os.getuid() == os.geteuid() == _CONFIG["uid"]
    layers["no_new_privs"] = libc.prctl(_PR_SET_NO_NEW_PRIVS, 1, 0, 0, 0) == 0
    if opened and layers["no_new_privs"]:
        layers["landlock"] = landlock.restrict(libc, opened, _CONFIG["network"])
    resource.setrlimit(resource.RLIMIT_NPROC, (_CONFIG["max_processes"],) * 2)
    layers["nproc"] = os.getuid() != 0
    return layers


def _fault(code, exc):
    return {
        "ok": False,
        "code": code,
        "message": f"{type(exc).__name__}: {exc}",
        "detail": traceback.format_exc(),
    }


def _classify(exc):
    if isinstance(exc, MemoryError):
        return "sandbox.memory"
    if _state["violation"] is not None or (isinstance(exc, PermissionError) and _MARK in str(exc)):
        return "sandbox.forbidden"
    return "sandbox.exception"


class _VerifierBlocker:
    """Meta-path finder refusing the verifier package: submitted code may use the public toolkit
    (``rle_design``) but never imports verifier internals (``rle_tasks``). A tripwire only: the
    verifier runs in the parent process, which nothing in the child can patch."""

    @staticmethod
    def find_spec(name, path=None, target=None):
        if name == "rle_tasks" or name.startswith("rle_tasks."):
            raise ImportError(
                f"{_MARK} importing the verifier package '{name}' is not allowed in the sandbox"
            )
        return None


def _flush():
    for stream in (sys.stdout, sys.stderr):
        try:  # noqa: SIM105 - contextlib.suppress costs a context manager per call of the loop
            stream.flush()
        except Exception:  # noqa: BLE001, S110 - a closed or replaced stream must not kill the loop
            pass


def _load():
    spec = importlib.util.spec_from_file_location(_CONFIG["module_name"], _CONFIG["module_file"])
    module = importlib.util.module_from_spec(spec)
    sys.modules[_CONFIG["module_name"]] = module
    spec.loader.exec_module(module)
    return module


def _call(module, name, args):
    fn = getattr(module, name, None)
    if not callable(fn):
        return {
            "ok": False,
            "code": "sandbox.missing_function",
            "message": f"no callable named '{name}'",
        }, None
    _state["violation"] = None
    try:
        value = fn(*args)
    except SystemExit as exc:
        _flush()
        _send({"ok": False, "code": "sandbox.exit", "message": f"sys.exit({exc.code!r}) called", "status": 0})
        os._exit(0)
    except BaseException as exc:  # noqa: BLE001 - every participant exception becomes a fault
        return _fault(_classify(exc), exc), None
    if _state["violation"] is not None:
        return {
            "ok": False,
            "code": "sandbox.forbidden",
            "message": _state["violation"] + " (error swallowed)",
        }, None
    return {"ok": True}, value


def main():
    try:
        layers = _isolate()
    except Exception as exc:  # noqa: BLE001 - our own setup failed: reported as an internal fault
        _send({"ok": False, "code": "internal", "message": f"{type(exc).__name__}: {exc}"})
        os._exit(0)
    sys.addaudithook(_audit)
    sys.meta_path.insert(0, _VerifierBlocker)
    sys.path.insert(0, _WORKDIR)
    try:
        module = _load()
    except SystemExit as exc:
        _send(
            {"ok": False, "code": "sandbox.exit", "message": f"sys.exit({exc.code!r}) called during import"}
        )
        os._exit(0)
    except BaseException as exc:  # noqa: BLE001
        code = _classify(exc)
        _send(_fault("sandbox.import_error" if code == "sandbox.exception" else code, exc))
        os._exit(0)
    _flush()
    _send({"ok": True, "op": "ready", "layers": layers})
    while True:
        meta, value = _receive()
        op = meta.get("op")
        if op == "wake":  # a call follows shortly: poll for it rather than sleep (no reply)
            _poll_request(_CONFIG["wake_poll_s"])
            continue
        if op == "call":
            reply, result = _call(module, meta["fn"], value)
        elif op == "has":
            reply, result = {"ok": True}, callable(getattr(module, meta["fn"], None))
        else:
            os._exit(0)
        _flush()
        _send(reply, result)


if __name__ == "__main__":
    main()
