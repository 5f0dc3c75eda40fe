"""Seeded WRS tidy-up rooms as scenario files: case I's arena with its items placed the way the WRS
world's seeded object spawner places them, alone (layout one) or joined to the dining room (two).

    python bench/wrs.py --layout one|two --out DIR [--rooms 20] [--first-seed 0]
                        [--wall-height 2.0] [--force]

writes ``DIR/wrs-<layout>-s<seed>.toml`` (seed with three digits) for each seed, never over an
existing file unless ``--force``; bad options exit 2 with one message. Every file is read back
with ``sim.scenario.read.load`` before it is put in place and must give the scenario generated;
if not, the script stops with the loader's messages (exit 1): that is a bug here.

Why: cases I-III are three rooms built by hand for the paper's figures. A planner tuned on them
should also meet rooms it was not tuned on, drawn the way the competition draws them.

From docs/sources.md (the WRS 2020 rules and Toyota's Gazebo world of the arena):
- room 1 (the living room), its furniture, deposits and the robot's entrance: taken from
  problems/case1.toml as read by ``sim.scenario.read.load`` (its viewpoints and bounds too);
- 12 objects, 3 in each of the 4 categories food, kitchen, tool, task (the O-FSM paper's choice;
  WRS used 5 categories), so ``[prior] count`` is 3 of each per room;
- the spawn zones: floor x in [-1.0, -0.4], y in [-0.35, 1.35] takes half the objects, the long
  table x in [-0.45, -0.2], y in [-0.35, 0.7] a third, the tall table x in [-0.45, -0.2],
  y in [1.0, 1.35] a sixth; every two objects at least 0.2 m apart (centre to centre); seeded;
- the dining room, 2.5 m x 4.0 m beyond room 1, through a 1.2 m opening (layout two).

Our own choices:
- item sizes: each item's footprint sx, sy drawn uniformly from [0.05, 0.10] m and its height from
  [0.05, 0.15] m (the range of the small YCB objects WRS draws from: a can, a cup, a marker box),
  to the millimetre; positions to the millimetre; the draws are rejection sampling, in file order;
- a floor object keeps its footprint 5 cm from every furniture piece and wall; an object on a
  table keeps its footprint on the top (the tall table's zone starts on its edge, y = 1.0); the
  categories are shuffled over the places of each room, so each room holds 3 of each;
- layout two: the dividing wall stands on x = 0.5..0.8 (room 1's far wall; the dining room is then
  x = 0.8..3.3), as two furniture pieces of kind "wall", 2.0 m high (``--wall-height``), leaving
  the 1.2 m opening at a y drawn by the seed, at least 0.3 m from the outer walls; the dining table
  is 0.8 x 1.2 m, 0.70 m high, placed by the seed with at least 0.7 m of free floor around it;
  of the dining room's 12 objects half lie on the table top (footprint 5 cm inside its edges) and
  half on the floor within 0.5 m of the table, never in the 0.8 m deep doorway behind the opening
  (so the robot can always step in); the dining room gets no viewpoint (the planner must make its
  own); room 1 is drawn first with the same seed, so it is the room of layout one.
"""

from __future__ import annotations

import argparse
import math
import os
import random
import sys
from collections.abc import Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from string import ascii_lowercase

from sim.grid import Box
from sim.scenario.model import FLOOR, UNKNOWN, Expect, Furniture, Item, Orientation, Scenario, ScenarioError
from sim.scenario.read import load
from sim.scenario.write import dumps
from tidyplan.loop.scenarios import project_file

CASE1 = project_file("problems/case1.toml")
TASK1 = project_file("problems/wrs-task1.toml")  # its room and deposits: layout task1's base
CATEGORIES = ("food", "kitchen", "tool", "task")
PER_ROOM = 3  # objects of each category in each room
SPACING = 0.2  # m, centre to centre, between any two objects
FOOTPRINT, HEIGHT = (0.05, 0.10), (0.05, 0.15)  # m, drawn per item
FLOOR_GAP = 0.05  # m a floor object's footprint keeps from furniture and walls
TRIES = 20_000  # draws per object before the spawner gives up (it never has)

