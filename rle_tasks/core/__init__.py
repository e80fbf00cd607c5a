"""Task model, registry, verifier reports, hidden-seed derivation, RLE Index and exports."""

from rle_tasks.core.report import Checkpoint, ErrorEntry, VerifierReport
from rle_tasks.core.runtime.secrets import Secret, derive_rng, derive_seed, load_secret
from rle_tasks.core.task import ArtifactContract, Budget, TaskSpec, VerifyContext

__all__ = [
    "ArtifactContract",
    "Budget",
    "Checkpoint",
    "ErrorEntry",
    "Secret",
    "TaskSpec",
    "VerifierReport",
    "VerifyContext",
    "derive_rng",
    "derive_seed",
    "load_secret",
]
