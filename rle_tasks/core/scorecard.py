"""Human-readable scorecard of a verifier report."""

from __future__ import annotations

from rle_tasks.core.report import VerifierReport


def format_scorecard(report: VerifierReport) -> str:
    lines = [f"{report.task_id}  score {report.score:.3f}  valid {report.valid}  secret {report.secret}"]
    if report.cap is not None:
        lines.append(f"  cap applied: {report.cap}")
    if report.checkpoints:
        lines.append(f"  {'checkpoint':<35} {'weight':>6} {'score':>6} {'credit':>7}  message")
        for c in report.checkpoints:
            # a checkpoint that earns part of its weight is neither passed nor failed
            mark = "ok  " if c.passed else ("part" if c.score > 0 else "FAIL")
            msg = c.message.splitlines()[0][:90] if c.message else ""
            lines.append(f"  {mark} {c.id:<30} {c.weight:>6.3f} {c.score:>6.3f} {c.credit:>7.4f}  {msg}")
    for e in report.errors:
        first = e.message.splitlines()[0] if e.message else ""
        lines.append(f"  error [{e.code}] {first[:160]}" + (f" ({e.path})" if e.path else ""))
    lines.append(f"  elapsed {report.elapsed_s:.1f} s, artifact {report.artifact_sha256[:12] or '-'}")
    return "\n".join(lines)


def print_scorecard(report: VerifierReport) -> None:
    print(format_scorecard(report))
