"""What the editor shows over a name: an action's signature, probability, stratum, units and cost;
a unit's description and the worlds that offer it; a declaration as written."""

from __future__ import annotations

from tidyplan.editor.index import Occurrence
from tidyplan.editor.sexpr import Node, enclosing
from tidyplan.pddl import model as m


def describe(ws, doc, o: Occurrence) -> str | None:
    related = ws._related(doc)
    if o.kind == "unit":
        return _unit(o.name)
    if o.kind == "action":
        for d in related:
            info = d.index.action(o.name)
            if info is not None:
                return _action(d, info)
        return None
    if o.kind == "variable":
        decl = doc.index.definitions("variable", o.name, o.scope)
        if decl:
            return f"variable `{o.name}` of `{o.scope}`: {_declared(doc, decl[0])}"
        return f"variable `{o.name}` (not declared in `{o.scope}`)"
    for d in related:
        decl = d.index.definitions(o.kind, o.name)
        if decl:
            where = "" if d is doc else f"\n\n(in {d.path})"
            return f"{o.kind} `{o.name}`\n```pddl\n{_declared(d, decl[0])}\n```{where}"
    return f"{o.kind} `{o.name}`: not declared"


def _declared(doc, o: Occurrence) -> str:
    """The declaration as written: the predicate's form, or a typed list's entry with its type."""
    chain = enclosing(doc.index.top, o.token.start + 1)
    inner = chain[-1] if chain else None
    if inner is None:
        return o.name
    if o.kind in ("predicate", "function"):
        return doc.text[inner.open.start : inner.end]
    items = inner.items
    at = next((i for i, x in enumerate(items) if x == o.token), None)
    if at is None:
        return o.name
    for i in range(at + 1, len(items)):
        x = items[i]
        if not isinstance(x, Node) and x.text == "-" and i + 1 < len(items):
            t = items[i + 1]
            return f"{o.name} - {doc.text[t.open.start : t.end] if isinstance(t, Node) else t.text}"
    return f"{o.name} - object" if o.kind != "type" else f"{o.name} - object (a type)"


def _unit(name: str) -> str:
    from tidyplan.exec.binding_check import offered

    for spec, worlds in offered():
        if spec.name == name:
            return (
                f"behaviour unit `{spec.signature}`\n\n{spec.summary}\n\n"
                f"offered by: {', '.join(worlds) or 'no world'}; calls the skills {', '.join(spec.skills)}"
            )
    return f"`{name}`: not a behaviour unit of the catalogue"


def _action(d, info) -> str:
    kind = "assumption" if info.is_assumption else "action"
    model = d.last_model if isinstance(d.last_model, m.Domain) else None
    a = model.action(info.name) if model else None
    if a is None:  # the file does not read now: what is written
        params = next(
            (
                d.text[v.open.start : v.end]
                for k, v in zip(info.node.items, info.node.items[1:], strict=False)
                if not isinstance(k, Node) and k.text == ":parameters" and isinstance(v, Node)
            ),
            "()",
        )
        return f"{kind} `{info.name}` {params}\n\nstratum P{info.stratum} · probability {info.probability}"
    params = " ".join(f"{p.name} - {p.type_text}" for p in a.parameters)
    p = a.probability
    prob = f"{p:g}" if isinstance(p, float) else _term(p)
    lines = [
        f"{kind} `{a.name}`",
        f"```pddl\n({a.name} {params})\n```".replace(" )", ")"),
        f"stratum **P{a.stratum}** · probability **{prob}** · cost **{_cost(a, model)}**",
    ]
    if a.units is not None:
        units = " ".join(f"({u.unit}{''.join(' ' + x for x in u.args)})" for u in a.units)
        lines.append(f"units: {units or 'none'}")
    elif not a.is_assumption:
        lines.append("units: none (not executable)")
    return "\n\n".join(lines)


def _term(t: m.FunctionTerm) -> str:
    return f"({t.name}{''.join(' ' + x for x in t.args)})"


def _cost(a: m.Action, domain: m.Domain) -> str:
    found: list[str] = []

    def walk(e) -> None:
        if isinstance(e, m.Increase) and e.target.name == "total-cost":
            found.append(f"{e.amount:g}" if isinstance(e.amount, float) else _term(e.amount))
        elif isinstance(e, m.AndEffect):
            for part in e.parts:
                walk(part)
        elif isinstance(e, (m.When, m.ForallEffect)):
            walk(e.effect)

    walk(a.effect)
    if found:
        return " + ".join(found)
    return "0 (an assumption)" if a.is_assumption else "1 (no cost effect)"
