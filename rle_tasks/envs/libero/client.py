"""Evaluation client of family 05: LIBERO episodes driven by a served policy over the socket protocol.

``serving(solution_dir, socket_dir)`` starts ``solution.py`` in the project sandbox (its ``serve``
entry point gets the socket path and connects to it; the socket is the only one the child may open)
and yields a connected ``rle_design.policy_socket.PolicyServer``. ``run_episode`` resets a
``LiberoEnv`` to an official initial state and executes the policy's action chunks until success or
the task's horizon. The agent's development client and the replay verifier both use these.
"""

from __future__ import annotations

import contextlib
import dataclasses
import os
import shutil
import tempfile
import threading
import time
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from rle_design.policy_socket import PolicyServer, ProtocolError, Request
from rle_design.sandbox import ParticipantFault, Sandbox, SandboxLimits
from rle_tasks.envs.libero import LiberoEnv

SERVE_LIMITS = SandboxLimits(
    cpu_seconds=3600.0,
    memory_bytes=8 << 30,
    max_processes=4096,  # threads of torch and BLAS; fork and exec stay refused by the audit hook
    call_timeout_s=3600.0,
    startup_timeout_s=120.0,
)
"""Limits of a served policy's process: the whole evaluation (of one runner unit) is one ``serve``
call."""
CONNECT_S = 120.0
"""How long the served policy may take to load its checkpoint and connect [s]."""


@dataclass(frozen=True)
class EpisodeResult:
    """One evaluated episode.

    Attributes:
        init_index: Official initial state.
        success: The task's goal held at some step.
        steps: Environment steps taken.
        requests: Policy requests made.
        fault: ``protocol.*`` code that ended the episode, or "".
    """

    init_index: int
    success: bool
    steps: int
    requests: int
    fault: str = ""


def request(obs: dict[str, np.ndarray], instruction: str, episode: int, step: int) -> Request:
    """The protocol request of a LIBERO observation (both views stacked, state as float32)."""
    views = np.stack([obs["agentview"], obs["wrist"]]).astype(np.uint8)
    return Request(instruction, views, np.asarray(obs["state"], np.float32), episode, step)


def run_episode(
    env: LiberoEnv, policy: PolicyServer, init_index: int, episode: int = 0, max_steps: int | None = None
) -> EpisodeResult:
    """Reset ``env`` to ``init_index`` and run ``policy`` until success or ``max_steps`` (default: the
    task's horizon). A protocol fault ends the episode as a failure with its code."""
    task = env.start()
    horizon = task.max_steps if max_steps is None else int(max_steps)
    obs = env.reset(init_index)
    steps = requests = 0
    while steps < horizon:
        try:
            chunk = policy.act(request(obs, task.language, episode, steps))
        except ProtocolError as exc:
            return EpisodeResult(init_index, False, steps, requests, exc.code)
        requests += 1
        for i, a in enumerate(chunk):
            # only the chunk's last observation reaches the policy: the others are not rendered
            obs, success = env.step(np.clip(a, -1.0, 1.0), views=i == len(chunk) - 1)
            steps += 1
            if success:
                return EpisodeResult(init_index, True, steps, requests)
            if steps >= horizon:
                break
    return EpisodeResult(init_index, False, steps, requests)


@contextlib.contextmanager
def serving(
    solution_dir: Path, *, env: str = "libero", request_timeout_s: float = 10.0
) -> Iterator[PolicyServer]:
    """Serve ``solution_dir/solution.py`` (entry point ``serve(socket_path)``) in the sandbox and yield
    the connected evaluator side. On exit the policy gets ``bye`` and its process is closed.

    Raises:
        ProtocolError: ``protocol.no_policy`` when it does not connect within ``CONNECT_S`` or its
            process ends first; the child's own fault (``sandbox.*``) is in the message.
    """
    sock_dir = Path(tempfile.mkdtemp(prefix="rle-f05s-"))  # traversable by the child's uid
    os.chmod(sock_dir, 0o711)
    path = sock_dir / "policy.sock"
    limits = dataclasses.replace(SERVE_LIMITS, unix_socket=str(path))
    fault: list[ParticipantFault] = []
    try:
        with PolicyServer(path, env=env, request_timeout_s=request_timeout_s) as server:
            box = Sandbox(Path(solution_dir) / "solution.py", limits=limits, name="solution")

            def run() -> None:
                try:
                    box.call("serve", str(path))
                except ParticipantFault as exc:
                    fault.append(exc)

            box.start()
            thread = threading.Thread(target=run, daemon=True)
            thread.start()
            try:
                _accept(server, thread, fault)
                yield server
            finally:
                server.close()
                thread.join(timeout=10.0)
                box.close()
    finally:
        shutil.rmtree(sock_dir, ignore_errors=True)


def _accept(server: PolicyServer, thread: threading.Thread, fault: list[ParticipantFault]) -> None:
    """Wait for the policy to connect; give up when its process has ended or ``CONNECT_S`` passed."""
    deadline = time.monotonic() + CONNECT_S
    while True:
        try:
            server.accept(0.5)
            return
        except ProtocolError:
            if thread.is_alive() and time.monotonic() < deadline:
                continue
            why = f": {fault[0].code}: {fault[0].message}" if fault else ""
            ended = "its process ended" if not thread.is_alive() else f"{CONNECT_S:.0f} s passed"
            raise ProtocolError("no_policy", f"the policy did not connect ({ended}){why}") from None
