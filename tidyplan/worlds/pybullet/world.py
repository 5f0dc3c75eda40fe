"""The pybullet world: the Toyota HSR in the WRS room (``sim``), behind the same skills as the
symbolic world, so the behaviour units and the loop run unchanged on it.

What is real here: the room built from the scenario file, the robot model and its joint
speeds, the head camera's field of view, range and occlusion by ray tests, the base's collision
shape against the scene along every path, the arm reaching by pybullet's inverse kinematics,
a grasp as a fixed constraint, objects that fall, tip and settle under physics when let go.
What is drawn by rate from one seeded generator, as in the symbolic world: detection errors,
grasps that slip (``grasp_fail``; the object drops back), placements where the hand does not
open (``place_fail``), objects that slip out while carried (``grasp_drop``; they fall from the
hand to the floor, where perception must find them again), transient obstacles
(``path_blocked``).

Durations on the simulated clock come from the HSR (docs/sources.md): driving at 0.22 m/s
(0.8 km/h; a careful pose adjustment at half that), turning at 0.75 rad/s, every arm, head and
gripper motion from its joints' top speeds (all joints of a motion move at once); a head sweep
pans the camera across the head's whole range (-3.84 to 1.75 rad at 1 rad/s, 5.6 s); a
close-range look points the head at the place and recognises for 1 s; physics settles for
1 s after a release. docs/world.md lists them.
"""

from __future__ import annotations

import math

import numpy as np
import pybullet as p

from sim.camera import Camera
from sim.motion import TOUCH, base_contacts, blocked, contacts, settle
from sim.robot import RAISED, STOW, YAW_SPEED
from sim.room import build, inside, opening
from sim.scenario.model import ORIENTATION, STAND_DEG, Scenario
from tidyplan.belief.geometry import RoomMap
from tidyplan.belief.percepts import Detection
from tidyplan.worlds.base import FRAME_EVERY, Odometer, Outcome, Rates, TrueItem, WorldReferee
from tidyplan.worlds.pybullet.drawer import Drawers
from tidyplan.worlds.pybullet.hand import SETTLE_S, Hand
from tidyplan.worlds.pybullet.look import AIM_MARGIN_S, RECOGNISE_S, TORSO_UP, HeadCamera
from tidyplan.worlds.pybullet.put import HeldAs

Point = tuple[float, float]

STEP = 0.05  # m between collision checks along a path (the grid's cell)
# A robot stopped by a contact backs off this far along its way: stopped where the last check
# passed, it stood within a step of the obstacle, and the next path's first step (to the centre
# of its grid cell) could run into it again, which pinned the robot where it stood.
BACK_OFF = 0.10


