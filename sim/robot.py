"""The Toyota HSR in pybullet: a kinematic omnidirectional base, the arm, the head, the gripper.

The model is ``sim/hsr.urdf``, written from the published figures in docs/sources.md (the
hsrb_description joint origins, limits and speeds; the ROBOMECH Journal 2019 description of
the base). Motion is kinematic: a motion sets joint positions and returns how long the real
robot needs for it at its joint speeds, and the caller advances the simulated clock by that.
Physics is stepped by the caller only where it matters (an object falling, settling).

Reaching uses pybullet's own inverse kinematics on the arm joints with the virtual base joints
held where they are (nullspace limits lower = upper); the HSR's whole-body reach, which also
slides the base, is left to the caller (``approach``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import pybullet as p

URDF = Path(__file__).resolve().parent / "hsr.urdf"

YAW_SPEED = 0.75  # rad/s: the yaw rate seen in one configuration (not published)
CAMERA_TILT = (
    -0.35
)  # rad: the head looks 20 degrees down while sweeping: floor 1 m to 3.5 m away and table tops in view
GRIPPER_OPEN = 0.0675  # m per finger: 135 mm between the fingers
# the arm folded with the hand low in front of the base: how the HSR carries an object
CARRY = {
    "arm_lift_joint": 0.05,
    "arm_flex_joint": -1.9,
    "arm_roll_joint": 0.0,
    "wrist_flex_joint": -1.2,
    "wrist_roll_joint": 0.0,
}
# the arm straight up over the base: where the hand goes after letting go, so that nothing of
# the robot touches what it let go of while that settles (the stowed hand reaches 0.4 m ahead)
RAISED = {
    "arm_lift_joint": 0.69,
    "arm_flex_joint": 0.0,
    "arm_roll_joint": 0.0,
    "wrist_flex_joint": 0.0,
    "wrist_roll_joint": 0.0,
}
STOW = {
    "arm_lift_joint": 0.0,
    "arm_flex_joint": 0.0,
    "arm_roll_joint": 0.0,
    "wrist_flex_joint": -1.57,
    "wrist_roll_joint": 0.0,
}
ARM = ("arm_lift_joint", "arm_flex_joint", "arm_roll_joint", "wrist_flex_joint", "wrist_roll_joint")
WHOLE_BODY = ARM + ("base_yaw_joint",)  # what a reach moves
HAND_DOWN = p.getQuaternionFromEuler(
    (0.0, math.pi, 0.0)
)  # the grasp frame's z (towards the fingertips) points down
# Arm postures to start the IK from: pybullet's solver is local, and from the stowed arm (flex at
# its limit) it stalls. Low and folded, half out, and raised: together they cover 0.3 to 0.65 m
# in front of the base from the floor to 1 m up (measured: the hand within 1 cm).
IK_SEEDS = (
    {"arm_lift_joint": 0.1, "arm_flex_joint": -2.0, "wrist_flex_joint": -1.1},
    {"arm_lift_joint": 0.3, "arm_flex_joint": -1.2, "wrist_flex_joint": -1.6},
    {"arm_lift_joint": 0.5, "arm_flex_joint": -1.6, "wrist_flex_joint": 0.0},
    {"arm_lift_joint": 0.69, "arm_flex_joint": -0.6, "wrist_flex_joint": -1.0},
)
CONVERGED = 1e-6  # rad (or m) a joint moves at most in a re-solve that changes nothing
REACHED = 0.02  # m: the hand this close to the target counts as there
TILT = 0.1  # rad: a hand tilted this little from the wanted orientation holds an object upright
LEVEL = 0.2  # the vertical part of the fingertips' direction below which the hand counts as level
TURNS = tuple(k * math.pi / 4 for k in (0, 1, -1, 2, -2, 3, -3, 4))  # rad about the vertical, nearest first
# rad: a wanted orientation whose fingertips point this close to straight down (the tilt allowed
# included) is first checked against the arm's geometry (``HSR._may_reach_down``)
NEAR_DOWN = 0.6
FLEX_STEPS = 262  # arm flex postures in that check's table: 0.01 rad apart, the wrist 3.5 mm


@dataclass(frozen=True, slots=True)
class Joint:
    index: int
    name: str
    kind: int
    lower: float
    upper: float
    speed: float  # rad/s or m/s, the URDF's velocity limit


class HSR:
    """One HSR body in a pybullet client. Joint and link names are hsrb_description's."""

    def __init__(self, client: int, x: float = 0.0, y: float = 0.0, yaw: float = 0.0) -> None:
        self.client = client
        self.body = p.loadURDF(str(URDF), useFixedBase=True, physicsClientId=client)
        self.joints: dict[str, Joint] = {}
        self.links: dict[str, int] = {}
        for j in range(p.getNumJoints(self.body, physicsClientId=client)):
            info = p.getJointInfo(self.body, j, physicsClientId=client)
            name = info[1].decode()
            self.joints[name] = Joint(j, name, info[2], info[8], info[9], info[11])
            self.links[info[12].decode()] = j
        self.base_link = self.links["base_link"]
        self.grasp_link = self.links["hand_grasp_frame"]
        self.camera_link = self.links["head_rgbd_sensor_link"]
        self._level: tuple[list[tuple[float, float, float, float]], ...] | None = None  # _level_postures
        self._wrist: tuple[list[tuple[float, float, float]], float] | None = None  # _wrist_postures
        self._movable = [j for j in self.joints.values() if j.kind != p.JOINT_FIXED]
        self.set_joints(STOW)
        self.set_gripper(GRIPPER_OPEN)
        self.set_head(0.0, CAMERA_TILT)
        # the wrist's table now, with nothing in the hand: worked out in the middle of a put, its
        # postures (the base moved to the origin and back) would be tried with the object held
        self._wrist = self._wrist_postures()
        self.set_base(x, y, yaw)

    # ------------------------------------------------------------------ joints
    def q(self, name: str) -> float:
        return p.getJointState(self.body, self.joints[name].index, physicsClientId=self.client)[0]

    def set_joints(self, values: dict[str, float]) -> float:
        """Set joints (clamped to their limits); returns the seconds the real robot needs, all
        joints moving at once at their top speeds. The torso follows the arm lift at half."""
        seconds = 0.0
        if "arm_lift_joint" in values:
            values = {**values, "torso_lift_joint": 0.5 * values["arm_lift_joint"]}
        for name, value in values.items():
            j = self.joints[name]
            if j.kind != p.JOINT_REVOLUTE or j.upper > j.lower:
                value = min(max(value, j.lower), j.upper) if j.upper > j.lower else value
            seconds = max(seconds, abs(value - self.q(name)) / j.speed)
            p.resetJointState(self.body, j.index, value, physicsClientId=self.client)
        return seconds

    def hold_still(self) -> None:
        """Before physics steps: motors hold every joint where it is (otherwise the arm sags)."""
        idx = [j.index for j in self._movable]
        now = [s[0] for s in p.getJointStates(self.body, idx, physicsClientId=self.client)]
        p.setJointMotorControlArray(
            self.body,
            idx,
            p.POSITION_CONTROL,
            targetPositions=now,
            forces=[500.0] * len(idx),
            physicsClientId=self.client,
        )

    # ------------------------------------------------------------------ base
    def set_base(self, x: float, y: float, yaw: float | None = None) -> None:
        values = {"base_x_joint": x, "base_y_joint": y}
        if yaw is not None:
            values["base_yaw_joint"] = yaw
        for name, v in values.items():
            p.resetJointState(self.body, self.joints[name].index, v, physicsClientId=self.client)

    def base(self) -> tuple[float, float, float]:
        return self.q("base_x_joint"), self.q("base_y_joint"), self.q("base_yaw_joint")

    def turn_to(self, x: float, y: float) -> float:
        """Turn the base to face (x, y); returns the seconds it takes."""
        bx, by, yaw = self.base()
        want = math.atan2(y - by, x - bx)
        turn = (want - yaw + math.pi) % (2 * math.pi) - math.pi
        self.set_base(bx, by, yaw + turn)
        return abs(turn) / YAW_SPEED

    # ------------------------------------------------------------------ head and camera
    def set_head(self, pan: float, tilt: float) -> float:
        return self.set_joints({"head_pan_joint": pan, "head_tilt_joint": tilt})

    def camera(self) -> tuple[tuple[float, float, float], tuple[float, ...], tuple[float, ...]]:
        """The RGB-D lens: position, and its forward and up directions in the world."""
        state = p.getLinkState(
            self.body, self.camera_link, computeForwardKinematics=True, physicsClientId=self.client
        )
        pos, orn = state[4], state[5]
        m = p.getMatrixFromQuaternion(orn)
        forward = (m[0], m[3], m[6])  # the link's x axis
        up = (m[2], m[5], m[8])  # its z axis
        return pos, forward, up

    def head_parts(self) -> tuple[int, tuple[int, ...]]:
        """(body, links) of the head the camera looks out of."""
        names = ("head_pan_link", "head_tilt_link", "head_rgbd_sensor_link")
        return self.body, tuple(self.links[n] for n in names)

    # ------------------------------------------------------------------ arm and hand
    def hand(self) -> tuple[tuple[float, float, float], tuple[float, float, float, float]]:
        state = p.getLinkState(
            self.body, self.grasp_link, computeForwardKinematics=True, physicsClientId=self.client
        )
        return state[4], state[5]

    def reach(
        self,
        target: tuple[float, float, float],
        orientation=HAND_DOWN,
        *,
        strict: bool = False,
        turns: tuple[float, ...] = TURNS,
        carried: tuple[float, float, float] = (0.0, 0.0, 0.0),
    ) -> tuple[dict[str, float], float]:
        """Joint values that bring the point ``carried`` of the hand's frame (the grasp frame
        itself by default; the centre of a held object) to ``target`` (world), and how far from
        it they leave that point (m); the robot is left as it was. The hand as ``orientation``
        (a quaternion; pointing down, a top grasp, by default) turned about the vertical by one
        of ``turns`` (rad; any multiple of 45 degrees by default) is preferred: a turn about the
        vertical does not tilt what the hand holds. A solution counts only if it tilts the hand
        less than 0.1 rad from the wanted orientation; where none reaches, any orientation does
        (unless ``strict``). The base may turn in place, as the HSR's whole-body reach does (the
        arm is mounted 78 mm to the side of the base's centre); its x and y joints and the head
        get a large damping, so the solver moves the arm and the yaw only."""
        movable = self._movable
        saved = {j.name: self.q(j.name) for j in movable}
        damping = [0.02 if j.name in WHOLE_BODY else 1000.0 for j in movable]
        inverse = p.invertTransform((0, 0, 0), orientation)[1]
        turned = [_turn(orientation, a) for a in turns]
        best: tuple[dict[str, float], float] = ({}, math.inf)
        for wanted in turned if strict else [*turned, None]:
            # the hand's frame where the carried point lands on the target
            offset = p.multiplyTransforms((0, 0, 0), wanted or orientation, carried, (0, 0, 0, 1))[0]
            aim = tuple(t - o for t, o in zip(target, offset, strict=True))
            if strict and not self._may_reach_down(aim, wanted, offset):
                continue  # out of the arm's reach this way up: no solve can change that
            level = wanted is not None and abs(p.getMatrixFromQuaternion(wanted)[8]) < LEVEL
            for seed in (*self._level_seeds(aim), *IK_SEEDS) if level else IK_SEEDS:
                self.set_joints(seed)
                for _ in range(4):  # re-solve from the clamped solution: limits are soft in pybullet
                    now = [self.q(j.name) for j in movable]
                    sol = p.calculateInverseKinematics(
                        self.body,
                        self.grasp_link,
                        aim,
                        wanted,
                        jointDamping=damping,
                        currentPositions=now,
                        maxNumIterations=100,
                        residualThreshold=1e-4,
                        physicsClientId=self.client,
                    )
                    self.set_joints(
                        {j.name: v for j, v in zip(movable, sol, strict=True) if j.name in WHOLE_BODY}
                    )
                    # converged: re-solving from where this solve left the joints gives this again
                    settled = (
                        max(abs(a - self.q(j.name)) for a, j in zip(now, movable, strict=True)) < CONVERGED
                    )
                    pos, orn = self.hand()
                    err = math.dist(p.multiplyTransforms(pos, orn, carried, (0, 0, 0, 1))[0], target)
                    if wanted is None:  # any orientation: aim again for the one the hand has now
                        offset = p.multiplyTransforms((0, 0, 0), orn, carried, (0, 0, 0, 1))[0]
                        aim = tuple(t - o for t, o in zip(target, offset, strict=True))
                    tilted = (
                        wanted is not None
                        and _tilt(p.multiplyTransforms((0, 0, 0), orn, (0, 0, 0), inverse)[1]) > TILT
                    )
                    if not tilted and err < best[1]:
                        best = ({n: self.q(n) for n in WHOLE_BODY}, err)
                    if (not tilted and err < 0.005) or (settled and wanted is not None):
                        break
                if best[1] < 0.005:
                    break
            if best[1] < REACHED / 2:
                break
        for name, value in saved.items():
            p.resetJointState(self.body, self.joints[name].index, value, physicsClientId=self.client)
        return best

    def _may_reach_down(self, aim, wanted, offset) -> bool:
        """Could a solve of ``reach`` with the fingertips near down bring the hand's frame to
        ``aim`` (where the carried point lands on the target with the hand as ``wanted``; it is
        ``offset`` from the target) from where the base stands? A necessary condition from the
        arm's geometry, never a false no (tests/test_reach_envelope.py): the wrist is the hand's
        length above the hand's frame, within the tilt, and the wrist goes where the arm flex
        (with the lift, and the base's yaw about its centre) can put it. The arm roll does not
        move the wrist, which is on its axis. True for an orientation not near down.

        Of the reaches a mission's puts and grasps try, about half do not reach (case III: 40
        of 90, 2282 of the 3183 solves, 2.3 s of 11 s); this answers half of those at once."""
        m = p.getMatrixFromQuaternion(wanted)
        off_down = math.acos(max(-1.0, min(1.0, -m[8]))) + TILT  # the fingertips from down, at most
        if off_down > NEAR_DOWN:
            return True
        if self._wrist is None:
            self._wrist = self._wrist_postures()
        rows, hand = self._wrist
        # the hand's frame may end up to REACHED from the aim, and a turn about the vertical or
        # the tilt moves the carried point's offset: its level part twice, its whole by the tilt
        slack = REACHED + 2 * math.hypot(offset[0], offset[1]) + TILT * math.dist(offset, (0, 0, 0)) + 0.005
        bx, by, _ = self.base()
        r = math.dist(aim[:2], (bx, by))
        aside = hand * math.sin(off_down) + slack
        low, high = aim[2] + hand * math.cos(off_down) - slack, aim[2] + hand + slack
        return any(abs(rw - r) <= aside and z0 <= high and low <= z1 for rw, z0, z1 in rows)

    def _wrist_postures(self) -> tuple[list[tuple[float, float, float]], float]:
        """The wrist's reach from the base's centre and its height with the lift down and up,
        for arm flexes from upright to its limit, and the hand's length (wrist to the hand's
        frame, along the fingertips)."""
        saved = {n: self.q(n) for n in (*WHOLE_BODY, "base_x_joint", "base_y_joint")}
        self.set_base(0.0, 0.0, 0.0)
        flex, lift = self.joints["arm_flex_joint"], self.joints["arm_lift_joint"]
        wrist = self.links["wrist_flex_link"]

        def at() -> tuple[float, float, float]:
            return p.getLinkState(
                self.body, wrist, computeForwardKinematics=True, physicsClientId=self.client
            )[4]

        straight = {"arm_roll_joint": 0.0, "wrist_flex_joint": 0.0, "wrist_roll_joint": 0.0}
        self.set_joints({**straight, "arm_flex_joint": 0.0, "arm_lift_joint": 0.0})
        hand = math.dist(at(), self.hand()[0])
        rows = []
        for k in range(FLEX_STEPS + 1):
            a = flex.lower + (flex.upper - flex.lower) * k / FLEX_STEPS
            self.set_joints({**straight, "arm_flex_joint": a, "arm_lift_joint": lift.lower})
            x, y, z0 = at()
            self.set_joints({"arm_lift_joint": lift.upper})
            rows.append((math.hypot(x, y), z0, at()[2]))
        self.set_joints({n: v for n, v in saved.items() if n in WHOLE_BODY})
        self.set_base(saved["base_x_joint"], saved["base_y_joint"], saved["base_yaw_joint"])
        return rows, hand

    def _level_seeds(self, aim: tuple[float, float, float]) -> list[dict[str, float]]:
        """Postures that hold the hand level at ``aim`` (the hand's frame) by its distance and
        height, the base turned to it: one with the arm lowered (the wrist bent up), one raised.
        From the postures of IK_SEEDS pybullet's local solver stops short of a level hand: a
        0.45 m crate held over a bin from 0.6 to 0.7 m away was reached 3 to 16 cm short, where
        a lowered arm reaches it (docs/world.md)."""
        if self._level is None:
            self._level = self._level_postures()
        bx, by, _ = self.base()
        far = math.dist(aim[:2], (bx, by))
        lift = self.joints["arm_lift_joint"]
        seeds = []
        for branch in self._level:
            # the posture whose reach ahead, with the hand its sideways offset from the base's
            # line, is nearest the target's distance
            flex, ahead, aside, z0 = min(
                branch, key=lambda r: abs(math.sqrt(max(far * far - r[2] ** 2, 0.0)) - r[1])
            )
            if not lift.lower <= aim[2] - z0 <= lift.upper:
                continue
            ahead = math.sqrt(max(far * far - aside * aside, 0.0))
            yaw = math.atan2(aim[1] - by, aim[0] - bx) - math.atan2(aside, ahead)
            seeds.append(
                {
                    **_level_arm(flex),
                    "arm_lift_joint": aim[2] - z0,
                    "base_yaw_joint": yaw,
                }
            )
        return seeds

    def _level_postures(self) -> tuple[list[tuple[float, float, float, float]], ...]:
        """(arm flex, reach ahead of the base's centre, sideways, height) of the level hand with
        the lift at 0, for flexes from the arm lowered to upright: two branches, the arm below
        and above horizontal, each reaching farther as it nears horizontal."""
        saved = {n: self.q(n) for n in (*WHOLE_BODY, "base_x_joint", "base_y_joint")}
        self.set_base(0.0, 0.0, 0.0)
        flex = self.joints["arm_flex_joint"]
        rows = []
        for a in [flex.lower + (flex.upper - flex.lower) * k / 52 for k in range(53)]:
            self.set_joints({**_level_arm(a), "arm_lift_joint": 0.0})
            x, y, z = self.hand()[0]
            rows.append((a, x, y, z))
        self.set_joints({n: v for n, v in saved.items() if n in WHOLE_BODY})
        self.set_base(saved["base_x_joint"], saved["base_y_joint"], saved["base_yaw_joint"])
        return [r for r in rows if r[0] <= -math.pi / 2], [r for r in rows if r[0] > -math.pi / 2]

    def set_gripper(self, opening: float) -> float:
        """Each finger ``opening`` m from the centre; returns the seconds."""
        return self.set_joints({"hand_l_finger_joint": opening, "hand_r_finger_joint": opening})


def hand_level(yaw: float) -> tuple[float, float, float, float]:
    """The hand held level, the fingertips pointing along ``yaw`` (a side grasp)."""
    return p.getQuaternionFromEuler((0.0, math.pi / 2, yaw))


def _level_arm(flex: float) -> dict[str, float]:
    """The arm at ``flex`` with the wrist bent to hold the hand level (flex + wrist flex = -90
    degrees: the stowed posture's hand, pointing ahead)."""
    return {
        "arm_flex_joint": flex,
        "arm_roll_joint": 0.0,
        "wrist_flex_joint": -math.pi / 2 - flex,
        "wrist_roll_joint": 0.0,
    }


def _turn(orientation, angle: float) -> tuple[float, float, float, float]:
    """``orientation`` turned by ``angle`` about the world's vertical."""
    return p.multiplyTransforms((0, 0, 0), p.getQuaternionFromEuler((0, 0, angle)), (0, 0, 0), orientation)[1]


def _tilt(rotation) -> float:
    """How far (rad) ``rotation`` tips the vertical: 0 for any turn about it. A hand this far from
    the wanted orientation tilts what it holds by as much."""
    m = p.getMatrixFromQuaternion(rotation)
    return math.acos(max(-1.0, min(1.0, m[8])))
