"""Development renders: deterministic frames and push episodes by seed, with noisy pose labels.

``labelled_frames`` and ``labelled_episode`` are what the development server answers (the server
process holds the scene; the agent's client only receives arrays). Public seeds draw from
``numpy.random.default_rng(seed)``, never from the secret; the appearance and noise ranges are those
of the hidden set. Labels carry Gaussian noise (``LABEL_NOISE``: 1 mm on x and y, 0.01 rad on theta);
shape ids are withheld.
"""

from __future__ import annotations

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