BOUNDS_TWO = (-3.0, 3.3, -2.0, 2.0)
WALL_X = (0.5, 0.8)  # the dividing wall; the dining room is x = 0.8..3.3
WALL_HEIGHT = 2.0
OPENING, OPENING_MARGIN = 1.2, 0.3
TABLE_SIZE, TABLE_CLEAR, TABLE_EDGE = (0.8, 1.2, 0.70), 0.7, 0.05
RING = 0.5  # m around the dining table where its floor objects lie
DOORWAY = 0.8  # m behind the opening kept free of objects
ENTRANCE_CLEAR, APPROACH_CLEAR = 1.2, 0.6  # m squares kept free around the entrance and approaches


@dataclass(frozen=True, slots=True)
class Zone:
    """Where ``count`` objects of one room spawn: centres in x, y on ``on``; ``edge`` is how far an
    object's footprint keeps inside the top of the piece it stands on (unused on the floor)."""

    name: str
    on: str
    x: tuple[float, float]
    y: tuple[float, float]
    count: int
    edge: float = 0.0


ROOM1 = (
    Zone("floor", FLOOR, (-1.0, -0.4), (-0.35, 1.35), 6),
    Zone("long-table", "long-table", (-0.45, -0.2), (-0.35, 0.7), 4),
    Zone("tall-table", "tall-table", (-0.45, -0.2), (1.0, 1.35), 2),
)


# WRS Task 1 (RoboCup 2021 DSPL rulebook, docs/sources.md): 5 known objects in each of 5 categories
# and one unknown object of each, 30 in all, in the same zones (half, a third, a sixth)
TASK1_CATEGORIES = ("food", "kitchen", "tool", "shape", "task")
TASK1_KNOWN = 5
TASK1_ZONES = (
    Zone("floor", FLOOR, (-1.0, -0.4), (-0.35, 1.35), 15),
    Zone("long-table", "long-table", (-0.45, -0.2), (-0.35, 0.7), 10),
    Zone("tall-table", "tall-table", (-0.45, -0.2), (1.0, 1.35), 5),
)

# Task 1's orientation items (the rulebook: the small and large marker tip down, among the tools;
# the fork and the spoon handle up, among the kitchen items): name, category, length, width, height
# (m, our figures near the YCB objects), and the end that goes down in container B
ORIENTATION_ITEMS = (
    ("marker-large", "tool", 0.121, 0.020, 0.020, "tip"),
    ("marker-small", "tool", 0.100, 0.016, 0.016, "tip"),
    ("fork", "kitchen", 0.200, 0.025, 0.015, "tines"),
    ("spoon", "kitchen", 0.200, 0.040, 0.015, "bowl"),
)
ORIENTATION_GAP = 0.02  # m between an orientation item's footprint and another object's


class SpawnError(Exception):
    """A zone had no room left for an object: the rules cannot be met as drawn."""


def file_name(layout: str, seed: int, per_room: int = PER_ROOM) -> str:
    """wrs-one-s000.toml; at scale the object count too: wrs-two-s000-n96.toml."""
    if layout == "task1":
        return f"wrs-task1-s{seed:03d}.toml"
    n = per_room * len(CATEGORIES) * (2 if layout == "two" else 1)
    return f"wrs-{layout}-s{seed:03d}" + ("" if per_room == PER_ROOM else f"-n{n}") + ".toml"


