"""The physical pocket cube: model facts, detent closed forms, scripted quarter turns on the lattice."""

import itertools
import math

import mujoco
import numpy as np
import pytest

from rle_design.errors import MissingElement
from rle_tasks.f03_physical_reasoning.cube.detent import SLOT_PAIRS, CubeDetent
from rle_tasks.f03_physical_reasoning.cube.group import QUATS, ROTATIONS
from rle_tasks.f03_physical_reasoning.cube.lattice import CUBIES, MOVES, SOLVED
from rle_tasks.f03_physical_reasoning.cube.model import CubeConfig, cube_spec
from rle_tasks.f03_physical_reasoning.cube.reading import check_solved, poses_from_data, read
from rle_tasks.f03_physical_reasoning.cube.scripted import scripted_turn, step
from rle_tasks.f03_physical_reasoning.cube.turns import transitions

ON_LATTICE = math.radians(2.0)  # the bound for a settled cube


def _bench(**kw):
    """The cube alone, its core fixed 0.2 m above the origin, under gravity."""
    model = cube_spec(CubeConfig(free=False, pos=(0.0, 0.0, 0.2), **kw), floor=False).compile()
    data = mujoco.MjData(model)
    detent = CubeDetent(model)
    step(model, data, detent, 100)
    return model, data, detent


def test_model_facts():
    cfg = CubeConfig()
    model = cube_spec(cfg).compile()
    # 8 x 7.5 g cubies + 4 g core = 64 g; edge 64 mm; 24 coloured stickers that never collide.
    assert sum(model.body_mass) == pytest.approx(0.064)
    assert 2 * (cfg.cubie_half + cfg.gap / 2) * 2 == pytest.approx(cfg.edge)
    stickers = [
        g for g in range(model.ngeom) if model.geom(g).name[-2:] in ("_U", "_R", "_F", "_D", "_L", "_B")
    ]
    assert len(stickers) == 24
    assert all(model.geom_contype[g] == 0 and model.geom_conaffinity[g] == 0 for g in stickers)
    assert len(SLOT_PAIRS) == 12
    with pytest.raises(Exception, match="gap"):
        CubeConfig(gap=0.02).validate()


@pytest.mark.parametrize("scramble", [(), ("R", "U", "F'", "R", "R", "U'", "F")])
def test_detent_closed_form_and_zero_net_torque(scramble):
    model = cube_spec(CubeConfig(free=False), floor=False).compile()
    data = mujoco.MjData(model)
    det = CubeDetent(model)
    k, K = det.stiffness, det.tilt_stiffness
    state = SOLVED.apply_all(list(scramble))  # R, U, F keep DBL home: core frame = cube frame
    adr = [
        model.jnt_qposadr[mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, "cube_" + c + "_ball")]
        for c in CUBIES
    ]
    theta = 0.03
    for c, axis in itertools.product(range(8), np.eye(3)):
        for n in range(8):
            data.qpos[adr[n] : adr[n] + 4] = QUATS[state.orient[n]]
        tilt = np.array([math.cos(theta / 2), *(math.sin(theta / 2) * axis)])
        mujoco.mju_mulQuat(data.qpos[adr[c] : adr[c] + 4], tilt, QUATS[state.orient[c]].copy())
        mujoco.mj_kinematics(model, data)
        tau = det.torques(data.xmat[det.bodies].reshape(8, 3, 3), data.qvel[det._dofs])
        # Every cubie has three neighbours; rotating it about a core axis strains the neighbour
        # across that axis along its turn (soft k) and the other two as a tilt (stiff K):
        # tau = -(k + 2K) sin(theta) axis, expressed in the cubie's own frame (R^T axis).
        local = ROTATIONS[state.orient[c]].T @ axis
        np.testing.assert_allclose(tau[c], -(k + 2 * K) * math.sin(theta) * local, atol=1e-12)
        # Internal couples: the torques on all cubies, in the world (= core) frame, sum to zero.
        world = sum(data.xmat[b].reshape(3, 3) @ tau[i] for i, b in enumerate(det.bodies))
        np.testing.assert_allclose(world, 0.0, atol=1e-12)


@pytest.mark.parametrize("face", ["U", "R", "F", "D", "L", "B"])
def test_scripted_torque_turns_each_face_a_quarter_turn_back_onto_the_lattice(face):
    model, data, det = _bench()
    for move in (face, face + "'"):
        result = scripted_turn(model, data, det, move)
        assert result.push_steps < 200, "the layer was blocked"
        assert result.reading.misalignment < ON_LATTICE, math.degrees(result.reading.misalignment)
    assert result.reading.state == SOLVED  # X then X' is back to solved
    assert not any(w.number for w in data.warning)


def test_scripted_sequence_gives_the_move_models_state_and_its_transitions():
    model, data, det = _bench()
    moves = ["R", "U'", "F", "D", "L'", "B", "U", "R'"]
    record = []
    for move in moves:
        result = scripted_turn(model, data, det, move, record=record)
        assert result.reading.misalignment < ON_LATTICE
    # Faces are named in the cube's own (DBL cubie's) frame, which turns with D, L and B moves.
    expect = SOLVED
    for move in moves:
        expect = expect.apply(move).normalized()
    assert read(poses_from_data(model, data)).state == expect
    expected = [{"D": "U", "L": "R", "B": "F"}.get(m[0], m[0]) + m[1:] for m in moves]
    assert [t.move for t in transitions(record)] == expected


