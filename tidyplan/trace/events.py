"""The trace's vocabulary, which its writer, reader, score and command line share: the schema
version, the kinds of event, the replanning causes (i)-(v), which ``action`` event delivered an
item, and the one builder of an ``action`` event's fields (docs/trace.md has every kind's fields).
"""

from __future__ import annotations

from tidyplan.exec.catalogue import DELIVERS

SCHEMA_VERSION = 1
KINDS = frozenset(
    "start observe deadline plan assume unit recovery action bind assumption plan_kept forget "
    "explore_again look_again unblock give_up inspect_deposit sim_fault end summary".split()
)
# the five replan causes, numbered as in docs/trace.md and the Design (i)..(v)
CAUSES = {
    "precondition_failed": "i",
    "plan_invalid": "ii",
    "assumption_contradicted": "iii",
    "recovery_exhausted": "iv",
    "new_object": "v",
}


def action(text: str, stratum: int | None, report, robot, **more) -> dict:
    """The fields of the ``action`` event of one action the robot ran: ``report`` is the
    executor's (``tidyplan.exec.bindings.Report``), ``robot`` where it stands afterwards;
    ``more`` (``delivered``, ``purpose``) last."""
    return {
        "action": text,
        "stratum": stratum,
        "ok": report.ok,
        "failure": report.failure,
        "failure_class": report.failure_class,
        "recoveries": report.recoveries,
        "recovery_exhausted": report.recovery_exhausted,
        "seconds": round(report.seconds, 2),
        "metres": round(report.metres, 2),
        "robot": [round(v, 3) for v in robot],
        "path": report.path,
        "units": list(report.units),
        **more,
    }


def delivers(action: dict) -> bool:
    """An ``action`` event that put its item into a deposit: it ran the delivering unit
    (``tidyplan.exec.catalogue.DELIVERS``); a trace written before actions named their units
    is read by tidy.pddl's action name."""
    if not action.get("ok"):
        return False
    if "units" in action:
        return DELIVERS in action["units"]
    return action.get("action", "").startswith("(deliver_it")
