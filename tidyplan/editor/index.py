"""Where each name of a file is declared and used: the editor's symbol table.

Built from the forgiving s-expression reader (``sexpr``), so a file with a syntax error still
has its names: go to definition, references, the outline and completion work while the user
types. Kinds: ``type``, ``predicate``, ``function``, ``action`` (assumptions too), ``object``
(objects, virtual objects and constants: one namespace, as in PDDL), ``unit``, ``domain`` and
``variable`` (scoped to its action, predicate or quantifier's owner).
"""

from __future__ import annotations

import bisect
import re
from dataclasses import dataclass, field
from typing import NamedTuple

from tidyplan.editor.sexpr import Node, Token, define, read

_NUMBER = re.compile(r"^[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$")
_CONNECTIVES = {"and", "or", "not", "imply", "when", "preference"}
_QUANTIFIERS = {"forall", "exists"}
_NUMERIC_OPS = {"increase", "decrease", "assign", "scale-up", "scale-down"}
_COMPARISONS = {"=", "<", ">", "<=", ">=", "+", "-", "*", "/", "minimize", "maximize"}


class Occurrence(NamedTuple):
    kind: str
    name: str
    token: Token
    definition: bool
    scope: str = ""  # a variable's owner (an action's or a predicate's name)


@dataclass(slots=True)
class ActionInfo:
    """What the outline and hover read off an action as written, even when it does not parse."""

    name: str
    token: Token
    node: Node
    is_assumption: bool
    stratum: str = "1"
    probability: str = "1"


@dataclass(slots=True)
class Index:
    kind: str = ""  # "domain", "problem" or "" (neither: not PDDL yet)
    name: str = ""
    domain_name: str = ""  # a problem's (:domain NAME)
    occurrences: list[Occurrence] = field(default_factory=list)
    actions: list[ActionInfo] = field(default_factory=list)
    sections: list[tuple[str, Node]] = field(default_factory=list)
    tokens: list[Token] = field(default_factory=list)
    top: list = field(default_factory=list)
    _starts: list[int] = field(default_factory=list)
    _by_place: dict[tuple[int, int], Token] = field(default_factory=dict)

    def finish(self) -> None:
        self.occurrences.sort(key=lambda o: o.token.start)
        self._starts = [o.token.start for o in self.occurrences]
        self._by_place = {(t.line, t.col): t for t in self.tokens}

    def at(self, offset: int) -> Occurrence | None:
        """The name whose token holds `offset` (or ends right at it: the cursor after a word)."""
        i = bisect.bisect_right(self._starts, offset) - 1
        if i >= 0 and self.occurrences[i].token.start <= offset <= self.occurrences[i].token.end:
            return self.occurrences[i]
        return None

    def token_at(self, line: int, col: int) -> Token | None:
        return self._by_place.get((line, col))

    def definitions(self, kind: str, name: str, scope: str = "") -> list[Occurrence]:
        return [
            o
            for o in self.occurrences
            if o.definition and o.kind == kind and o.name == name and (kind != "variable" or o.scope == scope)
        ]

    def uses(self, kind: str, name: str, scope: str = "") -> list[Occurrence]:
        return [
            o
            for o in self.occurrences
            if o.kind == kind and o.name == name and (kind != "variable" or o.scope == scope)
        ]

    def names(self, kind: str) -> list[str]:
        return list(dict.fromkeys(o.name for o in self.occurrences if o.definition and o.kind == kind))

    def action(self, name: str) -> ActionInfo | None:
        return next((a for a in self.actions if a.name == name), None)


def build(text: str) -> Index:
    top, toks = read(text)
    ix = Index(tokens=toks, top=top)
    d = define(top)
    if d is not None:
        _Walker(ix).define(d)
    ix.finish()
    return ix


