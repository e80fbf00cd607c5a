"""``rle audit-verifiers``: the adversarial artifact corpus (``corpus.py``) and its runner (``runner.py``)."""

from rle_tasks.audit.runner import (
    AUDIT_SECRET,
    Case,
    CaseResult,
    audit_command,
    find_leaks,
    format_table,
    hidden_needles,
    load_corpus,
    run_case,
)

__all__ = [
    "AUDIT_SECRET",
    "Case",
    "CaseResult",
    "audit_command",
    "find_leaks",
    "format_table",
    "hidden_needles",
    "load_corpus",
    "run_case",
]
