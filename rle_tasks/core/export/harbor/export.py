"""Export tasks as Harbor (0.25, task schema 1.4) task directories with a separate verifier image.

Layout of ``OUT/<task id>/``::

    task.toml              schema 1.4; [task] name "rle-bench/<id>"; budgets; environment_mode "separate"
    instruction.md         the instruction I, the artifact contract A and the budget B
    README.md              for the operator: expected score, how to set the secret, resources
    environment/           agent image: the public toolkit and the task's public workspace only
                           (``harbor.images``)
    tests/                 verifier image: Dockerfile, test.sh, and a snapshot of the project
    solution/solve.sh      copies the reference solution into /logs/artifacts (only when one is shipped)

The agent writes its artifact into ``/logs/artifacts``, the only directory that crosses into the
verifier container. ``tests/test.sh`` runs ``rle verify`` there and turns the report into
``/logs/verifier/reward.json`` (``rle_tasks.core.export.harbor.reward``): ``reward`` (the task score),
``secret_private`` and one key per checkpoint. The verifier secret comes from the host's ``RLE_SECRET``
and has no default: without it the task does not verify.
"""

from __future__ import annotations

import json
import shutil
from collections.abc import Sequence
from pathlib import Path

from rle_design.errors import RleError
from rle_tasks.core.export.harbor.images import (
    AGENT_USER,
    SIDECAR,
    SIDECAR_LEDGER_DIR,
    agent_context,
    verifier_context,
)
from rle_tasks.core.export.harbor.readme import readme
from rle_tasks.core.report import VERIFIER_VERSION
from rle_tasks.core.task import TaskSpec

ORG = "rle-bench"


def _toml_str(text: str) -> str:
    """A TOML basic string (JSON escapes are valid TOML; DEL is not allowed raw)."""
    return json.dumps(text, ensure_ascii=False).replace("\x7f", "\\u007f")


def _number(x: float) -> str:
    return str(int(x)) if float(x).is_integer() else repr(float(x))


def project_root() -> Path:
    """Root of the source checkout that the images install (must hold ``pyproject.toml``)."""
    from rle_design.paths import REPO_ROOT

    if not (REPO_ROOT / "pyproject.toml").is_file():
        raise RleError(
            f"Harbor export needs the project source tree, but {REPO_ROOT} has no pyproject.toml; "
            "run from a source checkout installed with `pip install -e .`",
            code="harbor.source",
        )
    return REPO_ROOT


def not_exportable(spec: TaskSpec) -> str:
    """Why an implemented task is left out of a default export ("" when it is exported): the exporter
    does not support it, or a dataset its images hold is not built on this machine."""
    if spec.harbor_unsupported:
        return spec.harbor_unsupported
    for data in spec.harbor_data:
        if not (Path(data.source()) / data.built).is_file():
            return f"its images hold the dataset '{data.name}', not built here (`{data.build}`)"
    return ""


def _resolve_specs(task_ids: Sequence[str | TaskSpec] | None) -> list[TaskSpec]:
    from rle_tasks.core.registry import all_tasks, get_task

    if task_ids is None:
        return [t for t in all_tasks() if t.implemented and not not_exportable(t)]
    specs: list[TaskSpec] = []
    for item in task_ids:
        spec = item if isinstance(item, TaskSpec) else get_task(item)
        if not spec.implemented:
            implemented = [t.id for t in all_tasks() if t.implemented]
            raise RleError(
                f"task '{spec.id}' is registered but not implemented (no verifier), so it cannot be exported. "
                f"Implemented tasks: {', '.join(implemented) or '(none)'}",
                code="harbor.unimplemented",
            )
        if spec.harbor_unsupported:
            raise RleError(
                f"task '{spec.id}' cannot be exported as a Harbor task yet: {spec.harbor_unsupported}",
                code="harbor.unsupported",
            )
        if spec.id in {s.id for s in specs}:
            raise RleError(f"task '{spec.id}' is listed twice", code="harbor.duplicate")
        specs.append(spec)
    return specs


