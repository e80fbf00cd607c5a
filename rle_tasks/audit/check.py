"""``rle audit-verifiers``: the adversarial artifact corpus.

The corpus is ``rle_tasks/audit/corpus.py`` (installed with the package; no checkout needed): each case
builds one bad artifact (broken or hostile XML, meshes, physics cheats, hostile submitted code, tampered ledgers) and
states the error code it must produce and the score it may get at most. Each case is verified with a
private secret; the report is written to disk and then searched, with the artifact directory, for the
secret and the hidden seeds.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

from rle_design.excerpt import CLOSE, OPEN, WITHHELD
from rle_tasks.audit.case import AUDIT_SECRET, EXFIL_MARK, Case
from rle_tasks.core.runtime.secrets import Secret, derive_seed
from rle_tasks.core.task import VerifyContext

HIDDEN_INDICES = 64  # seeds 0..63 of each task are searched for in reports and artifacts
_MARKED = re.compile(f"{OPEN}[^{CLOSE}]*{CLOSE}")


@dataclass(frozen=True)
class CaseResult:
    name: str
    expect: str | None
    observed: tuple[str, ...]
    score: float
    seconds: float
    ok: bool
    why: str
    report: Path


def load_corpus() -> list[Case]:
    """Cases of ``rle_tasks/audit/corpus.py``."""
    from rle_tasks.audit.corpus import cases

    return list(cases())


def hidden_needles(secret: Secret, task_ids: list[str]) -> list[bytes]:
    """Byte strings that must never appear in a report or a workspace: the key and hidden seeds."""
    needles = [secret.key]
    for tid in task_ids:
        for i in range(HIDDEN_INDICES):
            s = derive_seed(secret, tid, i)
            needles += [str(s).encode(), f"{s:x}".encode()]
    return needles


def find_leaks(paths: list[Path], needles: list[bytes]) -> list[str]:
    """Files under ``paths`` containing any needle."""
    leaks = []
    for root in paths:
        files = (
            [root] if root.is_file() else [p for p in root.rglob("*") if p.is_file() and not p.is_symlink()]
        )
        for f in files:
            try:
                if f.stat().st_size > 64 << 20:
                    continue  # large generated hostile payloads (sparse meshes) are not outputs
                data = f.read_bytes()
            except OSError:
                continue
            if any(n in data for n in needles):
                leaks.append(str(f))
    return leaks


def run_case(case: Case, workdir: Path, secret: Secret = AUDIT_SECRET, hang_cap_s: float = 2.0) -> CaseResult:
    """Build and verify one case; the report goes to ``workdir/<case>/report.json``."""
    from rle_tasks.core.registry import get_task
    from rle_tasks.core.verify import run_verify

    slug = case.name.replace("/", "__")
    base = workdir / slug
    if base.exists():
        shutil.rmtree(base)
    (base / "artifact").mkdir(parents=True)
    artifact = case.build(base / "artifact")
    t0 = time.perf_counter()
    internal = False
    if case.run is not None:
        report = case.run(artifact, secret)
    else:
        ctx = VerifyContext(
            secret=secret,
            out_dir=base / "figures",
            quick=True,
            hang_cap_s=hang_cap_s,
            jobs=min(2, os.cpu_count() or 1),
            attempt=case.attempt,
        )
        report, internal = run_verify(get_task(case.task_id), artifact, ctx)
    seconds = time.perf_counter() - t0
    report_path = report.write(base / "report.json")
    observed = tuple(dict.fromkeys(e.code for e in report.errors))
    why = []
    if internal:
        why.append("internal verifier fault")
    text = json.dumps(report.to_dict(), ensure_ascii=False)
    shown = [m for m in _MARKED.findall(text) if m != WITHHELD] if not secret.public else []
    if EXFIL_MARK in text or shown:
        why.append("participant text in the report")
    if case.expect is not None and case.expect not in observed:
        why.append(f"expected {case.expect}")
    if report.score > case.max_score + 1e-9:
        why.append(f"score {report.score:.3f} > {case.max_score}")
    if seconds > case.wall_cap_s:
        why.append(f"took {seconds:.1f} s > {case.wall_cap_s} s")
    return CaseResult(
        case.name, case.expect, observed, report.score, seconds, not why, "; ".join(why), report_path
    )


def format_table(results: list[CaseResult]) -> str:
    lines = [f"{'artifact':<44} {'expected code':<28} {'observed code':<28} {'score':>6} {'s':>6}  ok"]
    for r in results:
        shown = r.expect if r.expect in r.observed else (r.observed[0] if r.observed else "-")
        expect = r.expect or "(score bound only)"
        lines.append(
            f"{r.name:<44} {expect:<28} {shown:<28} {r.score:>6.3f} {r.seconds:>6.2f}  "
            + ("yes" if r.ok else f"NO ({r.why})")
        )
    n_ok = sum(r.ok for r in results)
    lines.append(f"{len(results)} cases, {n_ok} matching, {sum(r.seconds for r in results):.1f} s verifying")
    return "\n".join(lines)


def audit_command(args) -> int:
    cases = [c for c in load_corpus() if not args.filter or args.filter in c.name]
    t0 = time.perf_counter()
    results = []
    with tempfile.TemporaryDirectory(prefix="rle-audit-") as tmp:
        for case in cases:
            r = run_case(case, Path(tmp))
            results.append(r)
            print(f"  {'ok ' if r.ok else 'BAD'} {r.name} ({r.seconds:.1f} s)", flush=True)
        leaks = find_leaks([Path(tmp)], hidden_needles(AUDIT_SECRET, sorted({c.task_id for c in cases})))
    print(format_table(results))
    print(f"total run time {time.perf_counter() - t0:.1f} s")
    if leaks:
        print("hidden data found in: " + ", ".join(leaks))
    if args.json:
        Path(args.json).write_text(
            json.dumps(
                [r.__dict__ | {"report": str(r.report), "observed": list(r.observed)} for r in results],
                indent=2,
            )
        )
    return 0 if all(r.ok for r in results) and not leaks else 1
