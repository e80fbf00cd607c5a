"""Build-time: the searches that follow the greedy placement of the reference leaders' parts.

Parameters of the joint search over every joint's placements together (``SEARCH_*``,
``INSIDE_LOSS``) and of the coordinate descent (``DESCENT_*``) that
``placement_search.clear_fastened`` runs, and the joint search's exhaustive estimate of the
combinations of one candidate per joint from the candidates' records (``best_combinations``).
"""

from __future__ import annotations

import numpy as np

from rle_tasks.f09_gello.solutions.placement_loss import _search_loss

DESCENT_INSIDE = 100.0
"""What the coordinate descent counts per unit fraction of poses with a part inside the next link,
on top of those poses' collisions [1]: 0.1 for one pose in 1024, what 5 % of the poses colliding
cost; the reference must have no part inside another at any pose (issue 45)."""
DESCENT_SHORTLIST = 12
"""Candidates per coordinate (best on a quarter of the coarse poses first) the descent scores on the
fine grid."""
SEARCH_ABOVE = 0.02
"""The joint search (``clear_fastened``) replaces the greedy's later passes on an arm whose first pass
leaves added parts colliding at more than this fraction of the fine public poses, or a part inside
the next link at any [1]: 40 % of the card's 5 % fail value. Below it (panda: 1.3 %) the greedy's
passes stand."""
SEARCH_POSES = 256
"""Public poses on which the joint search records, per candidate placement, the poses its parts
collide at (one pose is 0.5 % of the counted ones); finalists are scored on the fine grid."""
SEARCH_SHORTLIST = 30
"""Candidates per joint (best alone first) whose combinations the joint search scores exhaustively."""
SEARCH_FINALISTS = 8
"""Combinations, best by the estimate, that the joint search scores exactly on the fine grid."""
SEARCH_ROUNDS = 1
"""Joint-search rounds; a second re-records every candidate around the first's result (on ur5e it
changed nothing, 5 more minutes)."""
INSIDE_LOSS = 0.02
"""What the joint search counts for each fine-grid pose with a part inside the next link, on top of
that pose's collision [1]: the loss of 1 % of the poses colliding, since the reference must have
no part inside another at any pose (issue 45)."""


def best_combinations(
    cands: dict[int, list[dict]], base: dict, counted: np.ndarray, top: int, mass_cap: float
) -> list[tuple[float, float, tuple[int, ...]]]:
    """The ``top`` combinations of one candidate per joint, best first by ``_search_loss``, estimated
    from the candidates' records.

    Args:
        cands: Joint -> candidates, each ``{"hit": (N,) bool, "ai": (P, nv), "mass", "unb"}``: the
            poses its own parts fail, the design's added inertia with it [kg m^2], the device mass
            [kg] and the unbalanced moment [N m], each measured with the other joints as in
            ``base``.
        base: ``{"hit"}`` the poses the other parts (spring posts) fail, ``{"ai", "mass"}`` of the
            current design, ``{"current"}`` joint -> index of its current candidate.
        counted: Poses the verifier counts.

    Returns:
        ``(estimated loss, estimated collision fraction, candidate index per joint)``; the added
        inertia and mass of a combination are the current ones plus each candidate's change (the
        mass matrix is linear in the parts), its collisions the union of the candidates'.
    """
    import itertools

    from rle_tasks.f09_gello.battery import ACCEL_REF

    joints = sorted(cands)
    out = []
    for idx in itertools.product(*(range(len(cands[j])) for j in joints)):
        hit, ai, mass, unb = base["hit"].copy(), base["ai"].copy(), base["mass"], 0.0
        for j, i in zip(joints, idx, strict=True):
            c, cur = cands[j][i], cands[j][base["current"][j]]
            hit |= c["hit"]
            ai = ai + c["ai"] - cur["ai"]
            mass += c["mass"] - cur["mass"]
            unb += c["unb"]
        if mass > mass_cap:
            continue
        frac = float(hit[counted].mean())
        out.append((_search_loss(frac, unb, ACCEL_REF * ai.max(axis=1)), frac, idx))
    out.sort()
    return out[:top]
