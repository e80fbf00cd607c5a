"""Shipped solutions of 03-cantilever (see the package docstring)."""

from rle_tasks.f03_physical_reasoning.solutions import committed, solution_set, unsealed

SOLUTIONS = solution_set(
    committed(
        "reference",
        "475b5ce76c103bb1cc24e63602d5630e03b82273f88a61e7626e86d0c5c1a63b",
        0.8264151512396387,
        "solutions/reference/cantilever",
    ),
    committed(
        "baseline/overreach",
        "03f7bf68eaa043965947a6cccc9076d99654e34b78da057fa2c0f8598a1b1539",
        0.5238966796327215,
        "solutions/baseline/overreach/cantilever",
    ),
    unsealed("5c104a55c9c685332d3a2d5b7ab793ee2f6fa843d3e065b766f8f386d3aa96fe"),
)


def harbor_oracle(spec, dest):
    """The Harbor oracle that plays 03-cantilever through its privileged sidecar (``oracle``)."""
    from rle_tasks.f03_physical_reasoning.solutions.oracle import harbor_oracle as write

    return write(spec, dest)