class _Walker:
    def __init__(self, ix: Index) -> None:
        self.ix = ix

    def add(self, kind: str, token: Token, definition: bool = False, scope: str = "") -> None:
        if kind == "object" and (_NUMBER.match(token.text) or token.text.startswith(":")):
            return
        self.ix.occurrences.append(Occurrence(kind, token.text, token, definition, scope))

    def define(self, d: Node) -> None:
        for item in d.items[1:]:
            if not isinstance(item, Node) or item.head is None:
                continue
            head, rest = item.head.text, item.items[1:]
            name = rest[0] if rest and isinstance(rest[0], Token) else None
            if head in ("domain", "problem") and name is not None:
                self.ix.kind, self.ix.name = head, name.text
                self.add("domain" if head == "domain" else "problem", name, definition=True)
                continue
            self.ix.sections.append((head, item))
            if head == ":domain" and name is not None:
                self.ix.domain_name = name.text
                self.add("domain", name)
            elif head == ":types":
                self.typed(rest, "type")
            elif head in (":constants", ":objects", ":virtual-objects"):
                self.typed(rest, "object")
            elif head in (":predicates", ":functions"):
                kind = "predicate" if head == ":predicates" else "function"
                for decl in rest:
                    if isinstance(decl, Node) and decl.head is not None:
                        self.add(kind, decl.head, definition=True)
                        self.typed(decl.items[1:], "variable", scope=decl.head.text)
            elif head in (":action", ":assumption") and name is not None:
                self.action(item, name, head == ":assumption")
            elif head in (":init", ":goal", ":metric"):
                for part in rest:
                    if isinstance(part, Node):
                        self.formula(part, "")

    def typed(self, items: list, kind: str, scope: str = "") -> None:
        """`a b - t c - (either u v) d`: the names are declared, the types used."""
        after_minus = False
        for item in items:
            if isinstance(item, Token) and item.text == "-":
                after_minus = True
                continue
            if after_minus:
                after_minus = False
                if isinstance(item, Token):
                    if item.text != "number":  # a function's value type
                        self.add("type", item)
                else:
                    for t in item.items[1:]:
                        if isinstance(t, Token):
                            self.add("type", t)
                continue
            if isinstance(item, Token):
                if item.text.startswith("?"):
                    self.add("variable", item, definition=True, scope=scope)
                elif kind != "variable":
                    self.add(kind, item, definition=True)

    def action(self, node: Node, name: Token, is_assumption: bool) -> None:
        info = ActionInfo(name.text, name, node, is_assumption)
        self.ix.actions.append(info)
        self.add("action", name, definition=True)
        items = node.items[2:]
        for i, key in enumerate(items):
            if not isinstance(key, Token) or not key.text.startswith(":") or i + 1 >= len(items):
                continue
            value = items[i + 1]
            if key.text == ":parameters" and isinstance(value, Node):
                self.typed(value.items, "variable", scope=name.text)
            elif key.text in (":precondition", ":effect") and isinstance(value, Node):
                self.formula(value, name.text)
            elif key.text == ":probability":
                if isinstance(value, Node):
                    self.term(value, name.text)
                    info.probability = _source(value)
                else:
                    info.probability = value.text
            elif key.text == ":stratum" and isinstance(value, Token):
                info.stratum = value.text
            elif key.text == ":units" and isinstance(value, Node):
                calls = [value] if value.head is not None else value.items
                for call in calls:
                    if isinstance(call, Node) and call.head is not None:
                        self.add("unit", call.head)
                        self.args(call.items[1:], name.text)

    def args(self, items: list, scope: str) -> None:
        for a in items:
            if isinstance(a, Token):
                self.add("variable" if a.text.startswith("?") else "object", a, scope=scope)
            else:
                self.term(a, scope)

    def term(self, node: Node, scope: str) -> None:
        """A function term, or a numeric expression over them."""
        head = node.head
        if head is None:
            return
        if head.text in _COMPARISONS:
            for part in node.items[1:]:
                if isinstance(part, Node):
                    self.term(part, scope)
            return
        self.add("function", head)
        self.args(node.items[1:], scope)

    def formula(self, node: Node, scope: str) -> None:
        head = node.head
        if head is None:
            return
        rest = node.items[1:]
        if head.text in _CONNECTIVES:
            for part in rest:
                if isinstance(part, Node):
                    self.formula(part, scope)
        elif head.text in _QUANTIFIERS:
            if rest and isinstance(rest[0], Node):
                self.typed(rest[0].items, "variable", scope=scope)
            for part in rest[1:]:
                if isinstance(part, Node):
                    self.formula(part, scope)
        elif head.text in _NUMERIC_OPS or head.text in _COMPARISONS:
            for part in rest:
                if isinstance(part, Node):
                    self.term(part, scope)
                else:
                    self.args([part], scope)
        else:
            self.add("predicate", head)
            self.args(rest, scope)


def _source(node: Node) -> str:
    parts: list[str] = []

    def walk(n: Node) -> None:
        parts.append("(")
        for i, item in enumerate(n.items):
            if i:
                parts.append(" ")
            if isinstance(item, Token):
                parts.append(item.text)
            else:
                walk(item)
        parts.append(")")

    walk(node)
    return "".join(parts)
