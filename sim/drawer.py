"""Drawers in pybullet: the carcass they slide out of and each drawer on a prismatic joint.

The WRS stairs-like drawer's drawers have a handle and must be opened (RoboCup 2021 DSPL rules,
docs/sources.md); the chest has three, a left one and two stacked in the middle. One multibody
for a carcass: the base is the carcass, a static box of the furniture's footprint and height
with a slot where each drawer is (built of the boxes left when the slots are cut out of the
footprint's box, so its bounding box is the footprint: the robot's map, ``Room.as_built``, is of
the closed carcass); each link is a drawer, an open-top box (a bottom and four sides, one
compound shape) with the handle's grip on its front, on a prismatic joint of its own along the
slide, 0 (closed, inside the carcass) to its travel: opened and closed independently. Where
each is comes from ``sim.scenario.model.drawer_layout``; the scenario's checks keep the drawers
of one carcass out of each other's slots and sliding out of one face.

The drawer is moved kinematically, as the robot is: ``drive`` sets the joint and a motor holds it
there while physics steps (an object dropped in does not push it). A jam is the drawer's own
state: stuck at a point, it goes no farther out until it has been pushed back closed.
"""

from __future__ import annotations

import pybullet as p

from sim.scenario.model import BOARD, HANDLE, PLAY, DrawerLayout

DRAWER_MASS = 2.0  # kg: a wooden drawer of 12 mm boards (the motor holds it; the figure hardly matters)
HOLD_FORCE = 500.0  # N: the motor that keeps it where it was put while physics steps
HANDLE_COLOUR = (0.2, 0.2, 0.22)
TOL = 1e-4  # m: an opening this close to a limit is at it

Part = tuple[tuple[float, float, float], tuple[float, float, float]]  # (centre, half extents)


class Drawer:
    """One built drawer: how far it is out, driving it, its jam, where its inside is now."""

    def __init__(self, client: int, body: int, layout: DrawerLayout, joint: int = 0) -> None:
        self.client, self.body, self.layout, self.joint = client, body, layout, joint
        self.jammed: float | None = None  # where it is stuck, until pushed back closed
        self.drive(layout.start)

    @property
    def travel(self) -> float:
        return self.layout.spec.travel

    def opening(self) -> float:
        """How far it is out (m), from the joint: 0.0 closed."""
        return max(0.0, p.getJointState(self.body, self.joint, physicsClientId=self.client)[0])

    def drive(self, to: float) -> float:
        """Move it to ``to`` m out, within 0 and its travel and, outwards, no farther than where
        it is jammed; pushed back closed, it is free again. Returns where it got."""
        now = self.opening()
        to = min(max(to, 0.0), self.travel)
        if self.jammed is not None and to > now:
            to = max(now, min(to, self.jammed))
        p.resetJointState(self.body, self.joint, to, physicsClientId=self.client)
        p.setJointMotorControl2(
            self.body,
            self.joint,
            p.POSITION_CONTROL,
            targetPosition=to,
            force=HOLD_FORCE,
            physicsClientId=self.client,
        )
        if to <= TOL:
            self.jammed = None
        return to

    def jam(self, at: float) -> None:
        """Stick at ``at`` m out (or where it is, if farther): it will not go farther out."""
        self.jammed = max(at, self.opening())

    def interior(self) -> tuple[float, float, float, float]:
        """(x0, x1, y0, y1) of its inside now: what holds its objects."""
        return self.layout.interior(self.opening())

    def exposed(self) -> tuple[float, float, float, float]:
        """(x0, x1, y0, y1) of its inside out of the carcass now: where objects can go in."""
        return self.layout.exposed(self.opening())

    def handle(self) -> tuple[float, float, float]:
        """The middle of the handle's grip now."""
        return self.layout.handle(self.opening())


def build(client: int, layout: DrawerLayout, carcass_colour, drawer_colour) -> Drawer:
    """A carcass with one drawer in ``client``, the drawer as the layout starts it."""
    return build_carcass(client, [layout], carcass_colour, [drawer_colour])[0]


def build_carcass(client: int, layouts: list[DrawerLayout], carcass_colour, drawer_colours) -> list[Drawer]:
    """One carcass and its drawers in ``client`` (``layouts`` all of the same carcass, one colour
    each in ``drawer_colours``), each drawer as its layout starts it; in the order given."""
    first = layouts[0]
    f = first.carcass
    around = _carcass_parts(layouts)
    carcass = box_shapes(client, around, [carcass_colour] * len(around))
    links = []
    for layout, colour in zip(layouts, drawer_colours, strict=True):
        parts = _drawer_parts(layout)
        shapes = box_shapes(client, parts, [colour] * (len(parts) - 1) + [HANDLE_COLOUR])
        axis = [0.0, 0.0, 0.0]
        axis[layout.k] = layout.sign
        x, y = layout.point(-layout.depth / 2)  # the closed drawer's middle: the link's frame
        links.append((shapes, (x - f.cx, y - f.cy, layout.floor_z), axis))
    n = len(links)
    body = p.createMultiBody(
        0,
        carcass[0],
        carcass[1],
        (f.cx, f.cy, 0.0),
        linkMasses=[DRAWER_MASS] * n,
        linkCollisionShapeIndices=[shapes[0] for shapes, _, _ in links],
        linkVisualShapeIndices=[shapes[1] for shapes, _, _ in links],
        linkPositions=[at for _, at, _ in links],
        linkOrientations=[(0, 0, 0, 1)] * n,
        linkInertialFramePositions=[(0, 0, 0)] * n,
        linkInertialFrameOrientations=[(0, 0, 0, 1)] * n,
        linkParentIndices=[0] * n,
        linkJointTypes=[p.JOINT_PRISMATIC] * n,
        linkJointAxis=[axis for _, _, axis in links],
        physicsClientId=client,
    )
    drawers = []
    for joint, layout in enumerate(layouts):
        # physics keeps it within its travel too, should anything push it while physics steps
        p.changeDynamics(
            body, joint, jointLowerLimit=0.0, jointUpperLimit=layout.spec.travel, physicsClientId=client
        )
        drawers.append(Drawer(client, body, layout, joint))
    return drawers


