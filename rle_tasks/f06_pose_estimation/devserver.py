"""Development renders: deterministic frames and push episodes by seed, noisy labels, design-set scores.

``labelled_frames``, ``labelled_episode`` and ``design_evaluation`` are what the development server
(``service.py``) answers: the server process holds the scene; the agent's client only receives arrays. Public seeds draw from
``numpy.random.default_rng(seed)``, never from the secret; the appearance and noise ranges are those
of the hidden set. Labels carry Gaussian noise (``LABEL_NOISE``: 1 mm on x and y, 0.01 rad on theta);
shape ids are withheld.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .episodes import RAISED_TIP, FrameSpec, frame_group, push_episode

LABEL_NOISE = (0.001, 0.01)
"""Standard deviation of the label noise: translation [m], angle [rad]."""


def _noisy(label: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    x, y, t = label[:3] + rng.normal(0, [LABEL_NOISE[0], LABEL_NOISE[0], LABEL_NOISE[1]])
    return np.array([x, y, (t + np.pi) % (2 * np.pi) - np.pi])


def _render(frames: list[FrameSpec], rng: np.random.Generator, depth: bool):
    from .appearance import APPEARANCE, SensorNoise
    from .verifier import renderer

    r = renderer(depth)
    r.apply(APPEARANCE.sample(rng))
    obs, labels = r.render(frames, SensorNoise.sample(rng), rng)
    return [(o, _noisy(lab.pose, rng)) for o, lab in zip(obs, labels)]


def labelled_frames(
    seed: int, n: int, *, raised: bool = False, depth: bool = True
) -> list[tuple[dict, np.ndarray]]:
    """``n`` independent frames of public seed ``seed``: (observation, noisy (x, y, theta)) pairs.

    Args:
        seed: Public seed.
        n: Number of frames.
        raised: Keep the stick out of the way.
        depth: Include depth and validity.
    """
    rng = np.random.default_rng(seed)
    frames = frame_group(rng, n)
    if raised:
        frames = [FrameSpec(f.pose, RAISED_TIP, f.t) for f in frames]
    return _render(frames, rng, depth)


def labelled_episode(seed: int, n: int = 60, *, depth: bool = True) -> list[tuple[dict, np.ndarray]]:
    """A push episode of public seed ``seed``: (observation, noisy (x, y, theta)) per frame."""
    rng = np.random.default_rng(seed)
    return _render(push_episode(rng, n), rng, depth)


DESIGN_GROUPS = (9001, 9002)
"""Public seeds of the design set's frame groups."""
DESIGN_TRAJECTORIES = (9101, 9102)
"""Public seeds of the design set's push trajectories (30 frames each)."""
DESIGN_TRAJ_FRAMES = 30


def design_evaluation(task_id: str, root: Path) -> dict:
    """Score and native metrics of the submission in ``root`` on the public design set.

    The same protocol as the verifier (sandboxed child per unit, ``reset`` before every independent
    frame, CPU-time frame rate), on two frame groups and two 30-frame trajectories of public seeds.
    """
    from .contract import variant
    from .scoring import group_score, reward, speed_deduction
    from .verifier import gate, open_runner, render_unit, reported_fps, run_frames

    v = variant(task_id)
    failed = gate(v, Path(root), 30.0)
    if failed is not None:
        return {"score": 0.0, "gate": {"code": failed[0], "message": failed[1]}}
    g = {"frames": [], "trajectory": []}
    metrics, spent, predictions, faults = [], 0.0, 0, []
    for kind, seeds in (("frames", DESIGN_GROUPS), ("trajectory", DESIGN_TRAJECTORIES)):
        for seed in seeds:
            obs, labels = render_unit(v, np.random.default_rng(seed), kind, DESIGN_TRAJ_FRAMES)
            with open_runner(v, Path(root), 30.0) as runner:
                pred, cpu, _ = run_frames(runner, obs, independent=kind == "frames")
                faults += [f"{r.code}: {r.message}" for r in runner.faults]
            score, m = group_score(pred, np.array([lab.pose for lab in labels]))
            g[kind].append(score)
            metrics.append({"kind": kind, "seed": seed, **m})
            spent += cpu
            predictions += int(np.isfinite(pred).all(1).sum())
    fps = predictions / spent if spent > 0 else 0.0
    return {
        "score": reward(g["frames"], g["trajectory"], reported_fps(fps)),
        "fps": reported_fps(fps),
        "fps_measured": fps,
        "fps_note": "fps as `rle verify` reports and scores it (rounded, capped at 10); fps_measured unrounded",
        "speed_deduction": speed_deduction(reported_fps(fps)),
        "groups": metrics,
        "faults": faults[:20],
    }
