"""Try a program in process: ``python -m rle_tasks.f01_robocasa_speedrun.solutions.agents.trial TASK [--level L] [--pretrain N] [--split]``.

Plays the program of harness level ``L`` (default 3) on the public key's five target kitchens (and
``N`` pretrain episodes) without a ledger server and prints each episode's outcome and action count.
Levels below 3 render the camera images their programs read.
"""

from __future__ import annotations

import argparse
import time

from rle_tasks.core.runtime.secrets import PUBLIC_KEY, Secret
from rle_tasks.envs.kitchen.harness.motion import Motion
from rle_tasks.envs.kitchen.harness.robot import Robot

from ...task import KITCHEN_TASKS, scenes
from . import Direct, solver
from .frame import Straightened


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("task", choices=[k.task for k in KITCHEN_TASKS])
    ap.add_argument("--pretrain", type=int, default=0)
    ap.add_argument("--level", type=int, default=3)
    ap.add_argument("--skip-targets", action="store_true")
    ap.add_argument("--split", action="store_true", help="kitchens of every layout kind (kitchens.SPLIT)")
    args = ap.parse_args()
    kitchen = next(k for k in KITCHEN_TASKS if k.task == args.task)
    image_size = None if args.level >= 3 else (128, 128)  # L3 programs read no images
    sc = scenes(
        kitchen, args.level, Secret(PUBLIC_KEY, public=True), image_size=image_size, split=args.split or None
    )
    session = sc.open_session(task_id=kitchen.task_id(args.level), budget=None)
    robot = Robot(Straightened(Direct(session)))
    motion = Motion(robot)
    solve = solver(args.task, args.level)
    wins = 0
    for k in range(args.pretrain):
        t = time.time()
        robot.reset(kitchen=k % 50, seed=k)
        ok = solve(robot, motion)
        wins += ok
        print(
            f"pretrain {k}: {'ok' if ok else 'FAIL'} ({session.info()['steps_used']} steps so far, {time.time() - t:.1f} s)",
            flush=True,
        )
    if args.pretrain:
        print(f"pretrain: {wins}/{args.pretrain}")
    if args.skip_targets:
        return
    wins = 0
    for k in range(5):
        t = time.time()
        robot.start_evaluation() if k == 0 else robot.reset()
        ok = solve(robot, motion)
        wins += ok
        print(
            f"target {k}: {'ok' if ok else 'FAIL'} ({session.trials[-1].actions} actions, {time.time() - t:.1f} s)",
            flush=True,
        )
    print(f"targets: {wins}/5")


if __name__ == "__main__":
    main()
