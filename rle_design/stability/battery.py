"""Stability battery runner: executes scenarios in MuJoCo and records stability signals over time.

A scenario sets controls through a callback and may impose a base acceleration a(t) as an equivalent
gravity g - a(t) (d'Alembert): in the frame of a base accelerating at a, every body feels the extra
body force -m a at its centre of mass while the reactions, drive and braking forces act at the wheel
contacts, so tip-over comes from the contact forces exactly as on an accelerating vehicle.

Recorded every ``sample_every`` steps: normal force per support, centre of pressure, COM, static
margin of the COM projected along the effective gravity, root tilt. A tip is declared when the root
tilt exceeds ``tip_tilt`` (1 deg by default): with elliptic cones and no-slip iterations this locates
the rigid-body tipping point within 2 % (notes/mobile-base.md), whereas wheel-load readings near
tipping are noisy.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import mujoco
import numpy as np

from rle_design.rollout import Event, SimulationWarnings, Term, root_tilt, run_episode
from rle_design.stability.contacts import SupportSet, sample_contacts
from rle_design.stability.support_loss import SupportLossMonitor
from rle_design.stability.support_polygon import StabilityError, support_polygon

__all__ = ["Scenario", "ScenarioResult", "StabilityProbe", "run_battery", "run_scenario", "tip_acceleration"]

ControlFn = Callable[[mujoco.MjModel, mujoco.MjData, float], None]
AccelFn = Callable[[float], np.ndarray]


@dataclass(frozen=True)
class Scenario:
    """One test of a battery.

    Attributes:
        name: Identifier used in reports.
        duration: Simulated time [s].
        control: Sets ``data.ctrl`` (and may set ``qfrc_applied``) at every step, given time [s].
        accel: Imposed base acceleration a(t) in world coordinates [m/s^2] (equivalent gravity).
        ignore_before: Samples before this time are excluded from the statistics (settling) [s].
        stop_on_tip: End the run at the first tip.
    """

    name: str
    duration: float
    control: ControlFn | None = None
    accel: AccelFn | None = None
    ignore_before: float = 0.0
    stop_on_tip: bool = True


@dataclass(frozen=True)
class StabilityProbe:
    """What to watch on a machine.

    Attributes:
        root_body: Body id of the floating root (its z axis defines the tilt).
        supports: Support geoms and ground.
        loss_fraction: Loss-of-support threshold as a fraction of the static share m g / n [1].
        loss_duration: Time below the threshold that counts as sustained loss [s].
        tip_tilt: Root tilt that counts as tipping [rad].
        sample_every: Steps between samples.
        smooth: Normal forces are averaged over this many samples before they are recorded and
            monitored (soft contacts of a statically indeterminate 4-wheel support chatter at the
            0.1 mm scale; the average keeps the load, not the chatter).
    """

    root_body: int
    supports: SupportSet
    loss_fraction: float = 0.05
    loss_duration: float = 0.1
    tip_tilt: float = math.radians(1.0)
    sample_every: int = 5
    smooth: int = 10


@dataclass
class ScenarioResult:
    """Signals and summary of one scenario run.

    Attributes:
        name: Scenario name.
        t: Sample times [s].
        normal: (T, k) normal force per support, averaged over ``probe.smooth`` samples [N].
        cop: (T, 2) centre of pressure [m].
        com: (T, 3) centre of mass [m].
        samples: Per sample, the contact points, normals, COM and effective gravity behind
            ``margin``: (T,) static margin along the effective gravity [m] (NaN with < 3 loaded
            supports), computed on first use.
        tilt: (T,) root tilt [rad].
        accel: (T, 3) imposed acceleration [m/s^2].
        tip_time: Time of the first tip, or None [s].
        longest_loss: Longest continuous loss of support of any support [s].
        lost_support: Whether a loss exceeded the loss duration.
        weight: Weight of the machine [N].
        warning: The MuJoCo warning that ended the scenario (``SimulationWarnings``' message), or
            None. A scenario with a warning never passes: its signals stop where the simulation
            stopped being trustworthy.
    """

    name: str
    t: np.ndarray
    normal: np.ndarray
    cop: np.ndarray
    com: np.ndarray
    samples: list
    tilt: np.ndarray
    accel: np.ndarray
    tip_time: float | None
    longest_loss: float
    lost_support: bool
    weight: float = 0.0
    warning: str | None = None
    extra: dict = field(default_factory=dict)

    @functools.cached_property
    def margin(self) -> np.ndarray:
        return np.array([_margin(*row) for row in self.samples], dtype=float)

    @property
    def tipped(self) -> bool:
        return self.tip_time is not None

    @property
    def min_normal(self) -> float:
        """Smallest normal force of any support over the counted samples [N]."""
        return float(np.min(self.normal)) if self.normal.size else float("nan")

    @property
    def peak_tilt_deg(self) -> float:
        return float(np.degrees(np.max(self.tilt))) if self.tilt.size else 0.0

    @property
    def min_margin(self) -> float:
        m = self.margin[np.isfinite(self.margin)]
        return float(m.min()) if m.size else float("nan")

    def tip_accel(self) -> np.ndarray | None:
        """Imposed acceleration at the first tip [m/s^2], or None."""
        if self.tip_time is None:
            return None
        i = int(np.searchsorted(self.t, self.tip_time))
        return self.accel[min(i, len(self.accel) - 1)]

    def summary(self) -> dict:
        return {
            "min_normal_N": self.min_normal,
            "min_normal_frac": self.min_normal / (self.weight / max(1, self.normal.shape[1]))
            if self.weight
            else None,
            "longest_loss_s": self.longest_loss,
            "lost_support": self.lost_support,
            "peak_tilt_deg": self.peak_tilt_deg,
            "min_margin_m": self.min_margin,
            "tipped": self.tipped,
        }


def _margin(points: np.ndarray, normal: np.ndarray, com: np.ndarray, g_eff: np.ndarray) -> float:
    loaded = normal > 1e-6
    if loaded.sum() < 3 or g_eff[2] >= 0:
        return float("nan")
    ground_z = float(np.mean(points[loaded, 2]))
    s = (com[2] - ground_z) / -g_eff[2]
    proj = com[:2] + s * g_eff[:2]
    try:
        poly = support_polygon(points[loaded])
    except StabilityError:
        return float("nan")
    return float(np.min(poly.edge_distances(proj)))


class _Recorder(Term):
    """Samples the stability signals of a scenario (every ``probe.sample_every`` steps).

    The root tilt is checked at every sample; samples before ``ignore_before`` only check the tilt;
    the others record the smoothed support loads, the centre of pressure, the COM and the margin,
    and, with ``stop_on_tip``, end the scenario once a tip has been seen.
    """

    name = "stability"

    def __init__(self, scenario: Scenario, probe: StabilityProbe, weight: float, g0: np.ndarray) -> None:
        self.scenario, self.probe, self.g0 = scenario, probe, g0
        self.every = probe.sample_every
        self.monitor = SupportLossMonitor(
            weight, len(probe.supports.names), probe.loss_fraction, probe.loss_duration
        )
        self.rows: dict[str, list] = {
            key: [] for key in ("t", "normal", "cop", "com", "margin", "tilt", "accel")
        }
        self.tip_time: float | None = None
        self.window: list[np.ndarray] = []
        self.a = np.zeros(3)

    def update(self, model: mujoco.MjModel, data: mujoco.MjData, t: float) -> Event | None:
        probe, rows = self.probe, self.rows
        tilt = root_tilt(data, probe.root_body)
        if self.tip_time is None and tilt > probe.tip_tilt:
            self.tip_time = t
        if t < self.scenario.ignore_before:
            return None
        s = sample_contacts(model, data, probe.supports)
        com = data.subtree_com[probe.root_body].copy()
        self.window.append(s.normal)
        if len(self.window) > max(1, probe.smooth):
            self.window.pop(0)
        normal = np.mean(self.window, axis=0)
        self.monitor.update(t, normal)
        rows["t"].append(t)
        rows["normal"].append(normal)
        rows["cop"].append(s.cop)
        rows["com"].append(com)
        rows["margin"].append((s.points, s.normal, com, self.g0 - self.a))
        rows["tilt"].append(tilt)
        rows["accel"].append(self.a.copy())
        if self.tip_time is not None and self.scenario.stop_on_tip:
            return Event(self.name, "fail", f"tipped at t = {self.tip_time:.3f} s", t)
        return None


def run_scenario(
    model: mujoco.MjModel, data: mujoco.MjData, scenario: Scenario, probe: StabilityProbe
) -> ScenarioResult:
    """Run ``scenario`` from the current ``data`` state (edited in place); gravity is restored after."""
    g0 = model.opt.gravity.copy()
    mass = float(model.body_subtreemass[probe.root_body])
    weight = mass * float(np.linalg.norm(g0))
    k = len(probe.supports.names)
    rec = _Recorder(scenario, probe, weight, g0)
    t0 = data.time

    def control(m: mujoco.MjModel, d: mujoco.MjData, t: float) -> None:
        if scenario.accel is not None:
            rec.a = np.asarray(scenario.accel(d.time - t0), dtype=float)
            m.opt.gravity[:] = g0 - rec.a
        if scenario.control is not None:
            scenario.control(m, d, d.time - t0)

    warn = SimulationWarnings(every=probe.sample_every)
    try:
        ep = run_episode(
            model,
            data,
            int(round(scenario.duration / model.opt.timestep)),
            control=control,
            terms=[warn, rec],
        )
    finally:
        model.opt.gravity[:] = g0
    warning = next((e.message for e in ep.events if e.term == warn.name), None)
    arr = {key: np.array(v, dtype=float) for key, v in rec.rows.items() if key != "margin"}
    if arr["normal"].size == 0:
        arr["normal"] = np.zeros((0, k))
    return ScenarioResult(
        scenario.name,
        arr["t"],
        arr["normal"],
        arr["cop"],
        arr["com"],
        rec.rows["margin"],
        arr["tilt"],
        arr["accel"],
        rec.tip_time,
        rec.monitor.longest_loss,
        rec.monitor.lost,
        weight,
        warning,
    )


def run_battery(
    model: mujoco.MjModel,
    reset: Callable[[mujoco.MjData], None],
    scenarios: Sequence[Scenario],
    probe: StabilityProbe,
) -> list[ScenarioResult]:
    """Run each scenario from a fresh state prepared by ``reset(data)``."""
    results = []
    for sc in scenarios:
        data = mujoco.MjData(model)
        reset(data)
        mujoco.mj_forward(model, data)
        results.append(run_scenario(model, data, sc, probe))
    return results


def _tips(model, reset, probe, u, a, onset, hold, control) -> bool:
    def accel(t: float) -> np.ndarray:
        return u * a * min(1.0, t / onset)

    sc = Scenario("tip_hold", onset + hold, control=control, accel=accel)
    (res,) = run_battery(model, reset, [sc], probe)
    return res.tipped


def tip_acceleration(
    model: mujoco.MjModel,
    reset: Callable[[mujoco.MjData], None],
    probe: StabilityProbe,
    direction: np.ndarray,
    rate: float = 2.0,
    a_max: float = 30.0,
    control: ControlFn | None = None,
    iterations: int = 7,
    onset: float = 0.3,
    hold: float = 0.6,
) -> float | None:
    """Smallest sustained base acceleration along ``direction`` that tips the machine [m/s^2].

    A ramp at ``rate`` [m/s^3] brackets the tipping acceleration (the first root tilt above
    ``probe.tip_tilt``, which overshoots by the ramp lag); ``iterations`` bisection steps then hold
    constant accelerations (reached over ``onset`` s, held ``hold`` s) inside the bracket. With
    ``iterations=0`` the ramp value is returned.

    Returns:
        The tipping acceleration, or None if ``a_max`` is reached without tipping.
    """
    u = np.asarray(direction, dtype=float)
    u = u / np.linalg.norm(u)

    def ramp(t: float) -> np.ndarray:
        return u * t * rate

    sc = Scenario("tip_ramp", a_max / rate, control=control, accel=ramp)
    (res,) = run_battery(model, reset, [sc], probe)
    a_tip = res.tip_accel()
    if a_tip is None:
        return None
    hi = float(np.dot(a_tip, u))
    lo = 0.6 * hi
    for _ in range(iterations):
        mid = 0.5 * (lo + hi)
        if _tips(model, reset, probe, u, mid, onset, hold, control):
            hi = mid
        else:
            lo = mid
    return hi if iterations == 0 else 0.5 * (lo + hi)
