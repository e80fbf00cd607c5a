"""``rle index``: verifier reports and Harbor job directories to the RLE Index's tables and page.

Report files form one system; a Harbor job directory contributes one result per system (agent and
model) and the resources table (``harbor.results``). The aggregation itself is ``index``.
"""

from __future__ import annotations

import os
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from rle_design.errors import RleError
from rle_tasks.core.export.harbor.results import (
    format_resources,
    is_job_dir,
    read_job,
    resources_section,
    systems,
)
from rle_tasks.core.index import IndexResult, compute_index, format_tables
from rle_tasks.core.results_page import write_index_html


def _gather(
    paths: Sequence[str | os.PathLike], name: str, allow_privileged: bool = False, allow_partial: bool = False
) -> tuple[list[IndexResult], dict[str, Any]]:
    """Index results per system from report files (system ``name``) and Harbor job directories."""
    reports = [p for p in paths if not is_job_dir(Path(p))]
    records = [r for p in paths if is_job_dir(Path(p)) for r in read_job(Path(p))]
    results = (
        [compute_index(reports, name=name, allow_privileged=allow_privileged, allow_partial=allow_partial)]
        if reports or not records
        else []
    )
    rows = {}
    for system, (result, res) in systems(
        records, allow_privileged=allow_privileged, allow_partial=allow_partial
    ).items():
        if system == name and reports:
            raise RleError(f"system '{system}' is named by both reports and a job", code="index.duplicate")
        results.append(result)
        rows[system] = res
    return results, rows


def index_command(
    paths: Sequence[str | os.PathLike],
    html: str | os.PathLike | None = None,
    name: str = "submission",
    allow_privileged: bool = False,
    allow_partial: bool = False,
    screenshot: str | os.PathLike | None = None,
) -> int:
    """``rle index REPORTS|JOB_DIRS... [--html OUT [--screenshot PNG]] [--name NAME]``: print the
    tables, optionally write the page and a full-page screenshot of it (headless Chromium). A Harbor job directory contributes one result per system (agent and model) and the
    resources table; report files form the system ``name``.

    Returns:
        0 on success; 2 (with the reason on stderr) when a report is missing, unreadable, unknown or
        duplicated.
    """
    if screenshot is not None and html is None:
        print("rle index: error [index.input]: --screenshot needs --html", file=sys.stderr)
        return 2
    try:
        results, rows = _gather(paths, name, allow_privileged, allow_partial)
    except RleError as exc:
        print(f"rle index: error [{exc.code}]: {exc}", file=sys.stderr)
        return 2
    print("\n\n".join(format_tables(r) for r in results))
    if rows:
        print("\n" + format_resources(rows))
    if html is not None:
        try:
            out = write_index_html(results, Path(html), resources_section(results, rows) if rows else "")
        except OSError as exc:
            print(f"rle index: error [index.output]: cannot write {html}: {exc.strerror}", file=sys.stderr)
            return 2
        print(f"\nHTML written to {out}")
    if screenshot is not None:
        from rle_tasks.core.browser import screenshot as take

        try:
            print(f"screenshot written to {take(out, Path(screenshot))}")
        except RleError as exc:
            print(f"rle index: error [{exc.code}]: {exc}", file=sys.stderr)
            return 2
    return 0
