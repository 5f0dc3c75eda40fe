"""Belief state to PDDL problem, as ROSPlan's problem interface does: one problem per (re)plan.

The problem is built as the model (``tidyplan.pddl.model.Problem``) in the words of
``VOCABULARY``, keeping what the domain declares, and handed to the planner as it is; its text
(``Snapshot.text``) is saved beside the trace, so what was planned on is what a person can open,
check with ``tidyplan check`` and plan again with ``tidyplan plan``. Nothing is parsed back.

Facts, from the belief and the map (``tidyplan.belief.geometry``):
- where the robot is, what it holds, where each untidied seen item is (``item-at`` its grasp
  waypoint) and that it is ``located``; tidied items are left out (nothing more to do with them);
- unseen items as ``:virtual-objects`` with their category; ``unexplored`` viewpoints with
  ``p-item-near`` for ``assume-item-near``;
- paths and their lengths (``distance``, metres) and the robot's time along them
  (``travel-time``, seconds: ``travel_time``), blocked paths and what blocks them, pose
  adjustments (never ``(shortest-paths)``: with it cases I and II failed, docs/planner.md);
- where the domain's moves cost ``travel-time`` (the shipped tidy.pddl: every cost in seconds),
  the goal reward R of the criterion c + R(1 - p) in seconds too (``goal_reward``).
- for every item that may need moving out of the way, the removal waypoint of Algorithm 1,
  computed from where that item is picked up (``tidyplan.planning.removal``).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

from sim.scenario.model import ORIENTATION, drawer_layout
from tidyplan.belief.mapfacts import MapFacts, deposit_waypoint
from tidyplan.belief.state import Belief
from tidyplan.belief.vocabulary import COST, GOAL, VOCABULARY
from tidyplan.pddl import model as m
from tidyplan.pddl.criterion import DEFAULT_REWARD
from tidyplan.pddl.simulate import Atoms, Overlay
from tidyplan.pddl.writer import problem_text
from tidyplan.planning.removal import Waypoint, removal_waypoint

Point = tuple[float, float]

NOT_FOR_REMOVAL = ("grasp", "deposit", "adjust", "robot")
# s a move takes beyond its length at the base's speed (its stop, the turn it was too short for):
# a move's pybullet mean, 10.1 s for 2.0 m, less 2.0 m at 0.22 m/s (docs/results.md)
STOP_S = 0.8
TRAVEL_TIME = "travel-time"
LENGTHS = ("distance", TRAVEL_TIME)  # a path's length in metres, and in the robot's seconds


def travel_time(metres: float, speed: float) -> float:
    """The seconds a move along ``metres`` of path takes the robot at ``speed`` m/s, as the
    problem states them (adding STOP_S keeps the triangle inequality: a detour costs a stop)."""
    return round(metres / speed + STOP_S, 2)


def goal_reward(domain: m.Domain | None, speed: float) -> float | None:
    """R for a problem whose costs are seconds (its domain's moves cost ``travel-time``): the
    criterion's default of 1000 (``tidyplan.pddl.criterion.DEFAULT_REWARD``) taken as metres
    of driving, as it was when moves cost metres, in the robot's seconds (4545 s at 0.22 m/s): an
    assumption's chance weighs against driving as it did when Table II was measured. None (the
    default R) for a domain that costs something else."""
    if domain is not None and domain.function(TRAVEL_TIME) is None:
        return None
    return round(DEFAULT_REWARD / speed, 2)


@dataclass(frozen=True, slots=True)
class Snapshot:
    """One problem as the model holds it, and what the loop needs to read the plan back."""

    problem: m.Problem
    header: tuple[str, ...]  # comments for a person reading the saved file
    facts: MapFacts
    goal: tuple[str, ...]
    virtual: tuple[tuple[str, str], ...]
    robot_waypoint: str
    removal: dict[str, str]  # item -> removal waypoint (Algorithm 1)
    atoms: frozenset[tuple[str, ...]]  # the init's atoms: the planning state the loop monitors

    @property
    def text(self) -> str:
        """The problem in the dialect, as saved beside the trace (``tidyplan plan`` reads it)."""
        return "\n".join(self.header) + "\n" + problem_text(self.problem)


def robot_waypoint(facts: MapFacts, belief: Belief) -> str:
    """The waypoint the robot stands on: its own name for it when that is on the map."""
    if belief.robot_wp in facts.points and _dist(facts.points[belief.robot_wp], belief.robot) < 0.03:
        return belief.robot_wp
    return min(facts.points, key=lambda n: (_dist(facts.points[n], belief.robot), n))


def removal_choices(
    facts: MapFacts, belief: Belief, robot_wp: str, only: frozenset[str] | None = None
) -> dict[str, str]:
    """Algorithm 1 for each item that could be moved (of ``only``, where given): p_r is where
    the robot stands when it has the item in hand (its grasp waypoint; the robot's waypoint for
    the item held now)."""
    # only the waypoints Algorithm 1 may choose (reached, none of NOT_FOR_REMOVAL's kinds, which
    # hold the grasp and deposit poses it passes over): every waypoint of the map, made for
    # each call, was two fifths of a problem's contents at 96 objects under a line profiler
    waypoints = [
        Waypoint(n, *facts.points[n], reached=True)
        for n in sorted(facts.points)
        if n in belief.reached and facts.kind[n] not in NOT_FOR_REMOVAL
    ]
    origins = dict(facts.grasp)
    if belief.holding is not None:
        origins[belief.holding] = robot_wp
    if only is not None:
        origins = {item: w for item, w in origins.items() if item in only}
    out = {}
    for item, origin in sorted(origins.items()):
        w = removal_waypoint(waypoints, facts.points[origin], lambda a, b, o=origin: _length(facts, o, b))
        if w is not None:
            out[item] = w.name
    held = belief.holding
    if held is not None and (out.get(held) is None or (robot_wp, out[held]) not in facts.path):
        # No removal waypoint open from here: the item in the way of it needs a free hand first.
        # Algorithm 1's "a free space nearby" is then beside the robot (case III had the robot
        # hold a tool it could neither deliver nor put aside, both ways shut by a box).
        out[held] = robot_wp
    return out


def focus(facts: MapFacts, belief: Belief, goal: Sequence[str]) -> tuple[MapFacts, set[str]]:
    """The part of the map a problem for ``goal`` needs, and the seen items it keeps: the goal's
    items, the one in the hand, the items in the way of a closed drawer's pull, and, until nothing
    changes, every item that blocks a way between the waypoints kept (P3 may have to move it).
    Other items' waypoints and ways are left out: in a room of 48 items they made most of the
    problem, and a plan for a dozen never used them."""
    robot_wp = robot_waypoint(facts, belief)
    fixed = {n for n, k in facts.kind.items() if k in ("entrance", "viewpoint", "deposit", "robot")}
    fixed |= {n + "-base" for n in fixed if n + "-base" in facts.points} | {robot_wp}
    keep = {g for g in goal if g in facts.grasp} | ({belief.holding} if belief.holding else set())
    keep |= {o for who in pull_blockers(belief).values() for o in who if o in facts.grasp}
    while True:
        wps = fixed | {facts.grasp[i] for i in keep if i in facts.grasp}
        wps |= {w + "-base" for w in wps if w + "-base" in facts.points}
        more = keep | {i for i, a, b in facts.blocks if a in wps and b in wps}
        if more == keep:
            break
        keep = more
    part = MapFacts(
        points={n: q for n, q in facts.points.items() if n in wps},
        kind={n: k for n, k in facts.kind.items() if n in wps},
        grasp={i: w for i, w in facts.grasp.items() if i in keep},
        unreachable=[i for i in facts.unreachable if i in keep],
        path={ab: d for ab, d in facts.path.items() if ab[0] in wps and ab[1] in wps},
        blocked={ab: d for ab, d in facts.blocked.items() if ab[0] in wps and ab[1] in wps},
        blocks={t for t in facts.blocks if t[1] in wps and t[2] in wps},
        adjust={ab: d for ab, d in facts.adjust.items() if ab[0] in wps and ab[1] in wps},
        reach_blockers={w: who for w, who in facts.reach_blockers.items() if w in wps},
    )
    return part, keep


def pull_blockers(belief: Belief) -> dict[str, list[str]]:
    """For each closed drawer, the believed floor items in the way the base backs off along the
    slide while it pulls the drawer out (from the approach, the drawer's travel; the base's
    radius and its margin either side): the pull would stop at them."""
    robot = belief.scenario.robot
    keep = robot.radius + robot.nav_margin
    out: dict[str, list[str]] = {}
    for d in belief.scenario.deposits:
        layout = drawer_layout(belief.scenario.furniture, d) if d.name in belief.closed else None
        if layout is None:
            continue
        a = d.approach
        b = layout.point(layout.out(a) + layout.spec.travel, a[1 - layout.k])
        who = [k.name for k in belief.placed() if k.on_floor and _near_segment(k, a, b, keep)]
        if who:
            out[d.name] = sorted(who)
    return out


def _near_segment(k, a: Point, b: Point, keep: float) -> bool:
    """Does the box of ``k`` come within ``keep`` of the segment a-b (a slide along x or y)?"""
    x0, x1 = sorted((a[0], b[0]))
    y0, y1 = sorted((a[1], b[1]))
    dx = max(x0 - (k.x + k.sx / 2), (k.x - k.sx / 2) - x1, 0.0)
    dy = max(y0 - (k.y + k.sy / 2), (k.y - k.sy / 2) - y1, 0.0)
    return math.hypot(dx, dy) < keep


def goal_atoms(belief: Belief, goal: Sequence[str], domain: m.Domain | None) -> tuple:
    """The goal's atoms: (tidied ITEM) for an item; for a drawer deposit's name, that drawer
    open, (not (closed DRAWER)) (the WRS rulebook rewards opening every drawer), where the domain
    has drawers that close."""
    drawers = {d.name for d in belief.scenario.deposits if d.drawer is not None}
    closes = domain is None or domain.predicate("closed") is not None
    return tuple(
        m.Not(m.Atom("closed", (g,))) if g in drawers else m.Atom(GOAL, (g,))
        for g in goal
        if g not in drawers or closes
    )


def belief_state(
    belief: Belief,
    facts: MapFacts,
    virtual: Sequence[tuple[str, str]],
    domain: m.Domain | None = None,
    only: frozenset[str] | None = None,
) -> Overlay:
    """``write(...).state`` without the model: what the monitor simulates the plan from after
    every action (at 96 objects the model's hundred thousand atoms were most of a turn).
    The map's atoms come as a set kept with the map (a state has no order to sort them into),
    the base of an `Overlay` whose small part is the rest of the belief. ``only``: the items
    whose removal waypoints are written (a plan's own, with ``facts`` among its waypoints:
    ``tidyplan.belief.focus``); all by default."""
    atoms = _contents(belief, facts, virtual, None, domain, with_map=False, only=only)[0]
    base, added, removed = _map_layers(facts)
    if domain is not None and not all(domain.predicate(p) is not None for p in _MAP_PREDICATES):
        base = Atoms({k: v for k, v in base.parts.items() if domain.predicate(k) is not None})
        added = {a for a in added if domain.predicate(a[0]) is not None}
    # the map's part shared, not copied: a turn adds the robot's pairs and the belief's few
    # hundred atoms to it
    return Overlay(base, [*added, *atoms], removed)


def _contents(belief, facts, virtual, keep, domain, with_map=True, only=None):
    """(atoms, values, objects, seen, robot_wp, removal) of the problem ``write`` builds;
    ``with_map`` False leaves out the map's atoms and distances (``_map_part``); ``only``: the
    items whose removal waypoints are worked out (all by default)."""
    robot_wp = robot_waypoint(facts, belief)
    removal = removal_choices(facts, belief, robot_wp, only)
    seen = [k for k in belief.untidied() if keep is None or k.name in keep]
    p_near = belief.exploration.p_item_near(facts) if virtual else {}
    deposits = belief.scenario.deposits
    categories = sorted({k.category for k in seen} | {c for _, c in virtual} | {d.category for d in deposits})
    atoms: list[tuple[str, ...]] = [("robot-at", robot_wp)]
    values: list[tuple[str, tuple[str, ...], float]] = []
    atoms.append(("holding", belief.holding) if belief.holding else ("hand-empty",))
    oriented = any(d.category == ORIENTATION for d in deposits)
    for k in seen:
        if k.name not in belief.undeliverable:
            # an orientation item goes into the deposit for them (standing it scores 10 more)
            atoms.append(("of-category", k.name, ORIENTATION if k.oriented and oriented else k.category))
        if k.state == "placed" and k.name in facts.grasp:
            atoms += [("item-at", k.name, facts.grasp[k.name]), ("located", k.name)]
        elif k.state == "held":
            atoms.append(("located", k.name))
    atoms += [("of-category", v, cat) for v, cat in virtual]
    for d in deposits:
        atoms += [("deposit-at", d.name, deposit_waypoint(d.name)), ("accepts", d.name, d.category)]
    atoms += [("closed", d) for d in sorted(belief.closed)]
    names = {k.name for k in seen}
    for d, who in pull_blockers(belief).items():
        atoms += [("pull-blocked", d)] + [("blocks-pull", o, d) for o in who if o in names]
    atoms += [("removal-waypoint", item, w) for item, w in removal.items()]
    for w, p in p_near.items():
        atoms.append(("unexplored", w))
        values.append(("p-item-near", (w,), p))
    if with_map:
        # the shipped tidy.pddl (no domain given) costs moves in seconds; another domain gets the
        # lengths it declares
        lengths = (TRAVEL_TIME,) if domain is None else tuple(f for f in LENGTHS if domain.function(f))
        map_atoms, map_values = _map_part(facts, belief.scenario.robot.speed, lengths)
        atoms += map_atoms
        values += map_values
    objects = [(n, "waypoint") for n in sorted(facts.points)] + [(k.name, "item") for k in seen]
    objects += [(d.name, "deposit") for d in deposits] + [(c, "category") for c in categories]
    named = {n for n, _ in objects} | {v for v, _ in virtual}
    if domain is not None:
        named |= {c.name for c in domain.constants}
    # the domain's own atoms (the scenario's facts, kept by the actions' effects) about objects
    # this problem has: a focused problem leaves out waypoints a fact may name
    atoms += sorted(a for a in belief.memory if a[0] not in VOCABULARY and set(a[1:]) <= named)
    if domain is not None:
        declared = {p for p in {a[0] for a in atoms} if domain.predicate(p) is not None}
        atoms = [a for a in atoms if a[0] in declared]
        values = [v for v in values if domain.function(v[0]) is not None]
    return atoms, values, objects, seen, robot_wp, removal


# id(facts) -> (facts, (speed, the lengths written), atoms, values)
_MAP_PARTS: dict[int, tuple[MapFacts, tuple, list, list]] = {}
_MAP_SETS: dict[int, tuple[MapFacts, Atoms]] = {}  # id(facts) -> (facts, its atoms as a set)
_MAP_PREDICATES = ("path", "blocked", "blocks", "pose-adjustment")  # the atoms _map_part writes


def _map_layers(facts: MapFacts) -> tuple[Atoms, set, set]:
    """``_map_part``'s atoms as (base, added, removed): the atoms of the floor's shared pairs
    (``MapFacts.shared``), kept with them, and what this answer adds and drops; a map put
    together otherwise is all base. After a move only the robot's pairs are new: a turn reads
    those, not the hundred thousand atoms of a 96-object room's pairs."""
    if facts.shared is None or facts.own is None:
        return _map_set(facts), set(), set()
    added = {a for atoms in _by_predicate(facts.own).values() for a in atoms}
    removed = set()
    for a, b in facts.dropped:
        for atom, there in ((("path", a, b), (a, b) in facts.blocked), (("pose-adjustment", a, b), False)):
            if not there:
                added.discard(atom)
                removed.add(atom)
    return _map_set(facts.shared), added, removed


def _by_predicate(facts: MapFacts) -> dict[str, list]:
    return {
        "path": [("path", u, v) for u, v in facts.path] + [("path", u, v) for u, v in facts.blocked],
        "blocked": [("blocked", u, v) for u, v in facts.blocked],
        "blocks": [("blocks", item, u, v) for item, u, v in facts.blocks],
        "pose-adjustment": [("pose-adjustment", u, v) for u, v in facts.adjust],
    }


def _map_set(facts: MapFacts) -> Atoms:
    """``_map_part``'s atoms as a set by predicate, unsorted (sorting a 96-object room's paths
    and blockers for each new map was a twentieth of a mission); kept like the parts."""
    hit = _MAP_SETS.get(id(facts))
    if hit is not None and hit[0] is facts:
        return hit[1]
    if len(_MAP_SETS) >= 4:
        _MAP_SETS.clear()
    parts = {k: frozenset(v) for k, v in _by_predicate(facts).items()}
    _MAP_SETS[id(facts)] = (facts, Atoms(parts))
    return _MAP_SETS[id(facts)][1]


def _map_part(facts: MapFacts, speed: float, lengths: tuple[str, ...]) -> tuple[list, list]:
    """The map's atoms and ``lengths`` (``distance``, ``travel-time``, as the domain declares) in
    order: paths, blocked paths and what blocks them, pose adjustments. Kept for the last few
    maps: the belief hands out one MapFacts while nothing it depends on changes (never edited
    after), and the monitor writes after every action."""
    key = (speed, lengths)
    hit = _MAP_PARTS.get(id(facts))
    if hit is not None and hit[0] is facts and hit[1] == key:
        return hit[2], hit[3]
    atoms: list[tuple[str, ...]] = []
    values: list[tuple[str, tuple[str, ...], float]] = []
    metres, seconds = "distance" in lengths, TRAVEL_TIME in lengths

    def length(u: str, v: str, d: float) -> None:
        if metres:
            values.append(("distance", (u, v), round(d, 2)))
        if seconds:
            values.append((TRAVEL_TIME, (u, v), travel_time(d, speed)))

    for (u, v), d in sorted(facts.path.items()):
        atoms.append(("path", u, v))
        length(u, v, d)
    for (u, v), d in sorted(facts.blocked.items()):
        atoms += [("path", u, v), ("blocked", u, v)]
        length(u, v, d)
    atoms += [("blocks", item, u, v) for item, u, v in sorted(facts.blocks)]
    for (u, v), d in sorted(facts.adjust.items()):
        atoms.append(("pose-adjustment", u, v))
        length(u, v, d)
    if len(_MAP_PARTS) >= 4:
        _MAP_PARTS.clear()
    _MAP_PARTS[id(facts)] = (facts, key, atoms, values)
    return atoms, values


def write(
    belief: Belief,
    facts: MapFacts,
    goal: Sequence[str],
    virtual: Sequence[tuple[str, str]],
    name: str,
    focused: bool = False,
    domain: m.Domain | None = None,
) -> Snapshot:
    """The problem for the items in ``goal`` (seen names and virtual names), built as the model;
    ``focused``: with only the part of the map and the items that goal needs (``focus``).
    With a ``domain``, only what it declares is written (its name, its predicates and functions);
    a predicate it declares beyond the vocabulary comes from ``belief.memory`` (the scenario's
    facts, kept by the domain's own effects) or is false."""
    keep = None
    if focused:
        facts, keep = focus(facts, belief, goal)
    atoms, values, objects, seen, robot_wp, removal = _contents(belief, facts, virtual, keep, domain)
    has_costs = domain is None or domain.has_costs
    problem = m.Problem(
        name=name,
        domain_name=domain.name if domain is not None else "tidy",
        objects=tuple(m.Typed(n, (t,)) for n, t in objects),
        virtual_objects=tuple(m.Typed(v, ("item",)) for v, _ in virtual),
        init=tuple(m.Atom(a[0], a[1:]) for a in dict.fromkeys(atoms)),
        values=((m.FunctionTerm(COST, ()), 0.0),) * has_costs
        + tuple((m.FunctionTerm(f, args), x) for f, args, x in values),
        goal=m.And(goal_atoms(belief, goal, domain)),
        metric=("minimize", m.FunctionTerm(COST, ())) if has_costs else None,
        goal_reward=goal_reward(domain, belief.scenario.robot.speed) if has_costs else None,
    )
    header = (
        f";; {name}: written from the belief state by tidyplan (scenario {belief.scenario.name}).",
        f";; Robot at {robot_wp} {_xy(belief.robot)}; holding {belief.holding or 'nothing'}.",
        ";; Waypoints (name kind x y):",
        *(f";;   {n} {facts.kind[n]} {_xy(facts.points[n])}" for n in sorted(facts.points)),
        *([f";; Out of reach (no grasp pose): {' '.join(facts.unreachable)}"] if facts.unreachable else []),
        ";; Items as believed (name category state x y):",  # read by tidyplan trace --html
        *(f";;   {k.name} {k.category} {k.state} {_xy((k.x, k.y))}" for k in seen),
    )
    state = frozenset(tuple([a.predicate, *a.args]) for a in problem.init)
    return Snapshot(problem, header, facts, tuple(goal), tuple(virtual), robot_wp, removal, state)


def _dist(a, b) -> float:
    return ((a[0] - b[0]) ** 2 + (a[1] - b[1]) ** 2) ** 0.5


def _length(facts: MapFacts, a: str, b_point) -> float | None:
    """Path length from waypoint a to the waypoint at b_point (Algorithm 1's "nearest")."""
    for n, q in facts.points.items():
        if q == b_point:
            return 0.0 if n == a else facts.distance(a, n)
    return None


def _xy(p) -> str:
    return f"{p[0]:.2f} {p[1]:.2f}"
