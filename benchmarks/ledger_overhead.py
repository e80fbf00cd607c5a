"""Cost of metering: ledger recording per executed action, and the IPC round trip (target: <= 5 %).

Scene: the Panda arm (robosuite asset, ``load_robot("panda", keyframes=False)``) on a fixed base with a floor,
timestep 2 ms, control period 20 ms = 10 physics steps, torque actions N(0, 5 N m) from a seeded RNG.

What is compared, per executed action:

- ``physics``: ``mj_step(model, data, 10)`` alone (context only);
- ``unmetered``: ``MeteredSession(key=None).step(action)`` -- action validation, 10 physics steps
  and the observation (qpos, qvel, time), no ledger;
- ``metered``: ``MeteredSession(key=KEY).step(action)`` -- the same plus the chained ledger record
  (action hex, canonical payload, SHA-256 digest, HMAC-SHA256, line hash, buffered write);
- ``client_plain``: ``LedgerClient.step(action)`` to a server process without a key (no ledger);
- ``client``: ``LedgerClient.step(action)`` to the metered server over the Unix socket (the server
  replies first and writes the record while the agent reads the reply).

Design: paired and interleaved. Both members of a pair replay the same actions from the same reset
state (identical physics work) and alternate action by action (ABBA order), so both see the same
machine load. The ledger groups ``GROUP`` = 16 actions per record (group commit), so one action in
16 pays for writing a record: the cost per action is therefore taken over blocks of 16 consecutive
actions aligned with the groups, ``d = median over blocks of sum(metered - unmetered) / 16``, which
keeps the record's cost in every block while the median still discards blocks hit by preemption
from other processes. The metering overhead is ``d / median(unmetered)`` (server CPU per action,
target <= 5 %); the same statistic for ``client - client_plain`` gives the agent-visible overhead,
and ``median(client) - median(metered)`` the IPC round trip. Exit status 1 if the server-side target
is missed.

Usage: ``.venv/bin/python -m benchmarks ledger_overhead [--steps N] [--rounds R]``.
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

import mujoco
import numpy as np

from rle_design.ledger import LedgerClient, LedgerServer, MeteredEnv, MeteredSession
from rle_design.scene import load_robot

KEY = b"benchmark-ledger-key-0123456789ab"
TARGET = 0.05
GROUP = 16
Step = Callable[[np.ndarray], object]


def panda_xml() -> str:
    """The Panda arm on a fixed base above a floor, 2 ms timestep, as a self-contained XML string."""
    spec = load_robot("panda", keyframes=False)
    spec.meshdir = spec.modelfiledir  # absolute mesh paths so the XML string compiles anywhere
    spec.option.timestep = 0.002
    spec.worldbody.add_geom(name="floor", type=mujoco.mjtGeom.mjGEOM_PLANE, size=[2, 2, 0.1])
    return spec.to_xml()


def paired(a: Step, b: Step, actions: np.ndarray) -> tuple[list[float], list[float]]:
    """Per-action wall times [s] of ``a`` and ``b`` stepping the same actions, alternating ABBA."""
    clock = time.perf_counter
    ta, tb = [], []
    for i, act in enumerate(actions):
        order = ((a, ta), (b, tb)) if i % 2 == 0 else ((b, tb), (a, ta))
        for step, out in order:
            t0 = clock()
            step(act)
            out.append(clock() - t0)
    return ta, tb


def measure(steps: int, rounds: int) -> dict[str, float]:
    """Medians [s] per executed action, and median paired differences (``d_*``)."""
    env = MeteredEnv(panda_xml(), n_substeps=10)
    tmp = Path(tempfile.mkdtemp(prefix="rle-ledger-bench-"))
    plain = MeteredSession(env, task_id="bench", budget=None)
    metered = MeteredSession(
        env, task_id="bench", budget=None, key=KEY, ledger_path=tmp / "inproc.jsonl", actions_per_record=GROUP
    )
    actions = np.random.default_rng(0).normal(0.0, 5.0, size=(steps, plain.model.nu))
    model, data = plain.model, mujoco.MjData(plain.model)

    def physics(a: np.ndarray) -> None:
        data.ctrl[:] = a
        mujoco.mj_step(model, data, 10)

    server = LedgerServer(
        env, key=KEY, ledger_path=tmp / "ipc.jsonl", socket_path=tmp / "s.sock", task_id="bench", budget=None
    )
    plain_server = LedgerServer(
        env, key=None, ledger_path=None, socket_path=tmp / "p.sock", task_id="bench", budget=None
    )
    t: dict[str, list[float]] = {k: [] for k in ("physics", "unmetered", "metered", "client_plain", "client")}
    server.start()
    plain_server.start()
    try:
        with (
            LedgerClient(server.socket_path) as client,
            LedgerClient(plain_server.socket_path) as plain_client,
        ):
            for _ in range(rounds):
                mujoco.mj_resetData(model, data)
                clock = time.perf_counter
                for a in actions:
                    t0 = clock()
                    physics(a)
                    t["physics"].append(clock() - t0)
                plain.reset()
                metered.reset()
                ta, tb = paired(plain.step, metered.step, actions)
                t["unmetered"] += ta
                t["metered"] += tb
                plain_client.reset()
                client.reset()
                ta, tb = paired(plain_client.step, client.step, actions)
                t["client_plain"] += ta
                t["client"] += tb
            client.seal()
        server.wait(30)
    finally:
        server.stop()
        plain_server.stop()
        metered.seal()
    out = {k: statistics.median(v) for k, v in t.items()}
    out["d_metered"] = _block_difference(t["unmetered"], t["metered"], steps)
    out["d_client"] = _block_difference(t["client_plain"], t["client"], steps)
    return out


def _block_difference(a: list[float], b: list[float], steps: int) -> float:
    """Median over group-aligned blocks of the mean per-action difference ``b - a`` [s]."""
    diff = np.asarray(b) - np.asarray(a)
    blocks = [
        diff[r * steps + k : r * steps + k + GROUP].mean()
        for r in range(len(diff) // steps)
        for k in range(0, steps - GROUP + 1, GROUP)
    ]
    return float(np.median(blocks))


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=2000, help="actions per round")
    parser.add_argument("--rounds", type=int, default=5, help="rounds (statistics over all actions)")
    args = parser.parse_args()
    t = measure(args.steps, args.rounds)
    us = {k: v * 1e6 for k, v in t.items()}
    overhead = t["d_metered"] / t["unmetered"]
    print(f"Panda, 10 x 2 ms physics steps per action, {args.rounds} rounds x {args.steps} actions (medians)")
    for name in ("physics", "unmetered", "metered", "client_plain", "client"):
        print(f"  {name:<12} {us[name]:8.1f} us/action")
    print(f"  ledger recording (group-aligned paired difference): {us['d_metered']:.2f} us/action")
    print(f"  metering overhead (metered vs unmetered server step): {overhead * 100:.2f} % (target <= 5 %)")
    print(f"  IPC round trip (client - metered): {us['client'] - us['metered']:.1f} us/action")
    print(
        f"  agent-visible metering overhead (client vs client_plain): "
        f"{us['d_client']:.1f} us/action = {t['d_client'] / t['client_plain'] * 100:.2f} %"
    )
    if overhead > TARGET:
        print(f"  MISSED: metering overhead exceeds the target by {(overhead - TARGET) * 100:.2f} points")
        return 1
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