def task_toml(spec: TaskSpec) -> str:
    """The ``task.toml`` text of one task."""
    b = spec.budget
    contract = spec.contract
    required = ", ".join(_toml_str(r) for r in contract.required)
    lines = [
        'schema_version = "1.4"',
        "",
        "[task]",
        f"name = {_toml_str(f'{ORG}/{spec.id}')}",
        f"description = {_toml_str(spec.title)}",
        f'keywords = ["rle-bench", {_toml_str(spec.workflow)}, "family-{spec.family:02d}"]',
        "",
        "[metadata]",
        f"family = {spec.family}",
        f"workflow = {_toml_str(spec.workflow)}",
        f"verifier_version = {_toml_str(VERIFIER_VERSION)}",
        f"required_artifacts = [{required}]",
        f"max_artifact_bytes = {contract.max_total_bytes}",
    ]
    if b.steps is not None:
        lines.append(f"interaction_steps = {b.steps}")
    lines += [
        "",
        "[agent]",
        f"timeout_sec = {_number(b.wall_time_s)}",
        f"user = {_toml_str(AGENT_USER)}",
        # Offline while the agent works (Harbor still allows the agent's model endpoint).
        'network_mode = "no-network"',
        "",
        "[verifier]",
        f"timeout_sec = {_number(b.verifier_timeout_s)}",
        'environment_mode = "separate"',
        'network_mode = "no-network"',
        # No default: Harbor refuses to start the verifier when the host has no RLE_SECRET.
        'env = { RLE_SECRET = "${RLE_SECRET}", RLE_ALLOW_PUBLIC_KEY = "${RLE_ALLOW_PUBLIC_KEY:-0}", '
        'RLE_ORACLE_PRIVILEGED = "${RLE_ORACLE_PRIVILEGED:-0}", RLE_VERIFY_QUICK = "${RLE_VERIFY_QUICK:-0}" }',
        "",
        # Every verifier runs on CPU (CI has no GPU): the separate verifier container asks for none,
        # whatever the agent's budget grants, so verification needs no GPU host.
        "[verifier.environment]",
        f"cpus = {b.cpus}",
        f"memory_mb = {b.memory_mb}",
        "gpus = 0",
        'network_mode = "public"',
        "build_timeout_sec = 1800",
        "",
        "[environment]",
        f"cpus = {b.cpus}",
        f"memory_mb = {b.memory_mb}",
        f"gpus = {b.gpus}",
        # Container start and agent setup may download (installed agents set themselves up); the
        # [agent] and [verifier] phases run offline.
        'network_mode = "public"',
        "build_timeout_sec = 1800",
        "",
    ]
    return "\n".join(lines)


def instruction_md(spec: TaskSpec, served: str = "") -> str:
    """The ``instruction.md`` text: instruction I, artifact contract A, budget B (``served``: the kind
    of its development server, which runs beside the agent's container)."""
    b, c = spec.budget, spec.contract
    parts = [
        f"# {spec.title}",
        "",
        spec.instruction.strip() or "(no instruction text)",
        "",
        "## Submission",
        "",
    ]
    parts.append(
        "Write your artifact into `/logs/artifacts/`. Only that directory reaches the verifier, which runs "
        "in a separate container with the hidden evaluation."
    )
    parts.append("")
    parts.append("Required files: " + (", ".join(f"`{r}`" for r in c.required) or "(none)"))
    if c.optional:
        parts.append("Optional files: " + ", ".join(f"`{o}`" for o in c.optional))
    parts.append(f"Size limit: {c.max_total_bytes / 2**20:.0f} MiB.")
    if c.description:
        parts += ["", c.description.strip()]
    budget = (
        f"Wall time {b.wall_time_s / 3600:.1f} h, {b.cpus} CPUs, {b.gpus} GPUs, {b.memory_mb} MiB memory, "
        "no network."
    )
    if b.steps is not None:
        budget += f" {b.steps} charged interaction steps (each reset and executed action costs one)."
    parts += ["", "## Budget", "", budget, "", "## Tools", ""]
    parts.append(
        "`/workspace` holds the development environment of this task (what `rle dev` lays out: the "
        "instruction, public helpers and assets). The design toolkit `rle_design` is importable; "
        'render an MJCF file with `python -c "from rle_design.viz.preview import preview; '
        "preview('robot.xml', png='robot.png', block=False)\"`."
    )
    if served:
        parts.append("")
        parts.append(
            "The development server (`rle dev`'s) already runs beside your container, in this trial's own "
            "attempt: the workspace's client connects to it through `/workspace/.rle/ledger.sock`; there is "
            "no `rle` command here. Its session is sealed after your work ends and is what the verifier "
            "scores"
            + (
                ": you need not copy a ledger into `/logs/artifacts`."
                if "ledger.jsonl" in c.required
                else "."
            )
        )
    return "\n".join(parts) + "\n"


def _ledger_task(spec: TaskSpec) -> bool:
    return "ledger.jsonl" in spec.contract.required


def sidecar_toml(spec: TaskSpec) -> str:
    """``task.toml`` entries of a task with a development server in the sidecar (``harbor.sidecar``):
    Harbor seals the session there after the agent phase and collects its ledger directory."""
    return f"""
# The development server's ledger, sealed after the agent phase and handed to the verifier.
[[verifier.collect]]
service = "{SIDECAR}"
command = "python3 -m rle_tasks.core.export.harbor.sidecar seal"
timeout_sec = 120

[[artifacts]]
source = "{SIDECAR_LEDGER_DIR}"
service = "{SIDECAR}"
"""


