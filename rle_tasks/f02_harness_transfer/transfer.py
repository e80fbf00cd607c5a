"""Transfer evaluation: one fresh agent, one unseen kitchen, the submitted harness and nothing else.

A ``TransferUnit`` is one of the five independent evaluation units (``run_unit``, fanned out by the
core fan-out):

1. A metered session of the group's held-out task in a kitchen from the secret is served by a ledger
   server (5,000 steps, 1 h; its key derived from the secret for this trial), on a socket the agent
   can reach.
2. A fresh workspace holds only a copy of the submitted ``agent_harness/`` (regular files only),
   ``instruction.md`` (the held-out task's instruction) and ``client.py`` (connects to the session).
3. The fresh agent runs there. ``scripted`` (tests, demo, default) is ``public/fresh_agent.py``, run in
   the sandbox (``rle_design.sandbox``: own uid, Landlock, no network but the session's socket); an
   operator's agent is an external command (``RLE_F02_AGENT``, e.g. a coding-agent CLI) started with
   the workspace as its working directory and ``RLE_WORKSPACE`` set, whose isolation is the
   operator's (run it in its own container).
4. The server seals the ledger when the agent ends (or its time is up); the verifier checks the seal
   under its key and replays every recorded reset and action on the same scene, evaluating each
   conjunct of the task after every one: ``b`` = conjuncts satisfied at the first reset, ``m`` = the
   most satisfied at once, ``n`` = their number; ``s_trial = 1`` on success, else
   ``clip((m - b) / (n - b), 0, 1)``, and 0 when the ledger holds no reset or ``n = b``.
"""

from __future__ import annotations

import os
import shlex
import shutil
import subprocess
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

import mujoco
import numpy as np

from rle_design.control.replay import ReplayError, replay
from rle_design.excerpt import EXCERPT_CHARS, excerpt
from rle_design.ledger import LedgerServer, Limits, check_ledger
from rle_design.sandbox import ParticipantFault, Sandbox, SandboxLimits
from rle_tasks.core.runtime.secrets import Secret, derive_seed
from rle_tasks.envs.kitchen.env import KitchenEnv
from rle_tasks.envs.kitchen.scene import build_scene

from .constants import TRIALS
from .groups import Group
from .harness import FRESH_INSTRUCTION, HARNESS_DIR, HarnessError, copy_harness

__all__ = [
    "AGENT_ENV",
    "TransferResult",
    "TransferUnit",
    "run_unit",
    "stage_score",
    "targets",
]

AGENT_ENV = "RLE_F02_AGENT"
"""Environment variable naming the operator's fresh-agent command (unset: the scripted agent)."""
FRESH_AGENT = Path(__file__).resolve().parent / "public" / "fresh_agent.py"
AGENT_STATUSES = ("ran", "no_manual", "no_entry_point", "missing_function")
"""How the scripted fresh agent may say it ended; any other reply is ``bad_reply``."""
_CLIENT = '''"""Metered client of this evaluation (one kitchen, the held-out task)."""

ADDRESS = {address!r}


def connect():
    """A new connection to the session (resets and actions cost one of its {steps} steps)."""
    from rle_design.ledger import LedgerClient

    return LedgerClient(ADDRESS)
'''


@dataclass(frozen=True)
class TransferUnit:
    """One fresh agent's evaluation.

    Attributes:
        trial: Index (0-4).
        task: Held-out composite task.
        layout_seed: Kitchen layout (from the secret).
        episode_seed: Episode (from the secret).
        harness: The submitted ``agent_harness/`` directory.
        key: Ledger key of this trial's session.
        ledger_task: Task id written into the ledger.
        agent: ``"scripted"`` or an external command line.
        steps: Charged steps of the session.
        wall_time_s: Time of the agent [s].
        out_dir: Where to write ``agent_<trial>.png`` (the session's final state), or None.
    """

    trial: int
    task: str
    layout_seed: int
    episode_seed: int
    harness: Path
    key: bytes = field(repr=False)
    ledger_task: str
    agent: str = "scripted"
    steps: int = 5000
    wall_time_s: float = 3600.0
    out_dir: Path | None = None


