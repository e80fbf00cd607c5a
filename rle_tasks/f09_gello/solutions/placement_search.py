"""Build-time: the placement search of the reference leaders (``clear_fastened``, run by ``build``):
greedy placements joint by joint, a joint search where they leave the arm colliding, then the chosen
design fastened (``attached``) and re-balanced (``rebalance``)."""

from __future__ import annotations

from pathlib import Path

import mujoco
import numpy as np

from rle_tasks.f09_gello.device import ASSET_DIR
from rle_tasks.f09_gello.solutions.attached import (
    BRACKETS,
    SPRING_DESCENT,
    SPRING_OPTIONS,
    Fastened,
    fasten,
    write_leader,
)
from rle_tasks.f09_gello.solutions.joint_search import (
    DESCENT_INSIDE,
    DESCENT_SHORTLIST,
    INSIDE_LOSS,
    SEARCH_ABOVE,
    SEARCH_FINALISTS,
    SEARCH_POSES,
    SEARCH_ROUNDS,
    SEARCH_SHORTLIST,
    best_combinations,
)
from rle_tasks.f09_gello.solutions.part_checks import part_collisions, structure_faults
from rle_tasks.f09_gello.solutions.placement_loss import _loss, _search_loss
from rle_tasks.f09_gello.solutions.rebalance import BOX, optimise


