"""Family 06 measurements: 240x320 RGB-D render rate, and one variant's verification time beside its floor.

The floor is rendering the same frames (with the occlusion pass) plus the estimator's own compute
(the sum of its ``update`` wall times); the rest is sandbox start-up and transfer.

    PYTHONPATH=. MUJOCO_GL=egl python benchmarks/f06_verify.py [--quick] [--task 06-pose-b-rgbd]
"""

from __future__ import annotations

import argparse
import time

import numpy as np


def render_fps(n: int = 300) -> float:
    """240x320 RGB-D frames per second of the task scene (no segmentation pass)."""
    from rle_design.sensors import RgbdSensor
    from rle_tasks.f06_pose_estimation.scene import (
        CAMERA,
        HEIGHT_PX,
        WIDTH,
        BlockPose,
        PoseScene,
        compile_scene,
    )

    model = compile_scene()
    scene = PoseScene(model)
    scene.set_block(BlockPose(0.02, 0.01, 0.4, 1))
    scene.reach(np.array([0.1, 0.0, 0.012]))
    scene.forward()
    with RgbdSensor(model, CAMERA, WIDTH, HEIGHT_PX, segmentation=False) as sensor:
        sensor.render(scene.data)
        t0 = time.perf_counter()
        for _ in range(n):
            sensor.render(scene.data)
        return n / (time.perf_counter() - t0)


def verification(task_id: str, quick: bool) -> dict:
    from rle_tasks.core.registry import get_task
    from rle_tasks.core.runtime.secrets import load_secret
    from rle_tasks.core.solutions import materialise
    from rle_tasks.core.task import VerifyContext
    from rle_tasks.f06_pose_estimation import verifier as V

    task = get_task(task_id)
    root = materialise(task, "reference")
    import json
    import tempfile
    from pathlib import Path

    out = Path(tempfile.mkdtemp(prefix="f06_bench_"))
    t0 = time.perf_counter()
    rep = task.verify(root, VerifyContext(secret=load_secret(None), quick=quick, out_dir=out))
    total = time.perf_counter() - t0
    timing = json.loads((out / "f06_timing.json").read_text())
    v = V.variant(task_id)
    n_groups, n_traj = (V.QUICK_GROUPS, V.QUICK_TRAJ) if quick else (V.N_GROUPS, V.N_TRAJ)
    n_frames = V.QUICK_TRAJ_FRAMES if quick else V.TRAJ_FRAMES
    t0 = time.perf_counter()
    for kind, count in (("frames", n_groups), ("trajectory", n_traj)):
        for i in range(count):
            V.render_unit(v, np.random.default_rng(i), kind, n_frames)
    render_s = time.perf_counter() - t0
    compute_s = timing["cpu_s"]
    return {
        "score": rep.score,
        "total_s": total,
        "render_s": render_s,
        "estimator_s": compute_s,
        "floor_s": render_s + compute_s,
        "fps": timing["fps"],
    }


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--task", default="06-pose-b-rgbd")
    args = ap.parse_args()
    fps = render_fps()
    print(f"240x320 RGB-D render: {fps:.0f} frames/s (target >= 100)")
    r = verification(args.task, args.quick)
    print(
        f"{args.task} verification ({'quick' if args.quick else 'full'}): {r['total_s']:.1f} s; floor "
        f"{r['floor_s']:.1f} s (render {r['render_s']:.1f} s + estimator {r['estimator_s']:.1f} s); "
        f"score {r['score']:.3f}, estimator {r['fps']:.1f} frames/s"
    )


if __name__ == "__main__":
    main()
