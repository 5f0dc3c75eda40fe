"""Text to model: the dialect reader.

The grammar (`grammar.lark`) is data; the transformer (`transform.py`) builds
frozen model values from it, bottom-up, inside lark's LALR parser (no parse
tree is built: this is what makes large problem files fast). Lark's errors
become `PddlError` with `path:line:col` here, at the boundary (`syntax.py`
words them), and the semantic checks of `check.py` run on the result.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from functools import lru_cache
from pathlib import Path

import lark

from tidyplan.errors import Diagnostic, PddlError
from tidyplan.pddl import model as m
from tidyplan.pddl.bulk import split_init
from tidyplan.pddl.check import check_domain, check_problem
from tidyplan.pddl.syntax import MAX_DEPTH, describe, never_closed, scan_parentheses
from tidyplan.pddl.transform import Build, paren_before

GRAMMAR = Path(__file__).with_name("grammar.lark")
_MAX_BYTES = 64 * 1024 * 1024  # a PDDL file larger than this is not what the user meant


@lru_cache(maxsize=1)
def _parser() -> lark.Lark:
    return lark.Lark(
        GRAMMAR.read_text(),
        parser="lalr",
        lexer="contextual",
        transformer=Build(),
        maybe_placeholders=False,
        cache=True,
    )


# ---------------------------------------------------------------- the API
def read_text(path: str | os.PathLike) -> str:
    """The file's text, or a `PddlError` saying why it cannot be had."""
    p = str(path)
    try:
        with open(p, "rb") as f:
            data = f.read(_MAX_BYTES + 1)
    except FileNotFoundError:
        raise PddlError(Diagnostic(p, None, None, "no such file")) from None
    except IsADirectoryError:
        raise PddlError(Diagnostic(p, None, None, "is a directory, not a PDDL file")) from None
    except OSError as e:
        raise PddlError(Diagnostic(p, None, None, f"cannot read: {e.strerror}")) from None
    if len(data) > _MAX_BYTES:
        raise PddlError(Diagnostic(p, None, None, "file too large to be PDDL"))
    if b"\0" in data:  # said where, as every PDDL message is: the first NUL byte's line and column
        raise PddlError(Diagnostic(p, *_byte_place(data, data.index(b"\0")), "binary file, not PDDL text"))
    try:
        return data.decode("utf-8-sig")  # a byte-order mark is not part of the text
    except UnicodeDecodeError as e:
        raise PddlError(Diagnostic(p, *_byte_place(data, e.start), "not UTF-8 text (binary file?)")) from None


def _byte_place(data: bytes, at: int) -> tuple[int, int]:
    """1-based line and column (in bytes: the text is not text yet) of offset `at`."""
    return data[:at].count(b"\n") + 1, at - (data.rfind(b"\n", 0, at) + 1) + 1


def parse(text: str, path: str = "<string>", fast: bool = True):
    """Parse dialect text into a Domain or a Problem (unchecked).

    `fast=False` reads it all with lark, never with `bulk`'s fast path: the reference that
    tests/test_bulk.py holds the fast path to.
    """
    still_open, too_deep = scan_parentheses(text, path)  # a ')' that closes nothing: said here
    if too_deep is not None and not still_open:
        # said before the parse, flat but slow that deep (3.6 s at 100,000 levels), and before what
        # reads the model, which recurses per level; unbalanced, the '(' never closed says more
        why = f"nested more than {MAX_DEPTH} levels deep; tidyplan reads formulas up to that depth"
        raise PddlError(Diagnostic(path, *too_deep, why))
    try:
        result = (fast and _parse_fast(text)) or _parser().parse(text)
    except lark.exceptions.UnexpectedInput as e:
        lost = never_closed(text, path, e) if still_open else None
        if lost is not None:
            raise PddlError(lost) from None
        raise PddlError(Diagnostic(path, e.line, e.column, describe(e, text, _parser().terminals))) from None
    return _model(result, text, path)


