"""`tidyplan check` for text in an editor: every error and warning, each on its range.

The checks are the command line's own (``tidyplan.pddl.check`` and, for a domain that binds
units, ``tidyplan.exec.binding_check``); this module adds what an editor needs beyond them:

- several syntax errors at once. The reader stops at the first; here the top-level section
  holding it is blanked out (spaces, so every place stays where it was) and the text read
  again, up to `MAX_SYNTAX` times. The semantic checks still run when only actions were blanked
  (no declaration is missing, so nothing is reported that the user did not write);
- a range for each message: the token the checker's line and column point at, or, for a message
  with no place, the first token it quotes.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from tidyplan.editor.index import Index
from tidyplan.editor.sections import read_domain, splittable
from tidyplan.editor.sexpr import Node, define
from tidyplan.errors import Diagnostic, PddlError
from tidyplan.pddl import model as m
from tidyplan.pddl.reader import parse

MAX_SYNTAX = 20
_QUOTED = re.compile(r"'([^']+)'")


@dataclass(frozen=True, slots=True)
class Range:
    """0-based, end exclusive: the Language Server Protocol's."""

    line: int
    col: int
    end_line: int
    end_col: int


@dataclass(frozen=True, slots=True)
class Found:
    range: Range
    message: str
    warning: bool = False
    source: str = "tidyplan"


@dataclass(slots=True)
class Checked:
    found: list[Found]
    model: m.Domain | m.Problem | None  # None: the text does not parse even with sections blanked
    complete: bool  # the model is the whole text (no section blanked)


def check(text: str, path: str, ix: Index, domain: m.Domain | None = None) -> Checked:
    """Diagnostics of a domain, or of a problem read against `domain` (None: syntax only)."""
    model, syntax, blanked = _read(text, path, ix)
    found = [_place(d, ix) for d in syntax]
    only_actions = all(k in (":action", ":assumption") for k in blanked)
    if model is not None and only_actions:
        found += [_place(d, ix) for d in _semantic(model, domain)]
    return Checked(found, model, not blanked)


def _read(text: str, path: str, ix: Index):
    """(model or None, the syntax errors, the heads of the sections left out)."""
    errors: list[Diagnostic] = []
    blanked: list[str] = []
    d = define(ix.top)
    sections = [s for s in (d.items if d else []) if isinstance(s, Node)]
    split = d is not None and ix.kind == "domain" and splittable(d, text)
    skip: set[int] = set()
    work = text
    for _ in range(MAX_SYNTAX):
        try:
            if split:
                return read_domain(d, text, path, frozenset(skip)), errors, blanked
            return parse(work, path), errors, blanked
        except PddlError as e:
            errors += e.diagnostics
            if e.diagnostics[0].message.startswith("unbalanced parenthesis"):
                return None, errors, blanked  # the sections after it are guesses: stop here
            where = _offset(work, e.diagnostics[0])
            section = next((s for s in sections if s.open.start <= where < s.end), None)
            if section is None or section.close is None or section.head is None:
                return None, errors, blanked
            sections.remove(section)
            blanked.append(section.head.text)
            skip.add(section.open.start)
            a, b = section.open.start, section.end
            work = work[:a] + re.sub(r"[^\n]", " ", work[a:b]) + work[b:]
        except Exception as e:  # noqa: BLE001 - a reader fault must not take the editor down
            errors.append(Diagnostic(path, 1, 1, f"internal error reading the file: {type(e).__name__}: {e}"))
            return None, errors, blanked
    return None, errors, blanked


def _semantic(model, domain: m.Domain | None) -> list[Diagnostic]:
    from tidyplan.pddl.check import check_domain, check_problem

    if isinstance(model, m.Domain):
        from tidyplan.exec.binding_check import check_bindings

        return check_domain(model) + check_bindings(model)
    if domain is None:
        return []
    return check_problem(model, domain)


def _offset(text: str, d: Diagnostic) -> int:
    if d.line is None:
        return 0
    at = 0
    for _ in range(d.line - 1):
        nl = text.find("\n", at)
        if nl < 0:
            break
        at = nl + 1
    return at + max((d.col or 1) - 1, 0)


def _place(d: Diagnostic, ix: Index) -> Found:
    if d.line is not None:
        line, col = d.line - 1, max((d.col or 1) - 1, 0)
        t = ix.token_at(line, col)
        end = t.end_col if t is not None else col + 1
        return Found(Range(line, col, line, end), d.message, d.warning)
    for name in _QUOTED.findall(d.message):
        t = next((t for t in ix.tokens if t.text == name.lower()), None)
        if t is not None:
            return Found(Range(t.line, t.col, t.line, t.end_col), d.message, d.warning)
    return Found(Range(0, 0, 0, 1), d.message, d.warning)
