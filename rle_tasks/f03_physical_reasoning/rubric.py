"""The one shape of a family-03 rubric: a single checkpoint of weight 1 on one variant, scored by the
card's fraction (each task's ``scoring.py`` declares its own with ``ledger_rubric``)."""

from __future__ import annotations

from rle_tasks.core.scoring import Cap, CheckpointSpec, Fraction, Rubric

__all__ = ["ledger_rubric"]


def ledger_rubric(
    task_id: str, variant: str, checkpoint: str, measured: str, fraction: str, caps: tuple[Cap, ...] = ()
) -> Rubric:
    """The rubric of a metered family-03 task: checkpoint ``checkpoint`` (weight 1) measures ``measured``
    on ``variant`` and scores ``fraction``."""
    spec = CheckpointSpec(checkpoint, 1.0, measured, Fraction(fraction))
    return Rubric(
        task_id=task_id,
        family="03",
        workflow="interactive_control",
        variants=(variant,),
        checkpoints=(spec,),
        caps=caps,
    )