def generate(
    layout: str,
    seed: int,
    wall_height: float = WALL_HEIGHT,
    base: Scenario | None = None,
    per_room: int = PER_ROOM,
) -> Scenario:
    """The room of ``layout`` ("one" or "two") for ``seed``; ``base`` is case I (read when None).
    ``per_room`` objects of each category in each room (3, the paper's; more for rooms at scale:
    the zones' counts grow with it, and what a zone cannot hold spills onto the room's floor).
    Layout ``task1`` is WRS Task 1's room (``task1``)."""
    if layout == "task1":
        return task1(seed, base)
    base = base or load(CASE1)
    rng = random.Random(seed)
    furniture = list(base.furniture)
    zones = _scaled(ROOM1, per_room, OVERFLOW1)
    # where no zone reaches, and a room at scale must stay clear: where the robot comes in and
    # where it stands to deliver (an item there would shut it in or out)
    ex, ey = base.entrance
    clear = (Box(ex, ey, ENTRANCE_CLEAR, ENTRANCE_CLEAR, "entrance"),) + tuple(
        Box(*d.approach, APPROACH_CLEAR, APPROACH_CLEAR, d.name) for d in base.deposits if d.approach
    )
    items = _room(rng, zones, furniture, base.bounds, [], clear, per_room)
    bounds, notes = base.bounds, ""
    if layout == "two":
        bounds = BOUNDS_TWO
        walls, lo = _divider(rng, wall_height)
        table = _dining_table(rng)
        furniture += [*walls, table]
        doorway = Box(WALL_X[1] + DOORWAY / 2, lo + OPENING / 2, DOORWAY, OPENING, "doorway")
        zones = _scaled(_dining_zones(table), per_room, OVERFLOW2)
        items += _room(rng, zones, furniture, bounds, items, (doorway, *clear), per_room)
        notes = (
            f"\nThe dining room (x {WALL_X[1]:g}..{bounds[1]:g}) is reached through the {OPENING:g} m opening"
            f" at y {lo:g}..{lo + OPENING:g} in the dividing wall ({wall_height:g} m high); its table"
            f" stands at ({table.cx:g}, {table.cy:g}). It has no viewpoint: the planner makes its own."
        )
    elif layout != "one":
        raise ValueError(f"unknown layout {layout!r}")
    name = file_name(layout, seed, per_room).removesuffix(".toml")
    counts = {c: sum(i.category == c for i in items) for c in CATEGORIES}
    return Scenario(
        name=name,
        title=f"WRS tidy-up room, layout {layout}, seed {seed}",
        description=(
            f"Generated by bench/wrs.py: case I's arena with {len(items)} objects placed by the rules of"
            f" the WRS world's seeded object spawner (docs/sources.md).{notes}\n"
        ),
        bounds=bounds,
        entrance=base.entrance,
        heading_deg=base.heading_deg,
        robot=base.robot,
        sensing=base.sensing,
        furniture=tuple(furniture),
        deposits=base.deposits,
        items=tuple(items),
        viewpoints=base.viewpoints,
        expect=Expect(),
        path="",
        prior=tuple(sorted(counts.items())),
    )


def task1(seed: int, base: Scenario | None = None) -> Scenario:
    """WRS Task 1's room (``problems/wrs-task1.toml``'s, read when ``base`` is None) with its 30
    objects drawn for ``seed``: the spawner's zones, and what a zone cannot hold at 0.2 m apart
    on the room's floor; the categories shuffled over the places, then one object of each
    category made unknown (seen as ``unknown``, for bin B). The prior is what the rules announce."""
    base = base or load(TASK1)
    rng = random.Random(seed)
    ex, ey = base.entrance
    clear = (Box(ex, ey, ENTRANCE_CLEAR, ENTRANCE_CLEAR, "entrance"),) + tuple(
        Box(*d.approach, APPROACH_CLEAR, APPROACH_CLEAR, d.name) for d in base.deposits if d.approach
    )
    zones = (*TASK1_ZONES, OVERFLOW1)
    categories = [c for c in TASK1_CATEGORIES for _ in range(TASK1_KNOWN + 1)]
    known = _room(rng, zones, list(base.furniture), base.bounds, [], clear, categories=categories)
    unknown = {rng.choice([i.name for i in known if i.category == c]) for c in TASK1_CATEGORIES}
    items, n = [], 0
    for i in known:
        if i.name in unknown:
            items.append(replace(i, name=f"unknown-{_letters(n)}", unknown=True))
            n += 1
        else:
            items.append(i)
    items = _orientation_items(rng, items, {f.name: f for f in base.furniture})
    name = file_name("task1", seed).removesuffix(".toml")
    counts = {c: TASK1_KNOWN for c in TASK1_CATEGORIES} | {UNKNOWN: len(TASK1_CATEGORIES)}
    return replace(
        base,
        name=name,
        title=f"WRS Task 1 room, seed {seed}",
        description=(
            f"Generated by bench/wrs.py --layout task1: WRS Task 1's room 1 with {len(items)} objects"
            " placed by the rules of the WRS world's seeded object spawner (docs/sources.md); one"
            " object of each category is unknown.\n"
        ),
        items=tuple(items),
        expect=Expect(),
        path="",
        prior=tuple(sorted(counts.items())),
    )


