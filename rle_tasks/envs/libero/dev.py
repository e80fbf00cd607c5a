"""Development client of family 05: the agent's only way to run LIBERO (or the bimanual stand-in),
metered per episode.

``DevelopmentClient`` serves the agent's ``solution.py`` (as the replay does) and runs the requested
(task, initial state) episodes of the development suite (``env="standin"``: (task, layout seed)
episodes of the stand-in's clean scenes); every finished episode is charged one unit
of the card's 20,000-episode budget in an HMAC-chained ledger (``rle_design.ledger.ServedLedger``:
one ``request`` record per episode with the sha256 of the solution directory it ran, its task,
initial state, success and length; the seal counts them). The budget is the attempt's: a session
of an attempt that had sessions before starts with what they spent. A request that would pass the
budget is refused before anything runs (``f05.budget_exhausted``).

Trust: the ledger proves the count only when its key is kept from the agent (a server outside the
agent's user, as the metered sessions of other families run). With the public development key it is
a rehearsal.
"""

from __future__ import annotations

import contextlib
from pathlib import Path

from rle_design.errors import RleError
from rle_design.ledger.records import LedgerError
from rle_design.ledger.served import ServedLedger
from rle_tasks.envs.libero import LiberoEnv
from rle_tasks.envs.libero.client import EpisodeResult, run_episode, serving

DEV_EPISODE_BUDGET = 20_000
"""Development episodes the card allows [1]."""
TASK_ID = "05-libero-open"


class DevelopmentClient:
    """Metered LIBERO-10 episodes of a served solution.

    Args:
        ledger_path: A new ledger file.
        key: Ledger key (at least 16 bytes).
        budget: Episodes allowed over the whole session.
        suite: LIBERO suite the episodes come from.
        task_id: The task whose development session this is (the ledger names it).
        env: ``"libero"`` or ``"standin"`` (``rle_tasks.envs.standin``; ``suite`` is then unused).
        attempt: The attempt of the session (earlier sessions of it beside ``ledger_path`` count).
    """

    def __init__(
        self,
        ledger_path: Path,
        key: bytes,
        budget: int = DEV_EPISODE_BUDGET,
        suite: str = "libero_10",
        task_id: str = TASK_ID,
        env: str = "libero",
        attempt: str = "",
    ) -> None:
        self.budget = int(budget)
        self.env = env
        self.suite = suite if env == "libero" else "standin"
        self._ledger = ServedLedger(
            Path(ledger_path),
            key,
            task_id,
            budget=self.budget,
            unit="episodes",
            attempt=attempt,
            meta={"budget_episodes": self.budget, "suite": self.suite},
        )

    @property
    def used(self) -> int:
        """Episodes the attempt has spent, earlier sessions included."""
        return self._ledger.previous + self._ledger.used

    def evaluate(
        self,
        solution_dir: Path,
        episodes: list[tuple[int, int]],
        *,
        max_steps: int | None = None,
        envs: dict[int, LiberoEnv] | None = None,
    ) -> list[EpisodeResult]:
        """Serve ``solution_dir/solution.py`` (which reads its ``ckpt.pt`` there) and run ``episodes``.

        Raises:
            RleError: ``f05.budget_exhausted`` when the request exceeds what is left (nothing runs).
        """
        try:
            self._ledger.check(len(episodes))
        except LedgerError as exc:
            raise RleError(exc.message, code="f05.budget_exhausted") from None
        from rle_tasks.core.report import artifact_sha256

        digest = artifact_sha256(solution_dir)
        out: list[EpisodeResult] = []
        with serving(Path(solution_dir), env=self.env) as policy:
            for task_id in sorted({t for t, _ in episodes}):
                given = (envs or {}).get(task_id)
                with contextlib.nullcontext(given) if given else self._env(task_id) as env:
                    for t, init in episodes:
                        if t != task_id:
                            continue
                        res = self._run(env, policy, init, episode=self.used, max_steps=max_steps)
                        self._ledger.record(
                            "episode",
                            {"task": int(t), "init": int(init), "max_steps": max_steps},
                            1,
                            submission_sha256=digest,
                            success=bool(res.success),
                            env_steps=int(res.steps),
                            fault=res.fault,
                        )
                        out.append(res)
        return out

    def _env(self, task: int):
        if self.env == "standin":
            from rle_tasks.envs.standin import StandinEnv

            return contextlib.nullcontext(StandinEnv(task))
        return LiberoEnv(self.suite, task)

    def _run(self, env, policy, init: int, *, episode: int, max_steps: int | None) -> EpisodeResult:
        if self.env == "standin":
            from rle_tasks.envs.standin.client import run_episode as run_standin

            return run_standin(env, policy, init, episode=episode, max_steps=max_steps)
        return run_episode(env, policy, init, episode=episode, max_steps=max_steps)

    def info(self) -> dict:
        """Episodes of the attempt used and left, and those of this session (free)."""
        return self._ledger.info()

    def close(self) -> None:
        """Seal the ledger."""
        self._ledger.seal()