def _test_sh(spec: TaskSpec, served: bool = False) -> str:
    sidecar = f' --sidecar "{SIDECAR_LEDGER_DIR}"' if served and _ledger_task(spec) else ""
    return f"""#!/usr/bin/env bash
# Verifier of {ORG}/{spec.id}, run as root in the separate verifier image: only /logs/artifacts crosses
# over. rle_tasks.core.export.harbor.reward closes /logs/verifier to the sandboxed code, runs `rle verify` on a
# private copy of the artifact and writes reward.json atomically; any verifier fault exits non-zero
# without a reward file, so Harbor reports an error instead of a score.
set -euo pipefail
LOGS=/logs
# Workers: the task's CPU budget ({spec.budget.cpus}), fewer where the container sees fewer cores (nproc
# reports the host's cores under a CPU quota, so it is only an upper bound).
JOBS=$(( $(nproc) < {spec.budget.cpus} ? $(nproc) : {spec.budget.cpus} ))
exec python3 -m rle_tasks.core.export.harbor.reward {spec.id} --logs "$LOGS" --jobs "$JOBS"{sidecar}
"""


PLAYING_SOLVE_SH = """#!/usr/bin/env bash
# Oracle: the reference program (solution/oracle.py) plays the task through the development sidecar
# with the workspace's client, then seals.
set -euo pipefail
cd /workspace
PYTHONPATH="/workspace${PYTHONPATH:+:$PYTHONPATH}" exec python3 /solution/oracle.py
"""
"""``solve.sh`` of every playing oracle (a family's ``harbor_oracle`` writes ``oracle.py`` beside it)."""

_SOLVE_SH = """#!/usr/bin/env bash
# Oracle: submit the shipped reference solution.
set -euo pipefail
mkdir -p /logs/artifacts
# A plain recursive copy: /logs/artifacts may be owned by another uid, whose attributes cp -a would
# try (and fail) to overwrite.
cp -r /solution/reference/. /logs/artifacts/
"""


def export_task(spec: TaskSpec, out: Path, root: Path | None = None) -> Path:
    """Write one Harbor task directory ``out/<id>`` (replacing an earlier export there)."""
    root = root or project_root()
    task_dir = out / spec.id
    if task_dir.exists():
        if not (task_dir / "task.toml").is_file():
            raise RleError(
                f"{task_dir} exists and is not a Harbor task directory; remove it or choose another OUT"
            )
        shutil.rmtree(task_dir)
    task_dir.mkdir(parents=True)
    (task_dir / "task.toml").write_text(task_toml(spec))
    served = agent_context(spec, task_dir / "environment", root)
    (task_dir / "instruction.md").write_text(instruction_md(spec, served))
    if served:
        (task_dir / "task.toml").write_text(task_toml(spec) + sidecar_toml(spec))
    verifier_context(task_dir / "tests", root, {"test.sh": _test_sh(spec, bool(served))}, spec)
    plays = False
    if "reference" in spec.solutions:
        sol = task_dir / "solution"
        solve = _playing_oracle(spec, sol) if served else None
        plays = solve is not None
        if solve is None:
            from rle_tasks.core.solutions import materialise

            materialise(spec, "reference", dest=sol / "reference")
            solve = _SOLVE_SH
        (sol / "solve.sh").write_text(solve)
        (sol / "solve.sh").chmod(0o755)
    (task_dir / "README.md").write_text(readme(spec, served, plays))
    return task_dir


def _playing_oracle(spec: TaskSpec, sol: Path) -> str | None:
    """``solve.sh`` of an oracle that plays the task through the development sidecar, written by the
    family's ``harbor_oracle(spec, dest)`` (in its solutions module); None where it has none."""
    import importlib

    if not spec.solutions_module:
        return None
    write = getattr(importlib.import_module(spec.solutions_module), "harbor_oracle", None)
    return write(spec, sol) if write is not None else None


def export_harbor(out: Path, task_ids: Sequence[str | TaskSpec] | None = None) -> list[Path]:
    """Export tasks as Harbor task directories under ``out``.

    Args:
        out: Output directory (created).
        task_ids: Task ids or ``TaskSpec`` objects; None exports every implemented task that can be
            exported here (``not_exportable`` empty).

    Returns:
        The written task directories, in the given (or registry) order.

    Raises:
        RleError: An id is unknown, a task is not implemented, or the project source is unavailable.
    """
    specs = _resolve_specs(task_ids)
    root = project_root()
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    return [export_task(spec, out, root) for spec in specs]
