"""Text to model: the dialect reader.

The grammar (`grammar.lark`) is data; the transformer below builds frozen model
values from it, bottom-up, inside lark's LALR parser (no parse tree is built:
this is what makes large problem files fast). Lark's errors are turned into
`PddlError` with `path:line:col` here, at the boundary, and the semantic checks
of `check.py` run on the result.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from functools import lru_cache
from pathlib import Path

import lark
from lark import Token, Transformer

from ..errors import Diagnostic, PddlError
from . import model as m
from .check import check_domain, check_problem

GRAMMAR = Path(__file__).with_name("grammar.lark")
_MAX_BYTES = 64 * 1024 * 1024  # a PDDL file larger than this is not what the user meant


def _pos(token: Token) -> m.Pos:
    return m.Pos(token.line or 0, token.column or 0)


def _paren_before(token: Token, text: str) -> m.Pos:
    """Where the '(' that opens `token`'s form is (`(define` rather than `define`)."""
    at = text.rfind("(", 0, token.start_pos)
    if at < 0:
        return _pos(token)
    line = text.count("\n", 0, at) + 1
    return m.Pos(line, at - (text.rfind("\n", 0, at) + 1) + 1)


def _group(items: list, default_type: str = m.ROOT_TYPE) -> tuple[m.Typed, ...]:
    """Group a flat `a b - t c - (either u v) d` list into typed names."""
    out: list[m.Typed] = []
    pending: list[Token] = []
    for item in items:
        if isinstance(item, tuple):  # a `- type` marker
            out.extend(m.Typed(str(t), item, _pos(t)) for t in pending)
            pending = []
        else:
            pending.append(item)
    out.extend(m.Typed(str(t), (default_type,), _pos(t)) for t in pending)
    return tuple(out)


