"""Metered development sessions and their HMAC-chained, sealed ledger.

A ``LedgerServer`` process owns the ledger key, the ledger file and a ``MeteredSession`` (a MuJoCo
model stepped ``n_substeps`` times per action). The agent's ``LedgerClient`` connects over a Unix
socket; each reset and executed action costs one step of the budget, observations are free. Every
charged operation appends a record chained by HMAC-SHA256 (``records``); the session ends with a
seal. ``verify_ledger`` checks a file against the key and returns a ``LedgerVerdict`` whose code
names the first failure (``VERDICT_CODES``).

Trust: the key lives only in the server process (and in whoever derives it, e.g. ``rle dev`` from the
verifier secret). An agent that can read the server's memory or the secret can forge a ledger, so in
evaluation the server runs outside the agent's container or user; with the public development key
the ledger proves nothing and is only a rehearsal.

A ``SceneSet`` serves many scenes in one session (a development phase, then a terminal evaluation
phase of trials, ``scenes``); ``replay_trials`` re-executes its trials for a verifier (``trials``).

Verifiers pass a submitted ledger through ``check_ledger`` (``gate``): authenticity, the attempt, and
every card limit recounted from the records.
"""

from rle_design.ledger.client import LedgerClient
from rle_design.ledger.gate import GATE_CODES, GateResult, Limits, TrialCount, check_ledger
from rle_design.ledger.record import record_session
from rle_design.ledger.records import LedgerError, LedgerWriter
from rle_design.ledger.scenes import EvaluationPhase, SceneSession, SceneSet
from rle_design.ledger.server import LedgerServer, serve
from rle_design.ledger.session import MeteredEnv, MeteredSession
from rle_design.ledger.trials import TrialReplay, development_steps, replay_trials
from rle_design.ledger.verify import VERDICT_CODES, LedgerVerdict, verify_ledger

__all__ = [
    "GATE_CODES",
    "VERDICT_CODES",
    "GateResult",
    "Limits",
    "TrialCount",
    "check_ledger",
    "EvaluationPhase",
    "SceneSession",
    "SceneSet",
    "TrialReplay",
    "development_steps",
    "replay_trials",
    "LedgerClient",
    "LedgerError",
    "LedgerServer",
    "LedgerVerdict",
    "LedgerWriter",
    "record_session",
    "MeteredEnv",
    "MeteredSession",
    "serve",
    "verify_ledger",
]
