"""Progress a state through ground actions: the monitor's test of "does the rest still work".

The continual loop asks, after every observation, whether the next action's precondition holds
in the belief and whether the rest of the plan still reaches the goal (Brenner & Nebel's
monitoring, as Goebelbecker et al. use it). That is plain STRIPS/ADL progression over a
frozenset of ground atoms, done here in microseconds; going through unified-planning's
simulator would rebuild its problem on every belief change (hundreds of milliseconds).

A state is a frozenset of ``(predicate, args...)`` tuples; static and dynamic facts alike.
Numeric effects are ignored: costs never decide applicability in the dialect.

Derived predicates (`tidyplan.pddl.derived`) are closed wherever a state's truth is asked: the
states `apply` and `run` return hold their derived facts, and `applicable` and `holds` close
the state they are given first (a caller's state may have been built from basic facts alone).
A domain without them keeps `run`'s fast path: one set changed in place, nothing closed.

A state may also be an `Overlay`: a large frozen base (the map's atoms, shared while the map
stays) with a few atoms added and removed. The monitor hands one over after every action; `apply`
and `run` change only its small part, so a turn costs what the plan touches, not the room.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator, Mapping, Sequence
from collections.abc import Set as AbstractSet
from itertools import chain

from tidyplan.pddl import model as m
from tidyplan.pddl.derived import Closure

State = frozenset[tuple[str, ...]]
Atom = tuple[str, ...]


class Overlay(AbstractSet):
    """A state as ``base`` (a frozenset, shared) less ``removed`` plus ``added``: what a turn of
    the monitor changes is a few atoms of a belief whose map part has a hundred thousand, and
    copying that part per turn (and per step of a plan's progression) was most of a turn at 96
    objects. Reads like a frozenset; treat it as one (``apply`` and ``run`` return new ones).

    Invariants: ``added`` and ``base`` share nothing; ``removed`` lies within ``base``."""

    __slots__ = ("base", "added", "removed")

    def __init__(self, base: AbstractSet, added: Iterable[Atom] = (), removed: Iterable[Atom] = ()) -> None:
        self.base = base
        self.added = {a for a in added if a not in base}
        self.removed = {a for a in removed if a in base}

    @classmethod
    def _from_iterable(cls, it: Iterable[Atom]) -> frozenset:
        return frozenset(it)  # set algebra on an overlay gives a plain state

    def __contains__(self, atom: object) -> bool:
        return atom in self.added or (atom in self.base and atom not in self.removed)

    def __iter__(self) -> Iterator[Atom]:
        if not self.removed:
            return chain(self.added, self.base)
        return chain(self.added, (a for a in self.base if a not in self.removed))

    def __len__(self) -> int:
        return len(self.base) - len(self.removed) + len(self.added)

    __hash__ = AbstractSet._hash

    def __repr__(self) -> str:
        return f"Overlay({len(self.base)} base atoms, +{len(self.added)}, -{len(self.removed)})"

    def copy(self) -> Overlay:
        out = Overlay.__new__(Overlay)
        out.base, out.added, out.removed = self.base, set(self.added), set(self.removed)
        return out

    def change(self, add: set[Atom], delete: set[Atom]) -> None:
        """In place: less ``delete``, then plus ``add`` (PDDL: adds win over deletes)."""
        for a in delete:
            if a in self.base:
                self.removed.add(a)
            else:
                self.added.discard(a)
        for a in add:
            if a in self.base:
                self.removed.discard(a)
            else:
                self.added.add(a)

    def by(self, predicate: str, k: int | None):
        """The atoms of ``predicate``, all in a list (``k`` None) or by their argument k: the
        base's grouping kept with the base, the small part's merged in (read only)."""
        base = _grouped(self.base, predicate, k)
        mine = [a for a in self.added if a[0] == predicate]
        gone = [a for a in self.removed if a[0] == predicate]
        if not mine and not gone:
            return base
        if k is None:
            return [a for a in base if a not in self.removed] + mine
        out = {key: [a for a in atoms if a not in self.removed] for key, atoms in base.items()}
        for a in mine:
            if len(a) > k + 1:
                out.setdefault(a[k + 1], []).append(a)
        return out


class Atoms(AbstractSet):
    """A frozen state kept by predicate (a frozenset of atoms for each): what an overlay's base
    is best made of, since a run asks for a static predicate's atoms, and finding them in one
    set of a hundred thousand was a pass over all of them per new map."""

    __slots__ = ("parts", "_len")

    def __init__(self, parts: Mapping[str, frozenset]) -> None:
        self.parts = {k: v for k, v in parts.items() if v}
        self._len = sum(len(v) for v in self.parts.values())

    @classmethod
    def _from_iterable(cls, it: Iterable[Atom]) -> frozenset:
        return frozenset(it)

    def __contains__(self, atom: object) -> bool:
        part = self.parts.get(atom[0]) if isinstance(atom, tuple) and atom else None
        return part is not None and atom in part

    def __iter__(self) -> Iterator[Atom]:
        return chain.from_iterable(self.parts.values())

    def __len__(self) -> int:
        return self._len

    __hash__ = AbstractSet._hash


_GROUPS: dict[int, tuple[AbstractSet, dict]] = {}  # id(base) -> (base, {(predicate, k): grouping})


def _grouped(base: AbstractSet, predicate: str, k: int | None):
    """A base's atoms of ``predicate``, in a list (k None) or by argument k: worked out once per
    base (per map), kept for the last few bases."""
    hit = _GROUPS.get(id(base))
    if hit is None or hit[0] is not base:
        if len(_GROUPS) >= 4:
            _GROUPS.clear()
        by: dict = {None: {}}
        if isinstance(base, Atoms):
            by[None] = base.parts  # kept by predicate already
        else:
            for a in base:
                by[None].setdefault(a[0], []).append(a)
        hit = _GROUPS[id(base)] = (base, by)
    groups = hit[1]
    if (predicate, k) not in groups:
        atoms = groups[None].get(predicate, [])
        if k is None:
            groups[(predicate, k)] = atoms
        else:
            grouping: dict[str, list[Atom]] = {}
            for a in atoms:
                if len(a) > k + 1:
                    grouping.setdefault(a[k + 1], []).append(a)
            groups[(predicate, k)] = grouping
    return groups[(predicate, k)]


class Simulator:
    """Applicability and progression of a domain's actions over one problem's objects."""

    def __init__(self, domain: m.Domain, problem: m.Problem) -> None:
        self.domain = domain
        parents = domain.type_parents
        self._objects: dict[str, list[str]] = {}
        for obj in tuple(domain.constants) + problem.all_objects:
            for t in ancestors(obj.types, parents):
                self._objects.setdefault(t, []).append(obj.name)
        self._closure: Closure | None = None
        self._changed: set[str] | None = None  # predicates some action or rule changes (statically_possible)
        # forall effects' answers, kept from run to run (_StaticFacts.effect)
        self._kept: dict = {}
        if domain.derived:
            objects = self._objects
            self._closure = Closure(
                domain.derived,
                lambda f, facts, binding: _holds(f, facts, binding, objects),
                lambda variables: _bindings(variables, {}, objects),
            )

    def initial_state(self, problem: m.Problem) -> State:
        return self.close(frozenset((a.predicate, *a.args) for a in problem.init))

    def close(self, state: State) -> State:
        """The state with its derived facts (recomputed from its basic facts); itself without
        rules. (With rules, an `Overlay` becomes a plain state: its closure is recomputed.)"""
        if self._closure is None:
            return state
        return frozenset(self._closure.close(set(state)))

    def applicable(self, state: State, name: str, args: Sequence[str]) -> bool:
        action = self._action(name)
        return _holds(action.precondition, self.close(state), self._bind(action, args), self._objects)

    def apply(self, state: State, name: str, args: Sequence[str]) -> State:
        """The successor state (closed); the caller checks applicability first. An `Overlay`
        gives an `Overlay` over the same base where the domain has no derived predicates."""
        action = self._action(name)
        state = self.close(state)
        add: set[tuple[str, ...]] = set()
        delete: set[tuple[str, ...]] = set()
        if isinstance(state, Overlay):  # (no derived predicates: close gave it back)
            # a static condition's matches from the base's index, as in a run
            static = self._static_for(state)
            _effects(action.effect, state, self._bind(action, args), self._objects, add, delete, static)
            out = state.copy()
            out.change(add, delete)
            return out
        _effects(action.effect, state, self._bind(action, args), self._objects, add, delete)
        return self.close(frozenset((state - delete) | add))  # PDDL: adds win over deletes

    def run(self, state: State, steps: Iterable[tuple[str, Sequence[str]]]) -> tuple[State, int | None]:
        """Apply steps in turn; returns the state reached and the index of the first step whose
        precondition fails (None when all applied). One set changed in place, not a new state
        per step: the monitor runs a whole plan after every action, over a belief of a hundred
        thousand atoms in a 96-object room. With derived predicates, the set is closed before
        each step and at the end. An `Overlay` without derived predicates is progressed in its
        small part and comes back an `Overlay` (the base is never copied)."""
        closure = self._closure
        if isinstance(state, Overlay) and closure is None:
            layered = state.copy()
            static = self._static_for(layered)
            for k, (name, args) in enumerate(steps):
                action = self._action(name)
                binding = self._bind(action, args)
                if not _holds(action.precondition, layered, binding, self._objects):
                    return layered, k
                add: set[tuple[str, ...]] = set()
                delete: set[tuple[str, ...]] = set()
                _effects(action.effect, layered, binding, self._objects, add, delete, static)
                layered.change(add, delete)
            return layered, None
        now = set(state)
        if closure is not None:
            closure.close(now)
        static = _StaticFacts(now, self._static_predicates(), self._objects)
        for k, (name, args) in enumerate(steps):
            action = self._action(name)
            binding = self._bind(action, args)
            if not _holds(action.precondition, now, binding, self._objects):
                return frozenset(now), k
            add = set()
            delete = set()
            _effects(action.effect, now, binding, self._objects, add, delete, static)
            now -= delete
            now |= add  # PDDL: adds win over deletes
            if closure is not None:
                closure.close(now)
        return frozenset(now), None

    def _static_for(self, state: Overlay) -> _StaticFacts:
        """A run's (or one step's) static facts over an overlay, with the forall effects kept
        from run to run."""
        return _StaticFacts(state, self._static_predicates(), self._objects, self._kept)

    def holds(self, formula: m.Formula, state: State) -> bool:
        return _holds(formula, self.close(state), {}, self._objects)

    def statically_possible(self, initial: State, name: str, args: Sequence[str]) -> bool:
        """False where a precondition atom (of a conjunctive precondition) whose predicate no
        action, assumption or rule changes is false in the ``initial`` state: such facts hold
        or fail for a whole plan, so the step is applicable nowhere in it."""
        changed = self._changed_predicates()
        action = self._action(name)
        binding = self._bind(action, args)
        pre = action.precondition
        for f in pre.parts if isinstance(pre, m.And) else (pre,):
            if isinstance(f, m.Atom) and f.predicate != "=" and f.predicate not in changed:
                if (f.predicate, *_ground(f.args, binding)) not in initial:
                    return False
        return True

    def _changed_predicates(self) -> set[str]:
        """The predicates some action or derivation rule changes; the others are static."""
        if self._changed is None:
            self._changed = set(self.domain.derived_predicates)
            for a in self.domain.actions:
                _changed_by(a.effect, self._changed)
        return self._changed

    def _static_predicates(self) -> set[str]:
        changed = self._changed_predicates()
        return {p.name for p in self.domain.predicates} - changed

    def _action(self, name: str) -> m.Action:
        action = self.domain.action(name)
        if action is None:
            raise KeyError(f"no action {name!r} in domain {self.domain.name}")
        return action

    @staticmethod
    def _bind(action: m.Action, args: Sequence[str]) -> dict[str, str]:
        if len(args) != len(action.parameters):
            raise ValueError(f"{action.name} takes {len(action.parameters)} arguments, got {len(args)}")
        return {p.name: a for p, a in zip(action.parameters, args, strict=True)}


def _changed_by(e, out: set[str]) -> None:
    """The predicates effect ``e`` adds or deletes, into ``out``."""
    if isinstance(e, m.Literal):
        out.add(e.atom.predicate)
    elif isinstance(e, m.AndEffect):
        for p in e.parts:
            _changed_by(p, out)
    elif isinstance(e, (m.When, m.ForallEffect)):
        _changed_by(e.effect, out)


def ancestors(types: Sequence[str], parents: Mapping[str, Sequence[str]]) -> set[str]:
    """The types given, every type above them, and the root type."""
    seen: set[str] = set()
    todo = list(types)
    while todo:
        t = todo.pop()
        if t not in seen:
            seen.add(t)
            todo.extend(parents.get(t, ()))
    seen.add(m.ROOT_TYPE)
    return seen


def _ground(args: Sequence[str], binding: Mapping[str, str]) -> tuple[str, ...]:
    return tuple(binding.get(a, a) for a in args)


def _bindings(variables: Sequence[m.Typed], binding: dict[str, str], objects) -> Iterable[dict[str, str]]:
    if not variables:
        yield binding
        return
    first, rest = variables[0], variables[1:]
    names = sorted({o for t in first.types for o in objects.get(t, ())})
    for o in names:
        yield from _bindings(rest, {**binding, first.name: o}, objects)


def _holds(f: m.Formula, state: State, binding: dict[str, str], objects) -> bool:
    if isinstance(f, m.Atom):
        args = _ground(f.args, binding)
        if f.predicate == "=":
            return args[0] == args[1]
        return (f.predicate, *args) in state
    if isinstance(f, m.And):
        return all(_holds(p, state, binding, objects) for p in f.parts)
    if isinstance(f, m.Or):
        return any(_holds(p, state, binding, objects) for p in f.parts)
    if isinstance(f, m.Not):
        return not _holds(f.part, state, binding, objects)
    if isinstance(f, m.Imply):
        return not _holds(f.condition, state, binding, objects) or _holds(
            f.consequence, state, binding, objects
        )
    if isinstance(f, m.Exists):
        return any(_holds(f.body, state, b, objects) for b in _bindings(f.variables, binding, objects))
    if isinstance(f, m.Forall):
        return all(_holds(f.body, state, b, objects) for b in _bindings(f.variables, binding, objects))
    raise TypeError(f"not a formula: {f!r}")


def _effects(e, state: State, binding: dict[str, str], objects, add: set, delete: set, static=None) -> None:
    """Collect an effect's adds and deletes; conditions are evaluated in the state before.
    ``static``: a run's `_StaticFacts`, for the conditional effects it can match directly."""
    if isinstance(e, m.Literal):
        fact = (e.atom.predicate, *_ground(e.atom.args, binding))
        (delete if e.negated else add).add(fact)
    elif isinstance(e, m.AndEffect):
        for part in e.parts:
            _effects(part, state, binding, objects, add, delete, static)
    elif isinstance(e, m.When):
        if _holds(e.condition, state, binding, objects):
            _effects(e.effect, state, binding, objects, add, delete, static)
    elif isinstance(e, m.ForallEffect):
        done = None if static is None else static.effect(e, binding)
        if done is not None:  # literals over a static condition's matches: worked out before
            add |= done[0]
            delete |= done[1]
            return
        matches = None if static is None else static.matches(e, binding)
        if matches is not None:  # the bindings whose condition holds, from the facts themselves
            for b in matches:
                _effects(e.effect.effect, state, b, objects, add, delete, static)
            return
        for b in _bindings(e.variables, binding, objects):
            _effects(e.effect, state, b, objects, add, delete, static)
    elif isinstance(e, m.Increase):
        return
    else:
        raise TypeError(f"not an effect: {e!r}")


