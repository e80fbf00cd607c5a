"""Family 04: whole-body motion tracking on a Unitree G1 (``04-dance``, ``04-fight``, ``04-fall-getup``,
``04-run``, ``04-sprint``)."""

from __future__ import annotations

from rle_tasks.core.task import TaskSpec


def tasks() -> list[TaskSpec]:
    from rle_tasks.f04_motion_tracking.task import task_specs

    return task_specs()


def commands() -> tuple:
    """``rle import-motion CSV OUT``: a retargeted 30 fps G1 CSV to a 50 Hz clip; ``rle check-clip
    CLIP``: the clip's inverse dynamics against the G1's effort limits."""
    return (_add_import_motion, _add_check_clip)


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


def _frame_ranges(frames) -> str:
    """``[3, 4, 5, 9]`` -> ``3-5, 9``."""
    out, start, prev = [], None, None
    for f in [int(f) for f in frames] + [None]:
        if start is not None and (f is None or f != prev + 1):
            out.append(f"{start}" if start == prev else f"{start}-{prev}")
            start = None
        if f is not None and start is None:
            start = f
        prev = f
    return ", ".join(out) or "none"


def _check_clip(args) -> int:
    import json

    import numpy as np

    from rle_tasks.f04_motion_tracking.public.clip import Clip
    from rle_tasks.f04_motion_tracking.public.feasibility import PENETRATION_TOL, check_clip
    from rle_tasks.f04_motion_tracking.public.inverse_dynamics import FORCE_TOL, MOMENT_TOL

    clip = Clip.load(args.clip)
    frames = None
    if args.frames:
        a, _, b = args.frames.partition(":")
        frames = range(int(a or 0), int(b) if b else clip.frames)
    report = check_clip(clip, frames=frames, mu=args.mu, margin=args.margin)
    s = report.summary()
    print(
        f"{args.clip}: {len(report.frames)} frames, foot friction {args.mu:g}, margin {args.margin:.0%} of effort"
    )
    print(
        f"{'joint':28s} {'effort':>7s} {'max|tau|':>9s} {'ratio':>6s} {'frame':>6s} {'>margin':>8s} {'>limit':>7s}"
    )
    for row in report.joint_table():
        print(
            f"{row['joint']:28s} {row['effort']:7.1f} {row['max_torque']:9.2f} {row['max_ratio']:6.2f} "
            f"{row['frame']:6d} {row['frames_over_margin']:8d} {row['frames_over_limit']:7d}"
        )
    print(f"frames over the limit: {_frame_ranges(s['frames_over_limit'])}")
    print(f"frames over the margin: {_frame_ranges(s['frames_over_margin'])}")
    print(
        f"stance frames no admissible contact balances (residual > {FORCE_TOL:.1f} N or {MOMENT_TOL:.1f} N m): "
        f"{_frame_ranges(s['infeasible_stance_frames'])}"
    )
    print(
        f"flight frames ({s['flight_frames']}) not ballistic: {_frame_ranges(s['non_ballistic_flight_frames'])}"
    )
    if s["lowest_point"] is not None:
        print(
            f"frames with a point more than {PENETRATION_TOL * 1000:.0f} mm under the floor: "
            f"{_frame_ranges(s['through_floor_frames'])} (lowest {s['lowest_point'] * 1000:.1f} mm, "
            f"{s['lowest_body']})"
        )
    verdict = "PASS" if s["passed"] else "FAIL"
    print(
        f"{verdict}: worst {s['worst_joint']} at frame {s['worst_frame']}, {s['worst_ratio']:.2f} of its limit "
        f"(margin {args.margin:.2f}); largest base residual {s['max_residual_force']:.1f} N, "
        f"{s['max_residual_moment']:.1f} N m"
    )
    if args.json:
        out = dict(s, clip=str(args.clip), mu=args.mu, joints=report.joint_table())
        out["per_frame"] = {
            "frame": report.frames.tolist(),
            "torque": np.round(report.torque, 4).tolist(),
            "ratio": np.round(report.ratio, 4).tolist(),
            "residual": np.round(report.residual, 4).tolist(),
            "contacts": [list(c) for c in report.contacts],
        }
        with open(args.json, "w") as f:
            json.dump(out, f)
    return 0


def _add_check_clip(sub) -> None:
    from rle_tasks.f04_motion_tracking.public.feasibility import MARGIN
    from rle_tasks.f04_motion_tracking.public.g1 import FOOT_FRICTION

    s = sub.add_parser(
        "check-clip",
        help="G1 clip feasibility: inverse dynamics with admissible contact wrenches against the effort limits",
    )
    s.add_argument("clip", help="clip file (.npz, 50 Hz)")
    s.add_argument(
        "--margin", type=float, default=MARGIN, help="pass when no joint exceeds this share of its limit"
    )
    s.add_argument("--mu", type=float, default=FOOT_FRICTION, help="foot friction coefficient")
    s.add_argument("--frames", default=None, help="frame range A:B (default: all)")
    s.add_argument(
        "--json", default=None, help="write the summary, the joint table and per-frame torques here"
    )
    s.set_defaults(fn=_check_clip)
