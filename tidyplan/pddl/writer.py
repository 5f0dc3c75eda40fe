"""Model to PDDL text. Writes what Fast Downward, VAL and unified-planning read."""

from __future__ import annotations

from tidyplan.pddl import model as m


def _typed(items: tuple[m.Typed, ...]) -> str:
    return " ".join(f"{t.name} - {t.type_text}" for t in items)


def _num(x: float) -> str:
    return str(int(x)) if float(x).is_integer() else repr(float(x))


def _term(t: m.FunctionTerm) -> str:
    return "(" + " ".join((t.name,) + t.args) + ")"


def formula(f: m.Formula) -> str:
    if isinstance(f, m.Atom):
        return "(" + " ".join((f.predicate,) + f.args) + ")"
    if isinstance(f, m.And):
        return "(and " + " ".join(formula(p) for p in f.parts) + ")" if f.parts else "(and)"
    if isinstance(f, m.Or):
        return "(or " + " ".join(formula(p) for p in f.parts) + ")"
    if isinstance(f, m.Not):
        return f"(not {formula(f.part)})"
    if isinstance(f, m.Imply):
        return f"(imply {formula(f.condition)} {formula(f.consequence)})"
    word = "exists" if isinstance(f, m.Exists) else "forall"
    return f"({word} ({_typed(f.variables)}) {formula(f.body)})"


def effect(e: m.Effect) -> str:
    if isinstance(e, m.Literal):
        return f"(not {formula(e.atom)})" if e.negated else formula(e.atom)
    if isinstance(e, m.AndEffect):
        return "(and " + " ".join(effect(p) for p in e.parts) + ")" if e.parts else "(and)"
    if isinstance(e, m.When):
        return f"(when {formula(e.condition)} {effect(e.effect)})"
    if isinstance(e, m.ForallEffect):
        return f"(forall ({_typed(e.variables)}) {effect(e.effect)})"
    amount = _term(e.amount) if isinstance(e.amount, m.FunctionTerm) else _num(e.amount)
    return f"(increase {_term(e.target)} {amount})"


def domain_text(d: m.Domain) -> str:
    out = [f"(define (domain {d.name})"]
    if d.requirements:
        out.append("  (:requirements " + " ".join(d.requirements) + ")")
    types = [t for t in d.types if t.name != m.ROOT_TYPE]
    if types:
        out.append("  (:types " + _typed(tuple(types)) + ")")
    if d.constants:
        out.append("  (:constants " + _typed(d.constants) + ")")
    out.append("  (:predicates")
    out.extend(
        f"    ({p.name}{' ' if p.parameters else ''}{_typed(_distinct(p.parameters))})" for p in d.predicates
    )
    out.append("  )")
    if d.functions:
        out.append("  (:functions")
        out.extend(
            f"    ({f.name}{' ' if f.parameters else ''}{_typed(f.parameters)}) - number" for f in d.functions
        )
        out.append("  )")
    for r in d.derived:
        head = " ".join((r.predicate, _typed(r.parameters))) if r.parameters else r.predicate
        out.append(f"  (:derived ({head})")
        out.append(f"    {formula(r.body)})")
    for a in d.actions:
        kind = "assumption" if a.is_assumption else "action"
        out.append(f"  (:{kind} {a.name}")
        out.append(f"    :parameters ({_typed(a.parameters)})")
        if a.probability != 1.0:
            p = a.probability
            out.append(f"    :probability {_term(p) if isinstance(p, m.FunctionTerm) else _num(p)}")
        if a.stratum != 1:
            out.append(f"    :stratum {a.stratum}")
        out.append(f"    :precondition {formula(a.precondition)}")
        out.append(f"    :effect {effect(a.effect)})")
    out.append(")")
    return "\n".join(out) + "\n"


def _distinct(params: tuple[m.Typed, ...]) -> tuple[m.Typed, ...]:
    """Predicate parameters with repeated names (`(in ?obj ?obj)`) made distinct."""
    seen: set[str] = set()
    out = []
    for i, p in enumerate(params):
        name = p.name if p.name not in seen else f"{p.name}-{i}"
        seen.add(name)
        out.append(m.Typed(name, p.types, p.pos))
    return tuple(out)


def problem_text(p: m.Problem) -> str:
    out = [f"(define (problem {p.name})", f"  (:domain {p.domain_name})"]
    if p.objects:
        out.append("  (:objects " + _typed(p.objects) + ")")
    if p.virtual_objects:
        out.append("  (:virtual-objects " + _typed(p.virtual_objects) + ")")
    out.append("  (:init")
    out.extend("    " + formula(a) for a in p.init)
    out.extend(f"    (= {_term(t)} {_num(v)})" for t, v in p.values)
    out.append("  )")
    out.append(f"  (:goal {formula(p.goal)})")
    if p.goal_reward is not None:
        out.append(f"  (:goal-reward {_num(p.goal_reward)})")
    if p.metric is not None:
        direction, expr = p.metric
        expr_text = _term(expr) if isinstance(expr, m.FunctionTerm) else _num(expr)
        out.append(f"  (:metric {direction} {expr_text})")
    out.append(")")
    return "\n".join(out) + "\n"
