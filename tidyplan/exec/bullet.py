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

Durations on the simulated clock come from the HSR (../shared/HSR.md): driving at 0.22 m/s
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
from sim.motion import base_contacts, blocked, settle
from sim.robot import CARRY, GRIPPER_OPEN, REACHED, STOW
from sim.room import TRAY, build
from sim.scenario import Scenario
from tidyplan.exec.bullet_look import RECOGNISE_S, HeadCamera
from tidyplan.exec.geometry import RoomMap
from tidyplan.exec.symbolic import TAKE_TOLERANCE
from tidyplan.exec.world import Odometer, Outcome, Rates, WorldReferee

Point = tuple[float, float]

SETTLE_S = 1.0  # s of physics after a release
STEP = 0.05  # m between collision checks along a path (the grid's cell)
ABOVE = 0.05  # m: the hand comes down onto an object from this far above it
LEAN = (0.0, 0.05, 0.1)  # m the base may slide towards a place to put an object down upright


class BulletWorld(HeadCamera, WorldReferee):
    """The HSR in pybullet. ``gui`` opens the pybullet window and follows the robot."""

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
        self.hsr = self.scene.robot
        s = scenario.sensing
        self.camera = Camera(s.fov_h_deg, s.fov_v_deg, s.range_min, s.range_max)
        self.bodies = dict(self.scene.items)
        self._grip: int | None = None  # the grasp constraint
        self._grip_offset = ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0))
        self._last_released: str | None = None  # the object the last release let go of
        self._held_as = (
            (0.0, 0.0, 0.0, 1.0),
            0.0,
            0.0,
        )  # hand orientation, base yaw, hand over the object's bottom
        self._pan_forward = True  # sweeps alternate direction: no return swing
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
    def follow(self, path: list[Point], monitor=None, *, careful: bool = False) -> Outcome:
        """Drive along ``path`` kinematically at the HSR's speed (``careful``: half of it), testing
        the base's collision shape every 5 cm; stop short of a contact (``path_blocked``), or
        where a transient obstacle stands (the ``path_blocked`` fault). ``monitor.poll()`` runs
        after every segment and stops the motion when it returns False (``interrupted``). An
        object in the hand slips out on the way at the ``grasp_drop`` rate and falls."""
        speed = self.scenario.robot.speed / (2 if careful else 1)
        n = len(path)
        block_at, drop_at = self._faults_on_path(n)
        ignore = self._ignored()
        metres = seconds = 0.0
        before = base_contacts(self.hsr, ignore)
        for k in range(1, n):
            if k == block_at:
                return Outcome(False, "path_blocked", seconds, metres)
            a, b = path[k - 1], path[k]
            steps = max(1, math.ceil(math.dist(a, b) / STEP))
            for s in range(1, steps + 1):
                q = (a[0] + (b[0] - a[0]) * s / steps, a[1] + (b[1] - a[1]) * s / steps)
                self._place_base(q)
                if blocked(base_contacts(self.hsr, ignore), before):
                    self._place_base(self.robot)  # stop short: back where the last check passed
                    return Outcome(False, "path_blocked", seconds, metres)
                d = math.dist(self.robot, q)
                metres, seconds = metres + d, seconds + d / speed
                self._arrive(q, d, d / speed)
            if k == drop_at:
                self._slip()
            if monitor is not None and not monitor.poll():
                return Outcome(False, "interrupted", seconds, metres)
        return Outcome(True, None, seconds, metres)

    def grasp(self, target: Point) -> Outcome:
        """Turn to the object at ``target``, bring the hand down onto it (inverse kinematics),
        close the fingers (or the suction pad, for objects wider than the hand opens), attach,
        lift into the carrying posture. ``grasp_fail`` at 1 - the take rate: the object slips
        while lifted and drops back."""
        if self.holding is not None:
            return self._fail("hand_full", 1.0)
        near = [o for o in self._placed() if math.dist((o.x, o.y), target) <= TAKE_TOLERANCE]
        if not near:
            return self._fail("not_found", RECOGNISE_S)
        item = min(near, key=lambda o: (math.dist((o.x, o.y), target), o.name))
        body = self.bodies[item.name]
        (_, _, z0), (_, _, top) = p.getAABB(body, physicsClientId=self.client)
        seconds = self.hsr.turn_to(item.x, item.y)
        grip = (item.x, item.y, top - min(0.03, item.sz / 2))
        before = (grip[0], grip[1], grip[2] + ABOVE)
        above, err_above = self.hsr.reach(before)
        at, err = self.hsr.reach(grip)
        if max(err, err_above) > REACHED:
            seconds += self.hsr.set_joints(STOW)
            return self._fail("out_of_reach", seconds)
        seconds += self.hsr.set_joints(above) + self.hsr.set_joints(at)
        seconds += self.hsr.set_gripper(min(GRIPPER_OPEN, item.sx / 2))
        self._attach(item.name)
        hand_pos, hand_orn = self.hsr.hand()
        self._held_as = (hand_orn, self.hsr.base()[2], hand_pos[2] - z0)  # to put it down as it stood
        if self.rng.random() >= self.rates.take:
            seconds += self.hsr.set_joints(above)
            self._release()
            settle(self.hsr, SETTLE_S)
            seconds += SETTLE_S + self.hsr.set_gripper(GRIPPER_OPEN) + self.hsr.set_joints(STOW)
            self._sync(item.name)
            return self._fail("grasp_fail", seconds)
        seconds += self.hsr.set_joints(above) + self._carry()
        item.state = "held"
        return self._spend(seconds)

    def place(self, deposit: str, approach: Point) -> Outcome:
        """Put the held object into the tray of ``deposit`` from its approach pose: turn to it,
        reach above the tray, open, let it settle. ``place_fail`` at 1 - the deliver rate: the
        hand does not open and the object stays in it."""
        if self.holding is None:
            return self._fail("hand_empty", 1.0)
        if math.dist(self.robot, approach) > 0.1:
            return self._fail("not_at_deposit", 1.0)
        d = next(d for d in self.scenario.deposits if d.name == deposit)
        seconds = self.hsr.turn_to(d.x, d.y)
        self._carry_along()
        out = self._release_at((d.x, d.y), d.z + 0.01, seconds, fault_rate=self.rates.deliver)
        if not out.ok:
            return out
        item = self.items[self._last_released]
        if abs(item.x - d.x) <= TRAY / 2 and abs(item.y - d.y) <= TRAY / 2:
            item.state, item.deposit = "tidied", deposit
            return out
        # it bounced off the tray: it lies where physics left it, for perception to find
        return Outcome(False, "place_missed", out.seconds, 0.0, (item.x, item.y))

    def put_down(self, spot: Point) -> Outcome:
        """Put the held object on the floor at ``spot`` (next to the robot); ``place_fail`` at
        1 - the drop rate, or when an object already lies there."""
        if self.holding is None:
            return self._fail("hand_empty", 1.0)
        if any(math.dist(spot, (o.x, o.y)) < 0.2 for o in self._placed()):
            return self._fail("place_fail", 8.0)
        seconds = self.hsr.turn_to(*spot)
        self._carry_along()
        out = self._release_at(spot, 0.0, seconds, fault_rate=self.rates.drop)
        if not out.ok:
            return out
        item = self.items[self._last_released]
        return Outcome(True, None, out.seconds, 0.0, (item.x, item.y))

    # ------------------------------------------------------------------ helpers
    def _release_at(self, at: Point, surface_z: float, seconds: float, fault_rate: float) -> Outcome:
        name = self.holding
        item = self.items[name]
        # the hand as it was at the grasp, turned with the base: the object stands as it stood
        hand_orn, yaw, height = self._held_as
        turn = p.getQuaternionFromEuler((0.0, 0.0, self.hsr.base()[2] - yaw))
        upright = p.multiplyTransforms((0, 0, 0), turn, (0, 0, 0), hand_orn)[1]
        target = (at[0], at[1], surface_z + 0.015 + height)  # the object's bottom 1.5 cm above
        start = self.robot
        err = math.inf
        for lean in LEAN:  # whole-body reach: the base slides in a little where the arm alone falls short
            d = np.subtract(at, start)
            self._place_base(tuple(np.asarray(start) + d / (np.linalg.norm(d) or 1.0) * lean))
            if lean and blocked(base_contacts(self.hsr, self._ignored()), {}):
                break
            pose, err = self.hsr.reach(target, upright, strict=True)
            if err <= REACHED:
                seconds += 2 * lean / (self.scenario.robot.speed / 2)  # in and back out, carefully
                break
        if err > REACHED:  # upright out of reach: any orientation (a small object may tilt, the rim holds it)
            self._place_base(start)
            pose, err = self.hsr.reach(target)
        if err > REACHED:
            return self._fail("out_of_reach", seconds + 1.0)
        seconds += self.hsr.set_joints(pose)
        self._carry_along()
        if self.rng.random() >= fault_rate:
            seconds += 2.0 + self._carry()  # tried to open, and back
            self._place_base(start)
            return self._fail("place_fail", seconds)
        self._release()
        seconds += self.hsr.set_gripper(GRIPPER_OPEN)
        settle(self.hsr, SETTLE_S)
        seconds += SETTLE_S + self.hsr.set_joints(STOW)
        self._place_base(start)
        self._sync(name)
        item.state = "placed"
        self._last_released = name
        return self._spend(seconds)

    def _ignored(self) -> list[int]:
        """What the base may touch: the floor, and the object in its own hand."""
        return [self.scene.floor] + ([self.bodies[self.holding]] if self.holding else [])

    def _place_base(self, q: Point) -> None:
        self.hsr.set_base(q[0], q[1])
        self._carry_along()

    def _arrive(self, to: Point, metres: float, seconds: float) -> None:
        self.robot = to
        self.odometer.sim_time_s += seconds
        self.odometer.distance_m += metres
        if math.dist(self.odometer.track[-1], to) >= 0.1:  # the track at 10 cm: enough for plots
            self.odometer.track.append(to)
        self._follow_camera()

    def _attach(self, name: str) -> None:
        body = self.bodies[name]
        hand_pos, hand_orn = self.hsr.hand()
        obj_pos, obj_orn = p.getBasePositionAndOrientation(body, physicsClientId=self.client)
        inv_pos, inv_orn = p.invertTransform(hand_pos, hand_orn)
        self._grip_offset = p.multiplyTransforms(inv_pos, inv_orn, obj_pos, obj_orn)
        self._grip = p.createConstraint(
            self.hsr.body,
            self.hsr.grasp_link,
            body,
            -1,
            p.JOINT_FIXED,
            (0, 0, 0),
            self._grip_offset[0],
            (0, 0, 0),
            self._grip_offset[1],
            physicsClientId=self.client,
        )
        self.holding = name

    def _release(self) -> None:
        if self._grip is not None:
            p.removeConstraint(self._grip, physicsClientId=self.client)
        self._grip, self.holding = None, None

    def _carry(self) -> float:
        seconds = self.hsr.set_joints(CARRY)
        self._carry_along()
        return seconds

    def _carry_along(self) -> None:
        """A kinematic motion does not step physics: the held object is put where the hand has it."""
        if self.holding is None:
            return
        hand_pos, hand_orn = self.hsr.hand()
        pos, orn = p.multiplyTransforms(hand_pos, hand_orn, *self._grip_offset)
        p.resetBasePositionAndOrientation(self.bodies[self.holding], pos, orn, physicsClientId=self.client)
        item = self.items[self.holding]
        item.x, item.y = pos[0], pos[1]

    def _slip(self) -> None:
        """The held object slips out (grasp_drop): the robot stops, the object falls from the hand,
        pushed a little away from the base, and comes to rest wherever physics puts it."""
        name = self.holding
        body = self.bodies[name]
        bx, by, _ = self.hsr.base()
        pos = p.getBasePositionAndOrientation(body, physicsClientId=self.client)[0]
        away = np.array([pos[0] - bx, pos[1] - by])
        away = away / (np.linalg.norm(away) or 1.0)
        speed = float(self.rng.uniform(0.1, 0.6))
        self._release()
        p.resetBaseVelocity(body, (away[0] * speed, away[1] * speed, 0.0), physicsClientId=self.client)
        settle(self.hsr, SETTLE_S)
        self._sync(name)
        self.items[name].state = "placed"
        self.hsr.set_joints(STOW)

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
