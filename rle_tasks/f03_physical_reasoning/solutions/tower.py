"""Shipped solutions of 03-tower (see the package docstring)."""

from rle_tasks.f03_physical_reasoning.solutions import committed, solution_set, unsealed

SOLUTIONS = solution_set(
    committed(
        "reference",
        "1b504b934e5c948a8e02375be22122e1a1eb80b0d8dc881772c507e27ec8cbd6",
        0.883125946993273,
        "solutions/reference/tower",
    ),
    committed(
        "baseline/knocked_over",
        "ada13571c1d617bcd82c2d08c13c5092aee11f44d513bf6d9ffdebea8852decf",
        0.17362648559204488,
        "solutions/baseline/knocked_over/tower",
    ),
    unsealed("da9955f63daff919378608775b96129e95c4de5fef6b5da8f72f92c4c8ac73f8"),
)


def harbor_oracle(spec, dest):
    """The Harbor oracle that plays 03-tower through its privileged sidecar (``oracle``)."""
    from rle_tasks.f03_physical_reasoning.solutions.oracle import harbor_oracle as write

    return write(spec, dest)
