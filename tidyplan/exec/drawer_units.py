"""The behaviour units of the WRS drawer (RoboCup 2021 DSPL rules: the tools' deposit is a drawer
that must be opened by its handle): pull it open, and push it closed to free a jammed one.

``open_drawer`` runs ``approach_handle`` (``units.AlignAtDeposit`` with the hand empty: the
drawer is pulled from where items are put into it) then ``pull_handle``, whose failure classes
follow Yamazaki et al.:

- the hand cannot reach the handle: (A), before any manipulation;
- the handle slipped out of the hand, the drawer short of open but free: (B), the target almost
  unchanged, so pull again;
- the drawer jammed half-open: (C), the condition changed, so push it closed first (an inserted
  ``push_drawer``) and pull again.

The check after the pull reads how far the drawer is open; only a drawer open to nearly its full
travel counts, and the belief learns it is open (the planner's ``(closed ?d)`` is false).
"""

from __future__ import annotations

import math

from tidyplan.exec.catalogue import PULL_HANDLE, PUSH_DRAWER
from tidyplan.exec.context import Context
from tidyplan.monitor.unit import Failure, FailureClass, StateMonitor, Unit

A, B, C = FailureClass.A, FailureClass.B, FailureClass.C
OPEN_SHARE = 0.9  # of its travel a drawer must be out to take an item
AT_HANDLE = 0.1  # m: the base stands at the approach within this


class PullHandle(Unit):
    """Grasp the drawer's handle, pull it open, let go; check the opening."""

    name, phase = PULL_HANDLE, "manipulation"

    def __init__(self, ctx: Context, deposit: str) -> None:
        self.ctx, self.deposit = ctx, deposit
        d = next(d for d in ctx.belief.scenario.deposits if d.name == deposit)
        self.travel = d.drawer.travel if d.drawer is not None else 0.0
        self.approach = d.approach

    def check(self):
        if self.ctx.world.holds():
            return Failure(A, "hand_full", "the hand must be free to pull a handle")
        if self.approach is not None and math.dist(self.ctx.world.pose(), self.approach) > AT_HANDLE:
            return Failure(A, "out_of_reach", f"not at {self.deposit}'s handle")
        return None

    def do(self, monitor: StateMonitor):
        world = self.ctx.world
        if self._open():
            return None  # already open (a pull that slipped at the very end): nothing to do
        out = world.pull_handle(self.deposit)
        if out.failure == "drawer_jammed":
            return Failure(C, "drawer_jammed", f"{self.deposit} stuck part-way open")
        if out.failure in ("handle_unreached", "hand_full"):
            return Failure(A, out.failure)
        if not out.ok:
            return Failure(B, out.failure or "handle_slip", "the handle came out of the hand")
        if not self._open():
            return Failure(B, "drawer_not_open", f"{self.deposit} is not open after the pull")
        return None

    def insert_for(self, failure: Failure) -> list[Unit]:
        return [PushDrawer(self.ctx, self.deposit)] if failure.what == "drawer_jammed" else []

    def _open(self) -> bool:
        """The check: how far the drawer is out, as the robot sees it; the belief follows."""
        opening = self.ctx.world.drawer_opening(self.deposit)
        is_open = opening >= OPEN_SHARE * self.travel
        self.ctx.belief.drawer_seen(self.deposit, opening, is_open)
        return is_open


class PushDrawer(Unit):
    """Push a jammed drawer back closed, so that it can be pulled again (inserted for (C))."""

    name, phase = PUSH_DRAWER, "manipulation"

    def __init__(self, ctx: Context, deposit: str) -> None:
        self.ctx, self.deposit = ctx, deposit

    def do(self, monitor: StateMonitor):
        out = self.ctx.world.push_drawer(self.deposit)
        return None if out.ok else Failure(B, out.failure or "push_fail")
