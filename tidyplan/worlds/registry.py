"""The worlds a mission runs in, by name. A new world is one class that implements the contract of
``tidyplan.worlds.contract`` (``Skills``, ``Referee``) with a ``for_mission`` constructor, and one
entry here: its class as ``module:class`` and the skills it offers. Both are plain strings, so
the command line lists the worlds, and ``tidyplan check`` the units each can run, without
loading numpy or pybullet (tests/test_worlds.py holds each entry's skills to its class)."""

from __future__ import annotations

from dataclasses import dataclass
from importlib import import_module

# what the behaviour units call on a world (tidyplan.exec.catalogue names them per unit)
EVERY_SKILL = frozenset(
    (
        "drawer_opening",
        "follow",
        "grasp",
        "holds",
        "locate",
        "place",
        "pose",
        "pull_handle",
        "push_drawer",
        "put_down",
    )
)


@dataclass(frozen=True, slots=True)
class WorldEntry:
    target: str  # module:class
    skills: frozenset[str]  # the skills (tidyplan.worlds.contract.Skills) the class implements


WORLDS: dict[str, WorldEntry] = {
    # the HSR in the physics world (the default)
    "pybullet": WorldEntry("tidyplan.worlds.pybullet.world:BulletWorld", EVERY_SKILL),
    # the grid world: fast, no physics
    "symbolic": WorldEntry("tidyplan.worlds.symbolic:SymbolicWorld", EVERY_SKILL),
}


def world_class(name: str):
    """The class of the world ``name``; a ``KeyError`` for a name not in WORLDS."""
    module, _, cls = WORLDS[name].target.partition(":")
    return getattr(import_module(module), cls)
