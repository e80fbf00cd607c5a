"""Parameters of the whole-body QP expert (``expert_tracker.Expert``): its default task weights and gains,
and its capture steps.

``DEFAULT_GAINS`` are the QP's weights and gains for the G1 (COM, torso and pelvis orientation, wrist
positions; ``rle_design.control.wbc_tasks``), ``with_arm_lead`` turns them into gains that track the arms
a few frames ahead, and ``StepParams`` (default ``STEPPING``) sets when and how far the expert takes a
step the clip does not have after a push.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

from rle_design.control.wbc_tasks import FrameTask, WbcGains

from ..public.g1_constants import G1

__all__ = ["DEFAULT_GAINS", "STEPPING", "StepParams", "with_arm_lead"]

HANDS = ("left_wrist_yaw_link", "right_wrist_yaw_link")
DEFAULT_GAINS = WbcGains(
    contact_kd=20.0,  # the action jerk J on the nominal dance: 0.028 at 10, 0.022 at 20, 0.061 at 40
    frames=(
        FrameTask(G1.anchor_body, pos=0.0, ori=5.0, kp=100.0, kd=20.0),
        FrameTask("pelvis", pos=0.0, ori=2.0, kp=100.0, kd=20.0),
        FrameTask(HANDS[0], pos=1.0, kp=100.0, kd=20.0),
        FrameTask(HANDS[1], pos=1.0, kp=100.0, kd=20.0),
    ),
)


@dataclass(frozen=True)
class StepParams:
    """Capture steps of ``Expert`` (see ``Expert._capture_step``)."""

    margin: float = 0.01
    """The capture point this far outside the soles' hull triggers a step [m]."""
    error: float = 0.04
    """... and this far from the reference's capture point [m]."""
    duration: float = 0.2
    """Swing time [s] (0.26 on the dance's seeds 201 and 204: 0.28 and 0.24 survival instead of 0.65 and 0.24)."""
    height: float = 0.06
    """Swing apex [m]."""
    reach: tuple[float, float] = (0.3, 0.3)
    """Largest step along the stance foot's heading [m] (back, forward)."""
    width: tuple[float, float] = (0.14, 0.4)
    """Lateral distance of the swing sole's centre from the stance sole's [m]."""
    com_scale: float = 0.1
    """COM weight factor during the step."""
    cooldown: int = 5
    """Policy steps after a touchdown before another capture step [1]."""
    adjust: float = 0.0
    """Largest displacement of the clip's own swing foothold by the capture-point error [m] (0: off;
    0.2 on the dance's seeds 200-207: mean score 0.422 against 0.483 without)."""
    max_lean: float = 0.3
    """No step when the COM is further than this from the stance sole's centre (xy) [m]."""


STEPPING = StepParams()


def with_arm_lead(gains: WbcGains, lead: int) -> WbcGains:
    """``gains`` with the arms' posture and the wrists' positions tracked ``lead`` frames ahead (the
    fight's punches saturate the shoulders; with one or two steps of latency the wrist lags past the
    termination bound)."""
    arms = tuple(i for i, j in enumerate(G1.joints) if any(k in j for k in ("shoulder", "elbow", "wrist")))
    frames = tuple(dataclasses.replace(t, lead=lead) if t.body in HANDS else t for t in gains.frames)
    return dataclasses.replace(gains, frames=frames, posture_lead=lead, lead_joints=arms)
