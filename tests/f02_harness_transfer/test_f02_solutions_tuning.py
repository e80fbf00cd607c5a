"""The reference harness's ``motion.py`` is the kitchen harness's with the reference's constants."""

from __future__ import annotations

import pytest

from rle_tasks.f02_harness_transfer.solutions import TUNED_CONSTANTS, tune_constants


def test_tuning_sets_each_named_top_level_constant_and_nothing_else():
    text = 'A = 1\n"""doc of A"""\nAB = 2\n    A = 3\n'
    assert tune_constants(text, {"A": "0.5"}) == 'A = 0.5\n"""doc of A"""\nAB = 2\n    A = 3\n'


@pytest.mark.parametrize("text", ["B = 1\n", "A = 1\nA = 2\n"])
def test_tuning_refuses_a_constant_that_is_not_assigned_exactly_once(text):
    with pytest.raises(ValueError, match="A is assigned on"):
        tune_constants(text, {"A": "0"})


def test_the_kitchen_harness_still_assigns_every_tuned_constant_once():
    from rle_tasks.envs.kitchen.workspace import HARNESS

    for module, values in TUNED_CONSTANTS.items():
        tuned = tune_constants((HARNESS / module).read_text(), values)
        for name, value in values.items():
            assert f"\n{name} = {value}\n" in tuned
