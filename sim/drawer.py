"""A drawer in pybullet: the carcass it slides out of and the drawer on a prismatic joint.

The WRS stairs-like drawer's drawers have a handle and must be opened (RoboCup 2021 DSPL rules,
docs/sources.md). One multibody: the base is the carcass, a static box of the furniture's
footprint and height with a slot where the drawer is (built of the boxes around the slot, so its
bounding box is the footprint: the robot's map, ``Room.as_built``, is of the closed carcass); the
one link is the drawer, an open-top box (a bottom and four sides, one compound shape) with the
handle's grip on its front, on a prismatic joint along the slide, 0 (closed, inside the carcass)
to its travel. Where it is comes from ``sim.scenario.model.drawer_layout``.

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

    def __init__(self, client: int, body: int, layout: DrawerLayout) -> None:
        self.client, self.body, self.layout = client, body, layout
        self.jammed: float | None = None  # where it is stuck, until pushed back closed
        self.drive(layout.start)

    @property
    def travel(self) -> float:
        return self.layout.spec.travel

    def opening(self) -> float:
        """How far it is out (m), from the joint: 0.0 closed."""
        return max(0.0, p.getJointState(self.body, 0, physicsClientId=self.client)[0])

    def drive(self, to: float) -> float:
        """Move it to ``to`` m out, within 0 and its travel and, outwards, no farther than where
        it is jammed; pushed back closed, it is free again. Returns where it got."""
        now = self.opening()
        to = min(max(to, 0.0), self.travel)
        if self.jammed is not None and to > now:
            to = max(now, min(to, self.jammed))
        p.resetJointState(self.body, 0, to, physicsClientId=self.client)
        p.setJointMotorControl2(
            self.body, 0, p.POSITION_CONTROL, targetPosition=to, force=HOLD_FORCE, physicsClientId=self.client
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
    """The carcass and its drawer in ``client``, the drawer as the layout starts it."""
    f = layout.carcass
    around = [q for q in _carcass_parts(layout) if min(q[1]) > 1e-4]  # a slot at a side leaves no box there
    carcass = _shapes(client, around, [carcass_colour] * len(around))
    parts = _drawer_parts(layout)
    drawer = _shapes(client, parts, [drawer_colour] * (len(parts) - 1) + [HANDLE_COLOUR])
    axis = [0.0, 0.0, 0.0]
    axis[layout.k] = layout.sign
    x, y = layout.point(-layout.depth / 2)  # the closed drawer's middle: the link's frame
    body = p.createMultiBody(
        0,
        carcass[0],
        carcass[1],
        (f.cx, f.cy, 0.0),
        linkMasses=[DRAWER_MASS],
        linkCollisionShapeIndices=[drawer[0]],
        linkVisualShapeIndices=[drawer[1]],
        linkPositions=[(x - f.cx, y - f.cy, layout.floor_z)],
        linkOrientations=[(0, 0, 0, 1)],
        linkInertialFramePositions=[(0, 0, 0)],
        linkInertialFrameOrientations=[(0, 0, 0, 1)],
        linkParentIndices=[0],
        linkJointTypes=[p.JOINT_PRISMATIC],
        linkJointAxis=[axis],
        physicsClientId=client,
    )
    # physics keeps it within its travel too, should anything push it while physics steps
    p.changeDynamics(body, 0, jointLowerLimit=0.0, jointUpperLimit=layout.spec.travel, physicsClientId=client)
    return Drawer(client, body, layout)


def _carcass_parts(layout: DrawerLayout) -> list[Part]:
    """The carcass as the five boxes around the drawer's slot (below, above, either side, behind),
    in the base's frame (the footprint's middle on the floor). The slot leaves PLAY all round."""
    f, s = layout.carcass, layout.spec
    depth, width = (f.sx, f.sy) if layout.k == 0 else (f.sy, f.sx)
    half = s.width / 2 + BOARD + PLAY
    z0, z1 = layout.floor_z - BOARD - PLAY, layout.floor_z + s.rim + PLAY
    side = layout.across - (f.cy, f.cx)[layout.k]  # the slot's middle, across, from the footprint's
    s0, s1 = side - half, side + half
    d0, d1, w0, w1 = -depth / 2, depth / 2, -width / 2, width / 2
    back = d1 - layout.depth - PLAY  # the slot's back, along the slide from the footprint's middle
    return [
        _part(layout, d0, d1, w0, w1, 0.0, z0),
        _part(layout, d0, d1, w0, w1, z1, f.height),
        _part(layout, d0, d1, w0, s0, z0, z1),
        _part(layout, d0, d1, s1, w1, z0, z1),
        _part(layout, d0, back, s0, s1, z0, z1),
    ]


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


def _shapes(client: int, parts: list[Part], colours) -> tuple[int, int]:
    """(collision, visual) compound shapes of boxes."""
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