@lru_cache(maxsize=1)
def token_patterns() -> tuple[tuple[str, str], ...]:
    """The grammar's own token patterns, for the fast path to read exactly what lark reads."""
    terminals = _parser().terminals
    found = {t.name: t.pattern.to_regexp() for t in terminals}
    found["INIT"] = next(t.pattern.to_regexp() for t in terminals if t.pattern.value == ":init")
    return tuple((k, found[k]) for k in ("NAME", "VARIABLE", "NUMBER", "WS", "COMMENT", "INIT"))


def _parse_fast(text: str):
    """Lark's result for the text with its `:init` facts read by `bulk` (a 271 KB problem in 69
    ms instead of 229: bulk.py says how measured), or None to read the whole text with lark."""
    init = split_init(text, token_patterns())
    if init is None:
        return None
    try:
        result = _parser().parse(init.text)
    except lark.exceptions.UnexpectedInput:  # the whole text read by lark says what it is
        return None
    if result[0] != "problem":
        return None
    sections = [i for i, (key, _) in enumerate(result[3]) if key == "init"]
    if len(sections) != 1 or result[3][sections[0]][1] != ((), ()):
        return None  # not the section bulk blanked: leave it all to lark
    result[3][sections[0]] = ("init", (init.atoms, init.values))
    return result


def _model(result, text: str, path: str):
    kind = result[0]
    if kind == "domain":
        _, name, define, parts, actions, derived = result
        return m.Domain(
            name=name,
            requirements=parts["requirements"],
            types=parts["types"],
            constants=parts["constants"],
            predicates=parts["predicates"],
            functions=parts["functions"],
            actions=actions,
            path=path,
            pos=paren_before(define, text),
            derived=derived,
        )
    _, name, define, items = result
    fields: dict = {}
    for key, value in items:
        if key in ("objects", "virtual_objects", "requirements") and key in fields:
            value = fields[key] + value
        fields[key] = value
    atoms, values = fields.get("init", ((), ()))
    domain_name, domain_pos = fields.get("domain_name", ("", m.NOWHERE))
    reward = fields.get("goal_reward")
    return m.Problem(
        name=name,
        domain_name=domain_name,
        objects=fields.get("objects", ()),
        virtual_objects=fields.get("virtual_objects", ()),
        init=atoms,
        values=values,
        goal=fields.get("goal", m.TRUE),
        goal_reward=reward[0] if reward else None,
        metric=fields.get("metric"),
        requirements=fields.get("requirements", ()),
        path=path,
        domain_pos=domain_pos,
        pos=paren_before(define, text),
        goal_reward_pos=reward[1] if reward else m.NOWHERE,
    )


Warn = Callable[[Diagnostic], None]


def _ignore(_: Diagnostic) -> None:
    pass


def read_domain(path: str | os.PathLike, warn: Warn = _ignore) -> m.Domain:
    """Read and check a domain file; raises `PddlError` listing every problem.

    Warnings (an extension used without its requirement flag, say) do not stop
    reading: each goes to `warn`.
    """
    p = str(path)
    domain = parse(read_text(p), p)
    if not isinstance(domain, m.Domain):
        raise PddlError(Diagnostic(p, domain.pos.line, domain.pos.col, "expected a domain, found a problem"))
    _report(check_domain(domain), warn)
    return domain


def read_problem(path: str | os.PathLike, domain: m.Domain, warn: Warn = _ignore) -> m.Problem:
    """Read a problem file and check it against its domain."""
    p = str(path)
    problem = parse(read_text(p), p)
    if not isinstance(problem, m.Problem):
        raise PddlError(
            Diagnostic(p, problem.pos.line, problem.pos.col, "expected a problem, found a domain")
        )
    _report(check_problem(problem, domain), warn)
    return problem


def read(domain_path, problem_path=None, warn: Warn = _ignore):
    """Read a domain and, if given, a problem: `(domain, problem or None)`."""
    domain = read_domain(domain_path, warn)
    problem = read_problem(problem_path, domain, warn) if problem_path is not None else None
    return domain, problem


def _report(diagnostics: list[Diagnostic], warn: Warn) -> None:
    errors = [d for d in diagnostics if not d.warning]
    if errors:
        raise PddlError(errors)
    for d in diagnostics:
        warn(d)


# ------------------------------------------------------------- syntax errors
