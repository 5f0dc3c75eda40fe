"""Lark transformer: grammar rules to frozen model values.

It runs inside lark's LALR parser (no parse tree is built), so each method
gets its children already transformed. Positions come from the tokens.
"""

from __future__ import annotations

from decimal import Decimal

from lark import Token, Transformer

from tidyplan.pddl import model as m


def _pos(token: Token) -> m.Pos:
    return m.Pos(token.line or 0, token.column or 0)


def paren_before(token: Token, text: str) -> m.Pos:
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


class Build(Transformer):
    """Builds model values; one method a grammar rule."""

    # ------------------------------------------------------------ tokens
    def name(self, c):
        return c[0].update(value=c[0].value.lower())

    def VARIABLE(self, t):
        return t.update(value=t.value.lower())

    def REQUIREMENT(self, t):
        return t.update(value=t.value.lower())

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

    def unit_call(self, c):
        return m.UnitCall(str(c[0]), tuple(str(x) for x in c[1:]), _pos(c[0]))

    def units(self, c):
        return ("units", tuple(c))

    def derived(self, c):
        return m.Derived(str(c[0]), c[1], c[2], _pos(c[0]))

    def action(self, c):
        return _action(c, is_assumption=False)

    def assumption(self, c):
        return _action(c, is_assumption=True)

    def domain(self, c):
        parts: dict = {"requirements": (), "types": (), "constants": (), "predicates": (), "functions": ()}
        actions: list[m.Action] = []
        derived: list[m.Derived] = []
        for item in c[2:]:
            if isinstance(item, m.Action):
                actions.append(item)
            elif isinstance(item, m.Derived):
                derived.append(item)
            else:
                key, value = item
                parts[key] = parts[key] + value
        return ("domain", str(c[1]), c[0], parts, tuple(actions), tuple(derived))

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
    units = fields.get("units")
    stratum = 1
    if stratum_token is not None:
        value = Decimal(str(stratum_token))  # exact: 1e400 is no float, 1e23 no whole float
        # A fractional stratum becomes 0 and a huge one MAX_STRATUM + 1, which the checker
        # reports; never an integer of 10^400 digits built from a bad input.
        if value != value.to_integral_value():
            stratum = 0
        else:
            stratum = int(value) if value <= m.MAX_STRATUM else m.MAX_STRATUM + 1
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
        units=units,
        units_pos=units[0].pos if units else _pos(name),
    )
