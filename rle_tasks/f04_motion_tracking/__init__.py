"""Family 04: whole-body motion tracking on a Unitree G1 (``04-dance``, ``04-fight``, ``04-fall-getup``,
``04-run``, ``04-sprint``)."""

from __future__ import annotations

from rle_tasks.core.task import TaskSpec


def tasks() -> list[TaskSpec]:
    from rle_tasks.f04_motion_tracking.task import task_specs

    return task_specs()


def commands() -> tuple:
    """``rle import-motion CSV OUT``: a retargeted 30 fps G1 CSV to a 50 Hz clip."""
    return (_add_import_motion,)


def _import_motion(args) -> int:
    from rle_tasks.f04_motion_tracking.public.motion_import import import_motion

    clip = import_motion(args.csv, args.out)
    print(f"{args.out}: {clip.frames} frames at {clip.fps:g} Hz ({clip.duration:.2f} s)")
    return 0


def _add_import_motion(sub) -> None:
    s = sub.add_parser("import-motion", help="retargeted G1 CSV (30 fps) -> 50 Hz motion clip (.npz)")
    s.add_argument("csv", help="no header; x y z qx qy qz qw + 29 joint angles per line")
    s.add_argument("out", help="clip file to write (.npz)")
    s.set_defaults(fn=_import_motion)
