"""``README.md`` of an exported Harbor task directory: what an operator needs before ``harbor run``."""

from __future__ import annotations

from rle_tasks.core.task import TaskSpec


def _reference_line(spec: TaskSpec, served: str = "", plays: bool = False) -> str:
    if "reference" not in spec.solutions or not spec.solutions_module:
        return "This task ships no reference solution, so the oracle agent has nothing to submit."
    from rle_tasks.core.solutions import declaration

    ref = declaration(spec).get("reference")
    if plays and spec.privileged_oracle:
        return (
            "Harbor's oracle agent plays the reference program (`solution/oracle.py`) through the "
            "development sidecar. That program reads the pieces' poses and sizes, which agents are never "
            "given, so the sidecar serves them only for an oracle trial: run it with "
            "`RLE_ORACLE_PRIVILEGED=1` on the host (`RLE_ORACLE_PRIVILEGED=1 harbor run --path . --agent "
            "oracle -e docker`). The session's ledger records it, the verifier names it "
            "(`ledger.privileged`), `rle index` refuses the report, and the reward counts only because the "
            "verifier reads the same variable (without it, or in any agent's trial, such a session scores "
            f"0). With the public development key the reference scores **{ref.quick_score:.3f}** (the golden "
            f"score pinned in `{spec.solutions_module}`); with your private secret the blocks are others, "
            "so expect a score near it."
        )
    if plays:
        return (
            f"Harbor's oracle agent plays the reference program (`solution/oracle.py`) through the "
            f"development sidecar, in the trial's own attempt, and seals the session. With the public "
            f"development key its recorded session scores **{ref.quick_score:.3f}** (the golden score pinned in "
            f"`{spec.solutions_module}`); with your private secret the target scenes are others, so expect "
            "a score near it, not the same digits."
        )
    if served and "ledger.jsonl" in spec.contract.required:
        return (
            "The verifier scores the session of the development sidecar, never a ledger copied into "
            "`/logs/artifacts`; the reference program reads privileged state the agent's client does not "
            "give, so Harbor's oracle agent (which copies the shipped ledger) scores **0**. "
            f"The reference's own golden score (public key, quick mode) is {ref.quick_score:.3f}."
        )
    return (
        f"The reference solution (`solution/reference/`, submitted by Harbor's oracle agent) scores "
        f"**{ref.quick_score:.3f}** in the verifier's quick mode with the public development key (the "
        f"golden score pinned in `{spec.solutions_module}` and checked by the project's tests). The "
        "exported verifier runs the full evaluation on hidden variations derived from your private "
        "secret, so expect a score near this value, not the same digits; an oracle run measures it "
        f"(`harbor run --path . --agent oracle`)."
    )


def _data_note(spec: TaskSpec) -> str:
    """What the images hold besides the project: built datasets and side environments."""
    lines = []
    for d in spec.harbor_data:
        lines.append(
            f"The dataset `{d.name}` is built into the agent's, the sidecar's and the verifier's image at "
            f"`/opt/rle-data/{d.name}` (`{d.env}` points the code at it; the workspace links it): the exporter "
            f"copies the copy built on the exporting machine (`{d.build}`), with its manifest "
            f"(`{d.built}`). We build it in rather than mount it because Harbor's separate verifier container "
            "receives only `/logs/artifacts`; each image grows by the dataset's size, and every trial of one "
            "export trains and scores on the same bytes."
        )
    for name in spec.side_envs:
        lines.append(
            f"The sidecar's and the verifier's images also hold the `{name}` side environment "
            f"(`/opt/rle-bench/.venv-{name}`, installed from its own lock file: it pins another MuJoCo)."
        )
    return "\n" + "\n\n".join(lines) + "\n" if lines else ""


def _quick_note(spec: TaskSpec) -> str:
    if not spec.quick_reduces:
        return ""
    what = f" ({spec.quick_note})" if spec.quick_note else ""
    return (
        "\n## Quick evaluation\n\n"
        f"`RLE_VERIFY_QUICK=1` on the host asks the verifier for the task's quick evaluation{what}. Its "
        "reward says `partial` 1, and `rle index` takes such a job only with `--allow-partial`, which marks "
        "the score: a smoke test, never an official result.\n"
    )


def readme(spec: TaskSpec, served: str = "", plays: bool = False) -> str:
    """The README text of one exported task (``served``: its development environment's kind)."""
    b, c = spec.budget, spec.contract
    metered_note = (
        f"\nThe {served} development environment of `rle dev` runs beside the agent as the compose service "
        "`dev` (`environment/docker-compose.yaml`, built from `environment/dev/`): it holds the ledger key "
        "derived from `RLE_SECRET`, the hidden scenes and the ledger, draws the trial's attempt id, and "
        "serves the workspace's client through `/workspace/.rle/ledger.sock` (a volume of both). After "
        "the agent phase Harbor seals the session in it (`[[verifier.collect]]`) and hands its ledger and "
        "attempt to the verifier (`[[artifacts]]` of the service), which verifies that ledger as that "
        "attempt, whatever the agent left in `/logs/artifacts`. Docker's compose environment runs it "
        "(`harbor run -e docker`).\n"
        if served
        else ""
    )
    steps = f"{b.steps} charged interaction steps" if b.steps is not None else "unmetered"
    return f"""# rle-bench/{spec.id}: {spec.title}

Workflow: {spec.workflow}; family {spec.family:02d}. `instruction.md` is what the agent reads.

## Expected score

{_reference_line(spec, served, plays)}

## Secret

The verifier derives its hidden evaluation from `RLE_SECRET`, read from the environment of the host
that runs `harbor` (`task.toml` passes it with no default). Without it Harbor refuses to start the
verifier, and the verifier itself refuses an empty one, so no run is ever scored on the public key by
accident:

```bash
export RLE_SECRET="$(openssl rand -hex 32)"  # keep it: the same secret reproduces the same scores
harbor run --path . --agent oracle
```

The agent container never receives the secret. A smoke test on the public development key is possible
only on purpose (`RLE_SECRET= RLE_ALLOW_PUBLIC_KEY=1`), and its reward says so (`secret_private` 0).
`reward.json` holds `reward` (the task score), `secret_private` and one number per checkpoint; a
verifier fault leaves no reward file, so Harbor reports an error instead of a zero.
{_quick_note(spec)}
## Resources

| | |
|---|---|
| agent wall time | {b.wall_time_s / 3600:.1f} h |
| CPUs / memory / GPUs | {b.cpus} / {b.memory_mb} MiB / {b.gpus} |
| interaction budget | {steps} |
| verifier timeout | {b.verifier_timeout_s / 60:.0f} min (workers: at most {b.cpus}) |
| artifact size limit | {c.max_total_bytes / 2**20:.0f} MiB |
| network | public while the container starts and the agent installs; none for the agent and verifier phases |

## Images
{metered_note}{_data_note(spec)}
`environment/` (the agent's image) holds the public toolkit `rle_design` and the task's public
workspace (`/workspace`, what `rle dev` lays out); no solutions, generators or verifier code.
`tests/` (the verifier's image) holds the whole project. Both install `requirements.lock` (exact
versions). The base image is `python:3.11-slim-bookworm`; to pin it by digest (`harbor lint --select
ALL`), export with `RLE_HARBOR_BASE_IMAGE=python:3.11-slim-bookworm@sha256:<digest>`. The verifier
runs as root so that submitted code runs sandboxed as `nobody`; without CAP_SYS_ADMIN (Docker's default)
the sandbox has no network namespace of its own, which the report records (`sandbox_layers`).
"""
