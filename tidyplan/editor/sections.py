"""Read a domain section by section, remembering each: the incremental part of the diagnostics.

Reading a 2,000-line domain with the dialect's parser takes about 100 ms; a keystroke changes
one section. Each action is read alone, inside a text that holds only ``(define (domain N)`` and
that action, laid at the very line and column it has in the file (whitespace before it), so the
model's positions are the file's; the declarations are read the same way, apart from the
actions. Each piece is remembered by its text and place, so after a keystroke only the section
that changed is read again. The pieces make the same `Domain` the whole file makes: an action
sees nothing of the others when it is read (the grammar has no context), and the checks
(``tidyplan.pddl.check``) run on the whole model afterwards.
"""

from __future__ import annotations

from functools import lru_cache

from tidyplan.editor.sexpr import Node, Token
from tidyplan.pddl import model as m

_ACTIONS = (":action", ":assumption")


def splittable(define: Node, text: str) -> bool:
    """A domain whose `define` holds nothing but whole sections, and nothing after it."""
    if (
        define.close is None
        or text[define.close.end :].strip(" \t\r\n")
        and not _only_comments(text[define.close.end :])
    ):
        return False
    items = define.items[1:]
    return (
        bool(items)
        and all(isinstance(i, Node) and i.close is not None and i.head is not None for i in items)
        and items[0].head.text == "domain"
    )


def _only_comments(rest: str) -> bool:
    return all(not line.strip() or line.lstrip().startswith(";") for line in rest.splitlines())


def read_domain(define: Node, text: str, path: str, skip: frozenset[int] = frozenset()) -> m.Domain:
    """The domain of a `splittable` define, leaving out the sections that start at an offset in
    `skip` (blanked after a syntax error). Raises `PddlError` as the reader does."""
    head = text[define.open.start : define.items[0].end]
    name_node = define.items[1]
    sections = [s for s in define.items[2:] if s.open.start not in skip]
    name = _piece(name_node, text)
    declarations = tuple(_piece(s, text) for s in sections if s.head.text not in _ACTIONS)
    base = _read((_piece_at(define.open, head), name, *declarations), path)
    actions = []
    for s in sections:
        if s.head.text in _ACTIONS:
            actions += _read((_piece_at(define.open, head), name, _piece(s, text)), path).actions
    close = define.close
    assert isinstance(close, Token)
    return m.Domain(
        name=base.name,
        requirements=base.requirements,
        types=base.types,
        constants=base.constants,
        predicates=base.predicates,
        functions=base.functions,
        actions=tuple(actions),
        path=path,
        pos=base.pos,
        derived=base.derived,  # the rules are declarations: read with them
    )


def _piece(node: Node, text: str) -> tuple[int, int, str]:
    return _piece_at(node.open, text[node.open.start : node.end])


def _piece_at(t: Token, source: str) -> tuple[int, int, str]:
    return (t.line, t.col, source)


@lru_cache(maxsize=4096)
def _read(pieces: tuple[tuple[int, int, str], ...], path: str) -> m.Domain:
    from tidyplan.pddl.reader import parse

    return parse(_lay(pieces), path)


def _lay(pieces: tuple[tuple[int, int, str], ...]) -> str:
    """The pieces at their lines and columns, whitespace between, and the define's ')'."""
    out: list[str] = []
    line = col = 0
    for at_line, at_col, source in pieces:
        if at_line > line:
            out.append("\n" * (at_line - line) + " " * at_col)
        else:
            out.append(" " * max(at_col - col, 1 if out else 0))
        out.append(source)
        nl = source.count("\n")
        line += at_line - line + nl
        col = len(source) - source.rfind("\n") - 1 if nl else at_col + len(source)
    out.append(")")
    return "".join(out)