@pytest.mark.physics
def test_random_turns_keep_the_cube_on_the_lattice(full_battery):
    n = 40 if full_battery else 12
    model, data, det = _bench()
    rng = np.random.default_rng(7)
    expect = SOLVED
    worst = 0.0
    for move in (MOVES[i] for i in rng.integers(0, 12, n)):
        result = scripted_turn(model, data, det, move)
        expect = expect.apply(move).normalized()
        worst = max(worst, result.reading.misalignment)
        assert result.reading.state == expect
    assert worst < ON_LATTICE, math.degrees(worst)
    assert not any(w.number for w in data.warning)


def test_free_cube_rests_on_the_floor_without_warnings_and_stays_solved():
    model = cube_spec(CubeConfig(pos=(0.0, 0.0, 0.04))).compile()
    data = mujoco.MjData(model)
    det = CubeDetent(model)
    step(model, data, det, 500)  # 1 s
    assert not any(w.number for w in data.warning)
    poses = poses_from_data(model, data)
    assert read(poses).state == SOLVED and read(poses).misalignment < ON_LATTICE
    # Resting on the table is not a solve: the predicate wants it held above.
    check = check_solved(poses, 0.0)
    assert not check.solved and "not held above the table" in check.reason


def _push_one_cubie(model, data, det, cubie, axis, torque, steps):
    """Torque on a single cubie (world axis) for ``steps`` steps or until the cube reads within 25 deg of
    a new lattice state (every cubie well past halfway), then 250 steps to settle; every step's reading."""
    body = det.bodies[CUBIES.index(cubie)]
    record = []
    pushing = True
    for n in range(steps + 250):
        moved = record and record[-1].state != record[0].state and record[-1].misalignment < math.radians(25)
        pushing = pushing and n < steps and not moved
        data.xfrc_applied[body, 3:] = torque * np.asarray(axis, float) if pushing else 0.0
        step(model, data, det)
        mujoco.mj_kinematics(model, data)
        record.append(read(poses_from_data(model, data)))
    return record


def test_pushing_one_cubie_turns_its_whole_layer():
    # A real cube's layer moves as a whole: a torque on one corner about the U axis carries the three
    # other U cubies along (contacts within the layer), and the detent finishes the quarter turn. The
    # torque, 30 mN m, exceeds the layer's peak detent 4 k sin(45 deg) = 11 mN m plus what the
    # in-layer contacts lose to tilting the pushed corner.
    model, data, det = _bench()
    record = _push_one_cubie(model, data, det, "UFR", [0, 0, -1], 0.03, 200)
    final = record[-1]
    assert final.state == SOLVED.apply("U") and final.misalignment < ON_LATTICE
    assert [t.move for t in transitions(record)] == ["U"]


def test_a_tilting_torque_on_one_cubie_moves_nothing():
    # About the corner's diagonal the U, R and F layers would all have to turn at once and jam each
    # other: the cube yields (the soft turn detents of three layers) and springs back when released.
    model, data, det = _bench()
    diag = np.array([1.0, -1.0, 1.0]) / math.sqrt(3)
    record = _push_one_cubie(model, data, det, "UFR", diag, 0.02, 100)
    assert max(r.misalignment for r in record) < math.radians(45)
    assert all(r.state == SOLVED for r in record)
    assert record[-1].misalignment < ON_LATTICE and record[-1].misalignment < ON_LATTICE
    assert transitions(record) == []


def test_free_floating_cube_turns_by_internal_couples_alone():
    # Zero gravity, free core: the couples (scripted pair of hands and detent) are internal, so the
    # cube's centre stays put (momentum conserved) while its layers turn exactly as the move model says.
    spec = cube_spec(CubeConfig(pos=(0.0, 0.0, 0.5)), floor=False)
    spec.option.gravity = [0.0, 0.0, 0.0]
    model = spec.compile()
    data = mujoco.MjData(model)
    det = CubeDetent(model)
    expect = SOLVED
    for move in ["R", "U'", "F", "D", "L'", "B"]:
        result = scripted_turn(model, data, det, move)
        expect = expect.apply(move).normalized()
        assert result.reading.state == expect and result.reading.misalignment < ON_LATTICE
    mujoco.mj_kinematics(model, data)
    centre = data.xpos[det.bodies].mean(axis=0)
    np.testing.assert_allclose(centre, [0.0, 0.0, 0.5], atol=1e-3)


def test_errors_name_the_element_and_the_alternatives():
    model = cube_spec(CubeConfig(name="cube")).compile()
    with pytest.raises(MissingElement, match="cubex_detent") as err:
        CubeDetent(model, name="cubex")
    assert "cube_detent" in str(err.value)
    data = mujoco.MjData(model)
    with pytest.raises(ValueError, match="unknown move 'M'"):
        scripted_turn(model, data, CubeDetent(model), "M")
