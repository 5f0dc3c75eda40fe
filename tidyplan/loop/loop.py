"""The continual planning loop: plan, execute the next action, observe, update, monitor.

Goebelbecker et al. (after Brenner & Nebel): plan on the belief with assumptions for what is
not yet known, execute, and replan only when the monitor finds a reason (``triggers.Cause``).
A plan that is still valid is kept; assumptions are never executed but checked against what
is seen; a newly seen item that matches a virtual object of the plan is bound to it in place.
O-FSM (Yan et al.) is the ranking of the plans: strategy ``ofsm`` plans with strata P1..P3,
``greedy`` with P1 alone.

When the whole goal has no plan (an item out of reach, an unseen item no viewpoint can reveal),
or only plans whose commitment (the steps up to the first goal fact achieved,
``tidyplan.planning.commitment``) is less likely than the threshold, the loop narrows the goal rather
than stop: first to the items seen, then to those that have a plan on their own, and says so in
the trace. It gives up only when no goal is left that has such a plan.

Before it ends, the loop explores again while the prior names items nobody has found (new
rounds, from closer viewpoints), and looks into every deposit that should hold something: an
item knocked out is lost to the belief, found and tidied again.

The planner, the executor, the referee and the trace writer are passed in. The loop reaches the
robot only through the executor (actions, moves and looks, each reported with its track); the
referee (``tidyplan.worlds.contract.Referee``) is asked once, for the verdict when the mission
ends: an ending that depends on it (``Verdict``) is settled there. The loop knows the tidy
domain only through the belief, the problem writer and the executor.
"""

from __future__ import annotations

import gc
import math
import os
from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass

from sim.scenario.model import ORIENTATION
from tidyplan.belief.focus import focus, focus_safe
from tidyplan.belief.problem import Snapshot, belief_state, robot_waypoint, write
from tidyplan.belief.state import Belief
from tidyplan.belief.vocabulary import VOCABULARY
from tidyplan.loop.counting import Counters
from tidyplan.loop.looking import Excursions, inspection_tour
from tidyplan.loop.options import DEFAULTS
from tidyplan.loop.replanning import Replanner
from tidyplan.loop.triggers import Cause, bind, check_assumptions
from tidyplan.pddl import model as m
from tidyplan.pddl.reader import read_domain, read_text
from tidyplan.pddl.simulate import Overlay, Simulator
from tidyplan.pddl.static import changed_predicates
from tidyplan.planning.planner import PlanResult, Status, Step
from tidyplan.planning.strata import STRATEGIES, unproven_below
from tidyplan.trace import events
from tidyplan.trace.score import TIME_LIMIT_S
from tidyplan.worlds.contract import Referee, referee_view

# How a mission ends: a reason, or one that needs the referee's verdict (the items the world
# has left untidied), settled once when the loop ends
Ending = str | Callable[[list[str]], str]
LOOKS_BEFORE_GIVING_UP = 3  # as many as the belief needs to forget an item that is not there


@dataclass(frozen=True, slots=True)
class LoopConfig:
    strategy: str = DEFAULTS.strategy
    # a plan is adopted only when its commitment (tidyplan.planning.commitment) is at least this likely
    min_probability: float = DEFAULTS.min_probability
    # O-FSM's halting criterion: a cap on the actions performed, this many for each item the
    # robot knows of (told by the prior, or seen), and never fewer than 300 (12 items' worth): a
    # fixed 300 stopped a 96-object room at 70 tidied, each delivery taking four actions
    actions_per_item: int = 25
    min_actions: int = 300
    max_plans: int = 150
    # The error layer's last word: one action whose recoveries are exhausted this often, each
    # time replanned and tried again, will not go (the world has a reason the belief lacks).
    # The item it acts on is given up and the rest tidied; an action on no item ends the mission.
    max_same_failure: int = 5
    # the WRS referee's, for readers (tidyplan.trace.score)
    time_limit_s: float = TIME_LIMIT_S
    # the limit the robot plans against (tidyplan.loop.deadline; None: it plans to tidy
    # everything), and what it does once it has passed: go on tidying ("continue") or "stop"
    deadline_s: float | None = None
    after_limit: str = DEFAULTS.after_limit


@dataclass(slots=True)
class Outcome:
    success: bool
    reason: str
    counters: Counters


