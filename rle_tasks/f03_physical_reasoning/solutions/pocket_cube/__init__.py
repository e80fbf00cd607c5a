"""Agent programs of ``03-pocket-cube`` and a runner that records their sealed ledgers.

A submission is a session's sealed ledger (fresh nonce, opening time), so the programs are shipped and
``record`` plays one on a metered session of the secret's scramble. Every program acts only through
ordinary 14-D metered actions (``CartesianHelper`` with ``arm_size=7``) and reads no cube pose.

| program | expected score | why |
|---|---|---|
| ``reference`` | 1.0 | plans top-layer turns and whole-cube hand-offs for the public scramble and executes them with both hands, the cube in the air (``two_hands``): 4 quarter turns, optimum 4 |
| ``idle`` | 0.0 | the arms hold and the session is sealed: the cube stays scrambled on its stand |
| ``dropped`` | 0.0 | the right hand sweeps the cube off its stand; it ends on the table, not held |
| ``reset`` | 0.0 | a reset after the start abandons the attempt |
| ``forced_twist`` | 0.0 | a pitch the arm cannot follow forces the cube: one unclassified transition (cap 0.5), unsolved, on the table |
| ``top_turns`` | (building block) | quarter turns of the top layer by the right wrist against the stand, then the cube lifted |

Committed ledgers (``ledgers/<name>/ledger.jsonl``, recorded by ``__main__``): the ``SHIPPED`` programs on the
public scramble, and ``ledgers/reference_second`` = the reference on the second public scramble
(``U R U R'``; it verifies only against that scramble's scene, so the tests inject it).

"""

from __future__ import annotations

import importlib
from pathlib import Path

from rle_tasks.f03_physical_reasoning.solutions import committed, solution_set, unsealed

PROGRAMS = ("reference", "idle", "dropped", "reset", "forced_twist", "top_turns")
SHIPPED = ("reference", "idle", "dropped", "reset", "forced_twist")
"""Programs whose public-key ledgers are committed."""
SECOND = "reference_second"
"""Ledger directory of the reference on the second public scramble."""


def record(program: str, secret, dest: Path, camera_every: int = 100_000, inst=None, **kwargs) -> Path:
    """Play ``program`` on the scramble of ``secret``; write and return ``dest`` holding ``ledger.jsonl``.

    ``camera_every`` renders the front view only that often (no program reads it; the scene and its
    fingerprint do not change). ``inst`` replaces the secret's scramble (tests of the verifier's
    positive path on a shallow scramble; such a ledger verifies only against that scramble).
    """
    from rle_tasks.core.runtime.devenv import record_solution

    from ...constants import CUBE_ID, STEP_BUDGET, WALL_TIME_S
    from ...cube.env import make_env
    from ...cube.scene import instance
    from ...cube.verifier import LEDGER_FILE

    if program not in PROGRAMS:
        raise ValueError(f"unknown program {program!r}. Programs: {', '.join(PROGRAMS)}")
    solve = importlib.import_module(f"{__name__}.{program}").solve
    dest = Path(dest)
    env = make_env(instance(secret) if inst is None else inst, camera_every=camera_every)
    record_solution(
        env, lambda c: solve(c, **kwargs), dest / LEDGER_FILE, secret, CUBE_ID, STEP_BUDGET, WALL_TIME_S
    )
    return dest


def _ledgers(name: str) -> str:
    return f"solutions/pocket_cube/ledgers/{name}"


SOLUTIONS = solution_set(
    committed(
        "reference",
        "f3893a89d934f4621f84bf3a93291b49794fc8fef2c86fa06c88a5c3f09f0c47",
        1.0,
        _ledgers("reference"),
    ),
    committed(
        "baseline/idle",
        "aa1d032206d67b62a120e9a69b9bd526b7d634ab8acf1331e5ecff3d27a74bfc",
        0.0,
        _ledgers("idle"),
    ),
    committed(
        "baseline/dropped",
        "dbb418e71a1576081a3c4422c0c4e8b9666fb557c101d4d69dc49f6cdfeb28f1",
        0.0,
        _ledgers("dropped"),
    ),
    committed(
        "baseline/reset",
        "4c5e38c39f8e4288044cb2a0a61be40c368f1c49e7845095468f6e6e7cae9a90",
        0.0,
        _ledgers("reset"),
    ),
    committed(
        "baseline/forced_twist",
        "af50a798564aba8d3a84d914ea6f36c587b4375ed5c41f7b3778258fca4975b6",
        0.0,
        _ledgers("forced_twist"),
    ),
    unsealed("d5d5e16ca5329742a0922569f4fec5bbb614e83e8182fa442889fcc1006929a7"),
)
"""Committed public-key ledgers: the reference (1.0), four baselines (0 each for its reason), the reference
unsealed (0)."""

_ORACLE = '''"""Oracle of 03-pocket-cube: the reference's two-handed moves, executing the plan that the privileged
development sidecar serves (the reference's plan for this scramble; agents never get it)."""

import sys

sys.path[:0] = ["/workspace", "/solution"]

from client import connect  # noqa: E402
from two_hands import TwoHands, finish, take_up, turn, {moves}  # noqa: E402

MOVES = {{{table}}}
TURN_SENSE = {sense!r}

with connect() as env:
    obs = env.reset()
    if "plan" not in obs:
        sys.exit("the sidecar serves no privileged observations: run the oracle with RLE_ORACLE_PRIVILEGED=1")
    hands = TwoHands(env.step, obs)
    take_up(hands)
    for move in obs["plan"]:
        if move in MOVES:
            MOVES[move](hands)
        else:
            turn(hands, TURN_SENSE[move])
    finish(hands)
    print(f"played {{len(obs['plan'])}} moves: {{env.info()['steps_used']}} steps", flush=True)
    env.seal()
'''


def harbor_oracle(spec, dest: Path) -> str:
    """Write the privileged playing oracle (``oracle.py``, and ``two_hands.py`` and ``top_turns.py`` with
    the one constant they take from the environment inlined) into ``dest``; returns ``solve.sh``."""
    from rle_tasks.core.export.harbor.export import PLAYING_SOLVE_SH

    from ...cube.env import ARM_ACTION
    from .reference import MOVES, TURN_SENSE

    here = Path(__file__).resolve().parent
    dest = Path(dest)
    dest.mkdir(parents=True, exist_ok=True)
    for module in ("two_hands.py", "top_turns.py"):
        text = (here / module).read_text()
        text = text.replace("from ...cube.env import ARM_ACTION", f"ARM_ACTION = {ARM_ACTION}")
        text = text.replace("from .top_turns import", "from top_turns import")
        if "rle_tasks" in text or "from ." in text:
            raise ValueError(f"{module} imports rle_tasks, which the agent's image does not hold")
        (dest / module).write_text(text)
    names = {move: fn.__name__ for move, fn in MOVES.items()}
    (dest / "oracle.py").write_text(
        _ORACLE.format(
            moves=", ".join(sorted(set(names.values()))),
            table=", ".join(f"{m!r}: {fn}" for m, fn in names.items()),
            sense=TURN_SENSE,
        )
    )
    return PLAYING_SOLVE_SH
