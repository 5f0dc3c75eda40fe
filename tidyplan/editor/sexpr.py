"""A forgiving s-expression reader for the editor: tokens and nested lists with their places.

The dialect reader (``tidyplan.pddl.reader``) stops at the first syntax error; an editor must
still find names, sections and their places in a file that is half typed. This reader never
fails: a ')' that closes nothing is skipped, a '(' never closed is closed at the end of the text.
Lines and columns are 0-based here, as the Language Server Protocol counts them.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from functools import lru_cache
from typing import NamedTuple

_TOKEN = re.compile(r";[^\n]*|[()]|[^\s();]+")


class Token(NamedTuple):
    text: str  # lower case: PDDL names are case-insensitive
    start: int  # offset in the text
    end: int
    line: int
    col: int
    end_col: int  # a token never spans lines


@dataclass(slots=True)
class Node:
    """A parenthesised list: `open` is its '(' token, `close` its ')' (None: never closed)."""

    open: Token
    items: list[Token | Node] = field(default_factory=list)
    close: Token | None = None

    @property
    def head(self) -> Token | None:
        first = self.items[0] if self.items else None
        return first if isinstance(first, Token) else None

    @property
    def end(self) -> int:
        if self.close is not None:
            return self.close.end
        last = self.items[-1] if self.items else self.open
        return last.end if isinstance(last, Token) else last.end


def tokens(text: str) -> list[Token]:
    out: list[Token] = []
    start = 0
    for line, text_line in enumerate(text.split("\n")):
        for s, col, end in _line_tokens(text_line):
            out.append(Token(s, start + col, start + end, line, col, end))
        start += len(text_line) + 1
    return out


@lru_cache(maxsize=1 << 16)
def _line_tokens(line: str) -> tuple[tuple[str, int, int], ...]:
    """One line's tokens (lower case, start and end column); lines repeat and most do not
    change between two keystrokes, so they are remembered."""
    out = []
    for mt in _TOKEN.finditer(line):
        s = mt.group()
        if s[0] == ";":
            break
        out.append((s.lower(), mt.start(), mt.end()))
    return tuple(out)


def read(text: str) -> tuple[list[Token | Node], list[Token]]:
    """The top-level forms of the text, and every token in order."""
    toks = tokens(text)
    top: list[Token | Node] = []
    stack: list[Node] = []
    for t in toks:
        if t.text == "(":
            node = Node(t)
            (stack[-1].items if stack else top).append(node)
            stack.append(node)
        elif t.text == ")":
            if stack:
                stack.pop().close = t
        else:
            (stack[-1].items if stack else top).append(t)
    return top, toks


def define(top: list[Token | Node]) -> Node | None:
    for item in top:
        if isinstance(item, Node) and item.head is not None and item.head.text == "define":
            return item
    return None


def header(text: str) -> tuple[str, str] | None:
    """`("domain", NAME)` or `("problem", NAME)` with, for a problem, its domain's name instead
    of its own: what matching a problem to its domain needs, read from the first forms only."""
    top, _ = read(text)
    d = define(top)
    if d is None or len(d.items) < 2 or not isinstance(d.items[1], Node):
        return None
    first = d.items[1]
    kind = first.head.text if first.head else ""
    if kind == "domain" and len(first.items) > 1 and isinstance(first.items[1], Token):
        return ("domain", first.items[1].text)
    if kind == "problem":
        for item in d.items[2:]:
            if isinstance(item, Node) and item.head and item.head.text == ":domain" and len(item.items) > 1:
                name = item.items[1]
                if isinstance(name, Token):
                    return ("problem", name.text)
        return ("problem", "")
    return None


def enclosing(items: list[Token | Node], offset: int) -> list[Node]:
    """The lists that contain `offset`, outermost first."""
    chain: list[Node] = []
    level = items
    while True:
        for item in level:
            if not isinstance(item, Node):
                continue
            end = item.end if item.close is not None else 1 << 62  # never closed: to the end
            if item.open.start < offset <= end:
                chain.append(item)
                level = item.items
                break
        else:
            return chain
