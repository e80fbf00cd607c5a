"""Development workspace of the ``06-pose-*`` tasks (partial: see README, "Not done").

Lays out the instruction. The served renderer (a process the agent cannot read, answering
``devserver.labelled_frames`` / ``labelled_episode`` by seed and six metered design-set evaluations)
is not wired to a client yet; the render functions it would serve exist in ``devserver.py``.
"""

from __future__ import annotations

from pathlib import Path


def make_dev_env(task_id: str, workspace: Path) -> None:
    """Write the instruction of ``task_id`` into ``workspace``."""
    from .contract import variant
    from .task import instruction

    ws = Path(workspace)
    ws.mkdir(parents=True, exist_ok=True)
    (ws / "instruction.md").write_text(instruction(variant(task_id)))
