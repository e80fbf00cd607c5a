"""The parent's side of a sandbox child's pipes: frames written with as few ``writev`` calls as the
pipe allows, replies read into a pending buffer or straight into their own, and the wait for a reply
(a short poll first, then a sleep), each bounded by a deadline. Both pipe ends are non-blocking."""

from __future__ import annotations

import os
import select
import time

CHUNK = 1 << 16
"""Bytes read at once for small frames."""
IOV_MAX = 1024
"""Buffers per ``writev`` (Linux ``UIO_MAXIOV``)."""
POLITE_AFTER_S = 1e-4
"""A reply poll longer than this yields the CPU between reads [s]."""


class ChildGone(Exception):
    """The child closed its end of a pipe."""


class Expired(Exception):
    """Nothing could be written or read by the deadline."""


def write_all(fd: int, parts: list, deadline: float) -> None:
    """Write a frame's parts to ``fd``.

    Raises:
        ChildGone: the pipe is broken. Expired: the pipe stayed full until ``deadline``.
    """
    views = [memoryview(p).cast("B") for p in parts if len(p)]
    while views:
        try:
            k = os.writev(fd, views[:IOV_MAX])
        except BlockingIOError:
            k = 0
        except OSError:  # BrokenPipeError among them: the child is gone
            raise ChildGone from None
        while views and k >= len(views[0]):
            k -= len(views.pop(0))
        if views and k:
            views[0] = views[0][k:]
        elif views and not select.select([], [fd], [], max(0.0, deadline - time.monotonic()))[1]:
            raise Expired


def fill(fd: int, pending: bytearray, deadline: float, spin_s: float) -> None:
    """Append what ``fd`` holds (at least one byte) to ``pending``."""
    while True:
        try:
            chunk = os.read(fd, CHUNK)
        except BlockingIOError:
            await_readable(fd, deadline, spin_s)
            continue
        if not chunk:
            raise ChildGone
        pending += chunk
        return


def read_exact(fd: int, pending: bytearray, n: int, deadline: float, spin_s: float) -> bytearray:
    """``n`` bytes of the stream: ``pending``'s first (removed from it), then read straight into the
    buffer."""
    buf = bytearray(n)
    view, got = memoryview(buf), min(n, len(pending))
    if got:
        view[:got] = pending[:got]
        del pending[:got]
    while got < n:
        try:
            k = os.readv(fd, [view[got:]])
        except BlockingIOError:
            await_readable(fd, deadline, spin_s)
            continue
        if k == 0:
            raise ChildGone
        got += k
    return buf


def await_readable(fd: int, deadline: float, spin_s: float) -> None:
    """Return once ``fd`` is readable. Polls for up to ``spin_s`` first (a reply read while polling
    needs no wake-up, which costs more than a short call), yielding the CPU between polls after the
    first ``POLITE_AFTER_S`` so that whoever needs it gets it; then sleeps.

    Raises:
        Expired: Nothing to read by ``deadline``.
    """
    now = time.monotonic()
    spin_until, polite_from = now + spin_s, now + POLITE_AFTER_S
    while now < spin_until:
        if select.select([fd], [], [], 0)[0]:
            return
        if now > polite_from:
            os.sched_yield()
        now = time.monotonic()
    if deadline - now <= 0 or not select.select([fd], [], [], deadline - now)[0]:
        raise Expired