@dataclass(frozen=True)
class TransferResult:
    """What one fresh agent achieved.

    Attributes:
        trial: Index.
        status: ``scored``, or why there is nothing to score: ``harness_unusable`` ...
        agent: How the agent ended (``ran``, ``no_entry_point``, ``missing_function``, a fault code,
            ``timeout``, ``exit <code>``).
        message: The agent's or the harness's message.
        stages: Names of the conjuncts.
        b: Conjuncts satisfied at the first reset.
        m: Most conjuncts satisfied at once.
        n: Number of conjuncts.
        success: The task's success predicate held after some action.
        score: ``s_trial``.
        steps: Charged steps the ledger records.
        ledger: Verdict code of the session's ledger.
        elapsed_s: Wall time of the unit [s].
    """

    trial: int
    status: str
    agent: str
    message: str
    stages: tuple[str, ...] = ()
    b: int = 0
    m: int = 0
    n: int = 0
    success: bool = False
    score: float = 0.0
    steps: int = 0
    ledger: str = ""
    elapsed_s: float = 0.0

    def record(self) -> dict:
        """The report's copy: every field but the wall time (a report is the same on every run)."""
        return {
            k: (list(v) if isinstance(v, tuple) else v) for k, v in self.__dict__.items() if k != "elapsed_s"
        }


def targets(secret: Secret, group: Group) -> tuple[tuple[int, int], ...]:
    """(layout seed, episode seed) of each fresh agent's kitchen: HMAC(secret, task id, "agent/<k>/...")."""
    return tuple(
        (
            derive_seed(secret, group.task_id, f"agent/{k}/layout"),
            derive_seed(secret, group.task_id, f"agent/{k}/episode"),
        )
        for k in range(TRIALS)
    )


def stage_score(b: int, m: int, n: int, success: bool, recorded: bool) -> float:
    """The card's ``s_trial``: 1 on success; 0 without stage records or when ``n = b``; else
    ``clip((m - b) / (n - b), 0, 1)``."""
    if success:
        return 1.0
    if not recorded or n == b:
        return 0.0
    return float(np.clip((m - b) / (n - b), 0.0, 1.0))


def _env(unit: TransferUnit, images: bool) -> KitchenEnv:
    scene = build_scene(unit.layout_seed, unit.task, unit.episode_seed)
    return KitchenEnv(xml=scene.xml, scene=scene, level=2, image_size=(128, 128) if images else None)


def _run_scripted(stage: Path, socket_path: Path, unit: TransferUnit) -> tuple[str, str]:
    limits = SandboxLimits(
        cpu_seconds=unit.wall_time_s + 60.0,
        memory_bytes=6 << 30,
        call_timeout_s=unit.wall_time_s,
        startup_timeout_s=120.0,
        unix_socket=str(socket_path),
    )
    try:
        with Sandbox(stage / "fresh_agent.py", limits=limits, name="fresh_agent") as box:
            out = box.call("run")
        if isinstance(out, dict):  # the fresh agent's reply passes through the harness: participant text
            status = out.get("status", "ran")
            status = status if status in AGENT_STATUSES else "bad_reply"
            return status, excerpt(out.get("message", ""))
        return "ran", ""
    except ParticipantFault as exc:
        return exc.code, exc.message


def _run_command(stage: Path, unit: TransferUnit) -> tuple[str, str]:
    env = {"PATH": os.environ.get("PATH", "/usr/bin:/bin"), "HOME": str(stage), "RLE_WORKSPACE": str(stage)}
    try:
        proc = subprocess.run(
            shlex.split(unit.agent),
            cwd=stage,
            env=env,
            capture_output=True,
            text=True,
            timeout=unit.wall_time_s,
        )
    except subprocess.TimeoutExpired:
        return "timeout", f"the agent ran past {unit.wall_time_s:.0f} s"
    except OSError as exc:
        return "agent_error", f"cannot start the fresh agent '{unit.agent}': {exc}"
    return f"exit {proc.returncode}", excerpt((proc.stdout + proc.stderr)[-EXCERPT_CHARS:])


def _render(
    unit: TransferUnit, env: KitchenEnv, model: mujoco.MjModel, data: mujoco.MjData, label: str
) -> None:
    from PIL import Image, ImageDraw

    from rle_design.scene.mobile_panda import HIDDEN_GROUP
    from rle_design.viz.render import render_image

    ep = env.scene.episode
    x, y, _ = ep.robot
    img = Image.fromarray(
        render_image(
            model,
            data,
            width=480,
            height=360,
            lookat=np.array([x, y + 0.6, 1.0]),
            distance=2.6,
            azimuth=90.0,
            elevation=-25.0,
            groups=(HIDDEN_GROUP,),
            sites=False,
        )
    )
    ImageDraw.Draw(img).text((8, 6), f"agent {unit.trial}: {ep.instruction}", fill=(20, 20, 20))
    ImageDraw.Draw(img).text((8, 20), label, fill=(20, 20, 20))
    Path(unit.out_dir).mkdir(parents=True, exist_ok=True)
    img.save(Path(unit.out_dir) / f"agent_{unit.trial}.png")


