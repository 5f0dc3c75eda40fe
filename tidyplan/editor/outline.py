"""The outline of a file: types, predicates, functions, actions grouped by stratum, assumptions;
for a problem its objects, virtual objects, init and goal."""

from __future__ import annotations

from tidyplan.editor.diagnose import Range
from tidyplan.editor.sexpr import Node


def outline(doc) -> list:
    from tidyplan.editor.answers import Symbol, _node_range, _range

    ix, text = doc.index, doc.text
    out: list[Symbol] = []

    def group(label: str, node: Node, kind: str, names: list, detail: str = "") -> None:
        kids = tuple(Symbol(t.text, kind, _range(t), _range(t)) for t in names)
        r = _node_range(node, text)
        out.append(Symbol(label, "group", r, _range(node.head), detail or f"{len(kids)}", kids))

    for head, node in ix.sections:
        if head in (":types", ":constants", ":objects", ":virtual-objects"):
            kind = "type" if head == ":types" else "object"
            names = [
                o.token for o in ix.occurrences if o.definition and o.kind == kind and _inside(o.token, node)
            ]
            group(head[1:], node, kind, names)
        elif head in (":predicates", ":functions"):
            kind = head[1:-1]
            names = [
                o.token for o in ix.occurrences if o.definition and o.kind == kind and _inside(o.token, node)
            ]
            group(head[1:], node, kind, names)
        elif head in (":init", ":goal"):
            out.append(
                Symbol(
                    head[1:], "group", _node_range(node, text), _range(node.head), f"{len(node.items) - 1}"
                )
            )
    strata: dict[str, list] = {}
    assumptions = []
    for a in ix.actions:
        detail = f"P{a.stratum}, p {a.probability}"
        s = Symbol(
            a.name,
            "assumption" if a.is_assumption else "action",
            _node_range(a.node, text),
            _range(a.token),
            detail,
        )
        (assumptions if a.is_assumption else strata.setdefault(a.stratum, [])).append(s)
    for stratum in sorted(strata, key=lambda k: (not k.isdigit(), int(k) if k.isdigit() else 0, k)):
        kids = strata[stratum]
        out.append(_wrap(f"stratum P{stratum}", "group", kids, f"{len(kids)} actions"))
    if assumptions:
        out.append(_wrap("assumptions", "group", assumptions, f"{len(assumptions)}"))
    return out


def _wrap(label, kind, kids, detail):
    from tidyplan.editor.answers import Symbol

    first, last = kids[0].range, max((k.range for k in kids), key=lambda r: (r.end_line, r.end_col))
    r = Range(first.line, first.col, last.end_line, last.end_col)
    return Symbol(label, kind, r, kids[0].selection, detail, tuple(kids))


def _inside(t, node: Node) -> bool:
    return node.open.start < t.start < node.end
