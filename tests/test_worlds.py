"""The world contract (tidyplan.worlds.contract) and the registry of worlds
(tidyplan.worlds.registry): each world the registry names implements the skills and the
referee, and the command line offers exactly the registered worlds."""

from __future__ import annotations

from pathlib import Path

import pytest

from sim.scenario.read import load
from tidyplan.belief.geometry import RoomMap
from tidyplan.cli.main import _parser
from tidyplan.loop.mission import make_world
from tidyplan.loop.options import Settings
from tidyplan.worlds.contract import Referee, Skills, World
from tidyplan.worlds.registry import EVERY_SKILL, WORLDS, world_class

CASE1 = Path(__file__).resolve().parents[1] / "problems" / "case1.toml"


@pytest.mark.parametrize("name", sorted(WORLDS))
def test_each_registered_world_implements_the_contract(name):
    scenario = load(CASE1)
    world = make_world(scenario, RoomMap(scenario), Settings(world=name))
    try:
        assert isinstance(world, Skills) and isinstance(world, Referee) and isinstance(world, World)
        assert isinstance(world, world_class(name))
        assert world.untidied() == sorted(i.name for i in scenario.items)  # nothing tidied yet
        assert world.escaped() == []
    finally:
        world.close()


@pytest.mark.parametrize("name", sorted(WORLDS))
def test_each_registered_world_offers_the_skills_its_entry_declares(name):
    # `tidyplan check` lists the units each world can run from the entries, loading no world
    from tidyplan.exec.catalogue import UNITS

    called = {skill for spec in UNITS.values() for skill in spec.skills}
    assert called <= EVERY_SKILL, "a unit calls a skill the registry does not know"
    cls = world_class(name)
    assert {s for s in EVERY_SKILL | called if callable(getattr(cls, s, None))} == WORLDS[name].skills


def test_an_object_without_the_skills_is_not_a_world():
    class Half:
        def untidied(self):
            return []

    assert not isinstance(Half(), Skills) and not isinstance(Half(), World)


def test_the_command_line_offers_the_registered_worlds():
    run = _parser()._subparsers._group_actions[0].choices["run"]
    world = next(a for a in run._actions if a.dest == "world")
    assert set(world.choices) == set(WORLDS)


def test_an_unknown_world_is_refused_by_the_options_record():
    from tidyplan.errors import InputError

    with pytest.raises(InputError, match="world: 'mars' is not one of pybullet, symbolic"):
        Settings(world="mars")
