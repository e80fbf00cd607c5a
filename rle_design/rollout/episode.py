"""The episode loop shared by every battery, trial and evaluation episode.

``run_episode`` calls the controller every ``control_every`` physics steps and advances the physics
between calls in C (``mujoco.mj_step`` with ``nstep``), stopping only where a term is due. At every
boundary all due terms are evaluated in their given order (so each term sees the same state and
keeps its measurements), then the first ending event, in term order, ends the episode.

Timing: with ``control_every = k`` the controller sees the state at steps 0, k, 2k, ... and its
``data.ctrl`` holds for the next k steps (zero-order hold); a term with ``every = e`` is evaluated
after steps e, 2e, ...; a term whose ``final`` attribute is True is also evaluated after the last
step.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import mujoco

from rle_design.errors import RleError
from rle_design.rollout.terms import Event, Term

__all__ = ["ControlFn", "Episode", "RolloutError", "run_episode"]

ControlFn = Callable[[mujoco.MjModel, mujoco.MjData, float], None]
"""Sets ``data.ctrl`` (and may set ``qfrc_applied`` or options) given the episode time [s]."""


class RolloutError(RleError):
    """An episode configured wrongly (our bug, never a participant fault)."""

    code = "rollout.config"


@dataclass
class Episode:
    """Outcome of one episode.

    Attributes:
        steps: Physics steps taken.
        time: Episode time at the end [s].
        events: Every event reported, in order.
    """

    steps: int = 0
    time: float = 0.0
    events: list[Event] = field(default_factory=list)

    @property
    def end(self) -> Event | None:
        """The event that ended the episode, or None if it ran to its length."""
        for e in self.events:
            if e.ends:
                return e
        return None

    @property
    def success(self) -> bool:
        return self.end is not None and self.end.kind == "success"


def _next_boundary(step: int, periods: Sequence[int], n_steps: int) -> int:
    return min([n_steps] + [(step // p + 1) * p for p in periods])


def run_episode(
    model: mujoco.MjModel,
    data: mujoco.MjData,
    n_steps: int,
    *,
    control: ControlFn | None = None,
    control_every: int = 1,
    terms: Sequence[Term] = (),
    prepare: Callable[[], None] | None = None,
) -> Episode:
    """Run ``n_steps`` physics steps from the current ``data`` (edited in place).

    Args:
        model: Compiled model.
        data: State to start from.
        n_steps: Physics steps of the episode.
        control: Controller, called every ``control_every`` steps.
        control_every: Physics steps per control period (the decimation).
        terms: Terms, evaluated in this order at their boundaries.
        prepare: Called one physics step before each control call after the first (e.g.
            ``Sandbox.wake``: a sandboxed controller then wakes up during that step). The physics is
            the same: ``mj_step`` of n steps is n single steps.

    Raises:
        RolloutError: A period below 1.
    """
    periods = [control_every] + [t.every for t in terms]
    if min(periods) < 1 or any(int(p) != p for p in periods):
        raise RolloutError(f"control and term periods must be positive integers, got {periods}")
    t0 = data.time
    for term in terms:
        term.reset(model, data)
    ep = Episode()
    step = 0
    every_step = min(periods) == 1  # then the next boundary is always the next step
    checks = [(term.every, term.update, bool(getattr(term, "final", False))) for term in terms]
    physics = mujoco.mj_step  # looked up per episode (a profiler may wrap it)
    while step < n_steps:
        if control is not None and step % control_every == 0:
            control(model, data, data.time - t0)
        nxt = step + 1 if every_step else _next_boundary(step, periods, n_steps)
        if prepare is not None and control is not None and nxt < n_steps and nxt % control_every == 0:
            if nxt - step > 1:
                physics(model, data, nxt - step - 1)
            prepare()
            physics(model, data, 1)
        else:
            physics(model, data, nxt - step)
        step = nxt
        t = data.time - t0
        ended = None
        last = step == n_steps
        for every, update, final in checks:
            if step % every == 0 or (last and final):
                event = update(model, data, t)
                if event is not None:
                    ep.events.append(event)
                    if ended is None and event.ends:
                        ended = event
        if ended is not None:
            break
    ep.steps, ep.time = step, data.time - t0
    return ep
