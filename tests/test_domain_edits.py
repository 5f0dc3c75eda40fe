"""Edits of a domain change behaviour as they say: a copy of tidy.pddl with an action moved to
another stratum, or a probability lowered, run through `tidyplan run --domain COPY`, plans the
way the edit says (O-FSM's strata, Goebelbecker's p(pi)). Real missions through Fast Downward
(LAMA's first plan, deterministic) in the symbolic world."""

from __future__ import annotations

import json
import math

import pytest

from tidyplan.cli.main import main
from tidyplan.loop.scenarios import DOMAIN, project_file

pytestmark = pytest.mark.slow
TIDY = DOMAIN.read_text()
REMOVAL_IN_P3 = ("(:action drop_object\n    :parameters (?o - item ?w - waypoint)\n    :stratum 3",
                 "(:action move_back\n    :parameters (?from ?to - waypoint)\n    :stratum 3")  # fmt: skip
TAKE_P = "    :stratum 1\n    :probability 0.95\n    :units ((adjust_base ?o) (grasp ?o))"


def _mission(tmp_path, capsys, name: str, domain_text: str | None) -> tuple[dict, list[dict]]:
    args = [
        "run",
        str(project_file("problems/case2.toml")),
        "--world",
        "symbolic",
        "--planner",
        "lama-first",
        "--seed",
        "1",
    ]
    if domain_text is not None:
        copy = tmp_path / f"{name}-domain.pddl"
        copy.write_text(domain_text)
        args += ["--domain", str(copy)]
    trace = tmp_path / f"{name}.jsonl"
    status = main([*args, "--trace", str(trace), "--json", "--quiet"])
    out = capsys.readouterr()
    assert status in (0, 1), out.err
    summary = json.loads(out.out.strip().splitlines()[-1])
    return summary, [json.loads(line) for line in trace.open()]


def test_the_removal_moved_to_stratum_two_makes_those_plans_p2(tmp_path, capsys):
    shipped, _ = _mission(tmp_path, capsys, "shipped", None)
    assert shipped["strata"]["P3"] >= 1  # case II needs Algorithm 1's removal (P3) here
    edited = TIDY
    for declared in REMOVAL_IN_P3:
        assert edited.count(declared) == 1
        edited = edited.replace(declared, declared[: -len("3")] + "2")
    summary, events = _mission(tmp_path, capsys, "removal-p2", edited)
    drops = [e for e in events if e["kind"] == "action" and e["action"].startswith("(drop_object")]
    assert drops and all(e["stratum"] == 2 for e in drops)
    assert summary["strata"]["P3"] == 0 and summary["strata"]["P2"] >= 1  # what needed P3 is P2 now
    assert summary["delivered"] == shipped["delivered"]


def test_a_lowered_probability_is_the_one_plans_are_scored_with(tmp_path, capsys):
    edited = TIDY.replace(TAKE_P, TAKE_P.replace("0.95", "0.5"))
    assert edited != TIDY
    _, events = _mission(tmp_path, capsys, "take-half", edited)
    plans = [e for e in events if e["kind"] == "plan" and e["status"] == "solved"]
    assert plans
    for e in plans:
        steps = [s.strip("()").split()[0] for s in e["plan"]]
        takes = steps.count("take_object")
        delivers = steps.count("deliver_it")
        drops = steps.count("drop_object")
        actions_p = 0.5**takes * 0.98 ** (delivers + drops)
        rounding = 5e-7  # the trace keeps p to 6 decimals
        assert e["probability"] <= actions_p + rounding, e["plan"]  # assumptions only lower it
        if "assume-item-near" not in " ".join(e["plan"]):
            assert math.isclose(e["probability"], actions_p, abs_tol=rounding), (e["probability"], e["plan"])