Box3 = tuple[float, float, float, float, float, float]  # along0, along1, across0, across1, z0, z1


def _carcass_parts(layouts: list[DrawerLayout]) -> list[Part]:
    """The carcass as boxes: the footprint's box with every drawer's slot cut out (a slot leaves
    PLAY all round its drawer), in the base's frame (the footprint's middle on the floor)."""
    first = layouts[0]
    f = first.carcass
    depth, width = (f.sx, f.sy) if first.k == 0 else (f.sy, f.sx)
    d0, d1, w0, w1 = -depth / 2, depth / 2, -width / 2, width / 2
    boxes: list[Box3] = [(d0, d1, w0, w1, 0.0, f.height)]
    for layout in layouts:
        c0, c1, z0, z1 = layout.slot()
        middle = (f.cy, f.cx)[layout.k]  # across, the footprint's middle
        back = d1 - layout.depth - PLAY  # the slot's back, along the slide from the footprint's middle
        hole = (back, d1, c0 - middle, c1 - middle, z0, z1)
        boxes = [piece for box in boxes for piece in _cut(box, hole)]
    parts = [_part(first, *b) for b in boxes]
    return [q for q in parts if min(q[1]) > 1e-4]  # a slot at a side leaves no box there


def _cut(box: Box3, hole: Box3) -> list[Box3]:
    """``box`` less ``hole``: at most six boxes (below, above, either side across, either end
    along), or ``box`` itself where they do not meet."""
    a0, a1, c0, c1, z0, z1 = box
    h0, h1, hc0, hc1, hz0, hz1 = hole
    if not (h0 < a1 and a0 < h1 and hc0 < c1 and c0 < hc1 and hz0 < z1 and z0 < hz1):
        return [box]
    mz0, mz1 = max(z0, hz0), min(z1, hz1)
    mc0, mc1 = max(c0, hc0), min(c1, hc1)
    out = [(a0, a1, c0, c1, z0, mz0), (a0, a1, c0, c1, mz1, z1)]  # below and above the hole
    out += [(a0, a1, c0, mc0, mz0, mz1), (a0, a1, mc1, c1, mz0, mz1)]  # either side of it
    out += [(a0, max(a0, h0), mc0, mc1, mz0, mz1), (min(a1, h1), a1, mc0, mc1, mz0, mz1)]  # behind, before
    return [b for b in out if b[1] > b[0] and b[3] > b[2] and b[5] > b[4]]


def _drawer_parts(layout: DrawerLayout) -> list[Part]:
    """The drawer (a bottom and four sides) and its handle's grip, last, in the link's frame: the
    closed drawer's middle at its floor."""
    w, r, b = layout.spec.width / 2 + BOARD, layout.spec.rim, BOARD
    lo, hi = -layout.depth / 2, layout.depth / 2  # its back and its front, along the slide
    h = layout.handle_z - layout.floor_z
    gx, gy, gz = HANDLE
    return [
        _part(layout, lo, hi, -w, w, -b, 0.0),
        _part(layout, lo, lo + b, -w, w, 0.0, r),
        _part(layout, hi - b, hi, -w, w, 0.0, r),
        _part(layout, lo + b, hi - b, -w, -w + b, 0.0, r),
        _part(layout, lo + b, hi - b, w - b, w, 0.0, r),
        _part(layout, hi, hi + gx, -gy / 2, gy / 2, h - gz / 2, h + gz / 2),
    ]


def _part(layout: DrawerLayout, a0, a1, c0, c1, z0, z1) -> Part:
    """A box from ``a0`` to ``a1`` along the slide (outwards), ``c0`` to ``c1`` across it, ``z0``
    to ``z1`` up, as (centre, half extents) in the room's axes."""
    along, across = layout.sign * (a0 + a1) / 2, (c0 + c1) / 2
    ha, hc = abs(a1 - a0) / 2, abs(c1 - c0) / 2
    z, hz = (z0 + z1) / 2, (z1 - z0) / 2
    return ((along, across, z), (ha, hc, hz)) if layout.k == 0 else ((across, along, z), (hc, ha, hz))


def box_shapes(client: int, parts: list[Part], colours) -> tuple[int, int]:
    """(collision, visual) compound shapes of boxes, each part (centre, half extents) in its
    colour: a carcass, a drawer, and the room's open boxes and trays (``sim.room``)."""
    kinds = [p.GEOM_BOX] * len(parts)
    halves = [list(h) for _, h in parts]
    centres = [list(c) for c, _ in parts]
    col = p.createCollisionShapeArray(
        kinds, halfExtents=halves, collisionFramePositions=centres, physicsClientId=client
    )
    vis = p.createVisualShapeArray(
        kinds,
        halfExtents=halves,
        visualFramePositions=centres,
        rgbaColors=[[*c, 1] for c in colours],
        physicsClientId=client,
    )
    return col, vis