def _literals(e) -> bool:
    """Whether effect ``e`` is literals only (and conjunctions of them): nothing it does
    depends on the state it is applied in."""
    if isinstance(e, m.Literal):
        return True
    return isinstance(e, m.AndEffect) and all(_literals(p) for p in e.parts)


class _StaticFacts:
    """A run's facts of the predicates nothing changes, by predicate, found when first asked.

    ``(forall (?a ?b - waypoint) (when (blocks ?o ?a ?b) ...))`` enumerates every pair of
    waypoints, tens of thousands in a 96-object room, for each take in the plan; when the
    condition is one atom of a static predicate that names every variable, the bindings where
    it holds are exactly its facts that match: one pass over the state per predicate and run.
    """

    def __init__(self, state: set, predicates: set[str], objects, kept: dict | None = None) -> None:
        self._state, self._predicates, self._objects = state, predicates, objects
        self._index: dict[tuple[str, int | None], dict] = {}
        self._typed: dict[tuple[str, ...], frozenset[str]] = {}
        # ``effect``'s answers, by the facts they were read from: ``kept`` (the Simulator's)
        # serves every run over the same objects, whatever the state's other atoms
        self._effects: dict = {} if kept is None else kept

    def effect(self, e: m.ForallEffect, binding: dict[str, str]):
        """(adds, deletes) of ``e`` under ``binding`` where its body is literals only under a
        condition ``matches`` answers (so the state cannot change them), else None. A plan takes
        the same item in every run of the monitor; the room's blockers of it are read once for
        each set of them (a new floor changes a few items' blockers, not every item's). Over an
        overlay, the base's facts and the small part's (the robot's own pairs: new after every
        move) are read apart, the base's kept."""
        body = e.effect
        if not isinstance(body, m.When) or not _literals(body.effect):
            return None
        found = self._candidates(e, binding)
        if found is None:
            return None
        atom, names, facts = found
        parts = [facts]
        state = self._state
        if isinstance(state, Overlay) and not any(a[0] == atom.predicate for a in state.removed):
            fixed = next((k for k, a in enumerate(atom.args) if a not in names), None)
            if fixed is not None:
                value = binding.get(atom.args[fixed], atom.args[fixed])
                base = _grouped(state.base, atom.predicate, fixed).get(value, [])
                parts = [base, self._added(atom.predicate, fixed).get(value, [])]
        add: set[tuple[str, ...]] = set()
        delete: set[tuple[str, ...]] = set()
        for k, part in enumerate(parts):
            key = (id(e), tuple(sorted(binding.items())), frozenset(part))
            hit = self._effects.get(key) if k == 0 else None
            if hit is None:
                mine: set[tuple[str, ...]] = set()
                gone: set[tuple[str, ...]] = set()
                for b in self._bound(e, binding, atom, names, part):
                    _effects(body.effect, None, b, self._objects, mine, gone)
                hit = (frozenset(mine), frozenset(gone))
                if k == 0:
                    if len(self._effects) > 4096:
                        self._effects.clear()
                    self._effects[key] = hit
            add |= hit[0]
            delete |= hit[1]
        return add, delete

    def _added(self, predicate: str, k: int) -> dict[str, list]:
        """An overlay's added atoms of ``predicate`` by their argument k (static: never changed
        within a run)."""
        key = ("added", predicate, k)
        if key not in self._index:
            by: dict[str, list] = {}
            for a in self._state.added:
                if a[0] == predicate and len(a) > k + 1:
                    by.setdefault(a[k + 1], []).append(a)
            self._index[key] = by
        return self._index[key]

    def matches(self, e: m.ForallEffect, binding: dict[str, str]) -> list[dict[str, str]] | None:
        """The bindings of ``e``'s variables under which its condition holds, or None where ``e``
        is not ``(forall (vars) (when (static-atom) effect))`` with every variable in the atom."""
        found = self._candidates(e, binding)
        return None if found is None else self._bound(e, binding, *found)

    def _candidates(self, e: m.ForallEffect, binding: dict[str, str]):
        """(the condition's atom, the forall's variables, the facts that may match it), or None
        where ``matches`` does not apply."""
        body = e.effect
        if not isinstance(body, m.When) or not isinstance(body.condition, m.Atom):
            return None
        atom = body.condition
        names = {v.name for v in e.variables}
        if atom.predicate not in self._predicates or not names <= set(atom.args):
            return None
        # the facts agreeing with the atom's first argument that is no variable of the forall
        # (a take's item: a room's blocks facts are tens of thousands, an item's a few dozen)
        fixed = next((k for k, a in enumerate(atom.args) if a not in names), None)
        facts = self._by(atom.predicate, fixed)
        if fixed is not None:
            facts = facts.get(binding.get(atom.args[fixed], atom.args[fixed]), [])
        return atom, names, facts

    def _bound(self, e: m.ForallEffect, binding: dict[str, str], atom, names, facts) -> list[dict[str, str]]:
        typed = {v.name: self._of_type(v.types) for v in e.variables}
        out = []
        for fact in facts:
            if len(fact) != len(atom.args) + 1:
                continue
            new: dict[str, str] = {}
            for a, value in zip(atom.args, fact[1:], strict=True):
                if a in names:  # a variable of the forall (it shadows an outer one of that name)
                    if new.setdefault(a, value) != value:
                        break
                elif binding.get(a, a) != value:
                    break
            else:
                if all(value in typed[a] for a, value in new.items()):
                    out.append({**binding, **new})
        return out

    def _by(self, predicate: str, k: int | None):
        """The predicate's facts by their argument k (all of them in a list when k is None)."""
        key = (predicate, k)
        if key not in self._index:
            state = self._state
            if isinstance(state, Overlay):  # a static predicate's atoms: grouped with the base
                self._index[key] = state.by(predicate, k)
                return self._index[key]
            facts = [f for f in state if f[0] == predicate]
            if k is None:
                self._index[key] = facts
            else:
                by: dict[str, list] = {}
                for f in facts:
                    if len(f) > k + 1:
                        by.setdefault(f[k + 1], []).append(f)
                self._index[key] = by
        return self._index[key]

    def _of_type(self, types: Sequence[str]) -> frozenset[str]:
        key = tuple(types)
        if key not in self._typed:
            self._typed[key] = frozenset(o for t in types for o in self._objects.get(t, ()))
        return self._typed[key]