def _orientation_items(rng, items: list[Item], pieces: dict[str, Furniture]) -> list[Item]:
    """Four of the known objects made Task 1's orientation items, where they lie: a marker or a
    fork is long and thin, lying along x or y (drawn), its down end at either end (drawn), where
    that keeps its footprint on what it lies on and ORIENTATION_GAP from every other object (and,
    on the floor, FLOOR_GAP from the furniture); the candidates of its category in drawn order."""
    out = list(items)
    for name, category, length, width, height, down in ORIENTATION_ITEMS:
        candidates = [
            k for k, i in enumerate(out) if i.category == category and not i.unknown and i.orientation is None
        ]
        rng.shuffle(candidates)
        for k in candidates:
            i = out[k]
            along_x = rng.random() < 0.5
            sign = rng.choice((1.0, -1.0))
            for ax in (along_x, not along_x):
                size = (length, width, height) if ax else (width, length, height)
                axis = (sign, 0.0, 0.0) if ax else (0.0, sign, 0.0)
                made = replace(
                    i, name=name, sx=size[0], sy=size[1], sz=size[2], orientation=Orientation(axis, down)
                )
                if _fits_among(made, [o for j, o in enumerate(out) if j != k], pieces):
                    out[k] = made
                    break
            else:
                continue
            break
        else:
            raise SpawnError(f"no room for the orientation item {name!r}")
    return out


def _fits_among(item: Item, others: list[Item], pieces: dict[str, Furniture]) -> bool:
    if item.on != FLOOR:
        f = pieces[item.on]
        if abs(item.x - f.cx) + item.sx / 2 > f.sx / 2 or abs(item.y - f.cy) + item.sy / 2 > f.sy / 2:
            return False
    else:
        grown = Box(item.x, item.y, item.sx + 2 * FLOOR_GAP, item.sy + 2 * FLOOR_GAP, item.name)
        if any(_overlap(grown, f.box()) for f in pieces.values()):
            return False
    grown = Box(item.x, item.y, item.sx + 2 * ORIENTATION_GAP, item.sy + 2 * ORIENTATION_GAP, item.name)
    return not any(o.on == item.on and _overlap(grown, o.box()) for o in others)


# Where a zone's objects go when it is full (rooms at scale only): the open floor of each room,
# clear of the deposit wall's strip
OVERFLOW1 = Zone("room-floor", FLOOR, (-2.1, 0.3), (-1.8, 1.8), 0)
OVERFLOW2 = Zone("dining-room-floor", FLOOR, (1.0, 3.1), (-1.8, 1.8), 0)


