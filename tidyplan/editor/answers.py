"""The answers to an editor's questions as plain values (places, outline symbols, completions),
the dialect's keywords, and ranges of tokens and forms."""

from __future__ import annotations

from dataclasses import dataclass

from tidyplan.editor.diagnose import Range
from tidyplan.editor.sexpr import Node, Token


@dataclass(frozen=True, slots=True)
class Place:
    path: str
    range: Range


@dataclass(frozen=True, slots=True)
class Symbol:
    name: str
    kind: str  # type, predicate, function, action, assumption, object, group
    range: Range  # the whole form
    selection: Range  # its name
    detail: str = ""
    children: tuple[Symbol, ...] = ()


@dataclass(frozen=True, slots=True)
class Completion:
    label: str
    kind: str  # keyword, predicate, function, type, object, unit, variable, action
    detail: str = ""
    insert: str = ""


DOMAIN_KEYWORDS = (
    ":requirements :types :constants :predicates :functions :action :assumption :parameters "
    ":precondition :effect :probability :stratum :units".split()
)
PROBLEM_KEYWORDS = ":domain :objects :virtual-objects :init :goal :goal-reward :metric :requirements".split()
FORM_KEYWORDS = "and or not imply exists forall when increase either define domain problem".split()
REQUIREMENTS = sorted(
    ":strips :typing :negative-preconditions :disjunctive-preconditions :equality "
    ":existential-preconditions :universal-preconditions :quantified-preconditions "
    ":conditional-effects :adl :action-costs :constants :probabilities :assumptions :strata".split()
)


def _range(t: Token) -> Range:
    return Range(t.line, t.col, t.line, t.end_col)


def _node_range(n: Node, text: str) -> Range:
    end = n.close if n.close is not None else None
    if end is None:
        last = n.items[-1] if n.items else n.open
        while isinstance(last, Node):
            last = last.close or (last.items[-1] if last.items else last.open)
        end = last
    return Range(n.open.line, n.open.col, end.line, end.end_col)


def _offset(text: str, line: int, col: int) -> int:
    at = 0
    for _ in range(line):
        nl = text.find("\n", at)
        if nl < 0:
            return len(text)
        at = nl + 1
    return min(at + col, len(text))