class _Build(Transformer):
    """Builds model values; one method a grammar rule."""

    # ------------------------------------------------------------ tokens
    def name(self, c):
        return c[0].update(value=c[0].value.lower())

    def VARIABLE(self, t):
        return t.update(value=t.value.lower())

    def REQUIREMENT(self, t):
        return t.update(value=t.value.lower())

    def NUMBER(self, t):
        return t

    # ------------------------------------------------------------ typing
    def type_marker(self, c):
        return tuple(str(x) for x in c[0]) if isinstance(c[0], list) else (str(c[0]),)

    def either(self, c):
        return list(c)

    def typed_names(self, c):
        return _group(c)

    def typed_vars(self, c):
        return _group(c)

    # ---------------------------------------------------------- formulas
    def atom(self, c):
        return m.Atom(str(c[0]), tuple(str(x) for x in c[1:]), _pos(c[0]))

    def f_head(self, c):
        return m.FunctionTerm(str(c[0]), tuple(str(x) for x in c[1:]), _pos(c[0]))

    def gd_empty(self, c):
        return m.TRUE

    def gd_and(self, c):
        return m.And(tuple(c))

    def gd_or(self, c):
        return m.Or(tuple(c))

    def gd_not(self, c):
        return m.Not(c[0])

    def gd_imply(self, c):
        return m.Imply(c[0], c[1])

    def gd_exists(self, c):
        return m.Exists(c[0], c[1])

    def gd_forall(self, c):
        return m.Forall(c[0], c[1])

    def gd_equal(self, c):
        return m.Atom("=", (str(c[0]), str(c[1])), _pos(c[0]))

    # ----------------------------------------------------------- effects
    def eff_empty(self, c):
        return m.NO_EFFECT

    def eff_and(self, c):
        return m.AndEffect(tuple(_as_effect(x) for x in c))

    def eff_not(self, c):
        return m.Literal(c[0], negated=True)

    def eff_forall(self, c):
        return m.ForallEffect(c[0], _as_effect(c[1]))

    def eff_when(self, c):
        return m.When(c[0], _as_effect(c[1]))

    def eff_increase(self, c):
        amount = c[2]
        if isinstance(amount, Token):
            amount = float(amount)
        return m.Increase(c[1], amount, _pos(c[0]))

    # ------------------------------------------------------------ domain
    def requirements(self, c):
        return ("requirements", tuple(str(t) for t in c))

    def types(self, c):
        return ("types", c[0])

    def constants(self, c):
        return ("constants", c[0])

    def predicate_decl(self, c):
        return m.Predicate(str(c[0]), c[1], _pos(c[0]))

    def predicates(self, c):
        return ("predicates", tuple(c))

    def function_decl(self, c):
        return m.Function(str(c[0]), c[1], _pos(c[0]))

    def functions(self, c):
        # `- number` markers after a function declare its value type: skip them.
        return ("functions", tuple(x for x in c if isinstance(x, m.Function)))

    def parameters(self, c):
        return ("parameters", c[0])

    def precondition(self, c):
        return ("precondition", c[0])

    def effect(self, c):
        return ("effect", _as_effect(c[0]))

    def probability(self, c):
        v = c[0]
        if isinstance(v, Token):
            return ("probability", (float(v), _pos(v)))
        return ("probability", (v, v.pos))

    def stratum(self, c):
        return ("stratum", (c[0], _pos(c[0])))

    def action(self, c):
        return _action(c, is_assumption=False)

    def assumption(self, c):
        return _action(c, is_assumption=True)

    def domain(self, c):
        parts: dict = {"requirements": (), "types": (), "constants": (), "predicates": (), "functions": ()}
        actions: list[m.Action] = []
        for item in c[2:]:
            if isinstance(item, m.Action):
                actions.append(item)
            else:
                key, value = item
                parts[key] = parts[key] + value
        return ("domain", str(c[1]), c[0], parts, tuple(actions))

    # ----------------------------------------------------------- problem
    def problem_domain(self, c):
        return ("domain_name", (str(c[0]), _pos(c[0])))

    def objects(self, c):
        return ("objects", c[0])

    def virtual_objects(self, c):
        return ("virtual_objects", c[0])

    def init_value(self, c):
        return (c[0], float(c[1]))

    def init(self, c):
        atoms = tuple(x for x in c if isinstance(x, m.Atom))
        values = tuple(x for x in c if isinstance(x, tuple))
        return ("init", (atoms, values))

    def goal(self, c):
        return ("goal", c[0])

    def metric(self, c):
        expr = c[1]
        if isinstance(expr, Token):
            expr = float(expr)
        return ("metric", (str(c[0]).lower(), expr))

    def goal_reward(self, c):
        return ("goal_reward", (float(c[0]), _pos(c[0])))

    def problem(self, c):
        return ("problem", str(c[1]), c[0], list(c[2:]))

    def start(self, c):
        return c[0]


def _as_effect(x):
    """An atom in effect position is a positive literal."""
    return m.Literal(x) if isinstance(x, m.Atom) else x


def _action(c, is_assumption: bool) -> m.Action:
    name: Token = c[0]
    fields = dict(c[1:])
    probability, probability_pos = fields.get("probability", (1.0, m.NOWHERE))
    stratum_token, stratum_pos = fields.get("stratum", (None, m.NOWHERE))
    stratum = 1
    if stratum_token is not None:
        value = float(stratum_token)
        # A fractional stratum becomes 0, which the checker reports as invalid.
        stratum = int(value) if value == int(value) else 0
    return m.Action(
        name=str(name),
        parameters=fields.get("parameters", ()),
        precondition=fields.get("precondition", m.TRUE),
        effect=fields.get("effect", m.NO_EFFECT),
        probability=probability,
        stratum=stratum,
        is_assumption=is_assumption,
        pos=_pos(name),
        probability_pos=probability_pos,
        stratum_pos=stratum_pos,
    )


