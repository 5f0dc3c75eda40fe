"""The HSR's eyes in the pybullet world: the head sweep, the frames on the way and the close look a
behaviour unit's check makes. A mixin of ``BulletWorld`` (``tidyplan.worlds.pybullet.world``), kept apart
because perception is what makes the cases partially observable: the field of view, the range
and occlusion decide here what the belief learns.
"""

from __future__ import annotations

import math

from sim.camera import sample_points
from sim.motion import base_contacts, blocked
from sim.robot import CAMERA_TILT, YAW_SPEED
from tidyplan.belief.percepts import Detection, Frame
from tidyplan.worlds.base import TILTS, sweep_pans

Point = tuple[float, float]

AROUND, AROUND_LOOK = 0.3, 0.6  # m: a place this close is "around the robot"; looked at this far out
# rad the base turns for a close look past the arm held in its carrying posture (measured: with
# an object in the hand, a floor object 0.32 m in front is hidden from the head; turned, seen)
PAST_ARM = 0.6
RECOGNISE_S = 1.0  # s: object recognition on one camera frame (the symbolic world's locate)
PANS = (1.75, 0.80, -0.15, -1.10, -2.05, -3.00, -3.84)  # head pan stops of a sweep: 58 deg frames overlap
# two tilts per stop (TILTS): 7 deg above to 60 deg below the horizon, the floor from 0.6 m out and
# table tops across the room (one 45 deg frame cannot hold both)
# the head and camera as the robot drives: the posture frames on the way are taken in (the belief's
# frame model, sim.visibility.in_frame, assumes it) and the one a sweep starts from
DRIVING_HEAD = {"head_pan_joint": 0.0, "head_tilt_joint": CAMERA_TILT}
AIM_MARGIN_S = 0.2  # s before the end of a drive the head is to be aimed at what the robot will work on
TORSO_UP = 0.69  # m of arm lift: the torso at its top, the lens at 1.35 m, for a place too close below it


