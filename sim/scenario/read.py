"""Reading scenario files: TOML text to checked ``sim.scenario.model`` values, every problem reported.

Why collect every problem: a scenario is written by hand and checked by running it; one message
per run makes fixing a file a loop. Each message is ``path: key path: what is wrong`` (or
``path:line:col: what`` for TOML syntax), the form tidyplan's own diagnostics take, but this
module raises its own ``ScenarioError``: ``sim`` knows nothing of tidyplan.
"""

from __future__ import annotations

import dataclasses
import os
import re
import tomllib
from typing import Any

from sim.scenario.checks import (
    DRAWER_CHECKS,
    REQUIRED,
    ROBOT_CHECKS,
    SENSING_CHECKS,
    fmt,
    overlap,
    positive,
    syntax_message,
)
from sim.scenario.fields import FieldReader
from sim.scenario.model import (
    FLOOR,
    ITEM_SIZE,
    NAME_RE,
    ORIENTATION,
    SCHEMA,
    UNKNOWN,
    Deposit,
    DrawerLayout,
    DrawerSpec,
    Expect,
    Furniture,
    Item,
    Orientation,
    Robot,
    Scenario,
    ScenarioError,
    Sensing,
    Viewpoint,
    drawer_layout,
    drawer_problems,
    shared_carcass_problems,
)


def load(path: str | os.PathLike[str]) -> Scenario:
    """Read and check a scenario file; ScenarioError lists every problem found."""
    where = os.fspath(path)
    if os.path.isdir(where):
        raise ScenarioError([f"{where}: is a directory, not a scenario file"])
    try:
        with open(where, "rb") as fh:
            data = fh.read()
    except FileNotFoundError:
        raise ScenarioError([f"{where}: no such file"]) from None
    except OSError as e:
        raise ScenarioError([f"{where}: cannot read: {e.strerror}"]) from None
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as e:
        raise ScenarioError([f"{where}: not UTF-8 text (bad byte at offset {e.start})"]) from None
    return loads(text, where)


def loads(text: str, path: str = "<string>") -> Scenario:
    """Parse and check scenario text; ``path`` only labels the messages and ``Scenario.path``."""
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        raise ScenarioError([syntax_message(path, text, str(e))]) from None
    except RecursionError:  # tomllib recurses once per [ or { of a value; no room nests so deep
        raise ScenarioError([f"{path}: arrays or inline tables nested too deeply to read"]) from None
    except ValueError:  # TOML, but a whole number of more digits than int() takes (4,300)
        raise ScenarioError([f"{path}: a number of too many digits to read"]) from None
    return _Reader(path).scenario(doc)


_ATOM = re.compile(r"\(\s*([a-z][a-z0-9_-]*)((?:\s+[a-z][a-z0-9_-]*)*)\s*\)")
_TOP = ("schema", "name", "title", "description", "time_limit_s", "room", "robot", "sensing")
_ARRAYS = ("furniture", "deposit", "item", "viewpoint")
_A = {"furniture": "a furniture piece", "deposit": "a deposit", "item": "an item", "viewpoint": "a viewpoint"}
_EXPECT = tuple(f.name for f in dataclasses.fields(Expect))