def _scaled(zones, per_room: int, overflow: Zone) -> tuple[Zone, ...]:
    """The zones with their counts grown by per_room / PER_ROOM, and the overflow zone last."""
    if per_room == PER_ROOM:
        return tuple(zones)
    total = per_room * len(CATEGORIES)
    counts = [z.count * per_room // PER_ROOM for z in zones]
    counts[0] += total - sum(counts)
    return (*(replace(z, count=n) for z, n in zip(zones, counts, strict=True)), overflow)


def _letters(n: int) -> str:
    """0 -> a, 25 -> z, 26 -> aa, ...: the names of a category's objects."""
    out = ""
    n += 1
    while n:
        n, r = divmod(n - 1, 26)
        out = ascii_lowercase[r] + out
    return out


def _room(
    rng, zones, furniture, bounds, placed, keep_out, per_room: int = PER_ROOM, categories=None
) -> list[Item]:
    """One room's objects: the zones' places drawn in order, then the categories shuffled over them
    (PER_ROOM of each, or the ``categories`` given), lettered after those of the same category
    already ``placed``: food-a, food-b, ..., never like the belief's own names for what it sees
    (food-1, food-2, ...)."""
    shapes: list[tuple[float, float, float, float, float, str]] = []
    others = [(i.x, i.y) for i in placed]
    pieces = {f.name: f for f in furniture}
    spill = 0
    for zone in zones:
        for _ in range(zone.count + (spill if zone.count == 0 else 0)):
            try:
                shape = _spawn(rng, zone, pieces, bounds, others, keep_out)
            except SpawnError:
                if zone is zones[-1] or zones[-1].count != 0:
                    raise
                spill += 1  # full: onto the room's floor (the overflow zone, last)
                continue
            others.append(shape[:2])
            shapes.append(shape)
    categories = list(categories or [c for c in CATEGORIES for _ in range(per_room)])
    assert len(categories) == len(shapes), "the zones' counts must add up to the categories'"
    rng.shuffle(categories)
    seen = {c: sum(i.category == c for i in placed) for c in set(categories)}
    items = []
    for cat, (x, y, sx, sy, sz, on) in zip(categories, shapes, strict=True):
        seen[cat] += 1
        items.append(Item(f"{cat}-{_letters(seen[cat] - 1)}", cat, x, y, on, sx, sy, sz))
    return items


def _spawn(rng, zone: Zone, pieces, bounds, others, keep_out) -> tuple:
    """One object's (x, y, sx, sy, sz, on): its size drawn once, then its centre until it fits."""
    sx, sy, sz = (_draw(rng, *FOOTPRINT), _draw(rng, *FOOTPRINT), _draw(rng, *HEIGHT))
    for _ in range(TRIES):
        x, y = _draw(rng, *zone.x), _draw(rng, *zone.y)
        if any(math.dist((x, y), o) < SPACING for o in others):
            continue
        box = Box(x, y, sx, sy)
        if zone.on == FLOOR:
            grown = Box(x, y, sx + 2 * FLOOR_GAP, sy + 2 * FLOOR_GAP)
            blocked = [f.box() for f in pieces.values()] + list(keep_out)
            if any(_overlap(grown, b) for b in blocked) or not _inside(grown, bounds):
                continue
        elif not _inside(box, _top(pieces[zone.on], zone.edge)):
            continue
        return (x, y, sx, sy, sz, zone.on)
    raise SpawnError(f"no place left for an object in zone {zone.name} after {TRIES} draws")


def _divider(rng, height: float) -> tuple[list[Furniture], float]:
    """The wall between the rooms as two pieces, south and north of the opening, and the opening's
    lower y: drawn so that the opening keeps OPENING_MARGIN from the outer walls."""
    _, _, y0, y1 = BOUNDS_TWO
    lo = round(rng.uniform(y0 + OPENING_MARGIN, y1 - OPENING_MARGIN - OPENING), 2)
    cx, sx = round((WALL_X[0] + WALL_X[1]) / 2, 3), round(WALL_X[1] - WALL_X[0], 3)
    pieces = []
    for name, a, b in (("divider-south", y0, lo), ("divider-north", lo + OPENING, y1)):
        cy, sy = round((a + b) / 2, 3), round(b - a, 3)
        pieces.append(Furniture(name, cx, cy, sx, sy, height, "wall"))
    return pieces, lo


def _dining_table(rng) -> Furniture:
    """The dining table, long side along y, with TABLE_CLEAR of free floor to every wall."""
    sx, sy, h = TABLE_SIZE
    x0, x1 = WALL_X[1] + TABLE_CLEAR + sx / 2, BOUNDS_TWO[1] - TABLE_CLEAR - sx / 2
    y0, y1 = BOUNDS_TWO[2] + TABLE_CLEAR + sy / 2, BOUNDS_TWO[3] - TABLE_CLEAR - sy / 2
    return Furniture(
        "dining-table", round(rng.uniform(x0, x1), 2), round(rng.uniform(y0, y1), 2), sx, sy, h, "table"
    )


def _dining_zones(table: Furniture) -> tuple[Zone, Zone]:
    """Half the dining room's objects on the floor around the table, half on its top."""
    x0, x1 = table.cx - table.sx / 2, table.cx + table.sx / 2
    y0, y1 = table.cy - table.sy / 2, table.cy + table.sy / 2
    floor = Zone("dining-floor", FLOOR, (x0 - RING, x1 + RING), (y0 - RING, y1 + RING), 6)
    return floor, Zone("dining-table", table.name, (x0, x1), (y0, y1), 6, edge=TABLE_EDGE)


def _draw(rng, lo: float, hi: float) -> float:
    return round(rng.uniform(lo, hi), 3)


def _top(f: Furniture, edge: float) -> tuple[float, float, float, float]:
    """The part of a piece's top (x0, x1, y0, y1) an object's footprint may cover."""
    return (f.cx - f.sx / 2 + edge, f.cx + f.sx / 2 - edge, f.cy - f.sy / 2 + edge, f.cy + f.sy / 2 - edge)


def _inside(b: Box, area: tuple[float, float, float, float]) -> bool:
    x0, x1, y0, y1 = area
    return x0 <= b.cx - b.sx / 2 and b.cx + b.sx / 2 <= x1 and y0 <= b.cy - b.sy / 2 and b.cy + b.sy / 2 <= y1


def _overlap(a: Box, b: Box) -> bool:
    return abs(a.cx - b.cx) < (a.sx + b.sx) / 2 and abs(a.cy - b.cy) < (a.sy + b.sy) / 2


def write(s: Scenario, target: Path) -> None:
    """Write ``s`` to ``target`` through a file beside it that must load as ``s``; only then is it
    moved into place, so a target is never left half written or unreadable."""
    tmp = target.with_name(f".{target.name}.tmp")
    tmp.write_text(dumps(s), encoding="utf-8")
    try:
        back = load(tmp)
    except ScenarioError as e:
        tmp.unlink()
        raise SystemExit(f"wrs.py: BUG: {target} would not load:\n{e}") from None
    if replace(back, path="") != s:
        tmp.unlink()
        raise SystemExit(f"wrs.py: BUG: {target} does not read back as the scenario generated")
    os.replace(tmp, target)


# ---------------------------------------------------------------------- command line
class _Parser(argparse.ArgumentParser):
    def error(self, message: str):  # one line, exit 2: no usage block
        self.exit(2, f"wrs.py: {message}\n")


def main(argv: Sequence[str] | None = None) -> int:
    ap = _Parser(description=__doc__.splitlines()[0])
    ap.add_argument("--layout", choices=("one", "two", "task1"), required=True)
    ap.add_argument("--rooms", type=int, default=20)
    ap.add_argument("--first-seed", type=int, default=0)
    ap.add_argument("--out", required=True, metavar="DIR")
    ap.add_argument(
        "--wall-height", type=float, default=None, help=f"m, layout two (default {WALL_HEIGHT:g})"
    )
    ap.add_argument(
        "--per-room", type=int, default=PER_ROOM,
        help=f"objects of each category in each room (default {PER_ROOM}; 6 and 12 make the two-room"
        " layout's 48 and 96 objects)",
    )  # fmt: skip
    ap.add_argument("--force", action="store_true", help="overwrite existing files")
    args = ap.parse_args(argv)
    if args.rooms < 1:
        ap.error(f"--rooms must be at least 1, got {args.rooms}")
    if args.per_room < 1:
        ap.error(f"--per-room must be at least 1, got {args.per_room}")
    if args.first_seed < 0:
        ap.error(f"--first-seed must be >= 0, got {args.first_seed}")
    if args.wall_height is not None and args.layout != "two":
        ap.error("--wall-height is for --layout two (layout one has no dividing wall)")
    height = WALL_HEIGHT if args.wall_height is None else args.wall_height
    if not (math.isfinite(height) and height > 0):
        ap.error(f"--wall-height must be a number > 0, got {args.wall_height}")
    out = Path(args.out)
    if out.exists() and not out.is_dir():
        ap.error(f"--out {out}: not a folder")
    seeds = range(args.first_seed, args.first_seed + args.rooms)
    targets = [out / file_name(args.layout, seed, args.per_room) for seed in seeds]
    existing = [t for t in targets if t.exists()]
    if existing and not args.force:
        more = f" (and {len(existing) - 1} more)" if len(existing) > 1 else ""
        ap.error(f"{existing[0]} exists{more}; --force overwrites")
    out.mkdir(parents=True, exist_ok=True)
    base = load(TASK1 if args.layout == "task1" else CASE1)
    for seed, target in zip(seeds, targets, strict=True):
        write(generate(args.layout, seed, height, base, args.per_room), target)
        print(target)
    return 0


if __name__ == "__main__":
    sys.exit(main())
