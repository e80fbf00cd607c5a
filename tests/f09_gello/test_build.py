"""The reference build's placement rules (``solutions/build.py`` and its modules), pinned
on closed forms: the passive hold's loss estimate and a counterweight split into a pair."""

import numpy as np
import pytest

from rle_tasks.f09_gello.public.gello_helpers import load_leader, residual, workspace_grid
from rle_tasks.f09_gello.solutions.design import apply_design, exact_design
from rle_tasks.f09_gello.solutions.placement_loss import SERVO_FRICTION, hold_failure


def test_hold_failure_is_the_fraction_of_a_turn_where_the_moment_beats_the_friction():
    f = SERVO_FRICTION
    assert hold_failure(0.5 * f) == 0.0 and hold_failure(f) == 0.0
    # |sin| > 1/2 on 2/3 of a turn (asin(1/2) = pi/6)
    assert hold_failure(2 * f) == pytest.approx(2 / 3)
    assert hold_failure(f / np.sin(np.pi / 3)) == pytest.approx(1 / 3)  # |sin| > sqrt(3)/2: 1/3
    theta = np.random.default_rng(0).uniform(0, 2 * np.pi, 200_000)
    for moment in (1.2 * f, 1.9 * f, 5 * f):
        assert hold_failure(moment) == pytest.approx(np.mean(moment * np.abs(np.sin(theta)) > f), abs=0.005)


def _worst_residual(path) -> np.ndarray:
    m, km, springs = load_leader(path)
    return np.abs(residual(km, springs, workspace_grid(m.jnt_range, 256))).max(axis=0)


def test_a_pair_astride_the_axis_balances_what_a_single_weight_does(tmp_path):
    single = exact_design("xarm7", {6: (0.08, None)})
    pair = exact_design("xarm7", {6: (0.08, None, 0.055)})
    (one,) = [c for c in single.counterweights if c[0] == "link6"]
    two = [c for c in pair.counterweights if c[0] == "link6"]
    assert len(two) == 2 and two[0][2] == pytest.approx(one[2] / 2) and two[1][2] == pytest.approx(one[2] / 2)
    for (_, pos, _), dz in zip(two, (0.055, -0.055), strict=True):
        assert np.allclose(np.subtract(pos, one[1]), [0.0, 0.0, dz])
    # joint 6's weight puts the wrist's centre of mass where axes 5 and 6 cross: joint 5 needs none
    assert not any(c[0] == "link5" for c in pair.counterweights)
    assert max(pair.unbalanced.values()) < 1e-9
    worst = _worst_residual(apply_design("xarm7", pair, tmp_path / "pair"))
    assert worst.max() < 1e-6  # exact balance at every joint (zero-length spring on joint 2)
    # the same weight at a fixed axial shift leaves joint 5 its moment, more than the servo friction
    shifted = exact_design("xarm7", {6: (0.08, 0.055), 5: None})
    assert shifted.unbalanced[5] > SERVO_FRICTION
    assert _worst_residual(apply_design("xarm7", shifted, tmp_path / "shifted"))[4] > SERVO_FRICTION


def test_the_parts_collisions_add_up_to_the_verifiers_count():
    """``part_checks.part_collisions`` per rigid group of added parts: their union over a design is
    ``clearance.collision_fraction`` of the whole design (what the joint search adds up)."""
    import mujoco

    from rle_design.mjcf.loader import load_design
    from rle_tasks.core.solutions import materialise
    from rle_tasks.f09_gello.clearance import collision_fraction
    from rle_tasks.f09_gello.device import stock_names
    from rle_tasks.f09_gello.solutions.part_checks import part_collisions

    ref = materialise("09-gello", "reference")
    for robot in ("ur5e", "xarm7"):
        leader = load_design(ref / robot, entry="lead.xml")
        m = leader.compile()
        stock = set(stock_names(robot)[0])
        added = [mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_BODY, b) for b in range(1, m.nbody)]
        added = [b for b in added if b not in stock]
        poses = workspace_grid(m.jnt_range, 96, seed=7)
        frac, _, _ = collision_fraction(leader, added, poses)
        union = np.zeros(len(poses), bool)
        for name in added:
            counted, hit = part_collisions(leader, stock, [name], poses)
            union |= hit
        assert union[counted].mean() == pytest.approx(frac, abs=1e-12)


