"""The WRS tidy-up room in pybullet, built from a scenario file (``sim.scenario.model``).

Walls (1.5 m high, 0.3 m thick, standing outside the bounds) with the 1.2 m door at the
entrance shut, furniture as solid boxes of the scenario's footprint and height (a bin: an open
box of that size, WRS bins being 0.33 m deep), each deposit a tray (the WRS tray's size) with a
rim on the furniture it stands on (a deposit at a bin's rim: the bin itself), and the items:
small boxes of 0.1 kg that physics can drop, tip and settle, with continuous collision
detection. A deposit with a drawer is built with its carcass, in place of that furniture
piece's box (``sim.drawer``): ``Room.drawers`` holds them, ``Room.opening`` tells where each
drawer's inside is now. Colours follow the item categories (the deposits share their category's
colour). The robot is placed at the entrance facing the scenario's heading.

Nothing that physics moves may leave the room (measured, docs/world.md): a tall box knocked out
of a tray on a 0.4 m table at 2 m/s went over 0.6 m walls, and at 1 m/s tipped over a 0.12 m
sill; so the walls stand higher than a tall box on the drawer top, thick enough that an item
pressed into one is not pushed out of its far side, and the door is shut (the robot never
leaves the room: its paths keep the base inside the bounds).

What the robot's map needs from the scene, ``Room.as_built()``, is read back from pybullet
(the bodies' bounding boxes), not copied from the file: the map is of the room that was built.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import pybullet as p

from sim import drawer
from sim.robot import HSR
from sim.scenario.model import Furniture, Scenario, drawer_layout

# m: the WRS asks for 0.6 m at least; 1.5 m is above a 0.45 m box standing on the 0.94 m drawer
# top, a deposit. 0.3 m thick: an item pressed into a wall, its centre up to 12 cm past the face,
# is not pushed out of the far side (16 cm was; 6 cm was, through a 0.10 m wall)
WALL_HEIGHT, WALL_THICKNESS = 1.5, 0.30
DOOR = 1.2  # m, in the wall nearest the entrance: shut, a door leaf of the wall's height and thickness
TRAY, RIM = 0.38, 0.05  # m: inner side of a deposit tray (the WRS food tray, 0.38 x 0.36), rim height
BIN, BIN_WALL = "bin", 0.015  # the furniture kind built as an open box; m, its sides and bottom
CONTAINER_WALL = 0.005  # m: a container's sides and bottom (WRS container B is a 9.5 cm box)
ITEM_MASS = 0.1  # kg
# continuous collision detection for the items: a swept sphere of half the thinnest half-size
# (inside the box), which pybullet uses once a step moves the item more than half that radius
CCD_SHARE = 0.5
PALETTE = [(0.85, 0.33, 0.10), (0.00, 0.45, 0.74), (0.47, 0.67, 0.19), (0.49, 0.18, 0.56), (0.93, 0.69, 0.13)]
WALL_COLOUR, DOOR_COLOUR = (0.92, 0.92, 0.9), (0.62, 0.50, 0.38)
FURNITURE_COLOUR = {"table": (0.60, 0.45, 0.30), "shelf": (0.55, 0.40, 0.28), "chair": (0.35, 0.35, 0.40)}


@dataclass
class Room:
    client: int
    scenario: Scenario
    robot: HSR
    furniture: dict[str, int] = field(default_factory=dict)
    deposits: dict[str, int] = field(default_factory=dict)
    items: dict[str, int] = field(default_factory=dict)
    drawers: dict[str, drawer.Drawer] = field(default_factory=dict)  # deposit -> its drawer
    walls: list[int] = field(default_factory=list)  # the door leaf among them
    door: int = -1
    floor: int = -1

    def as_built(self) -> Scenario:
        """The scenario with its furniture as pybullet has it (each body's bounding box: centre,
        footprint, height): the robot's map is made of the room that was built."""
        out = []
        for f in self.scenario.furniture:
            (x0, y0, _), (x1, y1, z1) = p.getAABB(self.furniture[f.name], physicsClientId=self.client)
            box = {"cx": (x0 + x1) / 2, "cy": (y0 + y1) / 2, "sx": x1 - x0, "sy": y1 - y0, "height": z1}
            out.append(replace(f, **{k: round(v, 4) for k, v in box.items()}))
        return replace(self.scenario, furniture=tuple(out))

    def opening(self, deposit: str) -> tuple[float, float, float, float]:
        """(x0, x1, y0, y1) of what holds the deposit's objects now: a drawer's inside where the
        drawer is now, else ``opening``'s."""
        if deposit in self.drawers:
            return self.drawers[deposit].interior()
        return opening(self.scenario, next(d for d in self.scenario.deposits if d.name == deposit))

    def colour(self, category: str) -> tuple[float, float, float]:
        # the items' categories first (their colours as before), then deposits' own (orientation)
        known = self.scenario.categories()
        known += sorted({d.category for d in self.scenario.deposits} - set(known))
        return PALETTE[known.index(category) % len(PALETTE)]