class _Reader(FieldReader):
    """One pass over a parsed document, collecting messages instead of stopping at the first
    (the typed getters are ``FieldReader``'s)."""

    # ------------------------------------------------------------------ the document
    def scenario(self, doc: dict[str, Any]) -> Scenario:
        self.keys(doc, "", _TOP + _ARRAYS + ("expect", "prior", "facts"))
        present, schema = self.value(doc, "", "schema", REQUIRED)
        if present and (isinstance(schema, bool) or schema != SCHEMA):
            # another version's keys would only produce noise: this is the one message
            raise ScenarioError(
                [f"{self.path}: schema: unknown schema version {schema!r}; this tidyplan reads 1"]
            )
        name = self.string(doc, "", "name", name=True)
        title = self.string(doc, "", "title")
        description = self.string(doc, "", "description", "")
        time_limit = self.number(doc, "", "time_limit_s", None, positive)
        bounds = entrance = None
        heading = 0.0
        room = self.table(doc, "room", required=True)
        if room is not None:
            self.keys(room, "room", ("bounds", "entrance", "heading_deg"))
            bounds = self.vector(room, "room", "bounds", "[x0, x1, y0, y1]")
            if bounds is not None and not (bounds[0] < bounds[1] and bounds[2] < bounds[3]):
                self.error("room.bounds", f"needs x0 < x1 and y0 < y1, got {fmt(bounds)}")
                bounds = None
            entrance = self.vector(room, "room", "entrance", "[x, y]")
            self.inside("room.entrance", entrance, bounds)
            heading = self.number(room, "room", "heading_deg", 0.0)
        robot = self.settings(doc, "robot", Robot, ROBOT_CHECKS)
        sensing = self.settings(doc, "sensing", Sensing, SENSING_CHECKS)
        if sensing is not None and sensing.range_min >= sensing.range_max:
            self.error(
                "sensing.range_min", f"must be < range_max ({sensing.range_max:g}), got {sensing.range_min:g}"
            )

        names: dict[str, str] = {}  # one namespace: they all become PDDL objects
        parsed: dict[str, list] = {}
        for key in _ARRAYS:
            parsed[key] = []
            for i, label, t in self.entries(doc, key):
                n = t.get("name")
                if isinstance(n, str) and n in names:
                    self.error(f"{key}[{i}].name", f"{n!r} is already the name of {names[n]}")
                elif isinstance(n, str):
                    names[n] = f"{key}[{i}]"
                before = len(self.messages)
                obj = getattr(self, f"_{key}")(label, t, bounds)
                parsed[key].append((label, t, obj if len(self.messages) == before else None))
        furniture = {o.name: o for _, _, o in parsed["furniture"] if o is not None}
        self._cross_check(parsed, furniture)
        self._drawers(parsed, furniture, robot or Robot())
        expect = self._expect(doc, parsed)
        prior = self._prior(doc, parsed)
        self._fillable(parsed, prior)
        facts = self._facts(doc)
        if self.messages:
            raise ScenarioError(self.messages)
        head = (name, title, description, bounds, entrance, heading, robot, sensing)
        arrays = (tuple(o for _, _, o in parsed[k]) for k in _ARRAYS)
        return Scenario(*head, *arrays, expect, self.path, prior, facts, time_limit)

    def _furniture(self, where: str, t: dict, bounds: tuple | None) -> Furniture | None:
        self.keys(t, where, ("name", "center", "size", "height", "kind"))
        name = self.string(t, where, "name", name=True)
        if name == FLOOR:
            self.error(f"{where}.name", f'"{FLOOR}" is reserved: it is what an item on the floor stands on')
        center = self.vector(t, where, "center", "[x, y]")
        self.inside(f"{where}.center", center, bounds)
        size = self.vector(t, where, "size", "[sx, sy]", positive=True)
        height = self.number(t, where, "height", check=positive)
        kind = self.string(t, where, "kind")
        if None in (name, center, size, height, kind):
            return None
        return Furniture(name, center[0], center[1], size[0], size[1], height, kind)

    def _deposit(self, where: str, t: dict, bounds: tuple | None) -> Deposit | None:
        self.keys(t, where, ("name", "category", "position", "approach", "drawer", "container"))
        name = self.string(t, where, "name", name=True)
        category = self.string(t, where, "category", name=True)
        pos = self.vector(t, where, "position", "[x, y, z]")
        self.inside(f"{where}.position", pos, bounds)
        if pos is not None and pos[2] < 0:
            self.error(f"{where}.position", f"z must be >= 0 (the floor), got {pos[2]:g}")
        approach = self.vector(t, where, "approach", "[x, y]", default=())
        self.inside(f"{where}.approach", approach or None, bounds)
        drawer = self._drawer(f"{where}.drawer", t["drawer"]) if "drawer" in t else ()
        if drawer and approach == ():
            self.error(f"{where}.approach", "missing required key (a drawer is pulled open from there)")
        container = self.vector(t, where, "container", "[sx, sy, height]", default=(), positive=True)
        if container and drawer:
            self.error(f"{where}.container", "a deposit is a drawer or a container, not both")
        if None in (name, category, pos, approach, drawer, container):
            return None
        return Deposit(name, category, *pos, approach or None, drawer or None, container or None)

    def _drawer(self, where: str, t: Any) -> DrawerSpec | None:
        """[deposit.drawer]: the drawer a deposit's objects go into; every key optional."""
        if not isinstance(t, dict):
            self.error(where, f"must be a table ([deposit.drawer]), got {t!r}")
            return None
        self.keys(t, where, ("closed", *DRAWER_CHECKS))
        before = len(self.messages)
        closed = t.get("closed", True)
        if not isinstance(closed, bool):
            self.error(f"{where}.closed", f"must be true or false, got {closed!r}")
        default = DrawerSpec()
        values = {k: self.number(t, where, k, getattr(default, k), c) for k, c in DRAWER_CHECKS.items()}
        return DrawerSpec(closed, **values) if len(self.messages) == before else None

    def _item(self, where: str, t: dict, bounds: tuple | None) -> Item | None:
        self.keys(t, where, ("name", "category", "position", "on", "size", "unknown", "orientation"))
        name = self.string(t, where, "name", name=True)
        category = self.string(t, where, "category", name=True)
        pos = self.vector(t, where, "position", "[x, y]")
        self.inside(f"{where}.position", pos, bounds)
        on = self.string(t, where, "on", FLOOR)
        size = self.vector(t, where, "size", "[sx, sy, sz]", ITEM_SIZE, positive=True)
        unknown = t.get("unknown", False)
        if not isinstance(unknown, bool):
            self.error(f"{where}.unknown", f"must be true or false, got {unknown!r}")
        if category == UNKNOWN:
            self.error(f"{where}.category", f"the true category, not {UNKNOWN!r}: say unknown = true")
        orientation = (
            self._orientation(f"{where}.orientation", t["orientation"]) if "orientation" in t else ()
        )
        if None in (name, category, pos, on, size, orientation) or not isinstance(unknown, bool):
            return None
        return Item(
            name, category, pos[0], pos[1], on, *size, unknown=unknown, orientation=orientation or None
        )

    def _orientation(self, where: str, t: Any) -> Orientation | None:
        """[item.orientation]: the axis (in the item's own frame) to the end that goes down, and
        that end's name."""
        if not isinstance(t, dict):
            self.error(where, f"must be a table ([item.orientation]), got {t!r}")
            return None
        self.keys(t, where, ("axis", "down"))
        before = len(self.messages)
        if "axis" not in t:
            self.error(
                f"{where}.axis", "missing required key (which way, in the item's frame, its down end lies)"
            )
        axis = self.vector(t, where, "axis", "[x, y, z]", default=None)
        if axis is not None and max(abs(v) for v in axis) == 0:
            self.error(f"{where}.axis", "must not be [0, 0, 0]: it points to the end that goes down")
        down = self.string(t, where, "down", name=True)
        if len(self.messages) > before:
            return None
        norm = sum(v * v for v in axis) ** 0.5
        return Orientation(tuple(v / norm for v in axis), down)

    def _viewpoint(self, where: str, t: dict, bounds: tuple | None) -> Viewpoint | None:
        self.keys(t, where, ("name", "position"))
        name = self.string(t, where, "name", name=True)
        pos = self.vector(t, where, "position", "[x, y]")
        self.inside(f"{where}.position", pos, bounds)
        return None if None in (name, pos) else Viewpoint(name, *pos)

    def _cross_check(self, parsed: dict[str, list], furniture: dict[str, Furniture]) -> None:
        """Checks between entries; on raw values where a bad sibling field should not hide them."""
        # raw values, each a string or bad input said elsewhere (a list is no name, nor hashable)
        furniture_names = {n for _, t, _ in parsed["furniture"] if isinstance(n := t.get("name"), str)}
        accepted = {c for _, t, _ in parsed["deposit"] if isinstance(c := t.get("category"), str)}
        for label, t, _ in parsed["item"]:
            on, category = t.get("on", FLOOR), t.get("category")
            if isinstance(on, str) and on != FLOOR and on not in furniture_names:
                self.error(f"{label}.on", f'no furniture named {on!r} (nor "{FLOOR}")')
            if t.get("unknown") is True:  # it goes where the deposits for unknown objects are
                if UNKNOWN not in accepted:
                    self.error(f"{label}.unknown", f"an unknown object, and no deposit accepts {UNKNOWN!r}")
            elif isinstance(category, str) and NAME_RE.fullmatch(category) and category not in accepted:
                if not ("orientation" in t and ORIENTATION in accepted):
                    self.error(f"{label}.category", f"no deposit accepts category {category!r}")
        for label, _, item in parsed["item"]:
            if item is None:
                continue
            where = f"{label}.position"
            if item.on in furniture and furniture[item.on].box().clearance(item.x, item.y) > 0:
                self.error(
                    where, f"{fmt((item.x, item.y))} is outside the footprint of {item.on!r} it stands on"
                )
            for f in furniture.values() if item.on == FLOOR else ():
                if overlap(item.box(), f.box()):
                    self.error(where, f"on the floor but overlaps furniture {f.name!r}")

    def _fillable(self, parsed: dict[str, list], prior: tuple | None) -> None:
        """A deposit of a category that no item has, nor the prior names, can never be filled:
        a misspelt category, most likely (checked where the file names items or a prior)."""
        items = [i for _, _, i in parsed["item"] if i is not None]
        if not items and not prior:
            return
        can = {i.label for i in items} | {c for c, _ in prior or ()}
        if any(i.orientation is not None for i in items):
            can.add(ORIENTATION)
        for label, _, d in parsed["deposit"]:
            if d is not None and d.category not in can:
                what = "no item is of it" + (", nor does the prior name it" if prior else "")
                self.error(f"{label}.category", f"nothing can fill a deposit of {d.category!r}: {what}")

    def _drawers(self, parsed: dict[str, list], furniture: dict[str, Furniture], robot: Robot) -> None:
        """A drawer must slide out of a furniture piece, fit it, and open clear of the robot; the
        drawers of one carcass (the WRS stairs-like drawer has three) slide out of one face and
        keep out of each other's slots."""
        placed: dict[str, list[tuple[str, str, DrawerLayout]]] = {}  # carcass -> (label, name, layout)
        for label, _, d in parsed["deposit"]:
            if d is None or d.drawer is None:
                continue
            layout = drawer_layout(furniture.values(), d)
            if layout is None:
                closed = f"{d.drawer.travel:g} m back from it towards the approach"
                self.error(f"{label}.position", f"no furniture piece holds the closed drawer ({closed})")
                continue
            for key, what in drawer_problems(layout, d.approach, robot.radius):
                self.error(f"{label}.{key}", what)
            for _, other, earlier in placed.get(layout.carcass.name, []):
                why = shared_carcass_problems(layout, earlier)
                if why is not None:
                    what = f"its drawer {why} the drawer of {other!r} in {layout.carcass.name!r}"
                    self.error(f"{label}.position", what)
            placed.setdefault(layout.carcass.name, []).append((label, d.name, layout))

    def _expect(self, doc: dict, parsed: dict[str, list]) -> Expect:
        t = self.table(doc, "expect", required=False)
        if t is None:
            return Expect()
        self.keys(t, "expect", _EXPECT)
        names = {k: {n for _, e, _ in parsed[k] if isinstance(n := e.get("name"), str)} for k in _ARRAYS}
        values = {}
        for key in _EXPECT:
            kind = key.rsplit("_", 1)[1].removesuffix("s")  # items -> item, deposits -> deposit
            v = t.get(key, [])
            if not isinstance(v, list) or not all(isinstance(n, str) for n in v):
                self.error(f"expect.{key}", f"must be a list of {kind} names, got {v!r}")
                continue
            for i, n in enumerate(v):
                if n not in names[kind]:
                    other = next((k for k in _ARRAYS if n in names[k]), None)
                    what = f"names {_A[other]}, not {_A[kind]}" if other else f"no {kind} has this name"
                    self.error(f"expect.{key}[{i}]", f"{n!r}: {what}")
            values[key] = tuple(v)
        return Expect(**values)

    def _prior(self, doc: dict, parsed: dict[str, list]) -> tuple[tuple[str, int], ...] | None:
        """[prior] count = {category = n, ...}: what the robot is told the room holds."""
        if "prior" not in doc:
            return None
        t = self.table(doc, "prior", required=False)
        if t is None:
            return None
        self.keys(t, "prior", ("count",))
        count = t.get("count")
        if not isinstance(count, dict) or not count:
            self.error("prior.count", f"must be a table of category = count, got {count!r}")
            return None
        accepted = {t.get("category") for _, t, _ in parsed["deposit"]}
        out = []
        for cat, n in count.items():
            where = f"prior.count.{cat}"
            if not NAME_RE.fullmatch(cat):
                self.error(where, f"{cat!r} must match [a-z][a-z0-9_-]* (it becomes a PDDL name)")
            elif cat not in accepted:
                self.error(where, f"no deposit accepts category {cat!r}")
            elif isinstance(n, bool) or not isinstance(n, int) or n < 0:
                self.error(where, f"must be a whole number >= 0, got {n!r}")
            else:
                out.append((cat, n))
        return tuple(sorted(out))

    def _facts(self, doc: dict) -> tuple[tuple[str, ...], ...]:
        """facts = ["(name arg ...)", ...]: what a domain's own predicates hold at the start (the
        planner side checks them against the domain; here only their form)."""
        facts = doc.get("facts", [])
        if not isinstance(facts, list):
            self.error("facts", f'must be a list of atoms like "(on-duty drawer)", got {facts!r}')
            return ()
        out = []
        for i, text in enumerate(facts):
            atom = _ATOM.fullmatch(text.strip().lower()) if isinstance(text, str) else None
            if atom is None:
                self.error(f"facts[{i}]", f'must be an atom like "(on-duty drawer)", got {text!r}')
            else:
                out.append((atom[1], *atom[2].split()))
        return tuple(dict.fromkeys(out))
