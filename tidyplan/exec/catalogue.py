"""The behaviour units a domain's actions may name in ``:units``: the one place their names, their
arguments and the world skills they call are written.

A domain binds each executable action to units of this catalogue (docs/dialect.md, ``:units``);
``tidyplan check`` and ``tidyplan run --domain`` check the binding against it before anything
runs (``tidyplan.exec.binding_check``), the executor builds the units from it
(``tidyplan.exec.bindings``), and counting and plots read unit names from here. Light on purpose:
``tidyplan check`` imports it without a world.

An argument's kind is the type of the objects the problem writer gives it (``waypoint``,
``item``, ``deposit``): the action's parameter bound to it must be of that type or below it.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True, slots=True)
class UnitSpec:
    name: str
    parameters: tuple[tuple[str, str], ...]  # (role, kind) in order
    skills: tuple[str, ...]  # what the unit calls on a world (tidyplan.worlds.contract.Skills)
    summary: str

    @property
    def signature(self) -> str:
        return f"({self.name}{''.join(f' {role}:{kind}' for role, kind in self.parameters)})"


NAVIGATE = "navigate"
ADJUST_POSE = "adjust_pose"
ADJUST_BASE = "adjust_base"
GRASP = "grasp"
APPROACH_DEPOSIT = "approach_deposit"
PLACE = "place"
PUT_DOWN = "put_down"
APPROACH_HANDLE = "approach_handle"
PULL_HANDLE = "pull_handle"
LOOK = "look"  # run after every action by the executor; not bound in a domain
PUSH_DRAWER = "push_drawer"  # inserted by pull_handle for a jammed drawer; not bound in a domain

_MOTION = ("pose", "follow")
_SPECS = (
    (NAVIGATE, (("to", "waypoint"),), _MOTION, "plan a path on the robot's map to a waypoint, drive it"),
    (ADJUST_POSE, (("to", "waypoint"),), _MOTION, "a careful pose adjustment to a waypoint"),
    (
        ADJUST_BASE,
        (("item", "item"),),
        (*_MOTION, "locate"),
        "find an item close up, bring the base in reach",
    ),
    (
        GRASP,
        (("item", "item"),),
        ("locate", "grasp", "holds"),
        "grasp an item, verify with the gripper's sensor",
    ),
    (
        APPROACH_DEPOSIT,
        (("at", "waypoint"),),
        (*_MOTION, "holds"),
        "stand at a deposit's approach, item in hand",
    ),
    (
        PLACE,
        (("item", "item"), ("deposit", "deposit"), ("at", "waypoint")),
        ("place", "holds"),
        "put the held item into a deposit, verify the hand let go",
    ),
    (PUT_DOWN, (("item", "item"),), ("put_down", "holds"), "put the held item down beside the robot"),
    (
        APPROACH_HANDLE,
        (("at", "waypoint"),),
        (*_MOTION, "holds"),
        "stand at a drawer's handle, the hand empty",
    ),
    (
        PULL_HANDLE,
        (("deposit", "deposit"),),
        ("pull_handle", "push_drawer", "drawer_opening"),
        "grasp a drawer's handle, pull it open, check the opening",
    ),
)
UNITS: dict[str, UnitSpec] = {name: UnitSpec(name, *rest) for name, *rest in _SPECS}

# What counting and the plots ask of an action by the units it ran
DELIVERS = PLACE  # a delivery (Table II counts it by the stratum of its segment)
REMOVES = PUT_DOWN  # Algorithm 1's removal: the bare move after it is the move back
MOVES = (NAVIGATE,)  # a bare move: part of the next take for Yan et al., unless it carries
