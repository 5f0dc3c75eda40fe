"""Checks that a domain can be run, before anything runs: each executable action bound to units of
the catalogue (``tidyplan.exec.catalogue``) with arguments of the right kind, and the words the
worlds' problems are written in (``tidyplan.belief.vocabulary``) declared as the writer uses them.

``tidyplan check DOMAIN`` prints these diagnostics beside the dialect's own; ``tidyplan run
--domain FILE`` refuses a domain with any error among them, exit 2, before a world is made. A
domain that binds no action at all is a planning domain (the IPC corpus): ``check`` says so on
its summary line, ``run`` refuses it.
"""

from __future__ import annotations

from tidyplan.belief.vocabulary import GOAL, VOCABULARY, VOCABULARY_FUNCTIONS, VOCABULARY_TYPES
from tidyplan.errors import Diagnostic
from tidyplan.exec.catalogue import UNITS, UnitSpec
from tidyplan.pddl import model as m


def check_bindings(domain: m.Domain, for_run: bool = False) -> list[Diagnostic]:
    """Every unbound action, unknown unit and wrong argument, as ``path:line:col: what``.
    ``for_run``: an action without ``:units`` is an error even when none has them."""
    out: list[Diagnostic] = []

    def say(pos: m.Pos, message: str) -> None:
        out.append(Diagnostic(domain.path, pos.line or None, pos.col or None, message))

    actions = [a for a in domain.actions if not a.is_assumption]
    if not for_run and not any(a.units is not None for a in domain.actions):
        return out  # a planning domain (the IPC corpus): nothing to check here
    ancestors = _ancestors(domain)
    constants = {c.name: c for c in domain.constants}
    for a in domain.actions:
        if a.is_assumption:
            if a.units is not None:
                say(a.units_pos, f"assumption '{a.name}' is never executed: it takes no :units")
            continue
        if a.units is None:
            say(a.pos, f"action '{a.name}' has no :units: nothing can execute it")
            continue
        if not a.units:
            say(a.units_pos, f"action '{a.name}' runs no unit: give at least one in :units")
        params = {p.name: p for p in a.parameters}
        for call in a.units:
            spec = UNITS.get(call.unit)
            if spec is None:
                say(call.pos, f"unknown unit '{call.unit}' in '{a.name}' (units: {', '.join(UNITS)})")
                continue
            if len(call.args) != len(spec.parameters):
                n = len(spec.parameters)
                say(
                    call.pos,
                    f"unit {spec.signature} takes {n} argument{'s' * (n != 1)}, given {len(call.args)}",
                )
                continue
            for arg, (role, kind) in zip(call.args, spec.parameters, strict=True):
                typed = params.get(arg) if arg.startswith("?") else constants.get(arg)
                if typed is None:
                    what = "a parameter" if arg.startswith("?") else "a constant"
                    say(call.pos, f"'{arg}' in ({call.unit} ...) is not {what} of '{a.name}'")
                elif not all(kind in ancestors.get(t, {t}) for t in typed.types):
                    say(
                        call.pos,
                        f"unit '{call.unit}' takes a {kind} as {role}; '{arg}' is a {typed.type_text}",
                    )
    if for_run or actions:
        out += check_vocabulary(domain)
    return out


def check_vocabulary(domain: m.Domain) -> list[Diagnostic]:
    """The types, predicates and functions the problem writer fills from the belief, where the
    domain declares them, must take the objects it writes; the goal predicate must be there."""
    out: list[Diagnostic] = []

    def error(pos: m.Pos, message: str) -> None:
        out.append(Diagnostic(domain.path, pos.line or None, pos.col or None, message))

    declared = set(domain.type_parents)
    missing = [t for t in VOCABULARY_TYPES if t not in declared]
    if missing:
        error(
            domain.pos,
            f"the worlds' problems have objects of type {', '.join(missing)}: declare them in :types",
        )
        return out
    ancestors = _ancestors(domain)
    words = [(p, VOCABULARY.get(p.name)) for p in domain.predicates]
    words += [(f, VOCABULARY_FUNCTIONS.get(f.name)) for f in domain.functions]
    for decl, kinds in words:
        if kinds is None:
            continue
        fits = len(decl.parameters) == len(kinds) and all(
            all(t in ancestors.get(k, {k}) for t in p.types)
            for p, k in zip(decl.parameters, kinds, strict=True)
        )
        if not fits:
            given = " ".join(p.type_text for p in decl.parameters) or "nothing"
            error(
                decl.pos,
                f"'{decl.name}' is written from the belief with ({' '.join(kinds)}); declared with ({given})",
            )
    if domain.predicate(GOAL) is None:
        error(domain.pos, f"the worlds' goal is ({GOAL} ?o - item): declare the predicate {GOAL}")
    return out


def check_facts(domain: m.Domain, scenario) -> list[Diagnostic]:
    """A scenario's ``facts`` against the domain: each of a predicate it declares, with as many
    arguments, none of the words the writer fills from the belief, each argument a name the
    problems have (a deposit, a category, a viewpoint, a deposit's waypoint) or a constant."""
    from tidyplan.belief.mapfacts import ENTRANCE, deposit_waypoint

    names = {d.name for d in scenario.deposits} | {d.category for d in scenario.deposits}
    names |= {v.name for v in scenario.viewpoints} | {deposit_waypoint(d.name) for d in scenario.deposits}
    names |= {ENTRANCE} | {c.name for c in domain.constants}
    out = []
    for i, (name, *args) in enumerate(scenario.facts):
        atom = "(" + " ".join([name, *args]) + ")"
        p = domain.predicate(name)
        if p is None:
            why = f"the domain declares no predicate {name}"
        elif name in VOCABULARY:
            why = f"{name} is written from the belief, not given"
        elif len(p.parameters) != len(args):
            why = f"{name} takes {len(p.parameters)} arguments, given {len(args)}"
        elif unknown := [a for a in args if a not in names]:
            why = f"{', '.join(unknown)}: not a deposit, category, viewpoint or constant of the room"
        else:
            continue
        out.append(Diagnostic(scenario.path, None, None, f"facts[{i}] {atom}: {why}"))
    return out


def offered() -> list[tuple[UnitSpec, list[str]]]:
    """Each catalogue unit with the worlds that offer every skill it calls (as the registry
    declares them: no world is loaded)."""
    from tidyplan.worlds.registry import WORLDS

    return [(spec, [n for n, w in WORLDS.items() if set(spec.skills) <= w.skills]) for spec in UNITS.values()]


def _ancestors(domain: m.Domain) -> dict[str, set[str]]:
    """Each type with itself and every type above it."""
    parents = domain.type_parents
    out: dict[str, set[str]] = {}
    for t in parents:
        seen, todo = {t}, [t]
        while todo:
            for p in parents.get(todo.pop(), ()):
                if p not in seen:
                    seen.add(p)
                    todo.append(p)
        out[t] = seen
    return out
