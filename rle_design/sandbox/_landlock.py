"""Landlock rules of a sandbox child (Linux >= 5.13, unprivileged): read its interpreter's library
trees and the public toolkit, read and write its working directory; with ABI >= 4 no TCP bind or
connect, with ABI >= 6 no signal to a process outside the sandbox.

Trusted code, loaded by ``_bootstrap.py`` from this file (the child runs in isolated mode and never
imports ``rle_design``), before the submitted module is imported: ``rule_paths`` opens the rules'
paths while the child is still root, ``restrict`` applies them after ``no_new_privs``.
"""

import ctypes
import importlib.util
import os
import struct
import sys

# Landlock (Linux >= 5.13, unprivileged): syscall numbers (the same on every architecture) and rights.
_LL_CREATE, _LL_ADD_RULE, _LL_RESTRICT = 444, 445, 446
_LL_VERSION = 1  # landlock_create_ruleset flag: return the ABI version
_LL_PATH_BENEATH = 1
_LL_EXECUTE, _LL_WRITE_FILE, _LL_READ_FILE, _LL_READ_DIR = 1, 2, 4, 8
_LL_TRUNCATE, _LL_IOCTL_DEV = 1 << 14, 1 << 15
_LL_READ = _LL_EXECUTE | _LL_READ_FILE | _LL_READ_DIR
_SYSTEM_READABLE = (
    "/usr",
    "/lib",
    "/lib64",
    "/lib32",
    "/etc/ld.so.cache",
    "/etc/localtime",
    "/proc/self",
    "/proc/cpuinfo",
    "/proc/meminfo",
    "/proc/stat",
    "/sys/devices/system/cpu",
    "/sys/fs/cgroup",
    "/dev/urandom",
    "/dev/random",
    "/dev/zero",
)
"""Read-only outside the interpreter's own trees: shared libraries and what numeric libraries probe."""


def _readable_trees(readable):
    """The interpreter's library trees, the public toolkit (never the verifier package) and
    ``readable``."""
    paths = {sys.prefix, sys.base_prefix, sys.exec_prefix, sys.base_exec_prefix, *_SYSTEM_READABLE}
    paths.update(p for p in sys.path if p and not p.startswith("/proc/self/fd/"))
    spec = importlib.util.find_spec("rle_design")  # locates only: nothing is imported
    if spec is not None and spec.submodule_search_locations:
        paths.update(spec.submodule_search_locations)
    paths.update(readable)
    return sorted(paths)


def rule_paths(workdir, readable):
    """``(O_PATH descriptor, rights, is_dir)`` per rule, opened now (before any uid drop, so that an
    interpreter under a private directory can still be named)."""
    rules = [(p, _LL_READ) for p in _readable_trees(readable)]
    rules += [(os.devnull, _LL_READ_FILE | _LL_WRITE_FILE), (workdir, -1)]
    opened = []
    for path, rights in rules:
        try:
            opened.append((os.open(path, os.O_PATH | os.O_CLOEXEC), rights, os.path.isdir(path)))
        except OSError:
            continue  # absent on this system
    return opened


def restrict(libc, opened, network):
    """Restrict this process (and nothing else) to reading its library trees and reading and writing
    its working directory; with ABI >= 4 no TCP bind or connect, with ABI >= 6 no signal to a
    process outside the sandbox. Returns whether the restriction is in force."""
    syscall = libc.syscall
    syscall.restype = ctypes.c_long
    try:
        abi = syscall(ctypes.c_long(_LL_CREATE), None, ctypes.c_size_t(0), ctypes.c_uint32(_LL_VERSION))
        if abi < 1:
            return False
        fs = (1 << 13) - 1 | (1 << 13 if abi >= 2 else 0) | (_LL_TRUNCATE if abi >= 3 else 0)
        fs |= _LL_IOCTL_DEV if abi >= 5 else 0
        net = 3 if abi >= 4 and not network else 0
        scoped = 3 if abi >= 6 else 0
        attr = struct.pack("=QQQ", fs, net, scoped)[: 8 if abi < 4 else 16 if abi < 6 else 24]
        ruleset = syscall(
            ctypes.c_long(_LL_CREATE), ctypes.c_char_p(attr), ctypes.c_size_t(len(attr)), ctypes.c_uint32(0)
        )
        if ruleset < 0:
            return False
        try:
            file_rights = _LL_EXECUTE | _LL_WRITE_FILE | _LL_READ_FILE | (fs & (_LL_TRUNCATE | _LL_IOCTL_DEV))
            for fd, rights, is_dir in opened:
                rights = fs if rights < 0 else rights & fs
                rule = struct.pack("=Qi", rights if is_dir else rights & file_rights, fd)
                added = syscall(
                    ctypes.c_long(_LL_ADD_RULE),
                    ctypes.c_int(ruleset),
                    ctypes.c_int(_LL_PATH_BENEATH),
                    ctypes.c_char_p(rule),
                    ctypes.c_uint32(0),
                )
                if added != 0:
                    return False
            return syscall(ctypes.c_long(_LL_RESTRICT), ctypes.c_int(ruleset), ctypes.c_uint32(0)) == 0
        finally:
            os.close(ruleset)
    finally:
        for fd, _, _ in opened:
            os.close(fd)