def build(scenario: Scenario, client: int) -> Room:
    """Every body of the scenario in ``client`` (an empty world), gravity on."""
    p.setGravity(0, 0, -9.81, physicsClientId=client)
    floor = _box(client, (0, 0, -0.05), (20, 20, 0.1), (0.9, 0.9, 0.88))
    x, y = scenario.entrance
    robot = HSR(client, x, y, math.radians(scenario.heading_deg))
    room = Room(client, scenario, robot, floor=floor)
    room.walls, room.door = _walls(client, scenario)
    # the deposits' drawers are built with the carcass they slide out of, in place of its box
    carcasses: dict[str, list] = {}  # furniture name -> [(deposit, its drawer's layout)], file order
    for d in scenario.deposits:
        layout = drawer_layout(scenario.furniture, d) if d.drawer else None
        if layout is not None:
            carcasses.setdefault(layout.carcass.name, []).append((d, layout))
    for f in scenario.furniture:
        colour = FURNITURE_COLOUR.get(f.kind, (0.7, 0.7, 0.68))
        if f.name in carcasses:
            held = carcasses[f.name]
            colours = [room.colour(d.category) for d, _ in held]
            built = drawer.build_carcass(client, [layout for _, layout in held], colour, colours)
            room.furniture[f.name] = built[0].body
            for (d, _), one in zip(held, built, strict=True):
                room.drawers[d.name], room.deposits[d.name] = one, one.body
        elif f.kind == BIN:
            room.furniture[f.name] = _bin(client, f, colour)
        else:
            room.furniture[f.name] = _box(client, (f.cx, f.cy, f.height / 2), (f.sx, f.sy, f.height), colour)
    for d in scenario.deposits:
        if d.name in room.drawers:
            continue
        held_by = holder(scenario, d)
        if held_by is not None:
            room.deposits[d.name] = room.furniture[held_by.name]
        elif d.container is not None:
            sx, sy, h = d.container
            room.deposits[d.name] = _open_box(client, (d.x, d.y, d.z), sx, sy, h, room.colour(d.category))
        else:
            room.deposits[d.name] = _tray(client, (d.x, d.y, d.z), room.colour(d.category))
    for i in scenario.items:
        z = scenario.item_base_z(i) + i.sz / 2
        room.items[i.name] = _item(client, (i.x, i.y, z), (i.sx, i.sy, i.sz), room.colour(i.category))
    return room


def _walls(client: int, s: Scenario) -> tuple[list[int], int]:
    """Four walls just outside the bounds, their inner faces on them; the 1.2 m door in the wall
    nearest the entrance is shut: a leaf as high and thick as the wall, in its own colour.
    Returns the bodies (the door among them) and the door."""
    x0, x1, y0, y1 = s.bounds
    ex, ey = s.entrance
    t, h = WALL_THICKNESS, WALL_HEIGHT
    sides = {  # name: (fixed coordinate, along from, along to, horizontal?)
        "south": (y0 - t / 2, x0 - t, x1 + t, True),
        "north": (y1 + t / 2, x0 - t, x1 + t, True),
        "west": (x0 - t / 2, y0, y1, False),
        "east": (x1 + t / 2, y0, y1, False),
    }
    gaps = {"south": abs(ey - y0), "north": abs(y1 - ey), "west": abs(ex - x0), "east": abs(x1 - ex)}
    door_side = min(gaps, key=gaps.get)
    bodies, door = [], -1
    for name, (fixed, a, b, horizontal) in sides.items():
        pieces = [(a, b, WALL_COLOUR)]
        if name == door_side:
            centre = ex if horizontal else ey
            lo, hi = max(a, centre - DOOR / 2), min(b, centre + DOOR / 2)
            pieces = [(a, lo, WALL_COLOUR), (lo, hi, DOOR_COLOUR), (hi, b, WALL_COLOUR)]
        for lo, hi, colour in pieces:
            if hi - lo < 1e-3:
                continue
            mid, length = (lo + hi) / 2, hi - lo
            pos = (mid, fixed, h / 2) if horizontal else (fixed, mid, h / 2)
            size = (length, t, h) if horizontal else (t, length, h)
            bodies.append(_box(client, pos, size, colour))
            if colour == DOOR_COLOUR:
                door = bodies[-1]
    return bodies, door


def holder(scenario: Scenario, deposit) -> Furniture | None:
    """The bin whose inside ``deposit`` is: a piece of kind "bin" under its place, the place at
    the bin's rim. Objects are dropped into a bin; everywhere else a deposit is a tray."""
    for f in scenario.furniture:
        if (
            f.kind == BIN
            and f.box().clearance(deposit.x, deposit.y) == 0.0
            and abs(deposit.z - f.height) < 0.02
        ):
            return f
    return None