def _stages(unit: TransferUnit, ledger: Path) -> tuple[tuple[str, ...], int, int, bool, bool, int]:
    """(conjunct names, b, m, success, recorded, resets) from a replay of the session's ledger; with
    ``unit.out_dir`` the final state is rendered there."""
    env = _env(unit, images=False)
    names = tuple(env.conditions_names())
    counts: list[int] = []
    success = False

    def watch(model: mujoco.MjModel, data: mujoco.MjData, kind: str) -> None:
        nonlocal success
        if kind == "steps" and not counts:
            return  # before the first reset the scene is not the task's start: no stage record
        vals = env.conditions(model, data)
        counts.append(sum(vals.values()))
        if kind == "steps" and all(vals.values()):
            success = True

    model, data, _ = replay(env, ledger, on_step=watch)
    if unit.out_dir is not None and counts:
        _render(
            unit,
            env,
            model,
            data,
            f"b={counts[0]} m={max(counts)} n={len(names)}" + (" success" if success else ""),
        )
    if not counts:
        return names, 0, 0, False, False, 0
    return names, counts[0], max(counts), success, True, len(counts)


def run_unit(unit: TransferUnit) -> TransferResult:
    """Serve, run the fresh agent, seal, replay and score one trial (see the module docstring)."""
    t0 = time.monotonic()
    private = Path(tempfile.mkdtemp(prefix="rle-f02-"))
    sock_dir = Path(tempfile.mkdtemp(prefix="rle-f02s-"))
    stage = Path(tempfile.mkdtemp(prefix="rle-f02w-"))
    try:
        try:
            copy_harness(Path(unit.harness), stage / HARNESS_DIR)
        except HarnessError as exc:
            return TransferResult(
                unit.trial, "harness_unusable", "not_run", str(exc), elapsed_s=time.monotonic() - t0
            )
        env = _env(unit, images=True)
        ledger = private / "ledger.jsonl"
        server = LedgerServer(
            env,
            key=unit.key,
            ledger_path=ledger,
            socket_path=sock_dir / "ledger.sock",
            task_id=unit.ledger_task,
            budget=unit.steps,
            wall_time_s=unit.wall_time_s,
        )
        server.start()
        try:
            os.chmod(sock_dir, 0o711)
            os.chmod(server.socket_path, 0o666)  # the sandboxed agent runs as an unprivileged uid
            (stage / "client.py").write_text(
                _CLIENT.format(address=str(server.socket_path), steps=unit.steps)
            )
            (stage / "instruction.md").write_text(
                FRESH_INSTRUCTION.read_text().format(
                    instruction=env.scene.episode.instruction, steps=unit.steps, minutes=unit.wall_time_s / 60
                )
            )
            if unit.agent == "scripted":
                shutil.copyfile(FRESH_AGENT, stage / "fresh_agent.py")
                agent, message = _run_scripted(stage, server.socket_path, unit)
            else:
                agent, message = _run_command(stage, unit)
        finally:
            server.stop()
        # the verifier's own server wrote it; the gate still recounts the card's limits on it
        gate = check_ledger(ledger, unit.key, unit.ledger_task, Limits(unit.steps, unit.wall_time_s))
        if not gate.ok:
            return TransferResult(
                unit.trial,
                "no_session",
                agent,
                f"{message} (ledger: {gate.message})",
                ledger=gate.code,
                elapsed_s=time.monotonic() - t0,
            )
        try:
            names, b, m, success, recorded, _ = _stages(unit, ledger)
        except ReplayError as exc:
            return TransferResult(
                unit.trial,
                "unverifiable",
                agent,
                exc.message,
                ledger=exc.code,
                elapsed_s=time.monotonic() - t0,
            )
        score = stage_score(b, m, len(names), success, recorded)
        status = "scored" if recorded else "no_stage_records"
        return TransferResult(
            unit.trial,
            status,
            agent,
            message,
            names,
            b,
            m,
            len(names),
            success,
            score,
            gate.steps,
            gate.code,
            time.monotonic() - t0,
        )
    finally:
        for d in (private, sock_dir, stage):
            shutil.rmtree(d, ignore_errors=True)
