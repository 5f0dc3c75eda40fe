"""The monitor checks the plan against the map among the plan's own waypoints
(tidyplan.belief.focus): over a whole mission, every turn's check says what the whole map says,
and a domain whose steps ask about other pairs is checked against the whole map."""

from __future__ import annotations

from pathlib import Path

import pytest

from tidyplan.belief.focus import focus_safe
from tidyplan.loop.loop import Mission
from tidyplan.loop.mission import run
from tidyplan.loop.options import Settings
from tidyplan.loop.scenarios import DOMAIN
from tidyplan.pddl.reader import parse
from tidyplan.worlds.rates import Rates

PROBLEMS = Path(__file__).resolve().parent.parent / "problems"
# what the monitor reads of the simulation's end: the goal, and where the robot and items are
READ = ("tidied", "closed", "holding", "robot-at", "item-at", "hand-empty")


@pytest.mark.parametrize(
    ("case", "seed", "faults"), [("case3", 0, ""), ("case2", 1, "grasp_fail=0.3,perception_miss=0.2")]
)
def test_every_turns_check_among_the_plans_waypoints_is_the_whole_maps(
    monkeypatch, tmp_path, case, seed, faults
):
    focused_state = Mission._belief_state
    turns = []

    def both(self):
        focused = focused_state(self)
        self._focused = False
        try:
            whole = focused_state(self)
        finally:
            self._focused = True
        steps = [(s.name, s.args) for s in self.steps]
        end_f, broken_f = self.sim.run(focused, steps)
        end_w, broken_w = self.sim.run(whole, steps)
        assert broken_f == broken_w, [s.text for s in self.steps]
        assert {a for a in end_f if a[0] in READ} == {a for a in end_w if a[0] in READ}
        turns.append(len(set(whole)) - len(set(focused)))
        return focused

    monkeypatch.setattr(Mission, "_belief_state", both)
    rates = Rates.parse(faults) if faults else Rates()
    settings = Settings(
        "ofsm", seed=seed, rates=rates, planner="lama-first", time_budget=30.0, world="symbolic"
    )
    summary = run(PROBLEMS / f"{case}.toml", tmp_path / "t.jsonl", settings)
    assert summary["success"], summary["reason"]
    assert len(turns) > 20 and max(turns) > 0  # checked often, and with fewer atoms than the room's


def test_a_domain_whose_steps_ask_about_other_pairs_is_checked_against_the_whole_map():
    tidy = DOMAIN.read_text()
    assert focus_safe(parse(tidy, "tidy.pddl"))
    # a move that asks whether its start has a path anywhere: pairs beyond the step's own
    anywhere = tidy.replace(
        "(path ?from ?to)\n", "(path ?from ?to) (exists (?w - waypoint) (path ?from ?w))\n", 1
    )
    assert anywhere != tidy
    assert not focus_safe(parse(anywhere, "tidy.pddl"))
    # a take's freed paths marking something other than the map: not shown safe
    marks = tidy.replace(
        "(when (blocks ?o ?a ?b) (not (blocked ?a ?b)))", "(when (blocks ?o ?a ?b) (located ?o))"
    )
    assert marks != tidy
    assert not focus_safe(parse(marks, "tidy.pddl"))