def clear_fastened(
    robot: str,
    n_poses: int = 256,
    passes: int = 2,
    shortlist: int = 24,
    n_fine: int = 1024,
    verbose: bool = False,
    search: bool = True,
    start: tuple[dict, dict] | None = None,
    descent: int = 0,
    box: float = BOX,
    flush: frozenset[str] = frozenset(),
) -> Fastened:
    """The fastened, re-balanced reference of ``robot``, with placements chosen for clearance.

    Clearance is what the verifier counts (``clearance.collision_fraction``): MuJoCo's contacts of
    added parts with the arm, the base or the table, spring paths through parts, and added parts
    inside the next link across a joint (the exact test of ``rle_design.mjcf.interpenetration``,
    which MuJoCo's contact filter skips), on public-grid poses.

    1. Spring mount (``SPRING_OPTIONS``): the one whose posts, alone on the arm, clear the most
       poses (ties: the first listed); chosen again before each pass and at the end, since the
       attachment follows link 2's centre of mass and so the counterweights.
    2. Greedy passes from the tip (joint n down to 3): each joint's placement (``design.PLACEMENTS``)
       and mount (shell or servo housing; straight rod or an L-bracket, ``BRACKETS``) is chosen
       with the others fixed: every candidate is ranked by ``_loss`` with the clearance of the
       parts on the joints already placed and the candidate's own on every fourth of ``n_poses``
       poses, then the best ``shortlist`` again on ``n_fine`` poses (the first ``n_poses`` of them
       those above; 1024 estimate a 1 % collision rate to +-0.3 %, so the choice holds on the hidden
       grid) (ties: lighter device). Devices over ``design.MASS_CAP`` or with a workshop finding
       (``structure_faults``; one of the spring's posts only: the next spring mount is tried) lose.
       Joints whose subtree's centre of mass lies on their axis (no counterweight) are skipped.
    2b. Joint search (``search``): where the first pass leaves collisions at more than
       ``SEARCH_ABOVE`` of the fine grid or a part inside the next link, every joint's candidates
       are recorded with the others as they stand (``part_collisions``: the poses its parts fail on
       ``SEARCH_POSES`` poses; the added inertia, mass and unbalanced moment), the combinations of
       the best ``SEARCH_SHORTLIST`` per joint estimated exhaustively (``best_combinations``:
       collisions the union, clearance at its full slope, ``_search_loss``), and the best
       ``SEARCH_FINALISTS`` scored as whole designs on the fine grid (``INSIDE_LOSS`` more per pose
       with a part inside the next link). The best replaces the greedy's later passes if it beats
       the first pass's design; otherwise they run as before. (The greedy alone cannot get there:
       beyond the 5 % fail value each joint's collisions are hidden by the others', so ur5e's
       weights moved out to r = 0.15 m, 12.8 % of the hidden poses.)
    2c. Coordinate descent (``descent`` rounds, xarm7 only: ``build.BUILD_OPTIONS``): each joint's
       placement and mount, then the spring mount (``SPRING_OPTIONS`` and ``SPRING_DESCENT``), re-chosen
       with the others fixed on the whole design, by ``_search_loss`` plus ``DESCENT_INSIDE`` per
       fraction of poses with a part inside the next link; candidates are ranked on a quarter of the
       coarse poses plus every fine pose the design then fails (a per-pose penalty), the best
       ``DESCENT_SHORTLIST`` scored on the fine grid; no candidate may leave more gravity moment
       to the servos.
    3. The chosen design is re-balanced by ``optimise`` (centres within ``box`` of the placement), the
       straight rods on the links in ``flush`` starting on their link's surface (``fasten``).
    """
    import tempfile

    from rle_design.mjcf.loader import load_design
    from rle_tasks.f09_gello.battery import ACCEL_REF, added_inertia
    from rle_tasks.f09_gello.buildable import SPRING_CUT_MAX, spring_cut_poses
    from rle_tasks.f09_gello.clearance import collision_fraction
    from rle_tasks.f09_gello.device import stock_names
    from rle_tasks.f09_gello.public.gello_helpers import workspace_grid
    from rle_tasks.f09_gello.solutions.design import MASS_CAP, PLACEMENTS, exact_design

    m = mujoco.MjModel.from_xml_path(str(ASSET_DIR / robot / "lead.xml"))
    stock_leader = m
    fine = workspace_grid(m.jnt_range, max(n_fine, n_poses))
    grid = fine[:n_poses]  # the same stream: the first rows of a larger draw
    placement: dict[int, tuple[float, float] | None] = {}
    mount: dict[str, tuple[bool, tuple[float, float] | None]] = {}  # link -> (on the servo, L-bracket)
    stock = set(stock_names(robot)[0])
    spring = SPRING_OPTIONS[0]
    spring_order = list(SPRING_OPTIONS)

    def fastened(pl, mounts, sp=None, flush_links=frozenset()) -> Fastened:
        za, zb, drop, *side = sp or spring  # (a fourth number: ``exact_design``'s spring side)
        servo = frozenset(link for link, (on_servo, _) in mounts.items() if on_servo)
        bracket = {link: post for link, (_, post) in mounts.items() if post is not None}
        return fasten(robot, exact_design(robot, pl, (za, zb), *side), servo, bracket, drop, flush_links)

    def link_of(lm, b: int) -> str:
        while (name := mujoco.mj_id2name(lm, mujoco.mjtObj.mjOBJ_BODY, b)) not in stock:
            b = int(lm.body_parentid[b])
        return name

    def cost(pl, mounts, poses: np.ndarray, detail: bool = False, mount_of_spring=None) -> tuple[float, ...]:
        # ``detail`` (the joint search): every part counted, clearance at its full slope (``_search_loss``),
        # and the collision fraction and the count of poses with a part inside the next link returned
        with tempfile.TemporaryDirectory() as tmp:
            # the best-clearing spring mount whose posts this placement can carry (the attachment
            # follows link 2's centre of mass, so a post may end up too short to be seated)
            for sp in spring_order if mount_of_spring is None else [mount_of_spring]:
                path = write_leader(robot, fastened(pl, mounts, sp), Path(tmp) / robot)
                faults = structure_faults(path, stock, grid)
                if not faults or not all("'spring_" in f for f in faults):
                    break
            leader = load_design(path.parent, entry="lead.xml")
            lm = leader.compile()
            added = [
                b
                for b in range(1, lm.nbody)
                if mujoco.mj_id2name(lm, mujoco.mjtObj.mjOBJ_BODY, b) not in stock
            ]
            names = [mujoco.mj_id2name(lm, mujoco.mjtObj.mjOBJ_BODY, b) for b in added]
            # the parts of the joints not yet placed (default placements) are left out
            placed = {f"link{k}" for k in pl} | {"link1", "link2"}
            if not detail:  # (the joint search scores whole designs: a weight its choice adds counts)
                names = [n for n, b in zip(names, added, strict=True) if link_of(lm, b) in placed]
            frac, _, inside = collision_fraction(leader, names, poses)
            mass = float(lm.body_mass[1:].sum())
            # the rods' own moments are re-balanced by ``optimise``; a joint left without a
            # counterweight keeps its subtree's gravity moment, and so does every joint nearer the
            # base, down to the shoulder spring (that subtree's centre of mass moves with the joint)
            worst = sum(exact_design(robot, pl).unbalanced.values())
            cuts = len(spring_cut_poses(lm, poses)) / len(poses)
            refused = mass > MASS_CAP or cuts > 0.8 * SPRING_CUT_MAX  # margin to the structure rule
            refused = refused or bool(faults)
            effort = ACCEL_REF * np.max(added_inertia(lm, stock_leader, grid[:64]), axis=1)
            loss = (_search_loss if detail else _loss)(frac, worst, effort) + (1.0 if refused else 0.0)
            return (loss, mass, frac, len(inside)) if detail else (loss, mass)

    def spring_clearance(sp) -> float:
        design = fastened(placement, mount, sp)
        bare = Fastened((), design.spring, (), design.anchor_elbow)
        with tempfile.TemporaryDirectory() as tmp:
            path = write_leader(robot, bare, Path(tmp) / robot)
            leader = load_design(path.parent, entry="lead.xml")
            frac = collision_fraction(leader, ["spring_anchor_post", "spring_attach_post"], grid)[0]
            return frac + (1.0 if structure_faults(path, stock, grid) else 0.0)

    def choose_spring() -> None:
        nonlocal spring, spring_order
        spring_order = sorted(SPRING_OPTIONS, key=spring_clearance)  # stable: ties keep their order
        spring = spring_order[0]
        if verbose:
            print(f"  {robot} spring {spring}: posts clear of all but {spring_clearance(spring):.3f}")

    kinds = [(on_servo, post) for post in (None, *BRACKETS) for on_servo in (False, True)]

    def record(pl, mounts, poses: np.ndarray, link: str) -> dict:
        # the poses the parts on ``link`` fail (spring posts: ``link`` "spring"), the added inertia,
        # the mass and the link's unbalanced moment of the design ``pl``, ``mounts``; a weight the
        # choice adds on a joint the greedy skipped (its subtree's centre of mass no longer on its
        # axis: ``exact_design``'s default placement) counts as the choice's
        own = {"link1", "link2"} if link == "spring" else {link}
        own |= set() if link == "spring" else {f"link{j}" for j in range(3, m.nv + 1) if j not in pl}
        with tempfile.TemporaryDirectory() as tmp:
            path = write_leader(robot, fastened(pl, mounts), Path(tmp) / robot)
            leader = load_design(path.parent, entry="lead.xml")
            lm = leader.compile()
            names = [
                mujoco.mj_id2name(lm, mujoco.mjtObj.mjOBJ_BODY, b)
                for b in range(1, lm.nbody)
                if mujoco.mj_id2name(lm, mujoco.mjtObj.mjOBJ_BODY, b) not in stock and link_of(lm, b) in own
            ]
            counted, hit = part_collisions(leader, stock, names, poses)
            unb = exact_design(robot, pl).unbalanced.get(int(link[4:]), 0.0) if link != "spring" else 0.0
            return {
                "counted": counted,
                "hit": hit,
                "ai": added_inertia(lm, stock_leader, grid[:64]),
                "mass": float(lm.body_mass[1:].sum()),
                "unb": unb,
            }

    def joint_search() -> bool:
        # every joint's candidates recorded with the others as they stand, their combinations
        # estimated exhaustively over per-joint shortlists, the best few scored exactly on the fine
        # grid (``_search_loss`` plus ``INSIDE_LOSS`` per pose with a part inside the next link,
        # then the lighter device); True when one beats the design as it stands
        nonlocal placement, mount
        found = False
        poses = fine[:SEARCH_POSES]
        joints = sorted(placement, reverse=True)
        options = [(opt, kind) for opt in PLACEMENTS if opt is not None for kind in kinds]
        options.append((None, (False, None)))

        def exact(pl, mo) -> tuple:
            loss, mass, frac, inside = cost(pl, mo, fine, detail=True)
            return (loss + INSIDE_LOSS * inside, mass), frac

        here, frac = exact(placement, mount)
        for _ in range(SEARCH_ROUNDS):
            base = record(placement, mount, poses, "spring")
            counted = base["counted"]
            cands, current = {}, {}
            for k in joints:
                link = f"link{k}"
                rows = []
                for opt, kind in options:
                    r = record({**placement, k: opt}, {**mount, link: kind}, poses, link)
                    r["option"] = (opt, kind)
                    rows.append(r)
                now = options.index((placement[k], mount[link]))
                alone = [
                    _search_loss(
                        float((r["hit"] | base["hit"])[counted].mean()),
                        r["unb"],
                        ACCEL_REF * r["ai"].max(axis=1),
                    )
                    for r in rows
                ]
                order, seen = [], set()
                for i in sorted(range(len(rows)), key=lambda i: (alone[i], rows[i]["mass"])):
                    sig = (round(alone[i], 9), round(rows[i]["mass"], 9))  # a mount that changes nothing
                    if sig not in seen or i == now:
                        seen.add(sig)
                        order.append(i)
                keep = order[:SEARCH_SHORTLIST] + ([now] if now not in order[:SEARCH_SHORTLIST] else [])
                cands[k] = [rows[i] for i in keep]
                current[k] = keep.index(now)
            base["current"] = current
            combos = best_combinations(cands, base, counted, SEARCH_FINALISTS, MASS_CAP)
            best = None
            for est, est_frac, idx in combos:
                pl = {
                    **placement,
                    **{k: cands[k][i]["option"][0] for k, i in zip(sorted(cands), idx, strict=True)},
                }
                mo = {
                    **mount,
                    **{f"link{k}": cands[k][i]["option"][1] for k, i in zip(sorted(cands), idx, strict=True)},
                }
                key, f = exact(pl, mo)
                if verbose:
                    print(
                        f"  {robot} search: {pl} {mo} estimate {est:.4f} ({est_frac:.4f}) -> {key} ({f:.4f})",
                        flush=True,
                    )
                if best is None or key < best[0]:
                    best = (key, f, pl, mo)
            if best is None or not best[0] < here:
                break
            here, frac, placement, mount = best[0], best[1], best[2], best[3]
            found = True
            if verbose:
                print(
                    f"  {robot} joint search: {placement} {mount} -> {here} ({frac:.4f} of the fine grid)",
                    flush=True,
                )
        return found

    def coordinate_descent(rounds: int) -> None:
        # each joint's placement and mount, then the spring mount, re-chosen with the others fixed
        # on the whole design (every part counted, clearance at its full slope, ``DESCENT_INSIDE``
        # per pose with a part inside the next link), the balance kept; rounds until nothing moves
        nonlocal placement, mount, spring

        def key(pl, mo, sp, poses) -> tuple:
            loss, mass, frac, inside = cost(pl, mo, poses, detail=True, mount_of_spring=sp)
            return (loss + DESCENT_INSIDE * inside / len(poses), mass), frac, inside

        def failing(pl, mo, sp) -> np.ndarray:
            # the fine poses the design fails (what the verifier counts, pose by pose)
            with tempfile.TemporaryDirectory() as tmp:
                path = write_leader(robot, fastened(pl, mo, sp), Path(tmp) / robot)
                leader = load_design(path.parent, entry="lead.xml")
                lm = leader.compile()
                names = [mujoco.mj_id2name(lm, mujoco.mjtObj.mjOBJ_BODY, b) for b in range(1, lm.nbody)]
                counted, hit = part_collisions(leader, stock, [b for b in names if b not in stock], fine)
                return np.flatnonzero(counted & hit)

        here, frac, inside = key(placement, mount, spring, fine)
        options = [(opt, kind) for opt in PLACEMENTS if opt is not None for kind in kinds]
        options.append((None, (False, None)))
        springs = list(dict.fromkeys((*SPRING_OPTIONS, *SPRING_DESCENT)))
        if verbose:
            print(f"  {robot} descent from {here} ({frac:.4f} of the fine grid, {inside} inside)", flush=True)
        for _ in range(rounds):
            moved = False
            for k in [*range(m.nv, 2, -1), 0]:
                if k == 0:
                    cands = [(placement, mount, sp) for sp in springs]
                elif any(
                    c[0] == f"link{k}"
                    for c in exact_design(robot, {**placement, k: PLACEMENTS[0]}).counterweights
                ):
                    # the balance is kept: no candidate leaves more gravity moment to the servos
                    held = sum(exact_design(robot, placement).unbalanced.values()) + 1e-9
                    cands = [
                        ({**placement, k: o}, {**mount, f"link{k}": kd}, spring)
                        for o, kd in options
                        if sum(exact_design(robot, {**placement, k: o}).unbalanced.values()) <= held
                    ]
                else:
                    continue  # the subtree's centre of mass is on the axis: nothing to place
                # ranked on a quarter of the coarse poses and every fine pose the design now fails
                # (a per-pose penalty: a candidate is ranked by which of those it clears)
                poses = np.concatenate([grid[::4], fine[failing(placement, mount, spring)]])
                rough = sorted(range(len(cands)), key=lambda i: key(*cands[i], poses)[0])
                for i in rough[:DESCENT_SHORTLIST]:
                    new, f, ins = key(*cands[i], fine)
                    if new < here:
                        here, frac, inside = new, f, ins
                        placement, mount, spring = dict(cands[i][0]), dict(cands[i][1]), cands[i][2]
                        moved = True
                if verbose:
                    print(
                        f"  {robot} descent {'spring' if k == 0 else f'joint {k}'}: {placement} {mount} "
                        f"{spring} -> {here} ({frac:.4f} of the fine grid, {inside} inside)",
                        flush=True,
                    )
            if not moved:
                break

    if start is not None:  # a first pass's placements and mounts (diagnostics): go on from there
        placement, mount = dict(start[0]), dict(start[1])

    for pass_no in range(0 if start is None else 1, passes):
        choose_spring()
        if pass_no > 0 and search:
            _, _, frac, inside = cost(placement, mount, fine, detail=True)
            if frac > SEARCH_ABOVE or inside:
                if verbose:
                    print(
                        f"  {robot}: the greedy leaves {frac:.4f} of the fine grid ({inside} inside): joint search"
                    )
                if joint_search():
                    break
                # nothing better found: the greedy goes on
        for k in range(m.nv, 2, -1):
            link = f"link{k}"
            if not any(
                c[0] == link for c in exact_design(robot, {**placement, k: PLACEMENTS[0]}).counterweights
            ):
                continue  # the subtree's centre of mass is on the axis: nothing to place
            options = [(opt, kind) for opt in PLACEMENTS if opt is not None for kind in kinds]
            options.append((None, (False, None)))

            def score(o, poses, k=k, link=link):
                return cost({**placement, k: o[0]}, {**mount, link: o[1]}, poses)

            rough = sorted(options, key=lambda o: score(o, grid[::4]))
            best = min(rough[:shortlist], key=lambda o: score(o, fine))
            placement[k] = best[0]
            mount[link] = best[1]
            if verbose:
                what = (
                    "no counterweight"
                    if best[0] is None
                    else f"r_c {best[0][0]:.2f} m, axial {best[0][1] if best[0][1] is None else round(best[0][1], 3)} m, "
                    + (f"a pair +-{best[0][2]} m apart, " if len(best[0]) > 2 else "")
                    + f"{'servo' if best[1][0] else 'shell'} mount"
                    + (f", L-bracket at {best[1][1]} m" if best[1][1] else "")
                )
                print(f"  {robot} joint {k}: {what} -> {cost(placement, mount, fine)}", flush=True)
    choose_spring()
    if descent:
        coordinate_descent(descent)
    with tempfile.TemporaryDirectory() as tmp:
        design, worst = optimise(robot, fastened(placement, mount, flush_links=flush), grid, Path(tmp), box)
        if verbose:  # what the verifier will count on the public fine grid, after the re-balance
            path = write_leader(robot, design, Path(tmp) / robot)
            leader = load_design(path.parent, entry="lead.xml")
            lm = leader.compile()
            added = [mujoco.mj_id2name(lm, mujoco.mjtObj.mjOBJ_BODY, b) for b in range(1, lm.nbody)]
            frac, _, inside = collision_fraction(leader, [b for b in added if b not in stock], fine)
            print(
                f"  {robot}: re-balanced with rods and posts, worst residual {worst:.2e} N m on the grid; "
                f"collisions at {frac:.4f} of the fine grid, {len(inside)} with a part inside the next link"
            )
    return design
