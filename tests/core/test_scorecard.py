"""The scorecard `rle verify` prints: a checkpoint that earns part of its weight reads as partial."""

from rle_tasks.core.report import Checkpoint, VerifierReport
from rle_tasks.core.scorecard import format_scorecard


def test_marks_say_passed_partial_and_failed():
    report = VerifierReport(
        task_id="03-cantilever",
        family="03",
        workflow="interactive_control",
        score=0.5,
        valid=True,
        checkpoints=(
            Checkpoint("whole", 0.4, 1.0, True, "all of it"),
            Checkpoint("overhang", 0.4, 0.921, False, "92 % of the optimum"),
            Checkpoint("nothing", 0.2, 0.0, False, "none of it"),
        ),
    )
    lines = format_scorecard(report).splitlines()
    marks = {line.split()[1]: line.split()[0] for line in lines[2:5]}
    assert marks == {"whole": "ok", "overhang": "part", "nothing": "FAIL"}