@lru_cache(maxsize=1)
def _parser() -> lark.Lark:
    return lark.Lark(
        GRAMMAR.read_text(),
        parser="lalr",
        lexer="contextual",
        transformer=_Build(),
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
    if b"\0" in data:
        raise PddlError(Diagnostic(p, None, None, "binary file, not PDDL text"))
    try:
        return data.decode("utf-8-sig")  # a byte-order mark is not part of the text
    except UnicodeDecodeError as e:
        line = data[: e.start].count(b"\n") + 1
        col = e.start - (data.rfind(b"\n", 0, e.start) + 1) + 1
        raise PddlError(Diagnostic(p, line, col, "not UTF-8 text (binary file?)")) from None


def parse(text: str, path: str = "<string>"):
    """Parse dialect text into a Domain or a Problem (unchecked)."""
    balanced = not _open_parentheses(text, path)
    try:
        result = _parser().parse(text)
    except lark.exceptions.UnexpectedInput as e:
        if not balanced:
            raise PddlError(_never_closed(text, path, e)) from None
        raise PddlError(Diagnostic(path, e.line, e.column, _describe(e, text))) from None
    kind = result[0]
    if kind == "domain":
        _, name, define, parts, actions = result
        return m.Domain(
            name=name,
            requirements=parts["requirements"],
            types=parts["types"],
            constants=parts["constants"],
            predicates=parts["predicates"],
            functions=parts["functions"],
            actions=actions,
            path=path,
            pos=_paren_before(define, text),
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
        pos=_paren_before(define, text),
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
def _open_parentheses(text: str, path: str, stop: int | None = None) -> list[tuple[int, int]]:
    """The '(' still open at offset `stop` (default: the end), outermost first.

    Raises at a ')' that closes nothing: that mistake is unambiguous.
    """
    stack: list[tuple[int, int]] = []
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
        elif ch == ")":
            if not stack:
                raise PddlError(Diagnostic(path, line, col, "unbalanced parenthesis: ')' closes nothing"))
            stack.pop()
    return stack


def _at_end(e: lark.exceptions.UnexpectedInput) -> bool:
    """Lark's LALR parser reports the end of the text as a `$END` token."""
    token = getattr(e, "token", None)
    return isinstance(e, lark.exceptions.UnexpectedEOF) or getattr(token, "type", None) == "$END"


def _never_closed(text: str, path: str, e: lark.exceptions.UnexpectedInput) -> Diagnostic:
    """Locate the '(' a section lost its ')' from, when the parser stumbles over it.

    Counting alone cannot tell which '(' lacks its ')'. The parser stops at the
    first token that does not fit, typically the next section's keyword: the
    culprit is the innermost '(' still open before that token's own '('.
    """
    at = getattr(e, "pos_in_stream", None)
    if _at_end(e) or at is None or at < 0:
        stack = _open_parentheses(text, path)
    else:
        stack = _open_parentheses(text, path, at)
        if text[:at].rstrip().endswith("(") and len(stack) > 1:
            stack = stack[:-1]
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


def _describe(e: lark.exceptions.UnexpectedInput, text: str) -> str:
    if isinstance(e, lark.exceptions.UnexpectedCharacters):
        return f"unexpected character {text[e.pos_in_stream]!r}"
    if isinstance(e, lark.exceptions.UnexpectedEOF):
        return "unexpected end of file"
    if isinstance(e, lark.exceptions.UnexpectedToken):
        found = e.token
        what = "end of file" if found.type == "$END" else repr(str(found))
        expected = sorted(_TOKEN_WORDS.get(x, _keyword(x)) for x in (e.expected or ()))
        hint = ""
        if expected and len(expected) <= 6:
            hint = "; expected " + " or ".join(expected)
        return f"unexpected {what}{hint}"
    return str(e).splitlines()[0]


def _keyword(terminal: str) -> str:
    """Lark names anonymous keyword terminals like `__ANON_3`; make them readable."""
    for t in _parser().terminals:
        if t.name == terminal:
            return repr(t.pattern.value)
    return terminal.lower()
