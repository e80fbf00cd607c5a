"""The paper's task tuple (I, E_dev, B, A, E_eval, M) as a frozen dataclass."""

from __future__ import annotations

from collections.abc import Callable, Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

from rle_tasks.core.families import families, family, workflow_order

if TYPE_CHECKING:
    from rle_tasks.core.report import VerifierReport
    from rle_tasks.core.runtime.secrets import Secret

WORKFLOW_ORDER: tuple[str, ...] = workflow_order()
"""The four workflows in the paper's order (from ``families.yaml``)."""
WORKFLOWS: dict[int, str] = {f.number: f.workflow for f in families()}
"""Workflow of each family number (from ``families.yaml``)."""


@dataclass(frozen=True)
class Budget:
    """Development budget B and verifier limits.

    Attributes:
        wall_time_s: Agent development time [s].
        cpus: CPU cores for the development environment.
        gpus: GPUs for the development environment.
        memory_mb: Memory for the development environment [MiB].
        steps: Charged interaction steps (resets and executed actions), or None if unmetered.
        verifier_timeout_s: Wall-clock limit of one verification [s].
    """

    wall_time_s: float
    cpus: int = 4
    gpus: int = 0
    memory_mb: int = 16384
    steps: int | None = None
    verifier_timeout_s: float = 3600.0


@dataclass(frozen=True)
class ArtifactContract:
    """What a submission directory must contain.

    Attributes:
        required: File names that must exist in the submission directory.
        optional: File names or glob patterns that may exist.
        description: One paragraph for the instruction and ``rle show``.
        max_total_bytes: Size cap for the whole directory [B].
    """

    required: tuple[str, ...]
    optional: tuple[str, ...] = ()
    description: str = ""
    max_total_bytes: int = 64 * 1024 * 1024


@dataclass(frozen=True)
class VerifyContext:
    """Everything a verifier receives besides the artifact directory.

    Attributes:
        secret: Key for hidden-data derivation (never passed to submitted code).
        out_dir: Directory for figures and renders that accompany the report.
        jobs: Parallel worker processes.
        executor: ``"local"`` (process pool) or ``"ray"``.
        ray_address: Cluster address for ``executor="ray"``; None starts a local Ray.
        quick: Reduced batteries (tests and CI); the report marks it in native metrics.
        hang_cap_s: Per-call timeout for submitted code [s] (the card's 30 s hang cap by default).
        episodes: Run a seeded subset of this many episodes of a task's fixed episode set (tasks
            scored over episodes); the report marks it partial, never an official score. None: all.
        attempt: The attempt being verified (the operator's id, a Harbor trial's): a session ledger
            of another attempt is refused (``ledger.wrong_attempt``). None takes the ledger's own
            attempt and reports the verification as unbound.
        reuse_training: A verifier that trains the artifact (family 05) may take the checkpoint of an
            earlier training of the same bytes on the same data from this machine's cache instead of
            training again (``rle demo``); the report says so. Never for an official score.
    """

    secret: Secret
    out_dir: Path | None = None
    jobs: int = 1
    executor: str = "local"
    ray_address: str | None = None
    quick: bool = False
    hang_cap_s: float = 30.0
    episodes: int | None = None
    attempt: str | None = None
    reuse_training: bool = False


@dataclass(frozen=True)
class ImageData:
    """A built dataset that an exported task's images hold (``rle export harbor``), copied from the
    operator's build into the agent's, the development sidecar's and the verifier's image at
    ``/opt/rle-data/<name>``.

    Attributes:
        name: Folder under ``/opt/rle-data``.
        source: Returns the operator's built copy (a directory).
        env: Environment variable pointing the project's code at it inside the images.
        built: File of the dataset whose presence shows it is built (its manifest).
        build: The command that builds it (named when it is missing).
    """

    name: str
    source: Callable[[], Path]
    env: str
    built: str = "manifest.sha256"
    build: str = ""


VerifyFn = Callable[[Path, VerifyContext], "VerifierReport"]
DevEnvFn = Callable[[Path], object]  # returns a MeteredEnv for metered tasks, else None


@dataclass(frozen=True)
class TaskSpec:
    """One benchmark task.

    Attributes:
        id: Stable lowercase id starting with the family number, e.g. ``"08-mobile-base"``.
        family: Family number 1..9.
        title: Short human title.
        instruction: Instruction I given to the agent (markdown).
        budget: Budget B.
        contract: Artifact contract A.
        make_dev_env: Lays out the development environment E_dev in a workspace, or None.
        verify: Verifier M running the hidden evaluation E_eval, or None when not implemented.
        solutions: Names of the shipped solutions (``"reference"``, ``"baseline/..."``), materialised
            on demand by ``rle_tasks.core.solutions.materialise``.
        solutions_module: Dotted name of the module declaring them (its ``SOLUTIONS``), imported only
            when one is materialised.
        episode_scored: The score is a rate over a fixed episode set, so ``VerifyContext.episodes``
            (``rle verify --episodes N``) applies.
        harbor_unsupported: Why the task cannot be exported as a Harbor task yet ("" when it can).
        harbor_data: Built datasets its exported images hold (``ImageData``).
        side_envs: Side virtual environments its development server and verifier need (``"libero"``:
            ``.venv-libero`` from ``requirements-libero.lock``), installed in those exported images.
        quick_note: What ``--quick`` runs for this task ("" when it is the family's usual reduction).
        quick_reduces: ``--quick`` verifies less than the full evaluation (False where the verifier has
            nothing to reduce, e.g. a recorded ledger): a quick report is ``partial`` only then.
        privileged_oracle: ``make_dev_env`` can serve privileged observations (``serving_privileged``)
            for an operator's oracle trial; the session's ledger says so (``ledger.privileged``).
    """

    id: str
    family: int
    title: str
    instruction: str = ""
    budget: Budget = field(default_factory=lambda: Budget(wall_time_s=7200.0))
    contract: ArtifactContract = field(default_factory=lambda: ArtifactContract(required=()))
    make_dev_env: DevEnvFn | None = None
    verify: VerifyFn | None = None
    solutions: tuple[str, ...] = ()
    solutions_module: str = ""
    episode_scored: bool = False
    harbor_unsupported: str = ""
    harbor_data: tuple[ImageData, ...] = ()
    side_envs: tuple[str, ...] = ()
    quick_note: str = ""
    quick_reduces: bool = True
    privileged_oracle: bool = False

    @property
    def workflow(self) -> str:
        return family(self.family).workflow

    @property
    def implemented(self) -> bool:
        return self.verify is not None


_PRIVILEGED: ContextVar[bool] = ContextVar("rle_privileged_dev", default=False)


@contextmanager
def privileged_dev(on: bool = True) -> Iterator[None]:
    """Inside the block, ``make_dev_env`` serves privileged observations (``serving_privileged``)."""
    token = _PRIVILEGED.set(on)
    try:
        yield
    finally:
        _PRIVILEGED.reset(token)


def serving_privileged() -> bool:
    """Whether the development environment being laid out serves privileged observations: only for an
    operator's oracle trial (``harbor.sidecar`` with ``RLE_ORACLE_PRIVILEGED=1``), never for an agent."""
    return _PRIVILEGED.get()
