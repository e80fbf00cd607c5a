"""Command line: ``rle tasks|show|verify|preview|dev|ledger|export|index|demo|catalog|audit-verifiers``.

Exit codes: 0 a report or the requested output was produced; 2 usage error, unknown task, unreadable
input; 1 an internal fault (our bug).
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

from rle_design.errors import RleError
from rle_tasks.core.runtime.secrets import ATTEMPT_ENV


def _cmd_tasks(args: argparse.Namespace) -> int:
    from rle_tasks.core.registry import all_tasks

    rows = [t for t in all_tasks() if args.family is None or t.family == args.family]
    print(f"{'task id':<30} {'family':<6} {'workflow':<22} {'implemented':<11} title")
    for t in rows:
        print(
            f"{t.id:<30} {t.family:02d}     {t.workflow:<22} {'yes' if t.implemented else 'no':<11} {t.title}"
        )
    n_impl = sum(t.implemented for t in rows)
    print(f"{len(rows)} tasks, {n_impl} implemented")
    return 0


def _cmd_show(args: argparse.Namespace) -> int:
    from rle_tasks.core.registry import get_task

    t = get_task(args.task)
    b = t.budget
    print(
        f"# {t.id}: {t.title}\nfamily {t.family:02d}, workflow {t.workflow}, implemented: {t.implemented}\n"
    )
    print(t.instruction or "(instruction not written yet: the task is registered but not implemented)")
    print("\n## Budget")
    print(f"wall time {b.wall_time_s / 3600:.1f} h, {b.cpus} CPUs, {b.gpus} GPUs, {b.memory_mb} MiB memory")
    if b.steps is not None:
        print(f"{b.steps} charged interaction steps")
    print("\n## Artifact contract")
    print("required: " + (", ".join(t.contract.required) or "(none)"))
    if t.contract.optional:
        print("optional: " + ", ".join(t.contract.optional))
    if t.contract.description:
        print(t.contract.description)
    if t.quick_note:
        print(f"\n## Quick verification\n{t.quick_note}")
    return 0


def _cmd_verify(args: argparse.Namespace) -> int:
    from rle_tasks.core.registry import get_task
    from rle_tasks.core.runtime.secrets import load_secret
    from rle_tasks.core.scorecard import print_scorecard
    from rle_tasks.core.task import VerifyContext
    from rle_tasks.core.verify import run_verify

    task = get_task(args.task)
    out_json = Path(args.json) if args.json else None
    fig_dir = out_json.parent / (out_json.stem + "_figures") if out_json else None
    ctx = VerifyContext(
        secret=load_secret(args.secret_file),
        out_dir=fig_dir,
        jobs=args.jobs,
        executor=args.executor,
        ray_address=args.ray_address,
        quick=args.quick,
        episodes=args.episodes,
        attempt=args.attempt or os.environ.get(ATTEMPT_ENV) or None,
    )
    if args.quick:
        print(
            f"{task.id}: {task.quick_note or 'quick runs reduced batteries'} (marked partial in the report)"
        )
    report, internal = run_verify(task, args.dir, ctx)
    if out_json:
        report.write(out_json)  # before any printing: a closed pipe must not lose the report
    print_scorecard(report)
    if out_json:
        print(f"report written to {out_json}")
    return 1 if internal else 0


def _cmd_preview(args: argparse.Namespace) -> int:
    from rle_design.viz.preview import preview

    preview(
        args.file,
        arm=args.arm,
        png=args.png,
        payload=args.payload,
        port=args.port,
        block=not args.no_block,
        mount_site=args.mount_site,
    )
    return 0


def _cmd_dev(args: argparse.Namespace) -> int:
    from rle_tasks.core.runtime.devenv import make_workspace

    make_workspace(
        args.task,
        Path(args.workspace),
        serve=not args.no_serve,
        attempt=args.attempt or os.environ.get(ATTEMPT_ENV) or None,
    )
    return 0


def _cmd_ledger(args: argparse.Namespace) -> int:
    import json

    from rle_design.ledger import verify_ledger
    from rle_design.ledger.show import describe_ledger
    from rle_tasks.core.runtime.devenv import ledger_key
    from rle_tasks.core.runtime.secrets import load_secret

    path = Path(args.ledger)
    if not path.is_file():
        raise RleError(f"{path} is not a file", code="ledger.missing")
    verdict = None
    if not args.no_verify:
        try:
            task_id = json.loads(path.read_bytes().split(b"\n", 1)[0])["task_id"]
        except (ValueError, KeyError, TypeError):
            task_id = None
        if isinstance(task_id, str):
            verdict = verify_ledger(path, ledger_key(load_secret(args.secret_file), task_id), task_id)
    print(describe_ledger(path, verdict))
    return 0


def _cmd_export(args: argparse.Namespace) -> int:
    from rle_tasks.core.export.harbor.export import export_harbor, not_exportable

    written = export_harbor(Path(args.out), args.tasks or None)
    print(f"wrote {len(written)} Harbor task directories under {args.out}")
    if not args.tasks:
        from rle_tasks.core.registry import all_tasks

        for t in all_tasks():
            if t.implemented and (why := not_exportable(t)):
                print(f"not exported: {t.id}: {why}")
    return 0


def _cmd_index(args: argparse.Namespace) -> int:
    from rle_tasks.core.results import index_command

    return index_command(
        args.reports,
        html=args.html,
        name=args.name,
        allow_privileged=args.allow_privileged,
        allow_partial=args.allow_partial,
        screenshot=args.screenshot,
    )


def _cmd_demo(args: argparse.Namespace) -> int:
    from rle_tasks.demo import run_demo

    return run_demo(
        Path(args.out),
        quick=args.quick or not args.full,
        jobs=args.jobs,
        full_baselines=args.full_baselines,
        tasks=args.task,
        full=args.full,
    )


def _cmd_audit(args: argparse.Namespace) -> int:
    from rle_tasks.audit import audit_command

    return audit_command(args)


def _cmd_catalog(args: argparse.Namespace) -> int:
    import dataclasses
    import json

    from rle_design.catalog import catalog_kinds, load_catalog

    if args.kind is None:
        for kind in catalog_kinds():
            cat = load_catalog(kind)
            print(f"{kind:<16} {len(cat):>3} entries  {cat.source.split('. ')[0][:90]}")
        return 0
    cat = load_catalog(args.kind)
    rows = [dataclasses.asdict(e) for e in cat.entries]
    if args.json:
        print(
            json.dumps(
                {"kind": cat.kind, "units": dict(cat.units), "source": cat.source, "entries": rows}, indent=2
            )
        )
        return 0
    cols = [c for c in rows[0] if not isinstance(rows[0][c], dict)] if rows else []
    heads = [f"{c} [{cat.units[c]}]" if c in cat.units else c for c in cols]
    cells = [[f"{r[c]:.6g}" if isinstance(r[c], float) else str(r[c]) for c in cols] for r in rows]
    widths = [max(len(h), *(len(row[i]) for row in cells)) for i, h in enumerate(heads)]
    print("  ".join(h.ljust(w) for h, w in zip(heads, widths, strict=True)).rstrip())
    for row in cells:
        print("  ".join(v.ljust(w) for v, w in zip(row, widths, strict=True)).rstrip())
    print(f"\nsource: {cat.source}")
    return 0


def build_parser() -> argparse.ArgumentParser:
    from rle_design.scene import arm_ids

    p = argparse.ArgumentParser(prog="rle", description="RLE-Bench: tasks, verifiers and design toolkit")
    sub = p.add_subparsers(dest="command", required=True)

    s = sub.add_parser("tasks", help="list the 51 task ids")
    s.add_argument("--family", type=int, default=None, help="only this family number (1..9)")
    s.set_defaults(fn=_cmd_tasks)

    s = sub.add_parser("show", help="instruction, budget and artifact contract of a task")
    s.add_argument("task")
    s.set_defaults(fn=_cmd_show)

    s = sub.add_parser("verify", help="verify an artifact directory and write the report")
    s.add_argument("task")
    s.add_argument("dir")
    s.add_argument("--json", help="write the report JSON here (figures go beside it)")
    s.add_argument(
        "--secret-file", help="file holding the verifier secret (default: $RLE_SECRET, else public key)"
    )
    s.add_argument("--jobs", type=int, default=max(1, (os.cpu_count() or 2)), help="parallel workers")
    s.add_argument("--executor", choices=["local", "ray"], default="local")
    s.add_argument("--ray-address", default=None, help="Ray cluster address (default: a local Ray)")
    s.add_argument(
        "--quick",
        action="store_true",
        help="reduced batteries, marked partial in the report (`rle show ID` says what each task's quick runs)",
    )
    s.add_argument(
        "--episodes",
        type=int,
        default=None,
        help="episode-scored tasks: a seeded subset of N episodes (a partial report, never official)",
    )
    s.add_argument(
        "--attempt",
        default=None,
        help=f"the attempt being verified (default: ${ATTEMPT_ENV}); a session ledger of another attempt is "
        "refused. Without it the ledger's own attempt is taken and the report says it was unbound",
    )
    s.set_defaults(fn=_cmd_verify)

    s = sub.add_parser("preview", help="meshcat preview (prints the URL) or an offscreen PNG")
    s.add_argument("file")
    s.add_argument("--arm", choices=arm_ids(), default=None, help="catalog arm mounted at --mount-site")
    s.add_argument(
        "--mount-site",
        default="arm_mount_site",
        help="site of the design that carries the arm (default: %(default)s)",
    )
    s.add_argument("--payload", choices=["payload_1kg", "payload_2kg"], default=None)
    s.add_argument("--png", default=None, help="write an offscreen render here instead of serving meshcat")
    s.add_argument("--port", type=int, default=None, help="meshcat web port (default: meshcat's choice)")
    s.add_argument("--no-block", action="store_true", help="return after printing the URL")
    s.set_defaults(fn=_cmd_preview)

    s = sub.add_parser("dev", help="lay out an agent workspace and start the metered environment")
    s.add_argument("task")
    s.add_argument("--workspace", required=True)
    s.add_argument("--no-serve", action="store_true", help="lay out files only")
    s.add_argument(
        "--attempt",
        default=None,
        help=f"attempt id issued by the operator (default: ${ATTEMPT_ENV}, else one derived from the workspace "
        "path); one metered session per attempt, its hidden scenes bound to it",
    )
    s.set_defaults(fn=_cmd_dev)

    s = sub.add_parser("ledger", help="print what a session ledger recorded, request by request")
    s.add_argument("action", choices=["show"])
    s.add_argument("ledger", help="a ledger file (rle dev prints its path)")
    s.add_argument(
        "--secret-file",
        help="verifier secret to authenticate it with (default: $RLE_SECRET, else public key)",
    )
    s.add_argument("--no-verify", action="store_true", help="show the records without authenticating them")
    s.set_defaults(fn=_cmd_ledger)

    s = sub.add_parser("export", help="export tasks")
    s.add_argument("format", choices=["harbor"])
    s.add_argument("out")
    s.add_argument("--tasks", nargs="*", default=None)
    s.set_defaults(fn=_cmd_export)

    s = sub.add_parser("index", help="RLE Index from reports and Harbor job directories")
    s.add_argument("reports", nargs="+", help="verifier report files and/or Harbor job directories")
    s.add_argument("--html", default=None, help="write the results page (one self-contained HTML file)")
    s.add_argument(
        "--screenshot",
        default=None,
        metavar="PNG",
        help="also a full-page screenshot of the page (needs --html and a headless Chromium)",
    )
    s.add_argument("--name", default="submission", help="system name shown on the leaderboard")
    s.add_argument(
        "--allow-privileged",
        action="store_true",
        help="accept reports of privileged sessions (an operator's oracle trials; refused by default)",
    )
    s.add_argument(
        "--allow-partial",
        action="store_true",
        help="accept reports of a reduced evaluation (quick mode, an episode subset); the page marks them",
    )
    s.set_defaults(fn=_cmd_index)

    s = sub.add_parser("demo", help="verify every shipped solution and write out/demo/")
    s.add_argument("--out", default="out/demo")
    s.add_argument(
        "--quick",
        action="store_true",
        help="reduced batteries for every solution (the default without --full)",
    )
    s.add_argument(
        "--full-baselines", action="store_true", help="full batteries for baselines too (default: quick)"
    )
    s.add_argument("--jobs", type=int, default=max(1, (os.cpu_count() or 2)))
    s.add_argument(
        "--task",
        action="append",
        metavar="ID",
        help="only this task (an id, or a family number such as 05); repeatable (default: every task)",
    )
    s.add_argument(
        "--full",
        action="store_true",
        help="the complete run: references in full, every recipe retrained, and the solutions that exist "
        "to run out a long time limit (listed, not run, by default)",
    )
    s.set_defaults(fn=_cmd_demo)

    s = sub.add_parser("catalog", help="list the catalogs, or one catalog's entries with their units")
    s.add_argument("kind", nargs="?", default=None, help="a catalog kind (springs, profiles, servos ...)")
    s.add_argument("--json", action="store_true", help="entries, units and source as JSON")
    s.set_defaults(fn=_cmd_catalog)

    s = sub.add_parser("audit-verifiers", help="run the adversarial artifact corpus and print its table")
    s.add_argument("--filter", default=None, help="only cases whose name contains this")
    s.add_argument("--json", default=None)
    s.set_defaults(fn=_cmd_audit)
    _add_family_commands(sub)
    return p


def _add_family_commands(sub) -> None:
    """Subcommands a family package offers through ``commands()`` (each adds itself to ``sub``)."""
    import importlib

    from rle_tasks.core.registry import family_packages

    for package in family_packages().values():
        for add in getattr(importlib.import_module(package), "commands", lambda: ())():
            add(sub)


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    try:
        return int(args.fn(args) or 0)
    except RleError as exc:
        print(f"rle {args.command}: error [{exc.code}]: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        return 130
    except BrokenPipeError:  # output piped into `head` and the like: the work itself is done
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0


if __name__ == "__main__":
    sys.exit(main())
