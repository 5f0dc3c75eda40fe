"""The PDDL model: immutable values built by the reader.

Terms are plain strings: variables start with `?`, anything else is an object
or constant. Formulas and effects are small trees of frozen dataclasses. Every
element that can be wrong in a file keeps its position (`Pos`) so that the
checker can point at it.
"""

from __future__ import annotations

from dataclasses import dataclass, field

ROOT_TYPE = "object"
MAX_STRATUM = 1_000_000  # strata rank operator sets (O-FSM P1, P2, P3): a few are enough


@dataclass(frozen=True, slots=True)
class Pos:
    line: int
    col: int


NOWHERE = Pos(0, 0)


@dataclass(frozen=True, slots=True)
class Typed:
    """A name or variable with its type; `types` has several entries for `either`."""

    name: str
    types: tuple[str, ...] = (ROOT_TYPE,)
    pos: Pos = NOWHERE

    @property
    def type_text(self) -> str:
        if len(self.types) == 1:
            return self.types[0]
        return "(either " + " ".join(self.types) + ")"


# ------------------------------------------------------------------ formulas
@dataclass(frozen=True, slots=True)
class Atom:
    """`(name arg...)`; the predicate `=` is equality."""

    predicate: str
    args: tuple[str, ...]
    pos: Pos = field(default=NOWHERE, compare=False)


@dataclass(frozen=True, slots=True)
class And:
    parts: tuple[Formula, ...]


@dataclass(frozen=True, slots=True)
class Or:
    parts: tuple[Formula, ...]


@dataclass(frozen=True, slots=True)
class Not:
    part: Formula


@dataclass(frozen=True, slots=True)
class Imply:
    condition: Formula
    consequence: Formula


@dataclass(frozen=True, slots=True)
class Exists:
    variables: tuple[Typed, ...]
    body: Formula


@dataclass(frozen=True, slots=True)
class Forall:
    variables: tuple[Typed, ...]
    body: Formula


Formula = Atom | And | Or | Not | Imply | Exists | Forall
TRUE = And(())


def map_formula(f: Formula, atom, quantified) -> Formula:
    """Rebuild a formula bottom-up: `atom(a)` for each atom, and
    `quantified(q, body)` for each `exists`/`forall`, given its rebuilt body."""
    if isinstance(f, Atom):
        return atom(f)
    if isinstance(f, (And, Or)):
        return type(f)(tuple(map_formula(p, atom, quantified) for p in f.parts))
    if isinstance(f, Not):
        return Not(map_formula(f.part, atom, quantified))
    if isinstance(f, Imply):
        return Imply(map_formula(f.condition, atom, quantified), map_formula(f.consequence, atom, quantified))
    return quantified(f, map_formula(f.body, atom, quantified))


# ------------------------------------------------------------------- effects
@dataclass(frozen=True, slots=True)
class FunctionTerm:
    """`(name arg...)` in a numeric position: a cost, a probability, an init value."""

    name: str
    args: tuple[str, ...]
    pos: Pos = field(default=NOWHERE, compare=False)


@dataclass(frozen=True, slots=True)
class Literal:
    atom: Atom
    negated: bool = False


@dataclass(frozen=True, slots=True)
class AndEffect:
    parts: tuple[Effect, ...]


@dataclass(frozen=True, slots=True)
class When:
    condition: Formula
    effect: Effect


@dataclass(frozen=True, slots=True)
class ForallEffect:
    variables: tuple[Typed, ...]
    effect: Effect


@dataclass(frozen=True, slots=True)
class Increase:
    """`(increase (f ...) amount)`; only `total-cost` is planned with."""

    target: FunctionTerm
    amount: float | FunctionTerm
    pos: Pos = field(default=NOWHERE, compare=False)


Effect = Literal | AndEffect | When | ForallEffect | Increase
NO_EFFECT = AndEffect(())


# ---------------------------------------------------------------- the domain
@dataclass(frozen=True, slots=True)
class Predicate:
    name: str
    parameters: tuple[Typed, ...]
    pos: Pos = NOWHERE


@dataclass(frozen=True, slots=True)
class Function:
    name: str
    parameters: tuple[Typed, ...]
    pos: Pos = NOWHERE


@dataclass(frozen=True, slots=True)
class UnitCall:
    """One behaviour unit an action runs (`:units`): its name and its arguments, each a parameter
    of the action (a variable) or a constant."""

    unit: str
    args: tuple[str, ...]
    pos: Pos = field(default=NOWHERE, compare=False)


