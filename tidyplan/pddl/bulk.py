"""The bulk of a problem file, read without lark: the `:init` section's flat facts.

A big problem file is mostly `(:init ...)`: on a generated 40x40 visit-all grid (271 KB) it is
31,000 of 39,000 tokens, and lark's LALR parser spends about 6 µs a token on them (its lexer
3.5 µs, the parser's state machine and our callbacks the rest). Here a section made only of
atoms `(p a ?x)` and values `(= (f a) 3)` is matched one item at a time by a compiled regex
built from the grammar's own terminals, and its model values (with their positions) made
directly; the section's text is then blanked (spaces, newlines kept, so every other position is
the same) and lark reads the rest. Anything else, and any trouble, is left to lark reading the
whole text (`reader.parse`), so every diagnostic still comes from the one place.

Measured (`reader.parse` in one process, the fastest of 7, 2026-12-04): the 40x40 grid 229 ms
with lark alone, 69 ms with this (23 here, 46 in lark for the rest: objects and goal); the
corpus's nomystery p01 (108 KB, 3,700 facts) 134 ms to 17 ms. Lark's own options do not get
there: `lexer="basic"` is no faster (265 ms) and would read a predicate called `domain` as the
keyword; positions are not propagated already, and the grammar is cached.

Why the regex reads exactly what lark reads: names, variables and numbers are lark's own
patterns, each in an atomic group (lark's lexer takes the longest match of one terminal and
never splits it again); whitespace and comments are lark's WS and COMMENT. A ';' always starts
a comment for lark (no other terminal holds one), and '(' is always a token of its own, so a
'(' then ':init' found outside a comment is the one the grammar's `init` rule reads, if the
text parses at all. `reader.parse` checks that the blanked parse has exactly one, empty, init
section before it puts these facts there, and tests/test_bulk.py holds the two paths equal.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from functools import lru_cache

from tidyplan.pddl import model as m


@dataclass(frozen=True, slots=True)
class Init:
    """What the fast path read: the text with the section's body blanked, and the section."""

    text: str
    atoms: tuple[m.Atom, ...]
    values: tuple[tuple[m.FunctionTerm, float], ...]


@dataclass(frozen=True, slots=True)
class _Patterns:
    opening: re.Pattern  # a comment, or '(' ':init' (group 1)
    item: re.Pattern  # separators, then one atom or one value
    close: re.Pattern  # separators, then the section's ')'
    comment: re.Pattern
    term: re.Pattern


@lru_cache(maxsize=4)
def _patterns(terminals: tuple[tuple[str, str], ...]) -> _Patterns:
    t = dict(terminals)
    sep = f"(?:{t['WS']}|{t['COMMENT']})*+"
    name, var, number = f"(?>{t['NAME']})", f"(?>{t['VARIABLE']})", f"(?>{t['NUMBER']})"
    args = f"(?:{sep}(?:{name}|{var}))*+"
    atom = rf"\({sep}(?P<p>{name})(?P<pa>{args}){sep}\)"
    value = rf"\({sep}={sep}\({sep}(?P<f>{name})(?P<fa>{args}){sep}\){sep}(?P<n>{number}){sep}\)"
    return _Patterns(
        opening=re.compile(rf"{t['COMMENT']}|(\({sep}{t['INIT']})"),
        item=re.compile(f"{sep}(?:{atom}|{value})"),
        close=re.compile(rf"{sep}\)"),
        comment=re.compile(t["COMMENT"]),
        term=re.compile(f"{name}|{var}"),
    )


def split_init(text: str, terminals: tuple[tuple[str, str], ...]) -> Init | None:
    """The `:init` section read here, or None: no such section, more than one, or one holding
    anything but flat atoms and values. `terminals` are (name, regex) of the grammar's NAME,
    VARIABLE, NUMBER, WS, COMMENT and INIT (the `:init` keyword)."""
    p = _patterns(terminals)
    openings = [mt.end() for mt in p.opening.finditer(text) if mt.group(1)]
    if len(openings) != 1:
        return None
    start = at = openings[0]
    atoms: list[m.Atom] = []
    values: list[tuple[m.FunctionTerm, float]] = []
    # the line at offset `counted`, and the offset of the '\n' before it (-1 on the first line)
    line, counted = 1 + text.count("\n", 0, start), start
    newline = text.rfind("\n", 0, start)
    item, term, comment = p.item.match, p.term.findall, p.comment
    while mt := item(text, at):
        at = mt.end()
        name = mt.group("p")
        begin = mt.start("p" if name is not None else "f")
        if more := text.count("\n", counted, begin):  # searched since the last item only
            line += more
            newline = text.rfind("\n", counted, begin)
        counted = begin
        pos = m.Pos(line, begin - newline)
        raw = mt.group("pa" if name is not None else "fa")
        if ";" in raw:  # a comment between the arguments: its words are not arguments
            raw = comment.sub(" ", raw)
        args = tuple(term(raw.lower()))
        if name is not None:
            atoms.append(m.Atom(name.lower(), args, pos))
        else:
            values.append((m.FunctionTerm(mt.group("f").lower(), args, pos), float(mt.group("n"))))
    end = p.close.match(text, at)
    if end is None:
        return None
    body = text[start : end.end() - 1]
    blank = "\n".join(" " * len(part) for part in body.split("\n"))
    return Init(text[:start] + blank + text[end.end() - 1 :], tuple(atoms), tuple(values))
