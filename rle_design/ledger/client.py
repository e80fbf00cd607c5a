"""The agent's side of a metered session: ``LedgerClient(socket_path)``; it never holds the key."""

from __future__ import annotations

import warnings
from multiprocessing.connection import Client
from pathlib import Path
from typing import Any

from rle_design.ledger.records import LedgerError
from rle_design.ledger.server import MAX_MESSAGE_BYTES, decode, encode


class LedgerClient:
    """Connection to a ledger server.

    Each ``reset`` and each ``step`` costs one step of the budget; ``observe`` and ``info`` are free.
    Observations are dicts with ``qpos`` [m, rad], ``qvel`` [m/s, rad/s], ``time`` [s] and the
    environment's extra observers.

    Args:
        address: The server's Unix socket (``.rle/ledger.sock`` in a dev workspace).
    """

    def __init__(self, address: str | Path) -> None:
        try:
            self._conn = Client(str(address), family="AF_UNIX")
        except OSError as exc:
            raise LedgerError(
                f"cannot connect to the ledger server at {address}: {exc.strerror or exc}",
                code="ledger.no_server",
            ) from None
        self.steps_used = 0
        self.clipped_actions = 0
        """Actions the server clipped to the environment's range (see ``info()["action_low"/"action_high"]``)."""

    def _request(self, op: str, value: Any = None) -> tuple[dict, Any]:
        try:
            self._conn.send_bytes(encode({"op": op}, value))
            meta, result = decode(self._conn.recv_bytes(MAX_MESSAGE_BYTES))
        except (EOFError, OSError) as exc:
            raise LedgerError(
                f"ledger server connection lost during '{op}': {exc}", code="ledger.no_server"
            ) from None
        if not meta.get("ok"):
            raise LedgerError(str(meta.get("message")), code=str(meta.get("code")))
        self.steps_used = meta.get("steps_used", self.steps_used)
        return meta, result

    def reset(self, **options: Any) -> dict[str, Any]:
        """Reset the simulation (costs one step); returns the observation. Sessions over several scenes
        take options (e.g. ``evaluation=True``); others take none."""
        return self._request("reset", options or None)[1]

    def step(self, action: Any) -> dict[str, Any]:
        """Apply ``action`` (the actuators' ctrl) for one control period (costs one step).

        Entries outside the action range are clipped to it (the ledger records the applied action);
        the first clipped action of a connection warns (``RuntimeWarning``), ``clipped_actions``
        counts them."""
        meta, obs = self._request("step", action)
        clipped = meta.get("clipped", 0)
        if clipped:
            if not self.clipped_actions:
                warnings.warn(
                    f"{clipped} action entries were outside the action range and were clipped to it "
                    "(env.info() gives action_low / action_high); the ledger records the clipped action",
                    RuntimeWarning,
                    stacklevel=2,
                )
            self.clipped_actions += 1
        return obs

    def observe(self) -> dict[str, Any]:
        """Current observation (free)."""
        return self._request("observe")[1]

    def query(self, name: str, **args: Any) -> Any:
        """A free, read-only question to the environment (what it answers is its own, e.g. a segmentation)."""
        return self._request("query", {"name": name, "args": args})[1]

    def info(self) -> dict[str, Any]:
        """Budget (``steps_used``, ``budget``) and model dimensions (free)."""
        return self._request("info")[1]

    def seal(self) -> str:
        """End the session: the server seals the ledger and exits; returns the seal hash."""
        return self._request("seal")[1]

    def close(self) -> None:
        """Disconnect (the session stays open for the next connection)."""
        self._conn.close()

    def __enter__(self) -> LedgerClient:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
