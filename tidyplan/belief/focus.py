"""The map the monitor checks a plan against: the pairs of the plan's own waypoints, not the room's.

After every action the monitor simulates the rest of the plan over the belief (Brenner & Nebel's
monitoring). A step of the shipped domain asks the map about its own waypoints only: a move for
``path``/``blocked`` of its two ends, a take deletes ``blocked`` for the pairs its item frees (of
which only those a later step asks about matter), a move's shortcut test asks for a pose
adjustment out of its end and the removal waypoint of the item in the hand. So the state need
hold the map's atoms among the waypoints the steps name (and the pairs those tests reach), each
as the whole map has it: the simulation then gives what it gives over the whole room, at the
cost of the plan instead of the room's hundred waypoints' ten thousand pairs.

``focus_safe`` tells whether a domain's actions ask no more than that; where not (derived
predicates, a quantifier over waypoints in a map atom), the monitor uses the whole map.
"""

from __future__ import annotations

from collections.abc import Iterable

from tidyplan.belief.mapfacts import ENTRANCE, MapFacts
from tidyplan.belief.problem import NOT_FOR_REMOVAL
from tidyplan.belief.state import Belief
from tidyplan.pddl import model as m

# the map's predicates over waypoints: a quantifier over a waypoint in one of these would ask
# about pairs beyond the steps' own
PAIR_PREDICATES = ("path", "blocked", "blocks", "removal-waypoint")
ADJUST = "pose-adjustment"


def focus_safe(domain: m.Domain) -> bool:
    """Whether every atom of the map an action of ``domain`` asks about, or changes in a way a
    later step can see, names the step's own waypoints: no derived predicates; a quantified
    variable in a map atom only in ``(forall (..) (when (static atom) literals))`` (a take's
    freed paths) or as the far end of a pose adjustment out of a step's waypoint."""
    if domain.derived:
        return False
    return all(_safe_formula(a.precondition, frozenset()) and _safe_effect(a.effect) for a in domain.actions)


def _safe_formula(f, bound: frozenset[str]) -> bool:
    if isinstance(f, m.Atom):
        if f.predicate in (*PAIR_PREDICATES, ADJUST) and any(not a.startswith("?") for a in f.args):
            return False  # a constant names a waypoint no step's arguments do
        quantified = [a for a in f.args if a in bound]
        if not quantified:
            return True
        if f.predicate == ADJUST:  # the far end only: its partners are in the focus
            return len(f.args) == 2 and f.args[0] not in bound
        return f.predicate not in PAIR_PREDICATES
    if isinstance(f, (m.And, m.Or)):
        return all(_safe_formula(p, bound) for p in f.parts)
    if isinstance(f, m.Not):
        return _safe_formula(f.part, bound)
    if isinstance(f, m.Imply):
        return _safe_formula(f.condition, bound) and _safe_formula(f.consequence, bound)
    if isinstance(f, m.Exists):
        # an item in the hand: (exists (?o) (and (holding ?o) .. (removal-waypoint ?o ?w))) asks
        # about the held item alone, whose removal waypoint the focus writes
        parts = f.body.parts if isinstance(f.body, m.And) else (f.body,)
        held = {p.args[0] for p in parts if isinstance(p, m.Atom) and p.predicate == "holding" and p.args}
        quantified = {v.name for v in f.variables} - held
        return _safe_formula(f.body, bound | quantified)
    if isinstance(f, m.Forall):
        return _safe_formula(f.body, bound | {v.name for v in f.variables})
    return False  # a formula this check does not know: not shown safe


def _safe_effect(e) -> bool:
    if isinstance(e, (m.Literal, m.Increase)):
        return True
    if isinstance(e, m.AndEffect):
        return all(_safe_effect(p) for p in e.parts)
    if isinstance(e, m.When):
        return _safe_formula(e.condition, frozenset()) and _safe_effect(e.effect)
    if isinstance(e, m.ForallEffect):
        body = e.effect
        if not isinstance(body, m.When) or not _literals(body.effect):
            return False
        bound = frozenset(v.name for v in e.variables)
        # a take's freed paths: where the condition reads pairs beyond the focus, the effect
        # must change only the map's atoms, which no later step asks about beyond it
        return _safe_formula(body.condition, bound) or all(
            lit.atom.predicate in (*PAIR_PREDICATES, ADJUST) for lit in _literal_parts(body.effect)
        )
    return False


def _literals(e) -> bool:
    if isinstance(e, m.Literal):
        return True
    return isinstance(e, m.AndEffect) and all(_literals(p) for p in e.parts)


def _literal_parts(e):
    if isinstance(e, m.Literal):
        yield e
    else:
        for p in e.parts:
            yield from _literal_parts(p)


def focus(belief: Belief, poses: MapFacts, names: Iterable[str]) -> frozenset[str]:
    """The waypoints whose pairs the monitor needs for steps naming ``names``: those of them
    that are waypoints, the entrance, Algorithm 1's candidates (the removal waypoint of an item
    in the hand is the nearest of them), and each pose adjustment's other end (the robot's own
    waypoint and its pairs come with every answer)."""
    among = {n for n in names if n in poses.points}
    among.add(ENTRANCE)
    among |= {n for n, kind in poses.kind.items() if n in belief.reached and kind not in NOT_FOR_REMOVAL}
    for n in list(among):
        if n + "-base" in poses.points:
            among.add(n + "-base")
        if n.endswith("-base"):
            among.add(n[: -len("-base")])
    return frozenset(among)