class BulletWorld(Drawers, Hand, HeadCamera, WorldReferee):
    """The HSR in pybullet. ``gui`` opens the pybullet window and follows the robot."""

    @classmethod
    def for_mission(cls, scenario: Scenario, room: RoomMap, settings) -> BulletWorld:
        """The world for a mission's ``settings`` (``tidyplan.loop.mission.Settings``), the robot's
        map of the furniture read back from the built scene."""
        world = cls(scenario, room, seed=settings.seed, rates=settings.rates, gui=settings.gui)
        world.room = RoomMap(world.scene.as_built())
        return world

    def __init__(
        self,
        scenario: Scenario,
        room: RoomMap,
        seed: int = 0,
        rates: Rates = Rates(),  # noqa: B008 - frozen, never mutated
        gui: bool = False,
    ) -> None:
        super().__init__(scenario, room, seed, rates)
        self.gui = gui
        self.client = p.connect(p.GUI if gui else p.DIRECT)
        if gui:
            p.configureDebugVisualizer(p.COV_ENABLE_GUI, 0, physicsClientId=self.client)
        self.scene = build(scenario, self.client)
        # (x0, x1, y0, y1) of what holds each deposit's objects: its tray's or its bin's inside
        self.openings = {d.name: opening(scenario, d) for d in scenario.deposits}
        self.hsr = self.scene.robot
        s = scenario.sensing
        self.camera = Camera(s.fov_h_deg, s.fov_v_deg, s.range_min, s.range_max)
        self.bodies = dict(self.scene.items)
        self._grip: int | None = None  # the grasp constraint
        self._grip_offset = ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0))
        self._last_released: str | None = None  # the object the last release let go of
        # how the hand holds what it holds, to put it down as it stood, or stood on its end
        self._held_as = HeldAs((0.0, 0.0, 0.0, 1.0), 0.0, 0.0, 0.0, (0.0, 0.0))
        self._stood_up_as: HeldAs | None = None
        self._stood_down_as: HeldAs | None = None  # an orientation item stood on its down end
        self.knocked: list[str] = []  # tidied objects a release or a fall knocked out of their deposit
        self._pan_forward = True  # sweeps alternate direction: no return swing
        self._lift_after_look: float | None = None  # the arm lift a close look raised the torso from
        # (where the drive ended, what the detector found, seconds to go when it was taken) of the
        # frame taken in a drive's last second with the head on its work
        self._recognised: tuple[Point, list, float] | None = None
        x, y, _ = self.hsr.base()
        self.robot: Point = (x, y)
        self.odometer = Odometer(track=[self.robot])
        self._follow_camera()

    def close(self) -> None:
        if p.isConnected(self.client):
            p.disconnect(self.client)

    def holds(self) -> bool:
        """The gripper's sensor: is something in the hand?"""
        return self.holding is not None

    def pose(self) -> Point:
        return self.robot

    # ------------------------------------------------------------------ actions
    def follow(
        self, path: list[Point], monitor=None, *, careful: bool = False, face: Point | None = None
    ) -> Outcome:
        """Drive along ``path`` kinematically at the HSR's speed (``careful``: half of it), testing
        the base's collision shape every 5 cm; stop short of a contact (``path_blocked``), or
        where a transient obstacle stands (the ``path_blocked`` fault). ``monitor.poll()`` runs
        after every segment and stops the motion when it returns False (``interrupted``). An
        object in the hand slips out on the way at the ``grasp_drop`` rate and falls: at the end
        of the drawn segment, or of the first one after it where it is in the room and touches
        nothing (``_free``).

        ``face``: the base turns on the way to face it at the end (the HSR's base is
        omnidirectional: it turns at its yaw rate while it drives, and what is left of the turn
        when it arrives takes its own time after)."""
        speed = self.scenario.robot.speed / (2 if careful else 1)
        n = len(path)
        yaw0, turn = self.hsr.base()[2], 0.0
        if face is not None and n and math.dist(path[-1], face) > 1e-3:
            want = math.atan2(face[1] - path[-1][1], face[0] - path[-1][0])
            turn = (want - yaw0 + math.pi) % (2 * math.pi) - math.pi
        block_at, drop_at = self._faults_on_path(n)
        ignore = self._ignored()
        self._recognised = None
        # a torso a close look raised comes down while the base drives (joints and base together);
        # where the close look at the end will need it up, it rises in the drive's last seconds
        rise = n > 0 and self._torso_needed(face, path[-1], yaw0 + turn)
        lowering = 0.0 if rise else self._lower_torso()
        rise_s = TORSO_UP / self.hsr.joints["arm_lift_joint"].speed + AIM_MARGIN_S
        left_s = sum(math.dist(path[k - 1], path[k]) for k in range(1, n)) / speed
        metres = seconds = 0.0
        before = base_contacts(self.hsr, ignore)
        passed = [self.robot]  # poses whose check passed, latest last
        framed = 0.0  # m driven since the last frame kept
        for k in range(1, n):
            if k == block_at:
                return Outcome(False, "path_blocked", seconds + self._wait(lowering - seconds), metres)
            a, b = path[k - 1], path[k]
            steps = max(1, math.ceil(math.dist(a, b) / STEP))
            for s in range(1, steps + 1):
                q = (a[0] + (b[0] - a[0]) * s / steps, a[1] + (b[1] - a[1]) * s / steps)
                d = math.dist(self.robot, q)
                turned = min(abs(turn), YAW_SPEED * (seconds + d / speed))  # by the time it is at q
                self._place_base(q, yaw0 + math.copysign(turned, turn))
                hit = blocked(base_contacts(self.hsr, ignore), before)
                if hit:
                    touched = self._touched(hit)
                    back = next((r for r in reversed(passed) if math.dist(r, q) >= BACK_OFF), passed[0])
                    d = math.dist(self.robot, back)
                    self._place_base(back)  # stop short, and back off where the way was clear
                    self._arrive(back, d, d / speed)
                    seconds += d / speed
                    return Outcome(
                        False, "path_blocked", seconds + self._wait(lowering - seconds), metres + d, touched
                    )
                d = math.dist(self.robot, q)
                metres, seconds = metres + d, seconds + d / speed
                self._head_on_the_way(math.atan2(b[1] - a[1], b[0] - a[0]), face, left_s, d / speed)
                if rise and left_s - d / speed <= rise_s:
                    self._torso_rising(d / speed)
                left_s -= d / speed
                self._arrive(q, d, d / speed)
                if face is not None and self._recognised is None and left_s <= RECOGNISE_S:
                    self._recognition_frame(path[-1], left_s)
                passed.append(q)
                framed += d
                last = (k, s) == (n - 1, steps)  # the last frame is the glance's own
                # the belief's frames are from the lens at its usual height: none with the torso up
                if framed >= FRAME_EVERY and not last and self._lift_after_look is None:
                    self._frames.append(self._frame())
                    framed = 0.0
            if drop_at is not None and k >= drop_at and self.holding is not None and self._free():
                self._slip()
            if monitor is not None and not monitor.poll():
                return Outcome(False, "interrupted", seconds + self._wait(lowering - seconds), metres)
        # the turn's part the drive was too short for, and the torso's
        rest = max(abs(turn) / YAW_SPEED, lowering) - seconds
        if rest > 0:
            self._place_base(self.robot, yaw0 + turn)
            if face is not None:
                self._head_toward(*self._aim(face), rest)
            if rise:
                self._torso_rising(rest)
            self._arrive(self.robot, 0.0, rest)
            seconds += rest
        return Outcome(True, None, seconds, metres)

    # ------------------------------------------------------------------ helpers
    def _wait(self, seconds: float) -> float:
        """The robot stands ``seconds`` (if more than 0) while a joint finishes its motion."""
        seconds = max(seconds, 0.0)
        if seconds:
            self._arrive(self.robot, 0.0, seconds)
        return seconds

    def _touched(self, bodies: list[int]) -> Point:
        """Where on the base's edge it touches ``bodies``: the bumper's side (the mean of the
        contact points), for a close look there."""
        base, client = self.hsr.base_link, self.client
        points = [
            q[5][:2]
            for b in bodies
            for q in p.getClosestPoints(self.hsr.body, b, 0.0, linkIndexA=base, physicsClientId=client)
        ]
        if not points:
            return self.robot
        x, y = np.mean(points, axis=0)
        return round(float(x), 3), round(float(y), 3)

    def _ignored(self) -> list[int]:
        """What the base may touch: the floor, and the object in its own hand."""
        return [self.scene.floor] + ([self.bodies[self.holding]] if self.holding else [])

    def _place_base(self, q: Point, yaw: float | None = None) -> None:
        self.hsr.set_base(q[0], q[1], yaw)
        self._carry_along()

    def _arrive(self, to: Point, metres: float, seconds: float) -> None:
        self.robot = to
        self.odometer.sim_time_s += seconds
        self.odometer.distance_m += metres
        if math.dist(self.odometer.track[-1], to) >= 0.1:  # the track at 10 cm: enough for plots
            self.odometer.track.append(to)
        self._follow_camera()

    def _free(self) -> bool:
        """Is the held object in the room, touching nothing but the robot (a graze aside)? It is
        carried kinematically, through a table or a wall in its way: let go inside one, physics
        would throw it out to the nearest side, the far side of a wall too; and held out far
        enough over the base's edge, it is beyond the wall."""
        held = self.bodies[self.holding]
        x, y, _ = p.getBasePositionAndOrientation(held, physicsClientId=self.client)[0]
        x0, x1, y0, y1 = self.scenario.bounds
        touching = contacts(self.client, held, [self.hsr.body, self.scene.floor])
        return x0 <= x <= x1 and y0 <= y <= y1 and all(d <= TOUCH for d in touching.values())

    def _slip(self) -> None:
        """The held object slips out (grasp_drop): the robot stops, the object falls from the hand,
        pushed a little away from the base, and comes to rest wherever physics puts it. The hand
        goes up out of its way first, as after a release: the fingers of a hand opened wide
        would otherwise be inside an object wider than they open, and kick it."""
        name = self.holding
        body = self.bodies[name]
        bx, by, _ = self.hsr.base()
        pos = p.getBasePositionAndOrientation(body, physicsClientId=self.client)[0]
        away = np.array([pos[0] - bx, pos[1] - by])
        away = away / (np.linalg.norm(away) or 1.0)
        speed = float(self.rng.uniform(0.1, 0.6))
        self._release()
        self.hsr.set_joints(RAISED)
        p.resetBaseVelocity(body, (away[0] * speed, away[1] * speed, 0.0), physicsClientId=self.client)
        self._settle()
        self._sync(name)
        self.items[name].state = "placed"
        self.hsr.set_joints(STOW)

    def _settle(self) -> None:
        """Step physics with the robot holding still; then read back where every object rests: a
        release or a fall may knock others over, out of a deposit too (no longer tidied)."""
        # every object the hand does not hold: the one just let go too, still marked held
        settle(self.hsr, SETTLE_S, [b for n, b in self.bodies.items() if n != self.holding])
        for name, item in self.items.items():
            if item.state == "held":
                continue
            self._sync(name)
            if item.state == "tidied" and not inside(self.openings[item.deposit], (item.x, item.y)):
                item.state, item.deposit = "placed", None
                self.knocked.append(name)
            self._judge_stance(name)

    def _seen(self, o: TrueItem) -> Detection:
        """What the detector reports of ``o``: an orientation item's down end as it lies now."""
        return o.seen(round(o.x, 3), round(o.y, 3), self._down(o.name))

    def _down(self, name: str) -> tuple[float, float, float] | None:
        """The direction in the room of an orientation item's down end (None for other objects)."""
        o = self.items[name]
        if o.orientation is None:
            return None
        orn = p.getBasePositionAndOrientation(self.bodies[name], physicsClientId=self.client)[1]
        m = np.reshape(p.getMatrixFromQuaternion(orn), (3, 3))
        return tuple(float(v) for v in m @ np.asarray(o.orientation.axis))

    def _judge_stance(self, name: str) -> None:
        """The rulebook's orientation, from the object's pose: in a deposit for orientation items,
        its down end within STAND_DEG of straight down."""
        o = self.items[name]
        d = next((d for d in self.scenario.deposits if d.name == o.deposit), None)
        down = self._down(name)
        if o.state != "tidied" or d is None or d.category != ORIENTATION or down is None:
            o.stands = None
            return
        o.stands = -down[2] >= math.cos(math.radians(STAND_DEG))

    def _sync(self, name: str) -> None:
        """The truth of one object from pybullet: where it rests and on what."""
        item = self.items[name]
        body = self.bodies[name]
        (x0, y0, z0), (x1, y1, z1) = p.getAABB(body, physicsClientId=self.client)
        item.x, item.y = round((x0 + x1) / 2, 3), round((y0 + y1) / 2, 3)
        # its extent as it lies now: a tall box that toppled covers more floor
        item.sx, item.sy, item.sz = round(x1 - x0, 3), round(y1 - y0, 3), round(z1 - z0, 3)
        item.on = "floor"
        for f in self.scenario.furniture:
            if f.box().clearance(item.x, item.y) == 0.0 and z0 > 0.03:
                item.on = f.name
                break

    def _follow_camera(self) -> None:
        if self.gui:
            p.resetDebugVisualizerCamera(2.2, 45.0, -50.0, (*self.robot, 0.4), physicsClientId=self.client)