class Mission:
    """One run of the loop. ``planner(domain, problem, max_stratum) -> PlanResult``."""

    def __init__(
        self, domain_path, belief: Belief, executor, referee: Referee, planner, trace, config=LoopConfig()
    ):
        self.domain: m.Domain = read_domain(domain_path)
        self.domain_text = read_text(domain_path)
        self.belief, self.executor, self.referee = belief, executor, referee
        self.planner, self.trace, self.config = planner, trace, config
        self.max_stratum = STRATEGIES[config.strategy]
        self.count = Counters()
        self.snapshot: Snapshot | None = None
        self.steps: list[Step] = []
        self.goal: list[str] = []  # the adopted plan's goal: items, and drawers to open
        self._drawers = {d.name for d in self.belief.scenario.deposits if d.drawer is not None}
        self.goal_kind: str | None = None  # and which goal it was (monitor.goals)
        self.pending: list[Step] = []  # assumptions passed in the plan, not yet confirmed
        self.bound: dict[str, str] = {}  # virtual object -> seen item
        self.stratum: int | None = None
        self._looks_left = LOOKS_BEFORE_GIVING_UP
        self._unblocked = False  # blocked moves forgotten since the last plan adopted
        self._freezes = False  # whether each plan adopted freezes what was built (``run``)
        self._exhausted: Counter[tuple[str, str | None]] = Counter()  # (action, failure) -> times
        self._why: Counter[tuple[str, str]] = Counter()  # (cause, why) -> replans: what repeated
        self._went_to_look: Counter[str] = Counter()  # item -> drives to look at it before giving up
        self._verified_at: int | None = None  # actions done when the deposits were last looked into
        # deposit -> actions done at the last put into it, and when it was last looked into
        self._put_into: dict[str, int] = {}
        self._looked_into: dict[str, int] = {}
        self._plain = trace.save("domain.pddl", self.domain_text)
        self.replanner = Replanner(
            self.domain,
            belief,
            planner,
            self.max_stratum,
            trace,
            self.count,
            config.min_probability,
            self._plain,
            clock=trace.now,
            deadline_s=config.deadline_s,
        )
        self.excursions = Excursions(belief, executor, self._observe, trace.emit, self.count)
        self.executor.bind(self.domain)
        # the domain's predicates no sensor reports that its actions change (must-move-back):
        # the belief keeps them by the effects of the actions executed
        changed = changed_predicates(self.domain)
        self._remembered = {p.name for p in self.domain.predicates if p.name in changed} - set(VOCABULARY)
        # the plan is checked against the map among its own waypoints where the domain's steps
        # ask about no others (tidyplan.belief.focus); against the whole map otherwise
        self._focused = focus_safe(self.domain)

    # ------------------------------------------------------------------ the loop
    def run(self) -> Outcome:
        """The mission, to its end. What it has built by each plan adopted (the planner's ground
        operators, the map's pairs, the belief) mostly lives on, so the collector's full passes
        skip it from then (``gc.freeze``): over all of it they were 1.1 s of a 96-object mission,
        pauses of up to 0.14 s inside an action. At the end it is all given back to the
        collector (the little cyclic garbage among it, a few hundred objects a mission, is
        freed then); a process that froze objects of its own is left as it is."""
        self._freezes = gc.get_freeze_count() == 0
        try:
            return self._mission()
        finally:
            if self._freezes:
                gc.unfreeze()

    def _mission(self) -> Outcome:
        scenario = self.belief.scenario
        self.trace.emit(
            "start",
            strategy=self.config.strategy,
            domain=self._plain,
            expected=dict(self.belief.prior or {}),
            prior=self.belief.prior is not None,
            generated_viewpoints={
                n: list(map(_r, self.belief.room.fixed[n])) for n in self.belief.exploration.generated
            },
            scenario=scenario.name,
            scenario_file=os.path.abspath(scenario.path) if os.path.isfile(scenario.path) else scenario.path,
            robot=list(map(_r, self.belief.robot)),
            time_limit_s=self.config.time_limit_s,
            drawers=[d.name for d in scenario.deposits if d.drawer],  # for the score's drawers bonus
        )
        self._observe(self.executor.look(), "wp-entrance", "the first look")
        ending = self._replan(Cause.INITIAL)
        while ending is None:
            ending = self._tick()
        # the referee's verdict, the one time the loop asks it: what the world has left untidied.
        # It decides success, as the rulebook counts the room: a mission that ended on a failure
        # of its own (an action that would not go) with every object put away has tidied the room
        left = self.referee.untidied()
        reason = ending if isinstance(ending, str) else ending(left)
        if not left and not reason.startswith("goal reached"):
            reason = f"goal reached: the room is tidied, though {reason}"
        success = reason.startswith("goal reached")
        escaped = self.referee.escaped()
        if escaped:  # the simulation's fault, not the robot's: reported, never counted as lost
            self.trace.emit("sim_fault", what="objects outside the room", items=escaped)
        places, wrong = referee_view(self.referee)
        # orientation items standing the right way in their box: the score's orientation points
        standing = self.referee.standing()
        end = {"items": places, "escaped": escaped, "misplaced": wrong, "standing": standing}
        self.trace.emit("end", success=success, reason=reason, **end)
        return Outcome(success, reason, self.count)

    def _tick(self) -> Ending | None:
        """One turn: consume assumptions, check, execute one action, observe, monitor."""
        while self.steps and self.steps[0].assumption:
            step = self.steps.pop(0)
            self.pending.append(step)
            self.trace.emit("assume", action=step.text, probability=step.probability)
        if not self.steps:
            return self._finished()
        if self.count.actions >= (cap := self._action_cap()):
            return f"action limit {cap} reached"
        if self.config.after_limit == "stop" and self.trace.now() >= self.config.time_limit_s:
            return f"time limit {self.config.time_limit_s:g} s reached: stopped (after-limit stop)"
        # No check here: the plan was just made from this belief, or _monitor has checked the
        # rest of it (this step first) against the belief after the last action.
        step = self.steps.pop(0)
        before = self._belief_state() if self._remembered else None
        report = self.executor.execute(step, self.snapshot, self.belief, self._observe)
        if report.ok and before is not None:
            self._remember(before, step)
        self.count.action(step, report, self.belief.holding is not None)
        fields = events.action(step.text, step.stratum, report, self.belief.robot, delivered=report.delivered)
        self.trace.emit("action", **fields)
        if report.delivered is not None:
            self._after_put(report.delivered)
        return self._monitor(report.new, report, step)

    def _after_put(self, item: str) -> None:
        """The robot stands at the deposit it just put ``item`` into: where nothing is left for
        that deposit (no item known untidied, no virtual object, of its category; for the
        orientation deposit, none at all), it looks into it now, and the tour at the end of the
        mission need not come back (``_inspect_deposits``)."""
        deposit = self.belief.items[item].deposit
        if deposit is None:
            return
        self._put_into[deposit] = self.count.actions
        category = next(d.category for d in self.belief.scenario.deposits if d.name == deposit)
        left = [k.category for k in self.belief.untidied() if k.name not in self.belief.undeliverable]
        left += [c for _, c in self.belief.virtual()]
        if (category == ORIENTATION and left) or category in left:
            return
        self.excursions.look_into(deposit)
        self._looked_into[deposit] = self.count.actions

    def _monitor(self, new: list[str], report, step: Step) -> Ending | None:
        unbound = self._bind(new)
        contradicted = self._check_assumptions()
        if contradicted:
            return self._replan(Cause.ASSUMPTION, contradicted)
        if report.recovery_exhausted:
            self._exhausted[(step.text, report.failure)] += 1
            times = self._exhausted[(step.text, report.failure)]
            if times >= self.config.max_same_failure:
                failed = f"{step.text} failed ({report.failure}) {times} times, each after its recoveries"
                item = next((a for a in step.args if a in self.belief.items), None)
                item = item or next((a for a in step.args if a in self.belief.closed), None)
                if item is None:
                    return failed
                self._give_up(item, failed)
            return self._replan(Cause.RECOVERY, f"{step.text}: {report.failure}")
        if unbound and self.goal_kind not in ("horizon", "deadline"):
            # Under a horizon the plan is for the nearest dozen only (against the clock, for the
            # route's dozen): a new item waits for the next plan (unless it is in the way: the
            # simulation below finds that, (ii)).
            return self._replan(Cause.NEW_OBJECT, " ".join(unbound))
        if not self.steps:
            return None  # _finished decides on the next turn
        state = self._belief_state()
        end, broken = self.sim.run(state, ((s.name, s.args) for s in self.steps))
        done = {k.name for k in self.belief.items.values() if k.state == "tidied"}
        if broken == 0:  # (i): the very next action cannot run
            why = f"{self.steps[0].text} not applicable"
            if not report.ok:
                why += f" after {step.text} failed ({report.failure})"
            return self._replan(Cause.PRECONDITION, why)
        reached = all(
            ("closed", g) not in end if g in self._drawers else ("tidied", g) in end or g in done
            for g in self.goal
        )
        if broken is not None or not reached:
            why = (
                f"step {broken} {self.steps[broken].text} fails" if broken is not None else "goal not reached"
            )
            return self._replan(Cause.PLAN_INVALID, why)
        if new or not report.ok or report.recoveries:
            self.count.replans_avoided += 1
            self.trace.emit("plan_kept", steps=len(self.steps))
        return None

    def _finished(self, unreachable: bool = False) -> Ending | None:
        """The plan ran out, or nothing is left to plan for: explore again while the prior names
        items nobody found, look into the deposits, then ask the referee for its verdict.
        ``unreachable``: no plan reaches the unseen space left, so a new round is the next step."""
        if self._open():
            return self._replan(Cause.PLAN_INVALID, "plan done, items remain")
        unfound = self.belief.virtual()
        if unfound and self.belief.explorable() and not unreachable:
            return self._replan(Cause.PLAN_INVALID, "plan done, room not explored")
        if unfound:
            added = self.belief.explore_again()
            if added is not None:
                rounds = self.belief.exploration.rounds
                self.trace.emit("explore_again", unseen=len(unfound), round=rounds, viewpoints=added)
                return self._replan(Cause.PLAN_INVALID, f"{len(unfound)} items of the prior not found")
        if self._verified_at != self.count.actions:
            lost = self._inspect_deposits()
            self._verified_at = self.count.actions
            if lost or self._open():
                why = "deposits looked into: " + " ".join(lost or ["new items"])
                return self._replan(Cause.PLAN_INVALID, why)
        undeliverable = " ".join(sorted(self.belief.undeliverable))
        never_found = f" ({len(unfound)} items of the prior never found)" if unfound else ""

        def verdict(left: list[str]) -> str:
            # the referee's verdict decides (the rulebook counts the room, not the belief): what
            # the belief gave up on while the room has everything tidied is a mismatch, said so
            if not left:
                mismatch = (
                    f"; the belief gave up on {undeliverable}, not in the room" if undeliverable else ""
                )
                return "goal reached" + never_found + mismatch
            if undeliverable:
                return f"gave up on {undeliverable}, the rest tidied; the world has {len(left)} items left"
            return f"belief says tidy, the world has {len(left)} items left"

        return verdict

    def _inspect_deposits(self) -> list[str]:
        """Look into every deposit that should hold items, on the shortest tour from where the
        robot stands; the items lost (not there)."""
        facts = self.belief.facts()
        full = [
            d.name
            for d in self.belief.scenario.deposits
            if self.belief.in_deposit(d.name)
            and self._looked_into.get(d.name, -1) < self._put_into.get(d.name, 0)
        ]
        lost: list[str] = []
        for deposit in inspection_tour(facts, robot_waypoint(facts, self.belief), full):
            lost += self.excursions.inspect(deposit, self._map_now())
        return lost

    # ------------------------------------------------------------------ planning
    def _replan(self, cause: Cause, why: str = "") -> Ending | None:
        if not self._open() and not (self.belief.virtual() and self.belief.explorable()):
            return self._finished()  # nothing to plan for (the last item a false detection, say)
        if cause is not Cause.INITIAL:
            self.count.replans += 1
            self.count.causes[cause.value] = self.count.causes.get(cause.value, 0) + 1
        self._why[(cause.value, why)] += 1
        if self.count.replans + 1 > self.config.max_plans:
            (c, w), n = self._why.most_common(1)[0]
            return f"plan limit {self.config.max_plans} reached; most repeated: {c} ({w}) {n} times"
        self.pending.clear()
        self.bound.clear()
        unlikely: list[float] = []
        out_of_time = 0  # goals not planned in time (or by an incomplete search): nothing proven
        for label, goal, virtual in self.replanner.goals():
            if goal is not None and not goal:  # None: "feasible", worked out only when reached
                continue
            result, snap, problem, p = self.replanner.plan(goal, virtual, cause, why, label, self.stratum)
            if result.status is not Status.SOLVED:
                out_of_time += result.status in (Status.TIMEOUT, Status.UNKNOWN)
                continue
            if p < self.config.min_probability:  # narrow the goal: a shorter commitment may pass
                unlikely.append(p)
                continue
            self._adopt(result, snap, problem, label)
            self._looks_left, self._unblocked = LOOKS_BEFORE_GIVING_UP, False
            if self._freezes:  # what the mission built so far lives on (``run``)
                gc.freeze()
            return None
        if self.belief.virtual() and self.belief.exploration.scene_changed:
            self.belief.exploration.reset()  # items moved: views blocked before may be open now
            self.trace.emit("explore_again", unseen=len(self.belief.virtual()))
            return self._replan(cause, why)
        if (self.belief.blocked_moves or self.belief.failed_poses) and not self._unblocked:
            # The moves found blocked and the poses a grasp failed from were believed, not proven
            # for good (a transient obstacle, an item since moved; a look that missed by chance,
            # a grasp that slipped, at an item's only pose): before the goal shrinks, plan once
            # more without them (n96: the last item given up at its one tight pose)
            self._unblocked = True
            moves, poses = len(self.belief.blocked_moves), len(self.belief.failed_poses)
            self.trace.emit("unblock", moves=moves, poses=poses)
            self.belief.blocked_moves.clear()
            self.belief.failed_poses.clear()
            return self._replan(cause, why)
        if self._looks_left > 0 and self._worth_looking():
            # Before giving up, look again from here: an item believed in the way that is not
            # there (a false detection) is forgotten after a few looks that should have seen it.
            self._looks_left -= 1
            self.trace.emit("look_again", looks_left=self._looks_left)
            self._observe(self.executor.look(), None, "no plan: an item in the way may not be there")
            return self._replan(cause, why)
        if self._go_and_look():
            return self._replan(cause, why)
        if unlikely:
            best = max(unlikely)
            threshold = self.config.min_probability
            return f"no plan whose next commitment is likely enough: best {best:.2g} below {threshold:g}"
        if not self._open():  # only unseen items left, and no plan reaches them
            return self._finished(unreachable=True)
        held = " ".join([k.name for k in self._open()] + [v for v, _ in self.belief.virtual()])
        # "no plan" where the planner proved it; where a goal was not planned in time
        # (tidyplan.loop.mission.mission_plan), the reason says so: nothing was proven
        timed_out = f" ({out_of_time} goals not planned in time, unproven)" if out_of_time else ""

        def verdict(left: list[str]) -> str:
            if not left:  # nothing more could be done: the world has it all tidied
                return f"goal reached; no plan for {held}, which the belief still held"
            return (f"no plan for {held}" if held else "no plan") + timed_out

        return verdict

    def _adopt(self, result: PlanResult, snap: Snapshot, problem: m.Problem, goal_kind: str) -> None:
        self.snapshot, self.steps, self.goal_kind = snap, list(result.steps), goal_kind
        self.stratum = result.stratum
        if unproven_below(result.attempts):
            self.count.segment_unproven = True
        self.sim = Simulator(self.domain, problem)
        self.goal = list(snap.goal)  # item names; renamed as virtual objects are bound

    def _map_now(self) -> Snapshot:
        """The belief's map as it is, for a move the loop makes outside any plan."""
        return write(self.belief, self.belief.facts(), [], [], "map-now", domain=self.domain)

    def _go_and_look(self) -> bool:
        """Before giving up on an item no plan reaches, look at it from where it should be seen
        (``Excursions.go_and_look``), at most LOOKS_BEFORE_GIVING_UP times an item."""
        return self.excursions.go_and_look(self._went_to_look, LOOKS_BEFORE_GIVING_UP, self._map_now())

    def _worth_looking(self) -> bool:
        """A look can change the belief: some believed item is in view and could be missed."""
        boxes = self.belief.item_boxes()
        return any(self.belief.should_see(k, None, boxes) for k in self._open() if k.state == "placed")

    def _action_cap(self) -> int:
        told = sum(self.belief.prior.values()) if self.belief.prior is not None else 0
        known = max(told, len(self.belief.items))
        return max(self.config.min_actions, self.config.actions_per_item * known)

    def _open(self) -> list:
        """The untidied items the loop still plans for: all but those given up."""
        return [k for k in self.belief.untidied() if k.name not in self.belief.undeliverable]

    def _give_up(self, item: str, why: str) -> None:
        """Yamazaki's error layer, last word: the task is reworked without ``item`` (left where
        it is, or put down wherever a plan puts it), and the rest of the room is tidied."""
        self.belief.undeliverable.add(item)  # the one record of it: problems and goals read it
        self._went_to_look[item] = LOOKS_BEFORE_GIVING_UP  # nothing to look at it for
        self.trace.emit("give_up", item=item, why=why)

    # ------------------------------------------------------------------ monitoring
    def _belief_state(self):
        """The current belief as a planning state, in the names of the plan being executed."""
        virtual = [(v, c) for v, c in self.snapshot.virtual if v not in self.bound]
        # the problem's init as a state: no model built, nothing written or parsed; the map's
        # pairs among the plan's waypoints, the removal waypoints of its items (and the held one)
        among = only = None
        if self._focused:
            names = {a for s in self.steps + self.pending for a in s.args}
            among = focus(self.belief, self.belief.poses(), names)
            only = frozenset(names | ({self.belief.holding} if self.belief.holding else set()))
        state = belief_state(self.belief, self.belief.facts(among), virtual, self.domain, only)
        # Virtual objects the plan bound are seen items now; pending assumptions stand for
        # what the plan took for granted and the belief does not contradict yet.
        for a in self.pending:
            state = self.sim.apply(state, a.name, a.args)
        return state

    def _remember(self, before, step: Step) -> None:
        """What the executed ``step`` did to the predicates only the belief keeps: its effects."""
        after = self.sim.apply(before, step.name, step.args)
        kept = {a for a in self.belief.memory if a[0] not in self._remembered}
        # the map's part (an overlay's base) holds vocabulary only: its small part is read
        small = after.added if isinstance(after, Overlay) else after
        self.belief.memory = kept | {a for a in small if a[0] in self._remembered}

    def _observe(self, detections, waypoint, why: str = "", frames=None, stops=None) -> list[str]:
        """A sweep's ``detections`` from ``waypoint`` (of the pan ``stops`` given, all around by
        default), or the ``frames`` of a glance (each with its own detections, from its own
        place), into the belief; one trace event for them: for every sweep (why it was taken),
        for a glance that saw something."""
        if frames is None:
            updates, seen = [self.belief.observe(detections, waypoint, stops=stops)], len(detections)
        else:
            updates = [self.belief.observe(f.detections, None, f) for f in frames]
            seen = sum(len(f.detections) for f in frames)
        new = [n for u in updates for n in u.new]
        forgotten = [n for u in updates for n in u.forgotten]
        if frames is None or seen or new or forgotten:
            confirmed = list(dict.fromkeys(n for u in updates for n in u.confirmed))
            if frames is not None:
                fields = {"frames": len(frames)}
            else:  # the stops' headings, degrees in the room's frame
                fields = {} if stops is None else {"stops": [round(math.degrees(h)) for h in stops]}
            self.trace.emit(
                "observe",
                waypoint=waypoint,
                why=why,
                seen=seen,
                new=new,
                confirmed=confirmed,
                forgotten=forgotten,
                overlapping=list(dict.fromkeys(n for u in updates for n in u.overlapping)),
                **fields,
            )
        return [n for n in new if n in self.belief.items]

    def _bind(self, new: list[str]) -> list[str]:
        """Bind new items to the plan's virtual objects (``triggers.bind``); the rest the plan
        could use, cause (v)."""
        virtual = self.snapshot.virtual if self.snapshot else ()
        self.steps, self.pending, self.goal, unbound = bind(
            new, self.steps, self.pending, self.goal, virtual, self.bound, self.belief, self.trace.emit
        )
        return unbound

    def _check_assumptions(self) -> str | None:
        """Cause (iii): a pending assumption, or one still ahead in the plan, that the belief now
        contradicts (whether the plan looks before or after it assumes must not change the
        cause). Pending ones the belief confirms are done with; those ahead wait their turn."""
        for a, ok, why in check_assumptions(self.pending, self.belief):
            self.pending.remove(a)
            self.trace.emit("assumption", action=a.text, holds=ok)
            if not ok:
                return why
        ahead = [s for s in self.steps if s.assumption]
        for a, ok, why in check_assumptions(ahead, self.belief):
            if not ok:
                self.trace.emit("assumption", action=a.text, holds=False)
                return why
        return None


def _r(x: float) -> float:
    return round(x, 3)
