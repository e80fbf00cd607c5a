"""Development progress of a trial, from the ledgers of its served development sessions.

A served session that runs the agent's candidate on episodes (family 05's evaluation service) records
one ``request`` record per episode: the ``submission_sha256`` of the directory it ran, ``success``, and
``wall`` (seconds since the session opened; the open record's ``created`` is its epoch). Harbor
collects a trial's session ledgers from the development sidecar (``artifacts/rle-ledger/*.jsonl``).
From them the results page (``results_page.development_figure``) draws the paper's development-progress figure: the best development success
so far over the session (a candidate's success is its successes over its episodes so far), and the
episodes each system requested against its official score.

The ledgers are read as the operator's records, not verified (``rle index`` holds no key); a line that
is not a ledger record is skipped, so a damaged file shortens a curve but never stops the page.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

LEDGER_DIR = "artifacts/rle-ledger"
"""Where a Harbor trial keeps the ledgers its development sidecar left."""


@dataclass(frozen=True)
class Episode:
    """One development episode.

    Attributes:
        t_s: Seconds since the first session of the trial opened [s].
        submission: sha256 of the candidate the episode ran.
        success: The episode succeeded.
    """

    t_s: float
    submission: str
    success: bool


def _records(path: Path) -> list[dict]:
    out = []
    try:
        lines = path.read_text(errors="replace").splitlines()
    except OSError:
        return out
    for line in lines:
        try:
            rec = json.loads(line)
        except ValueError:
            continue
        if isinstance(rec, dict) and isinstance(rec.get("payload"), dict):
            out.append(rec)
    return out


def development_episodes(trial_dir: Path) -> tuple[Episode, ...]:
    """The development episodes of a trial's sessions in time order (none when it kept no ledger or its
    sessions ran no episodes). A session kept twice (``ledger.jsonl`` beside its session file) counts once."""
    sessions: dict[str, tuple[float, list[tuple[float, str, bool]]]] = {}
    for path in sorted((Path(trial_dir) / LEDGER_DIR).glob("*.jsonl")):
        records = _records(path)
        opened = next((r["payload"] for r in records if r.get("kind") == "open"), None)
        if opened is None or not isinstance(opened.get("created"), int | float):
            continue
        key = str(opened.get("nonce") or path.name)
        episodes = []
        for r in records:
            p = r["payload"]
            if r.get("kind") != "request" or "success" not in p or not isinstance(p.get("wall"), int | float):
                continue
            episodes.append((float(p["wall"]), str(p.get("submission_sha256", "")), bool(p["success"])))
        sessions.setdefault(key, (float(opened["created"]), episodes))
    if not sessions:
        return ()
    t0 = min(created for created, _ in sessions.values())
    out = [
        Episode(created - t0 + wall, sha, ok)
        for created, episodes in sessions.values()
        for wall, sha, ok in episodes
    ]
    return tuple(sorted(out, key=lambda e: e.t_s))


def best_so_far(episodes: tuple[Episode, ...] | list[Episode]) -> list[tuple[float, float]]:
    """``(t_s, best success)`` after each episode: the highest success rate any candidate has shown so
    far, a candidate's rate being its successes over its episodes up to then."""
    runs: dict[str, list[int]] = {}
    best = 0.0
    out = []
    for e in sorted(episodes, key=lambda e: e.t_s):
        n = runs.setdefault(e.submission, [0, 0])
        n[0] += int(e.success)
        n[1] += 1
        best = max(best, n[0] / n[1])
        out.append((e.t_s, best))
    return out


@dataclass(frozen=True)
class Progress:
    """One trial's development progress, for the results page.

    Attributes:
        trial: The trial's name.
        curve: ``(t_s, best development success so far)`` after each episode.
        official: The trial's official score (its reward), or None when it has none.
    """

    trial: str
    curve: tuple[tuple[float, float], ...]
    official: float | None

    @property
    def episodes(self) -> int:
        """Development episodes the trial requested."""
        return len(self.curve)


def progress(trial: str, episodes: tuple[Episode, ...], official: float | None) -> Progress | None:
    """A trial's ``Progress`` (None when its sessions ran no episodes)."""
    if not episodes:
        return None
    return Progress(trial, tuple(best_so_far(episodes)), official)