def opening(scenario: Scenario, deposit) -> tuple[float, float, float, float]:
    """(x0, x1, y0, y1) of what holds a deposit's objects: a bin's inside, a drawer's inside as it
    starts (``Room.opening`` follows the built drawer), else its tray's."""
    layout = drawer_layout(scenario.furniture, deposit)
    if layout is not None:
        return layout.interior(layout.start)
    f = holder(scenario, deposit)
    if f is not None:
        hx, hy = f.sx / 2 - BIN_WALL, f.sy / 2 - BIN_WALL
        return f.cx - hx, f.cx + hx, f.cy - hy, f.cy + hy
    if deposit.container is not None:
        hx, hy = deposit.container[0] / 2 - CONTAINER_WALL, deposit.container[1] / 2 - CONTAINER_WALL
        return deposit.x - hx, deposit.x + hx, deposit.y - hy, deposit.y + hy
    h = TRAY / 2
    return deposit.x - h, deposit.x + h, deposit.y - h, deposit.y + h


def _bin(client: int, f: Furniture, colour) -> int:
    """An open box of the piece's footprint and height: a bottom and four sides, one body. What
    is dropped in stays in, stacked or leaning, as in the WRS bins (0.38 x 0.33 x 0.33)."""
    return _open_box(client, (f.cx, f.cy, 0.0), f.sx, f.sy, f.height, colour, BIN_WALL)


def _open_box(client: int, at, sx: float, sy: float, h: float, colour, t: float = 0.0) -> int:
    """An open box of outer ``sx`` x ``sy`` x ``h`` standing at ``at`` (x, y, its bottom), its
    bottom and sides ``t`` thick (CONTAINER_WALL where not given): a bin, a container."""
    t = t or CONTAINER_WALL
    hx, hy = sx / 2, sy / 2
    parts = [
        ((0, 0, t / 2), (hx, hy, t / 2)),
        ((hx - t / 2, 0, h / 2), (t / 2, hy, h / 2)),
        ((-hx + t / 2, 0, h / 2), (t / 2, hy, h / 2)),
        ((0, hy - t / 2, h / 2), (hx, t / 2, h / 2)),
        ((0, -hy + t / 2, h / 2), (hx, t / 2, h / 2)),
    ]
    return _compound(client, parts, at, colour)


def _tray(client: int, at: tuple[float, float, float], colour) -> int:
    """A square tray on the surface at ``at`` (x, y, top of the furniture): a base and four rims,
    one body so that it is one deposit."""
    x, y, z = at
    half = TRAY / 2 + 0.01
    parts = [((0, 0, 0.005), (half, half, 0.005))]
    for dx, dy, hx, hy in (
        (half, 0, 0.01, half),
        (-half, 0, 0.01, half),
        (0, half, half, 0.01),
        (0, -half, half, 0.01),
    ):
        parts.append(((dx, dy, RIM / 2), (hx, hy, RIM / 2)))
    return _compound(client, parts, (x, y, z), colour)


def _compound(client: int, parts, at, colour) -> int:
    """A static body of boxes, each (offset from ``at``, half extents)."""
    col, vis = drawer.box_shapes(client, parts, [colour] * len(parts))
    return p.createMultiBody(0, col, vis, at, physicsClientId=client)


def _box(client: int, centre, size, colour) -> int:
    """A static box: the floor, a wall, a piece of furniture."""
    half = [s / 2 for s in size]
    col = p.createCollisionShape(p.GEOM_BOX, halfExtents=half, physicsClientId=client)
    vis = p.createVisualShape(p.GEOM_BOX, halfExtents=half, rgbaColor=[*colour, 1], physicsClientId=client)
    return p.createMultiBody(0, col, vis, centre, physicsClientId=client)


def _item(client: int, centre, size, colour) -> int:
    """An item: a box of ITEM_MASS with continuous collision detection. It is a rigid body of
    maximal coordinates, because pybullet sweeps only those: on a multibody (the default)
    ``ccdSweptSphereRadius`` is accepted and does nothing (measured: a 6 cm box at 24 m/s went
    through a 1 cm sheet 18 times in 20 as a multibody, with the sphere or without; as a rigid
    body 10 times without it, never with it)."""
    half = [s / 2 for s in size]
    col = p.createCollisionShape(p.GEOM_BOX, halfExtents=half, physicsClientId=client)
    vis = p.createVisualShape(p.GEOM_BOX, halfExtents=half, rgbaColor=[*colour, 1], physicsClientId=client)
    body = p.createMultiBody(ITEM_MASS, col, vis, centre, useMaximalCoordinates=True, physicsClientId=client)
    p.changeDynamics(
        body,
        -1,
        lateralFriction=0.8,
        rollingFriction=0.001,
        ccdSweptSphereRadius=CCD_SHARE * min(half),
        physicsClientId=client,
    )
    return body


def inside(held_in: tuple[float, float, float, float], xy: tuple[float, float]) -> bool:
    """Is a point (an object's centre) inside a deposit's ``opening`` (x0, x1, y0, y1)?"""
    x0, x1, y0, y1 = held_in
    return x0 <= xy[0] <= x1 and y0 <= xy[1] <= y1