@dataclass(frozen=True, slots=True)
class Action:
    """An action, or an assumptive action (Göbelbecker, Definition 1).

    `probability` is a number in (0, 1] or a static function of the
    parameters; `stratum` is the O-FSM operator set the action belongs to;
    `units` the behaviour units that execute it (None: the domain does not say).
    """

    name: str
    parameters: tuple[Typed, ...]
    precondition: Formula
    effect: Effect
    probability: float | FunctionTerm = 1.0
    stratum: int = 1
    is_assumption: bool = False
    pos: Pos = NOWHERE
    units: tuple[UnitCall, ...] | None = None
    # Where :probability and :stratum were written, for the checker's messages.
    probability_pos: Pos = field(default=NOWHERE, compare=False)
    stratum_pos: Pos = field(default=NOWHERE, compare=False)
    units_pos: Pos = field(default=NOWHERE, compare=False)


@dataclass(frozen=True, slots=True)
class Derived:
    """`(:derived (name ?x - t ...) body)`: the predicate holds of exactly the tuples for which
    some rule's body holds, in every state (Fast Downward's axioms; PDDL 2.2's derived
    predicates). Several rules for one predicate are a disjunction."""

    predicate: str
    parameters: tuple[Typed, ...]
    body: Formula
    pos: Pos = NOWHERE


@dataclass(frozen=True)
class Domain:
    name: str
    requirements: tuple[str, ...]
    types: tuple[Typed, ...]  # each declared type with its parent(s)
    constants: tuple[Typed, ...]
    predicates: tuple[Predicate, ...]
    functions: tuple[Function, ...]
    actions: tuple[Action, ...]
    path: str = "<domain>"
    pos: Pos = NOWHERE  # where `(define` is
    derived: tuple[Derived, ...] = ()  # the rules of the derived predicates, in file order

    def __post_init__(self) -> None:
        # Lookup tables, derived once; the dataclass stays a value.
        object.__setattr__(self, "_predicates", {p.name: p for p in self.predicates})
        object.__setattr__(self, "_functions", {f.name: f for f in self.functions})
        object.__setattr__(self, "_actions", {a.name: a for a in self.actions})

    def predicate(self, name: str) -> Predicate | None:
        return self._predicates.get(name)  # type: ignore[attr-defined]

    def function(self, name: str) -> Function | None:
        return self._functions.get(name)  # type: ignore[attr-defined]

    def action(self, name: str) -> Action | None:
        return self._actions.get(name)  # type: ignore[attr-defined]

    @property
    def type_parents(self) -> dict[str, tuple[str, ...]]:
        parents: dict[str, tuple[str, ...]] = {ROOT_TYPE: ()}
        for t in self.types:
            if t.name != ROOT_TYPE:  # some files declare the root type itself
                parents[t.name] = t.types
        return parents

    @property
    def strata(self) -> tuple[int, ...]:
        return tuple(sorted({a.stratum for a in self.actions}))

    @property
    def derived_predicates(self) -> frozenset[str]:
        """The predicates that rules derive: never an effect, never in :init."""
        return frozenset(r.predicate for r in self.derived)

    @property
    def has_costs(self) -> bool:
        return any(f.name == "total-cost" for f in self.functions)


@dataclass(frozen=True)
class Problem:
    name: str
    domain_name: str
    objects: tuple[Typed, ...]
    virtual_objects: tuple[Typed, ...]
    init: tuple[Atom, ...]
    values: tuple[tuple[FunctionTerm, float], ...]  # `(= (f a b) 3)` in :init
    goal: Formula
    goal_reward: float | None = None
    metric: tuple[str, FunctionTerm | float] | None = None
    requirements: tuple[str, ...] = ()
    path: str = "<problem>"
    domain_pos: Pos = NOWHERE
    pos: Pos = NOWHERE  # where `(define` is
    goal_reward_pos: Pos = field(default=NOWHERE, compare=False)

    @property
    def all_objects(self) -> tuple[Typed, ...]:
        return self.objects + self.virtual_objects

    def value_table(self) -> dict[str, dict[tuple[str, ...], float]]:
        """Numeric init values by function name, then argument tuple."""
        table: dict[str, dict[tuple[str, ...], float]] = {}
        for term, value in self.values:
            table.setdefault(term.name, {})[term.args] = value
        return table
