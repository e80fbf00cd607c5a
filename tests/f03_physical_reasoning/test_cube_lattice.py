"""Pocket-cube move model, coordinates and the quarter-turn distance table."""

import itertools

import numpy as np
import pytest

from rle_tasks.f03_physical_reasoning.cube import distance
from rle_tasks.f03_physical_reasoning.cube.coords import (
    GENERATORS,
    N_STATES,
    N_TWIST,
    decode,
    encode,
    move_tables,
    perm_rank,
    perm_unrank,
)
from rle_tasks.f03_physical_reasoning.cube.group import INV, MUL, QUATS, ROTATIONS
from rle_tasks.f03_physical_reasoning.cube.lattice import MOVES, SOLVED, inverse_move

# Published QTM distribution of the 2x2x2 (e.g. Wikipedia "Pocket Cube"): states at distance 0..14.
QTM_COUNTS = [1, 6, 27, 120, 534, 2256, 8969, 33058, 114149, 360508, 930588, 1350852, 782536, 90280, 276]


def test_the_24_rotations_form_a_group():
    assert len(ROTATIONS) == 24 and len({m.tobytes() for m in ROTATIONS}) == 24
    assert all(round(np.linalg.det(m)) == 1 for m in ROTATIONS)
    for a, b in itertools.product(range(24), repeat=2):
        assert np.array_equal(ROTATIONS[MUL[a, b]], ROTATIONS[a] @ ROTATIONS[b])
    assert all(MUL[a, INV[a]] == 0 for a in range(24))
    np.testing.assert_allclose(np.linalg.norm(QUATS, axis=1), 1.0)


def test_solved_facelets_and_the_u_turn_by_hand():
    assert SOLVED.facelets() == "UUUURRRRFFFFDDDDLLLLBBBB"
    # U clockwise seen from above: the front's top row shows the right face's colour, right shows back.
    # Faces U R F D L B, stickers by slot (R: UFR UBR DFR DBR; F: UFR UFL DFR DFL; ...).
    assert SOLVED.apply("U").facelets() == "UUUUBBRRRRFFDDDDFFLLLLBB"


@pytest.mark.parametrize("move", MOVES)
def test_quarter_turns_have_order_four_and_inverses(move):
    assert SOLVED.apply(move).apply(inverse_move(move)) == SOLVED
    assert SOLVED.apply_all([move] * 4) == SOLVED
    assert not SOLVED.apply(move).is_solved()
    assert SOLVED.apply_all([move] * 2) == SOLVED.apply_all([inverse_move(move)] * 2)


def test_opposite_faces_turn_the_same_puzzle_state():
    # Turning D clockwise (from below) equals turning U clockwise (from above) up to a whole-cube turn.
    for a, b in [("U", "D"), ("R", "L"), ("F", "B")]:
        assert SOLVED.apply(a).same_puzzle(SOLVED.apply(b))
        assert not SOLVED.apply(a).same_puzzle(SOLVED.apply(inverse_move(b)))


def test_rotations_of_the_whole_cube_are_solved():
    for r in range(24):
        assert SOLVED.rotated(r).is_solved() and encode(SOLVED.rotated(r)) == 0


def test_perm_rank_is_a_bijection():
    ranks = [perm_rank(list(p)) for p in itertools.permutations(range(7))]
    assert sorted(ranks) == list(range(5040))
    assert all(perm_unrank(perm_rank(list(p))) == list(p) for p in itertools.permutations(range(7)))


def test_move_tables_agree_with_the_geometric_model_and_twist_sum_is_invariant():
    perm_move, twist_move = move_tables()
    rng = np.random.default_rng(0)
    for _ in range(100):
        state = SOLVED.apply_all([MOVES[i] for i in rng.integers(0, 12, 25)]).normalized()
        i = encode(state)
        assert decode(i) == state
        for g, move in enumerate(GENERATORS):
            # encode() ranks 6 twists and implies the 7th from a zero sum mod 3; if a turn changed the
            # sum, the decoded state would differ from the geometric one.
            assert (
                encode(state.apply(move)) == perm_move[i // N_TWIST, g] * N_TWIST + twist_move[i % N_TWIST, g]
            )
            assert decode(encode(state.apply(move))) == state.apply(move).normalized()


def test_reduced_breadth_first_search_matches_published_counts():
    table = distance.build_table(max_depth=6)
    assert distance.depth_counts(table) == QTM_COUNTS[:7]


def test_reduced_table_agrees_with_brute_force_over_the_geometric_model():
    # Independent check: breadth-first over LatticeState with all 12 quarter turns, to depth 4.
    table = distance.build_table(max_depth=4)
    seen = {SOLVED.normalized(): 0}
    frontier = [SOLVED]
    for depth in range(1, 5):
        nxt = []
        for s in frontier:
            for m in MOVES:
                t = s.apply(m).normalized()
                if t not in seen:
                    seen[t] = depth
                    nxt.append(t)
        frontier = nxt
    assert len(seen) == sum(QTM_COUNTS[:5])
    assert all(table[encode(s)] == d for s, d in seen.items())


def test_full_table_gods_number_14_and_276_antipodes(tmp_path, monkeypatch):
    monkeypatch.setenv("RLE_CACHE_DIR", str(tmp_path))
    distance.distance_table.cache_clear()
    table = distance.distance_table()  # built (1-3 s), checked against the pinned sha256, cached
    assert table.shape == (N_STATES,) and N_STATES == 3_674_160
    assert distance.depth_counts(table) == QTM_COUNTS
    assert int(table.max()) == 14 and int((table == 14).sum()) == 276
    assert distance.table_path().is_file() and str(tmp_path) in str(distance.table_path())
    assert distance.optimal_turns(SOLVED.apply_all(["R", "U"])) == 2
    assert distance.optimal_turns(SOLVED.apply_all(["R", "U", "U'", "R'"])) == 0
    assert distance.optimal_turns(SOLVED.apply_all(["D", "U'"])) == 0  # the same puzzle as a whole-cube turn
    assert distance.optimal_turns(SOLVED.apply_all(["R", "R"])) == 2

    # Altered, truncated or junk cache files are refused by the checksum; the last one is rebuilt.
    good = distance.table_path().read_bytes()
    for junk in (good[:-10] + b"0123456789", good[:1000], b"not a table"):
        distance.table_path().write_bytes(junk)
        assert distance._load(distance.table_path()) is None
    distance.distance_table.cache_clear()
    assert distance._digest(distance.distance_table()) == distance.TABLE_SHA256
    assert distance.table_path().read_bytes() == good
    distance.distance_table.cache_clear()
