"""``rle audit-verifiers``: the adversarial artifact corpus (``corpus.py``) and its check of one case (``check.py``)."""

from rle_tasks.audit.check import (
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
