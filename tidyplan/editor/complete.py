"""Completion: the dialect's keywords, the declared predicates, functions, types and objects, and
inside `:units` the behaviour units with their arguments."""

from __future__ import annotations

from tidyplan.editor.sexpr import Node


def complete(ws, doc, offset: int) -> list:
    from tidyplan.editor.answers import (
        DOMAIN_KEYWORDS,
        FORM_KEYWORDS,
        PROBLEM_KEYWORDS,
        REQUIREMENTS,
        Completion,
    )

    chain = ws.enclosing(doc, offset)
    prev = _previous(doc, offset)
    related = ws._related(doc)
    if _in_section(chain, ":units", doc):
        from tidyplan.exec.binding_check import offered

        return [
            Completion(
                s.name,
                "unit",
                f"{s.signature}: {s.summary} ({', '.join(w) or 'no world'})",
                s.name + "".join(f" ${{{i}:{role}}}" for i, (role, _) in enumerate(s.parameters, 1)),
            )
            for s, w in offered()
        ]
    if prev == "-" or (chain and chain[-1].head is not None and chain[-1].head.text == "either"):
        return [Completion(t, "type") for d in related for t in d.index.names("type")] + [
            Completion("object", "type")
        ]
    if chain and chain[-1].head is not None and chain[-1].head.text == ":requirements":
        return [Completion(r, "keyword") for r in REQUIREMENTS]
    out: list[Completion] = []
    keywords = PROBLEM_KEYWORDS if doc.index.kind == "problem" else DOMAIN_KEYWORDS
    out += [Completion(k, "keyword") for k in (*keywords, *FORM_KEYWORDS)]
    for d in related:
        for kind in ("predicate", "function"):
            for o in d.index.occurrences:
                if o.definition and o.kind == kind:
                    out.append(Completion(o.name, kind, _form(d, o)))
        out += [Completion(n, "object") for n in d.index.names("object")]
        out += [Completion(n, "type") for n in d.index.names("type")]
    scope = next((a.name for a in doc.index.actions if a.node in chain), None)
    if scope:
        out += [
            Completion(o.name, "variable")
            for o in doc.index.occurrences
            if o.definition and o.kind == "variable" and o.scope == scope
        ]
    seen: set[tuple[str, str]] = set()
    return [c for c in out if (c.label, c.kind) not in seen and not seen.add((c.label, c.kind))]


def _form(d, o) -> str:
    node = next((n for n in _nodes(d.index.top) if n.head is o.token), None)
    return d.text[node.open.start : node.end] if node else o.name


def _nodes(items):
    for x in items:
        if isinstance(x, Node):
            yield x
            yield from _nodes(x.items)


def _previous(doc, offset: int) -> str:
    """The token before the word being typed."""
    toks = [t for t in doc.index.tokens if t.end <= offset]
    if toks and toks[-1].end == offset and toks[-1].text not in ("(", ")", "-"):
        toks = toks[:-1]  # the word being typed itself
    return toks[-1].text if toks else ""


def _in_section(chain: list[Node], key: str, doc) -> bool:
    """Inside the value of `key` in the innermost action of `chain`."""
    for i, n in enumerate(chain):
        items = n.items
        for j, x in enumerate(items[:-1]):
            if (
                not isinstance(x, Node)
                and x.text == key
                and i + 1 < len(chain)
                and items[j + 1] is chain[i + 1]
            ):
                return True
    return False
