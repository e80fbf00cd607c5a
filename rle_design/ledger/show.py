"""A ledger in words: what a session recorded, request by request (``rle ledger show``)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from rle_design.ledger.verify import LedgerVerdict

__all__ = ["describe_ledger"]

_RESULT_KEYS = (
    "submission_sha256",
    "score",
    "fps",
    "fps_measured",
    "gate",
    "success",
    "env_steps",
    "fault",
    "frames",
)


def _fmt(value: Any) -> str:
    if isinstance(value, float):
        return f"{value:.4g}"
    if isinstance(value, str) and len(value) == 64:
        return value[:12] + "..."
    return str(value)


def _details(payload: dict[str, Any]) -> str:
    args = payload.get("args") if isinstance(payload.get("args"), dict) else {}
    parts = [f"{k}={_fmt(v)}" for k, v in args.items()]
    parts += [
        f"{k}={_fmt(payload[k])}" for k in _RESULT_KEYS if k in payload and payload[k] not in (None, "")
    ]
    return " ".join(parts)


def describe_ledger(path: Path, verdict: LedgerVerdict | None = None) -> str:
    """Header, one line per request (consecutive action records folded into one line), the seal.

    ``verdict`` (from ``verify_ledger`` with the key, when the caller has it) is stated under the
    header; without it the text says the records were not authenticated. Never raises on bad input.
    """
    path = Path(path)
    try:
        recs = [json.loads(line) for line in path.read_bytes().splitlines() if line.strip()]
    except (OSError, ValueError) as exc:
        return f"{path}: not a readable ledger ({exc})"
    recs = [r for r in recs if isinstance(r, dict) and isinstance(r.get("payload"), dict)]
    if not recs or recs[0].get("kind") != "open":
        return f"{path}: no open record"
    opened = recs[0]["payload"]
    budget = opened.get("budget")
    unit = opened.get("unit", "steps")
    prev = opened.get("previous") or {}
    lines = [
        f"ledger {path}: task {recs[0].get('task_id')}, attempt {opened.get('attempt', '')!r}, "
        f"format {opened.get('format', 1)}, budget {budget} {unit}"
        + (f" (earlier sessions of the attempt used {prev.get('used')})" if prev.get("sessions") else "")
    ]
    if verdict is None:
        lines.append("not authenticated (no key given): the records are shown as written")
    else:
        lines.append(f"{verdict.code}: {verdict.message}")
    lines.append(f"{'seq':>5} {'wall s':>9}  {'kind':<8} {'op':<10} {'cost':>5} {'used':>6}  details")
    fold: list[dict] = []

    def flush() -> None:
        if fold:
            n = sum(len(r["payload"].get("actions") or []) for r in fold)
            last = fold[-1]["payload"]
            lines.append(
                f"{fold[0].get('seq', ''):>5} {_fmt(last.get('wall', '')):>9}  {'steps':<8} {'':<10} {n:>5} "
                f"{_fmt(last.get('steps', '')):>6}  {len(fold)} record(s), sim time {_fmt(last.get('time', ''))} s"
            )
            fold.clear()

    for rec in recs[1:]:
        kind, p = rec.get("kind"), rec["payload"]
        if kind == "steps":
            fold.append(rec)
            continue
        flush()
        if kind == "seal":
            extra = " ".join(
                f"{k}={_fmt(v)}"
                for k, v in p.items()
                if k in ("elapsed_s", "previous_used", "development_steps")
            )
            lines.append(f"seal: {p.get('steps')} charged in {p.get('records')} records {extra}".rstrip())
            continue
        if kind == "reset":
            what = " ".join(f"{k}={_fmt(p[k])}" for k in ("phase", "trial", "scene") if k in p)
            lines.append(
                f"{rec.get('seq', ''):>5} {_fmt(p.get('wall', '')):>9}  {'reset':<8} {'':<10} {1:>5} {_fmt(p.get('steps', '')):>6}  {what}"
            )
            continue
        lines.append(
            f"{rec.get('seq', ''):>5} {_fmt(p.get('wall', '')):>9}  {str(kind):<8} {str(p.get('op', '')):<10} "
            f"{_fmt(p.get('cost', '')):>5} {_fmt(p.get('steps', '')):>6}  {_details(p)}"
        )
    flush()
    if recs[-1].get("kind") != "seal":
        lines.append("no seal: the session was not closed (or the file is cut)")
    return "\n".join(lines)
