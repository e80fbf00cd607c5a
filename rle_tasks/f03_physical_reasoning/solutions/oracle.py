"""Harbor oracles of family 03: the reference programs, playing through the sidecar.

The programs of 03-cantilever and 03-tower (``agents.harmonic_cantilever``, ``agents.tower`` with the
plan ``tower_optimum`` computes from the pieces' sizes) read each piece's pose and size, which the
card withholds from agents. An exported task's sidecar serves them only when the operator runs the
oracle with ``RLE_ORACLE_PRIVILEGED=1`` on the host (``harbor.sidecar``); the session's ledger then
says so (``privileged``), the verifier names it (``ledger.privileged``), ``rle index`` refuses the
report, and the Harbor reward is 0 unless the verifier, too, was told it verifies the oracle (the same
variable). An agent's trial never gets a privileged session: the variable is the host's, read by the
sidecar and the verifier, never by the agent's container.

``harbor_oracle`` writes ``agents.py`` (it imports only the public toolkit) and ``oracle.py`` into the
task's ``solution/``: connect with the workspace's ``client.py``, play the program, seal.
"""

from __future__ import annotations

from pathlib import Path

from rle_tasks.core.export.harbor.export import PLAYING_SOLVE_SH

HERE = Path(__file__).resolve().parent
SCALE = 0.93
"""The reference's fraction of the harmonic stack's critical offsets (``make_ledgers``)."""

_PROLOGUE = '''"""Oracle of {task}: the reference program plays through the privileged development sidecar."""

import sys

sys.path[:0] = ["/workspace", "/solution"]

from client import connect  # noqa: E402

{imports}

with connect() as env:
    obs = env.reset()
    if "sizes" not in obs:
        sys.exit("the sidecar serves no privileged observations: run the oracle with RLE_ORACLE_PRIVILEGED=1")
'''
_EPILOGUE = """    print(f"played: {env.info()['steps_used']} steps", flush=True)
    env.seal()
"""
_CANTILEVER = """    harmonic_cantilever(env.step, obs, edge_x={edge_x!r}, top_z={top_z!r}, scale={scale!r})
"""
_TOWER = """    blocks = []
    for name, (hx, hy, hz) in sorted(obs["sizes"].items()):  # each piece resting on its spawn face
        wedge = name == "wedge"
        mass = {density!r} * (4.0 if wedge else 8.0) * hx * hy * hz
        blocks.append(Block(name, min(hx, hy), 2.0 * hz, mass, supports=not wedge))
    plan = [(name, 0.0) for name in optimal_tower(blocks).order if name != "wedge"]
    tower(env.step, obs, plan, {spot!r}, {top_z!r})
"""


def harbor_oracle(spec, dest: Path) -> str | None:
    """Write the privileged playing oracle of ``spec`` into ``dest``; returns ``solve.sh`` (03-cantilever,
    03-tower), else None.

    Raises:
        ValueError: the copied program imports the verifier's package.
    """
    from ..constants import CANTILEVER_ID, TOWER_ID
    from ..scene import CONFIG
    from ..tower import verifier as tower

    if spec.id == CANTILEVER_ID:
        imports = "from agents import harmonic_cantilever  # noqa: E402"
        body = _CANTILEVER.format(edge_x=float(CONFIG.edge_x), top_z=float(CONFIG.top_z), scale=SCALE)
        modules = ("agents.py",)
    elif spec.id == TOWER_ID:
        imports = "from agents import tower  # noqa: E402\nfrom tower_optimum import Block, optimal_tower  # noqa: E402"
        body = _TOWER.format(density=tower.DENSITY, spot=tuple(tower.BUILD_SPOT), top_z=float(CONFIG.top_z))
        modules = ("agents.py", "../tower/optimum.py")
    else:
        return None
    oracle = _PROLOGUE.format(task=spec.id, imports=imports) + body + _EPILOGUE
    Path(dest).mkdir(parents=True, exist_ok=True)
    for module in modules:
        text = (HERE / module).read_text()
        if "rle_tasks" in text:
            raise ValueError(f"{module} imports rle_tasks, which the agent's image does not hold")
        name = "tower_optimum.py" if module.endswith("tower/optimum.py") else Path(module).name
        (Path(dest) / name).write_text(text)
    (Path(dest) / "oracle.py").write_text(oracle)
    return PLAYING_SOLVE_SH


def harbor_program_oracle(program: Path, dest: Path) -> str:
    """Write ``program`` (a reference agent that connects with ``client.connect()``, plays and seals
    when run as a script, reading only what agents get) into ``dest`` as ``oracle.py``; returns
    ``solve.sh``.

    Raises:
        ValueError: the program imports the verifier's package.
    """
    text = Path(program).read_text()
    if "rle_tasks" in text or "from ." in text:
        raise ValueError(f"{Path(program).name} imports rle_tasks, which the agent's image does not hold")
    Path(dest).mkdir(parents=True, exist_ok=True)
    (Path(dest) / "oracle.py").write_text(text)
    return PLAYING_SOLVE_SH


def reference_program_oracle(solutions_file: str):
    """The ``harbor_oracle`` hook of a task whose Harbor oracle is the ``reference.py`` beside
    ``solutions_file`` (a program that reads only what agents get), playing through the sidecar."""
    program = Path(solutions_file).resolve().parent / "reference.py"

    def harbor_oracle(spec, dest: Path) -> str:
        return harbor_program_oracle(program, dest)

    return harbor_oracle
