"""Syntax errors in words a PDDL author reads: where, and what was expected.

Lark's exceptions are turned into `Diagnostic`s here; unbalanced parentheses
get their own search, because the place the parser stops is rarely the place
the parenthesis went missing.
"""

from __future__ import annotations

import lark

from tidyplan.errors import Diagnostic, PddlError

# Levels of '(' a file may nest. The checker, the compiler and the translator recurse once or
# more per level, and Python stops at 1,000 frames; the deepest IPC or shipped file nests 8.
MAX_DEPTH = 100


def open_parentheses(text: str, path: str, stop: int | None = None) -> list[tuple[int, int]]:
    """The '(' still open at offset `stop` (default: the end), outermost first.

    Raises at a ')' that closes nothing: that mistake is unambiguous.
    """
    return scan_parentheses(text, path, stop)[0]


def scan_parentheses(
    text: str, path: str, stop: int | None = None
) -> tuple[list[tuple[int, int]], tuple[int, int] | None]:
    """`open_parentheses`, and where the nesting first goes deeper than MAX_DEPTH (or None),
    found in the same pass over the text."""
    stack: list[tuple[int, int]] = []
    too_deep = None
    line, col = 1, 0
    in_comment = False
    for ch in text if stop is None else text[:stop]:
        col += 1
        if ch == "\n":
            line, col, in_comment = line + 1, 0, False
        elif in_comment:
            continue
        elif ch == ";":
            in_comment = True
        elif ch == "(":
            stack.append((line, col))
            if too_deep is None and len(stack) > MAX_DEPTH:
                too_deep = (line, col)
        elif ch == ")":
            if not stack:
                raise PddlError(Diagnostic(path, line, col, "unbalanced parenthesis: ')' closes nothing"))
            stack.pop()
    return stack, too_deep


def _at_end(e: lark.exceptions.UnexpectedInput) -> bool:
    """Lark's LALR parser reports the end of the text as a `$END` token."""
    token = getattr(e, "token", None)
    return isinstance(e, lark.exceptions.UnexpectedEOF) or getattr(token, "type", None) == "$END"


def never_closed(text: str, path: str, e: lark.exceptions.UnexpectedInput) -> Diagnostic | None:
    """Locate the '(' a section lost its ')' from, when the parser stumbles over it.

    Counting alone cannot tell which '(' lacks its ')'. The parser stops at the
    first token that does not fit, typically the next section's keyword: the
    culprit is the innermost '(' still open before that token's own '('.
    None when no '(' is open where the parser stopped (`x (define`, or a '('
    after the whole define): the parser's own complaint is the first mistake.
    """
    at = getattr(e, "pos_in_stream", None)
    if _at_end(e) or at is None or at < 0:
        stack = open_parentheses(text, path)
    else:
        stack = open_parentheses(text, path, at)
        if text[:at].rstrip().endswith("(") and len(stack) > 1:
            stack = stack[:-1]
    if not stack:
        return None
    line, col = stack[-1]
    where = (
        "" if isinstance(e, lark.exceptions.UnexpectedEOF) else f" (reading stopped at {e.line}:{e.column})"
    )
    return Diagnostic(path, line, col, f"unbalanced parenthesis: '(' is never closed{where}")


_TOKEN_WORDS = {
    "LPAR": "'('",
    "RPAR": "')'",
    "NAME": "a name",
    "VARIABLE": "a variable",
    "NUMBER": "a number",
    "REQUIREMENT": "a requirement",
    "MINUS": "'-'",
    "$END": "end of file",
}


def describe(e: lark.exceptions.UnexpectedInput, text: str, terminals=()) -> str:
    if isinstance(e, lark.exceptions.UnexpectedCharacters):
        return f"unexpected character {text[e.pos_in_stream]!r}"
    if isinstance(e, lark.exceptions.UnexpectedEOF):
        return "unexpected end of file"
    if isinstance(e, lark.exceptions.UnexpectedToken):
        found = e.token
        what = "end of file" if found.type == "$END" else repr(str(found))
        expected = sorted(_TOKEN_WORDS.get(x, _keyword(x, terminals)) for x in (e.expected or ()))
        hint = ""
        if expected and len(expected) <= 6:
            hint = "; expected " + " or ".join(expected)
        return f"unexpected {what}{hint}"
    return str(e).splitlines()[0]


def _keyword(terminal: str, terminals) -> str:
    """Lark names anonymous keyword terminals like `__ANON_3`; make them readable."""
    for t in terminals:
        if t.name == terminal:
            return repr(t.pattern.value)
    return terminal.lower()
