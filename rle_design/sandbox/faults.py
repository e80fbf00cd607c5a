"""Participant faults raised by the sandbox, one stable code per failure mode."""

from __future__ import annotations

from rle_design.errors import RleError

FAULT_CODES: dict[str, str] = {
    "sandbox.import_error": "the submitted module could not be imported",
    "sandbox.missing_function": "the module has no callable of that name",
    "sandbox.exception": "the submitted code raised an exception",
    "sandbox.timeout": "a call or the import ran past its wall-clock cap",
    "sandbox.crash": "the child was killed by a signal",
    "sandbox.exit": "the submitted code called sys.exit or os._exit",
    "sandbox.memory": "the submitted code ran out of its address-space limit",
    "sandbox.cpu": "the child used up its CPU-time limit",
    "sandbox.forbidden": "the submitted code tried a forbidden operation (network, process, write outside)",
    "sandbox.bad_shape": "an array output has the wrong shape",
    "sandbox.non_finite": "an output holds NaN or infinity",
    "sandbox.bad_type": "an output has the wrong type or cannot cross the channel",
    "sandbox.dead": "the sandbox died earlier and cannot serve calls",
    "sandbox.output_too_large": "a reply exceeded the reply size cap",
    "sandbox.output_flood": "the child wrote more stdout/stderr than allowed and was killed",
}


class ParticipantFault(RleError):
    """A fault of the submitted code (never of the verifier).

    Attributes:
        code: One of ``FAULT_CODES``.
        detail: Supporting text, e.g. the traceback printed in the child; may be empty.
    """

    code = "sandbox.exception"

    def __init__(self, code: str, message: str, detail: str = "", *, path: str | None = None) -> None:
        if code not in FAULT_CODES:
            raise ValueError(f"unknown sandbox fault code '{code}'. Known codes: {', '.join(FAULT_CODES)}")
        super().__init__(message, code=code, path=path)
        self.detail = detail

    def __reduce__(self):
        return (_rebuild, (self.code, self.message, self.detail, self.path))


def _rebuild(code: str, message: str, detail: str, path: str | None) -> ParticipantFault:
    return ParticipantFault(code, message, detail, path=path)
