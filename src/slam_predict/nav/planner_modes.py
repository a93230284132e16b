"""The modes of the TrajectoryPlanner and the one rule that moves between them.

The planner carries a :class:`PlannerState` from one control cycle to the next. Its mode decides
what the next cycle samples; :func:`next_state` gives the mode after a cycle from the mode before
it and what the cycle commanded (:class:`Observed`). Modes:

- ``NORMAL`` (base_local_planner): forward samples, then in-place rotations, then (with
  ``reverse_when_blocked``) backward arcs, then the escape.
- ``REVERSING`` (extension ``reverse_when_blocked``): as NORMAL; backward arcs are kept up while
  they pay, and in any case until escape_reset_dist m from where reversing began (``anchor``).
- ``REVERSE_BLOCKED`` (same extension): reversing stopped short of escape_reset_dist (no
  backward arc was legal any more, or an in-place turn won). NORMAL without backward arcs — the
  best forward sample is taken even where it scores worse than standing still, as in
  base_local_planner — until the heading has turned escape_reset_theta rad from where reversing
  stopped (``anchor``) or escape mode begins: a robot boxed beside a wall drives on until it can
  turn instead of shuttling.
- ``ESCAPING`` (base_local_planner's ``escaping_``, the blind escape): no forward samples, no
  backward arcs, until escape_reset_dist m / escape_reset_theta rad from the escape pose
  (``anchor``).
- ``KEEPING_MOVE`` (extension ``escape_footprint_margin``): ESCAPING with a body-safe escape
  move (``move``) that the next cycle commands again while the shrunk footprint still rolls it out
  clear and the robot is within the escape reset of ``anchor``; otherwise the cycle runs as
  ESCAPING.

Pure functions only: the planner's rollouts decide what was commanded, this module what follows.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace
from enum import Enum

from slam_predict.geometry import wrap_angle

Pose = tuple[float, float, float]


class Mode(Enum):
    """What the planner does in its next cycle (see the module docstring)."""

    NORMAL = "normal"
    REVERSING = "reversing"
    REVERSE_BLOCKED = "reverse_blocked"
    ESCAPING = "escaping"
    KEEPING_MOVE = "keeping_move"


class Chosen(Enum):
    """What a control cycle commanded."""

    SAMPLE = "sample"            # a legal forward sample or in-place rotation (upstream)
    REVERSE = "reverse"          # a backward arc (reverse_when_blocked)
    BACK_UP = "back_up"          # nothing legal: straight back at escape_vel (upstream escape)
    NO_PATH = "no_path"          # nothing legal, and the straight escape has no path either
    BODY_SAFE = "body_safe"      # nothing legal: the shrunk footprint's escape move
    KEPT_MOVE = "kept_move"      # KEEPING_MOVE: the kept move again


@dataclass(frozen=True)
class PlannerState:
    """The mode and the values it needs: ``anchor`` (x m, y m, θ rad) where REVERSING or
    ESCAPING began or REVERSING stopped (REVERSE_BLOCKED); ``move`` (vx m/s, vθ rad/s) the
    move KEEPING_MOVE commands again."""

    mode: Mode = Mode.NORMAL
    anchor: Pose = (0.0, 0.0, 0.0)
    move: tuple[float, float] | None = None

    @property
    def may_reverse(self) -> bool:
        """May this cycle take a backward arc (``reverse_when_blocked``)?"""
        return not self.escaping and self.mode is not Mode.REVERSE_BLOCKED

    @property
    def escaping(self) -> bool:
        """In base_local_planner's escape mode (no forward samples, no backward arcs)."""
        return self.mode in (Mode.ESCAPING, Mode.KEEPING_MOVE)


@dataclass(frozen=True)
class Observed:
    """What one cycle did: the command kind, the robot pose (x m, y m, θ rad) it was planned
    from, and for BODY_SAFE the move (vx m/s, vθ rad/s)."""

    chosen: Chosen
    pose: Pose
    move: tuple[float, float] | None = None


@dataclass(frozen=True)
class Resets:
    """The distances that end a mode: escape_reset_dist (m), escape_reset_theta (rad)."""

    dist: float
    theta: float


def turned_past_reset(anchor: Pose, pose: Pose, resets: Resets) -> bool:
    """Heading more than resets.theta rad from ``anchor``'s."""
    return abs(wrap_angle(pose[2] - anchor[2])) > resets.theta


def past_escape_reset(anchor: Pose, pose: Pose, resets: Resets) -> bool:
    """Farther than resets.dist m or resets.theta rad from ``anchor`` (escape mode ends)."""
    return (math.hypot(pose[0] - anchor[0], pose[1] - anchor[1]) > resets.dist
            or turned_past_reset(anchor, pose, resets))


def reverse_committed(state: PlannerState, pose: Pose, resets: Resets) -> bool:
    """REVERSING and not yet resets.dist m from where it began: the backward arc is taken even
    where it no longer pays (else the robot shuttled: 2 cm back, 2 cm forward, for minutes — a
    GMapping run of scuola_secondaria_i_grado_mera_ was stopped as stuck)."""
    return (state.mode is Mode.REVERSING
            and math.hypot(pose[0] - state.anchor[0], pose[1] - state.anchor[1]) < resets.dist)


def keeps_move(state: PlannerState, pose: Pose, resets: Resets) -> bool:
    """KEEPING_MOVE and within the escape reset of the escape pose: the kept move is tried
    before sampling (it is commanded if the shrunk footprint still rolls it out clear)."""
    return state.mode is Mode.KEEPING_MOVE and not past_escape_reset(state.anchor, pose, resets)