class HeadCamera:
    """Perception for ``BulletWorld``: ``look`` and ``locate``. Uses the world's ``hsr``,
    ``camera``, ``client``, ``bodies``, ``items``, its seeded ``rng`` and false-negative rate
    ``fn``, ``_pan_forward`` (which way the next sweep goes), and its motions ``_place_base``,
    ``_ignored`` and ``_spend``."""

    def look(self, stops: tuple[float, ...] | None = None) -> list[Detection]:
        """A head sweep: the camera pans across the head's range (or to the ``stops`` only,
        headings in the room's frame), two tilts a stop; what any frame sees is detected, each
        item missed at the false-negative rate; a phantom at the false-positive rate (a random
        category somewhere in view on the floor)."""
        if stops is None:
            pans = list(PANS if self._pan_forward else PANS[::-1])
            self._pan_forward = not self._pan_forward
        else:
            pans = sweep_pans(self.hsr.base()[2], stops, self.hsr.q("head_pan_joint"))
        tilts = TILTS
        seconds = self._lower_torso()
        targets = self._targets()
        seen: set[str] = set()
        for pan in pans:  # a frame at both tilts at each stop, in turn, so the head never swings back
            for tilt in tilts:
                seconds += self.hsr.set_head(pan, tilt)
                eye, forward, up = self.hsr.camera()
                seen |= self.camera.seen(self.client, eye, forward, up, targets, self.hsr.head_parts())
            tilts = tilts[::-1]
        if pans:
            seconds += self.hsr.set_head(pans[-1], CAMERA_TILT)
        self._spend(seconds)
        out = []
        for it in sorted(self._placed(), key=lambda t: t.name):
            miss = self.rng.random() < self.fn  # drawn for every item in turn: seed fixes the run
            if it.name in seen and not miss:
                out.append(self._seen(it))
        return out + self._phantom(stops)

    def _frame(self) -> Frame:
        """One camera frame as the head looks now: what it sees, each item missed at the
        false-negative rate (drawn from the frames' own stream, for every item in turn)."""
        eye, forward, up = self.hsr.camera()
        seen = self.camera.seen(self.client, eye, forward, up, self._targets(), self.hsr.head_parts())
        out = []
        for it in sorted(self._placed(), key=lambda t: t.name):
            miss = self.frame_rng.random() < self.fn
            if it.name in seen and not miss:
                out.append(self._seen(it))
        down = math.degrees(-math.asin(max(-1.0, min(1.0, forward[2]))))
        return Frame((eye[0], eye[1]), math.atan2(forward[1], forward[0]), out, down)

    def _head_along(self, heading: float, seconds: float) -> None:
        """Turn the head toward ``heading`` (the room's frame) at the driving tilt, as far as its
        joints' speeds allow in ``seconds``: the head turns while the base drives, in no time of
        its own."""
        _, _, yaw = self.hsr.base()
        pan = (heading - yaw + math.pi) % (2 * math.pi) - math.pi
        if pan > PANS[0]:  # the head pans 1.75 rad left, 3.84 right: the long way round
            pan -= 2 * math.pi
        self._head_toward(min(max(pan, PANS[-1]), PANS[0]), CAMERA_TILT, seconds)

    def _head_toward(self, pan: float, tilt: float, seconds: float) -> None:
        """Each head joint toward its target as far as its speed allows in ``seconds``."""
        moved = {}
        for name, want in (("head_pan_joint", pan), ("head_tilt_joint", tilt)):
            q, most = self.hsr.q(name), self.hsr.joints[name].speed * seconds
            moved[name] = q + min(max(want - q, -most), most)
        self.hsr.set_joints(moved)

    def _aim(self, at: Point) -> tuple[float, float]:
        """(pan, tilt) that point the camera at ``at`` (on what lies there) from the base as it
        stands: the close look's."""
        eye, _, _ = self.hsr.camera()
        _, _, yaw = self.hsr.base()
        pan = (math.atan2(at[1] - eye[1], at[0] - eye[0]) - yaw + math.pi) % (2 * math.pi) - math.pi
        tilt = -math.atan2(eye[2] - self._surface_z(at) - 0.05, max(math.dist(eye[:2], at), 0.1))
        return min(max(pan, PANS[-1]), PANS[0]), max(tilt, -1.57)

    def _head_on_the_way(self, heading: float, face: Point | None, left_s: float, seconds: float) -> None:
        """The head while the base drives ``seconds`` more along ``heading``: along the way, and
        in the drive's last moments (``left_s`` to go) at ``face``, what the robot will work on
        there, so that the close look's head motion is done on the way, and aimed by the time
        the frame the detector works on as the base covers its last second is taken
        (``_recognition_frame``)."""
        # the aim asks the camera's pose; no head motion takes longer than its pan range at 1 rad/s
        ahead = AIM_MARGIN_S + RECOGNISE_S
        if face is not None and left_s - seconds <= (PANS[0] - PANS[-1]) + ahead:
            pan, tilt = self._aim(face)
            need = max(abs(pan - self.hsr.q("head_pan_joint")), abs(tilt - self.hsr.q("head_tilt_joint")))
            if left_s - seconds <= need / self.hsr.joints["head_tilt_joint"].speed + ahead:
                self._head_toward(pan, tilt, seconds)
                return
        self._head_along(heading, seconds)

    def _recognition_frame(self, end: Point, left_s: float) -> None:
        """A frame for the detector while the base drives its last ``left_s`` seconds to ``end``
        with the head on what it will work on there: its detections are ready RECOGNISE_S after
        it was taken, and a close look from ``end`` that finds its item in them waits only for
        what is left of that (``locate``). What the detector reports of it, missed at the
        false-negative rate as a frame's are."""
        self._recognised = (end, self._frame().detections, left_s)

    def _from_recognition(self, near: Point, radius: float, category: str | None) -> Detection | None:
        """The detection of the item of ``category`` nearest ``near`` within ``radius`` in the
        drive's recognition frame, once: only where the robot has not moved since it arrived
        (else None, and the close look looks)."""
        recognised, self._recognised = self._recognised, None
        if recognised is None:
            return None
        end, detections, left_s = recognised
        if math.dist(end, self.robot) > 1e-6:
            return None
        found = [
            d
            for d in detections
            if math.dist((d.x, d.y), near) <= radius and (category is None or d.category == category)
        ]
        if not found:
            return None
        self._spend(max(0.0, RECOGNISE_S - left_s))  # what is left of the detector's second
        return min(found, key=lambda d: (math.dist((d.x, d.y), near), d.category, d.x, d.y))

    def _torso_needed(self, face: Point | None, end: Point, yaw: float) -> bool:
        """Will the close look at ``face`` from ``end`` (the base turned to ``yaw``) need the torso
        up, the place nearer the lens than its range? Only for what the robot will take there:
        a put at a deposit moves the arm itself."""
        if face is None or any(math.dist(face, (d.x, d.y)) < 0.05 for d in self.scenario.deposits):
            return False
        x, y, yaw0 = self.hsr.base()
        self.hsr.set_base(end[0], end[1], yaw)
        close = self._too_close(face, self._surface_z(face))
        self.hsr.set_base(x, y, yaw0)
        return close

    def _torso_rising(self, seconds: float) -> None:
        """The torso up toward TORSO_UP as far as the arm lift's speed allows in ``seconds``,
        for the close look the drive ends with (the lift a drive lowers it to again, kept)."""
        if self._lift_after_look is None:
            self._lift_after_look = self.hsr.q("arm_lift_joint")
        q = self.hsr.q("arm_lift_joint")
        self.hsr.set_joints(
            {"arm_lift_joint": min(TORSO_UP, q + self.hsr.joints["arm_lift_joint"].speed * seconds)}
        )

    def _lower_torso(self) -> float:
        """The torso a close look raised, back down where it was: the seconds it takes. A close
        look leaves it up (the grasp that follows starts from there); what comes next that needs
        the lens at its usual height lowers it (a drive does while it drives)."""
        if self._lift_after_look is None:
            return 0.0
        lift, self._lift_after_look = self._lift_after_look, None
        return self.hsr.set_joints({"arm_lift_joint": lift})

    def glance(self):
        """``WorldReferee.glance``, but no frame from here while a close look has the torso up
        (the belief's frames are from the lens at its usual height); the head as it looks (a close
        look leaves it on its place: the frame says its tilt)."""
        if self._lift_after_look is None:
            return super().glance()
        frames, self._frames = self._frames, []
        return frames

    def locate(self, near: Point, radius: float, category: str | None = None) -> Detection | None:
        """Close-range look for the item of ``category`` nearest ``near`` within ``radius``: the
        robot faces the place and tilts the head to it. Where the place is too close for the
        camera (under 0.8 m from the lens: an object on a table right in front), the torso rises
        to the top first (the lens to 1.35 m); where that is not enough, the base steps back (if
        the way is free) until the place is in range, looks, and returns. The head stays on the
        place and the torso up for what comes next (the grasp moves them with the arm). Missed
        at the false-negative rate.

        Where the drive here ended with the head on the place and the detector found the item in
        the frame it took in the drive's last second (``_recognition_frame``), that is the close
        look: the robot has not moved since."""
        if math.dist(near, self.robot) >= AROUND:
            ready = self._from_recognition(near, radius, category)
            if ready is not None:
                return ready
        self._recognised = None
        candidates = {
            o.name: (self.bodies[o.name], sample_points(self.client, self.bodies[o.name]))
            for o in self._placed()
            if math.dist((o.x, o.y), near) <= radius and (category is None or o.label == category)
        }
        if math.dist(near, self.robot) < AROUND:
            return self._locate_around(near, candidates)
        surface = self._surface_z(near)
        seconds = self.hsr.turn_to(*near)  # face it: the head pans too little behind the robot
        seen: set[str] = set()
        if not self._too_close(near, surface):  # a look from too close sees nothing: the torso first
            seen, spent = self._look_at(near, surface, candidates)
            seconds += spent
        if (
            self.holding is not None
            and not self._too_close(near, surface)
            and not self._seen_near(seen, near)
        ):
            # the arm in its carrying posture hides the floor just in front: look past it, the
            # base turned a little either way and the head panned back to the place
            more, spent = self._look_past_the_arm(near, surface, candidates)
            seen, seconds = seen | more, seconds + spent
        if not seen and self._too_close(near, surface):
            if self._lift_after_look is None:
                self._lift_after_look = self.hsr.q("arm_lift_joint")
            seconds += self.hsr.set_joints({"arm_lift_joint": TORSO_UP})
            seen, spent = self._look_at(near, surface, candidates)
            seconds += spent
            if not seen and self._too_close(near, surface):
                start = self.robot
                pose = self._step_back(near, surface)
                if pose is not None:
                    self._place_base(pose)
                    self.hsr.turn_to(*near)
                    seconds += 2 * math.dist(start, pose) / (self.scenario.robot.speed / 2)  # there and back
                    seen, spent = self._look_at(near, surface, candidates)
                    seconds += spent
                self._place_base(start)
        # the head stays on the place and the torso up: the grasp that follows moves them back with
        # the arm, a drive on the way, a glance or a sweep first (``glance``, ``_lower_torso``)
        return self._found(seen, near, seconds)

    def _locate_around(self, near: Point, candidates) -> Detection | None:
        """``near`` is where the robot stands (an object slipped out of the hand here): look at
        the floor 0.6 m out to the front, then either side, then behind, until something is seen."""
        seconds = 0.0
        seen: set[str] = set()
        _, _, yaw = self.hsr.base()
        for turn in (0.0, math.pi / 2, -math.pi / 2, math.pi):
            a = yaw + turn
            spot = (near[0] + AROUND_LOOK * math.cos(a), near[1] + AROUND_LOOK * math.sin(a))
            seconds += self.hsr.turn_to(*spot)
            seen, spent = self._look_at(spot, self._surface_z(spot), candidates)
            seconds += spent
            if seen:
                break
        return self._found(seen, near, seconds)

    def _found(self, seen: set[str], near: Point, seconds: float) -> Detection | None:
        """The close look's result after ``seconds``: the seen item nearest ``near``, unless the
        detector misses it (at the false-negative rate)."""
        self._spend(seconds)
        if self.rng.random() < self.fn or not seen:
            return None
        o = min((self.items[n] for n in seen), key=lambda o: (math.dist((o.x, o.y), near), o.name))
        return self._seen(o)

    def _look_at(self, near: Point, surface: float, candidates, pan: float = 0.0) -> tuple[set[str], float]:
        """Tilt the head to the place (the base faces it, or ``pan`` turns the head back to it)
        and recognise; returns what was seen and the seconds it took."""
        eye, _, _ = self.hsr.camera()
        tilt = -math.atan2(eye[2] - surface - 0.05, max(math.dist(eye[:2], near), 0.1))
        seconds = self.hsr.set_head(pan, max(tilt, -1.57)) + RECOGNISE_S
        return self.camera.seen(self.client, *self.hsr.camera(), candidates, self.hsr.head_parts()), seconds

    def _seen_near(self, seen: set[str], near: Point) -> bool:
        return any(math.dist((self.items[n].x, self.items[n].y), near) <= AROUND for n in seen)

    def _look_past_the_arm(self, near: Point, surface: float, candidates) -> tuple[set[str], float]:
        """Looks at ``near`` with the base turned PAST_ARM either way and the head panned back,
        until something is seen near it; the base is turned back to face it."""
        seen: set[str] = set()
        seconds = 0.0
        x, y, yaw = self.hsr.base()
        for turn in (PAST_ARM, -PAST_ARM):
            self.hsr.set_base(x, y, yaw + turn)
            self._carry_along()
            more, spent = self._look_at(near, surface, candidates, pan=-turn)
            seen, seconds = seen | more, seconds + 2 * PAST_ARM / YAW_SPEED + spent
            if self._seen_near(seen, near):
                break
        self.hsr.set_base(x, y, yaw)
        self._carry_along()
        return seen, seconds

    def _step_back(self, near: Point, surface: float) -> Point | None:
        """The nearest free pose, straight back, back to either side or sideways, from which the
        place is far enough for the camera; None if there is none within 0.6 m (a grasp pose with
        its back to a wall needs a long step sideways). The robot is left where it was."""
        start = self.robot
        away = math.atan2(start[1] - near[1], start[0] - near[0])
        found = None
        for step in (0.1, 0.2, 0.3, 0.4, 0.5, 0.6):
            for turn in (0.0, 0.785, -0.785, 1.571, -1.571):
                a = away + turn
                q = (start[0] + step * math.cos(a), start[1] + step * math.sin(a))
                self._place_base(q)
                if not blocked(base_contacts(self.hsr, self._ignored()), {}) and not self._too_close(
                    near, surface
                ):
                    found = q
                    break
            if found:
                break
        self._place_base(start)
        return found

    def _too_close(self, near: Point, surface: float) -> bool:
        eye = self.hsr.camera()[0]
        return math.dist(eye, (near[0], near[1], surface + 0.05)) < self.camera.range_min + 0.02

    def _targets(self) -> dict[str, tuple[int, list]]:
        return {
            o.name: (self.bodies[o.name], sample_points(self.client, self.bodies[o.name]))
            for o in self._placed()
        }

    def _surface_z(self, at: Point) -> float:
        """The top of the furniture at ``at`` on the static map (0: the floor)."""
        tops = [f.height for f in self.scenario.furniture if f.box().clearance(*at) == 0.0]
        return max(tops, default=0.0)
