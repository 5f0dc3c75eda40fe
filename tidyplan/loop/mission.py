"""Assemble one mission: scenario -> map, belief, world, executor, planner, trace -> summary.

The command line and the Table II/III reproductions call ``run``; tests call it too, with a
small time budget. The summary's fields are the command-line contract's (docs/architecture.md).
"""

from __future__ import annotations

import math
import time
from pathlib import Path

from sim.scenario.model import Scenario
from sim.scenario.read import load
from tidyplan.belief.geometry import RoomMap
from tidyplan.belief.state import Belief
from tidyplan.exec.bindings import MonitoredExecutor
from tidyplan.loop.loop import LoopConfig, Mission
from tidyplan.loop.options import DEFAULTS, Settings
from tidyplan.loop.scenarios import DOMAIN
from tidyplan.monitor.recovery import RecoveryConfig
from tidyplan.planning.grounding import Grounder
from tidyplan.planning.planner import PlanResult, Status, plan
from tidyplan.trace.score import WrsTally
from tidyplan.trace.writer import NoTrace, TraceWriter
from tidyplan.worlds.contract import World
from tidyplan.worlds.registry import world_class


def run(
    scenario: Scenario | str | Path,
    trace_path: str | Path | None,
    settings: Settings = DEFAULTS,
    domain: str | Path = DOMAIN,
    on_event=None,
) -> dict:
    """Run a mission in the world ``settings.world`` names; returns the summary (also the trace's
    last event). The pybullet world's physics server is closed when the mission ends, however."""
    if not isinstance(scenario, Scenario):
        scenario = load(scenario)
    started = time.perf_counter()
    room = RoomMap(scenario)
    world = make_world(scenario, room, settings)
    room = world.room  # the map the robot is given, as the world built it
    try:
        return _run(scenario, room, world, trace_path, settings, domain, on_event, started)
    finally:
        world.close()


def make_world(scenario: Scenario, room: RoomMap, settings: Settings) -> World:
    """The world ``settings.world`` names (``tidyplan.worlds.registry``), made for this mission."""
    return world_class(settings.world).for_mission(scenario, room, settings)


def _run(scenario, room, world, trace_path, settings, domain, on_event, started) -> dict:
    belief = Belief(scenario, room)  # told the static room and the prior, never the items

    grounder = Grounder()  # the map's ground operators, kept from one replan to the next

    def planner(d, p, max_stratum):
        return mission_plan(d, p, settings, max_stratum, grounder)

    clock = lambda: world.odometer.sim_time_s  # noqa: E731
    with TraceWriter(trace_path, clock) if trace_path is not None else NoTrace(clock) as trace:
        limit, deadline = settings.clock(scenario)  # the score's limit; the one planned against
        tally = WrsTally(limit)  # the score, counted from the events as a reader would

        def listen(event: dict) -> None:
            tally.see(event)
            if on_event is not None:
                on_event(event)

        trace.listener = listen
        config = LoopConfig(
            strategy=settings.strategy,
            min_probability=settings.min_probability,
            time_limit_s=limit,
            deadline_s=deadline,
            after_limit=settings.after_limit,
        )
        executor = MonitoredExecutor(world, trace.emit, RecoveryConfig(max_iterations=settings.max_recovery))
        mission = Mission(domain, belief, executor, world, planner, trace, config)
        outcome = mission.run()
        summary = _summary(scenario, settings, world, belief, mission, outcome, started, trace.path)
        summary["wrs_score"] = tally.score()
        summary["time_limit_s"] = limit
        trace.emit("summary", **summary)
    return summary


def mission_plan(domain, problem, settings: Settings, max_stratum, grounder=None) -> PlanResult:
    """The mission's planner call. A stratum out of time ends it ("not found in time"): a P2
    plan is used only when P1 has none, never because P1 was slow (under load, or at scale).
    Where an incomplete search ended without a plan (nothing proven), the call is made again
    letting the next stratum plan; the trace marks such a plan (`unproven_below`) and Table II's
    count keeps it apart.

    Every move stays open (no `tidyplan.planning.moves` reduction): in a room partly unseen, a stop at
    an idle viewpoint on the way is worth what the model does not price (looking), and with
    moves only to where there is work, greedy failed case I at the first replan (0 of 12, the
    robot driven straight into items nobody had seen; docs/planner.md)."""
    args = (domain, problem, settings.planner, settings.time_budget, max_stratum)
    # detours taken out of the plan (tidyplan.planning.shortcut), but never a stop at a place
    # nobody has looked around from yet, for the same reason
    unexplored = {a.args[0] for a in problem.init if a.predicate == "unexplored"}
    kwargs = dict(
        first_plan_limit=settings.first_plan_limit,
        grounder=grounder,
        reduce_moves=False,
        patience=settings.improvement_patience,
        keep=unexplored.__contains__,
    )
    result = plan(*args, escalate_unproven=False, **kwargs)
    if result.status is Status.UNKNOWN:
        result = plan(*args, **kwargs)
    return result


def _summary(scenario, settings, world, belief, mission, outcome, started, trace_path) -> dict:
    count = outcome.counters
    delivered = len(scenario.items) - len(world.untidied())
    return {
        "scenario": scenario.name,
        "strategy": settings.strategy,
        "world": settings.world,
        "seed": settings.seed,
        "success": outcome.success and delivered == len(scenario.items),
        "reason": outcome.reason,
        "objects": len(scenario.items),
        "delivered": delivered,
        "lost_objects": lost_objects(world, belief),
        "escaped": world.escaped(),
        "given_up": sorted(belief.undeliverable),  # what the belief gave up on ...
        "untidied": world.untidied(),  # ... and what the room holds untidied (the referee's)
        "actions": count.actions,
        "paper_actions": count.paper_actions,
        "strata": dict(count.strata),
        "strata_unproven": count.unproven,
        "replans": count.replans,
        "replan_causes": dict(sorted(count.causes.items())),
        "replans_avoided": count.replans_avoided,
        "recoveries": count.recoveries,
        "distance_m": round(world.odometer.distance_m, 2),
        "sim_time_s": round(world.odometer.sim_time_s, 1),
        "wall_time_s": round(time.perf_counter() - started, 2),
        "replan_time_s": mission.count.plan_time_summary(),
        "trace": None if trace_path is None else str(trace_path),
    }


def lost_objects(world, belief: Belief) -> int:
    """Objects whose true place the belief does not hold: not tidied and not believed within
    20 cm of where they are (unseen, or believed elsewhere), or tidied without the belief knowing."""
    lost = 0
    escaped = set(world.escaped())  # a simulation fault, reported apart
    for item in world.items.values():
        if item.name in escaped:
            continue
        if item.state == "tidied":
            if not any(
                k.state == "tidied" and k.deposit == item.deposit and k.category == item.label
                for k in belief.items.values()
            ):
                lost += 1
            continue
        if item.state == "held":
            ok = belief.holding is not None and belief.items[belief.holding].category == item.label
        else:
            ok = any(
                k.state == "placed"
                and k.category == item.label
                and math.dist((k.x, k.y), (item.x, item.y)) <= 0.2
                for k in belief.items.values()
            )
        lost += not ok
    return lost