def next_state(state: PlannerState, seen: Observed, resets: Resets) -> PlannerState:
    """The state after a cycle. Rules, in order:

    1. KEPT_MOVE: unchanged (the move is kept until the escape reset; extension).
    2. REVERSE: REVERSING; the anchor is where reversing began (kept while it goes on;
       extension ``reverse_when_blocked``).
    3. BACK_UP or BODY_SAFE outside escape mode: escape mode begins at this pose (upstream:
       only "when the planner has given a valid goal point", hence not on NO_PATH).
    4. REVERSING that did not reverse this cycle within escape_reset_dist of its anchor:
       REVERSE_BLOCKED at this pose; REVERSE_BLOCKED until the heading is escape_reset_theta
       from its anchor's (extension: the robot shuttled 2–15 cm forward and back between a
       wall behind and a goal behind, for minutes, where its footprint beside a wall could not
       turn: NLB run_000 and office_a run_002 of the fidelity campaign ended stuck).
    5. In escape mode and farther than escape_reset_dist / escape_reset_theta from its anchor
       after any other command: NORMAL (upstream); outside escape mode: NORMAL (a REVERSING
       robot that did not reverse this cycle past escape_reset_dist stops reversing).
    6. Otherwise escape mode goes on: KEEPING_MOVE with the move after BODY_SAFE (extension
       ``escape_footprint_margin``), else ESCAPING (a kept move that is no longer clear or a
       fresh straight escape ends the keeping).
    """
    if seen.chosen is Chosen.KEPT_MOVE:
        return state
    if seen.chosen is Chosen.REVERSE:
        anchor = state.anchor if state.mode is Mode.REVERSING else seen.pose
        return PlannerState(Mode.REVERSING, anchor)
    if seen.chosen in (Chosen.BACK_UP, Chosen.BODY_SAFE) and not state.escaping:
        state = PlannerState(Mode.ESCAPING, seen.pose)
    if reverse_committed(state, seen.pose, resets):
        return PlannerState(Mode.REVERSE_BLOCKED, seen.pose)
    if state.mode is Mode.REVERSE_BLOCKED and not turned_past_reset(state.anchor, seen.pose,
                                                                    resets):
        return state
    if not state.escaping or past_escape_reset(state.anchor, seen.pose, resets):
        return PlannerState()
    if seen.chosen is Chosen.BODY_SAFE:
        return replace(state, mode=Mode.KEEPING_MOVE, move=seen.move)
    return replace(state, mode=Mode.ESCAPING, move=None)


@dataclass(frozen=True)
class BlindEscapes:
    """Extension ``escape_alternate``: was the last escape blind (its straight path collides
    in the costmap) with no legal command since, and does the current escape drive forward?"""

    last_blind: bool = False
    forward: bool = False

    def begin(self, blind: bool) -> BlindEscapes:
        """The memory when an escape begins: a blind one after a blind one turns round."""
        if blind and self.last_blind:
            return BlindEscapes(True, not self.forward)
        return BlindEscapes(blind, False)


@dataclass(frozen=True)
class Oscillation:
    """base_local_planner's in-place rotation memory: a side is "stuck" once the robot turned
    one way in place and then the other without moving oscillation_reset_dist m from
    ``prev_xy`` (m); a stuck side's rotations are not chosen. (Upstream names kept: a negative
    vθ sets ``rotating_left`` and is refused by ``stuck_left``.)"""

    rotating_left: bool = False
    rotating_right: bool = False
    stuck_left: bool = False
    stuck_right: bool = False
    prev_xy: tuple[float, float] = (0.0, 0.0)

    def allows(self, vth: float) -> bool:
        """May an in-place rotation at ``vth`` rad/s be chosen?"""
        return (vth < 0 and not self.stuck_left) or (vth > 0 and not self.stuck_right)

    def after(self, xv: float, thetav: float, xy: tuple[float, float],
              upstream: bool = False) -> Oscillation:
        """The memory after commanding (xv m/s, thetav rad/s) at ``xy``: a command that does
        not drive forward records its turn side and its position. ``upstream``: as the block
        of createTrajectories a differential robot reaches (a turn one way twice refuses the
        other way); otherwise as the block only a holonomic robot reaches (the project's
        rule before ``upstream_rules``: a turn one way, then the other, refuses the first)."""
        if xv > 0:
            return self
        osc = self
        if thetav < 0:
            osc = (replace(osc, stuck_right=osc.stuck_right or osc.rotating_right,
                           rotating_right=True) if upstream else
                   replace(osc, stuck_right=osc.stuck_right or osc.rotating_right,
                           rotating_left=True))
        elif thetav > 0:
            osc = (replace(osc, stuck_left=osc.stuck_left or osc.rotating_left,
                           rotating_left=True) if upstream else
                   replace(osc, stuck_left=osc.stuck_left or osc.rotating_left,
                           rotating_right=True))
        return replace(osc, prev_xy=(float(xy[0]), float(xy[1])))

    def reset_if_moved(self, xy: tuple[float, float], reset_dist: float) -> Oscillation:
        """All flags cleared once farther than ``reset_dist`` m from ``prev_xy``."""
        if math.hypot(xy[0] - self.prev_xy[0], xy[1] - self.prev_xy[1]) > reset_dist:
            return Oscillation(prev_xy=self.prev_xy)
        return self