def test_combinations_are_the_union_of_their_candidates_collisions():
    """``joint_search.best_combinations``: a combination's collisions are the union of its candidates'
    (here disjoint poses add, shared ones count once), its added inertia the current one plus each
    candidate's change, and the mass cap excludes what is too heavy."""
    from rle_tasks.f09_gello.solutions.joint_search import best_combinations
    from rle_tasks.f09_gello.solutions.placement_loss import _search_loss

    n, counted = 20, np.ones(20, bool)

    def cand(poses, mass, ai=0.0):
        hit = np.zeros(n, bool)
        hit[list(poses)] = True
        return {"hit": hit, "ai": np.full((4, 3), ai), "mass": mass, "unb": 0.0}

    cands = {
        3: [cand({0, 1}, 1.0), cand({0}, 1.2), cand(set(), 2.5)],
        4: [cand({1}, 1.0), cand({5, 6}, 1.0, ai=0.01)],
    }
    base = {"hit": cand({9}, 0)["hit"], "ai": np.zeros((4, 3)), "mass": 1.0, "current": {3: 0, 4: 0}}
    out = best_combinations(cands, base, counted, top=10, mass_cap=2.0)
    fracs = {idx: frac for _, frac, idx in out}
    assert (2, 0) not in fracs and (2, 1) not in fracs  # 1.0 + 2.5 - 1.0 kg > 2.0 kg
    assert fracs[(0, 0)] == pytest.approx(3 / n)  # {0, 1} | {1} | {9}
    assert fracs[(1, 0)] == pytest.approx(3 / n)  # {0} | {1} | {9}
    assert fracs[(1, 1)] == pytest.approx(4 / n)  # {0} | {5, 6} | {9}
    loss = {idx: est for est, _, idx in out}
    from rle_tasks.f09_gello.battery import ACCEL_REF

    assert loss[(1, 1)] == pytest.approx(_search_loss(4 / n, 0.0, np.full(4, ACCEL_REF * 0.01)))
    assert [idx for _, _, idx in out][:2] == [(0, 0), (1, 0)]  # equal loss: the first candidate first


def test_a_spring_anchored_below_joint_2_balances_what_one_above_does(tmp_path):
    """``exact_design(spring_side=-1)``: anchor below joint 2, attachment opposite link 2's centre of
    mass, the same k a . R b: the same exact balance (a mount the coordinate descent may choose)."""
    above = exact_design("xarm7", {6: (0.08, None, 0.055)})
    below = exact_design("xarm7", {6: (0.08, None, 0.055)}, spring_side=-1)
    assert below.spring[4] == pytest.approx(above.spring[4])
    assert below.spring[1][2] < above.spring[1][2]  # anchor below the shoulder (link 1's z is up)
    assert _worst_residual(apply_design("xarm7", below, tmp_path / "below")).max() < 1e-6


def test_a_flush_rod_starts_on_its_links_surface():
    """``attached.fasten(flush=...)``: a straight rod on a flush link starts ``EMBED`` nearer its weight
    (on the link's surface, not inside it): xarm7's joint-3 rod then stays out of link 4's shell."""
    from rle_tasks.f09_gello.solutions.attached import EMBED, fasten

    exact = exact_design("xarm7", {6: (0.08, None, 0.055), 4: (0.12, -0.055), 3: (0.10, 0.035)})
    (j3,) = [i for i, c in enumerate(exact.counterweights) if c[0] == "link3"]
    inside = fasten("xarm7", exact).counterweights[j3]
    flush = fasten("xarm7", exact, flush=frozenset({"link3"})).counterweights[j3]
    step = np.asarray(flush[3]) - np.asarray(inside[3])
    assert np.linalg.norm(step) == pytest.approx(EMBED)
    # towards the weight's centre
    assert np.linalg.norm(flush[1] - flush[3]) < np.linalg.norm(inside[1] - inside[3])
