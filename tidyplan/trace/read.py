"""Reading a trace back: its events, checked; the story of the run; the robot's track.

A trace is a run's only record (docs/trace.md), so the reader is lenient where a run can leave
a damaged file and strict where the file is not a trace at all:

- a last line cut off mid-way (the run was killed while writing) is dropped with one warning;
- event kinds this tidyplan does not know are skipped, and a newer schema version is read as
  far as it is understood, with one warning;
- a file that is not a trace (missing, binary, not JSON lines, no ``start`` event) raises
  ``InputError`` with one line that says why.

Every figure of ``summarise`` is computed from the events, so a trace without a ``summary``
event (a killed run) is summarised too; when the run's own summary is there, its figures are
the ones shown (the two agree: tests/test_trace_cli.py holds them to it), and the figures only
the world knew (objects lost, wall time with set-up) come from it alone.
"""

from __future__ import annotations

import json
import math
import os
from collections import Counter
from dataclasses import dataclass
from pathlib import Path
from statistics import median

from tidyplan.errors import Diagnostic, InputError
from tidyplan.trace.events import KINDS, SCHEMA_VERSION, delivers
from tidyplan.trace.score import TIME_LIMIT_S, wrs_score

NO_SUMMARY = "without a summary (the run was stopped before it ended)"
NUMBER = (int, float)
WHAT = {NUMBER: "a number", int: "a whole number", str: "a string", list: "a list", bool: "true or false"}
# What the readers below index without looking: a known event lacking it is not read as one.
REQUIRED = {
    "plan": {"replan": int, "plan": list, "cause": str, "status": str},
    "action": {"action": str, "ok": bool},
    "unit": {"unit": str, "step": str},
    "recovery": {"unit": str},
    "bind": {"virtual": str, "item": str},
    "assumption": {"holds": bool},
    "assume": {"action": str},
}

POINT, NAMES, COUNTS = "point", "names", "counts"  # [x, y]; a list of strings; {name: number}
WHAT |= {
    POINT: "a point [x, y]",
    NAMES: "a list of strings",
    COUNTS: "an object of numbers",
    dict: "an object",
}
# What the readers below take as is where it is present (a trace may lack it: older schemas,
# killed runs): of another kind, the event is not read as one, as for REQUIRED.
OPTIONAL = {
    "start": {"robot": POINT, "expected": COUNTS, "time_limit_s": NUMBER, "generated_viewpoints": dict},
    "action": {
        "path": list,
        "robot": POINT,
        "seconds": NUMBER,
        "metres": NUMBER,
        "recoveries": int,
        "stratum": int,
        "delivered": str,
        "units": NAMES,
    },
    "plan": {"planning_time_s": NUMBER, "assumptions": int, "stratum": int, "problem": str},
    "observe": {"new": NAMES, "forgotten": NAMES},
    "inspect_deposit": {"lost": NAMES},
    "unit": {"action": str, "depth": int, "seconds": NUMBER},
    "recovery": {"layer": str, "failure_class": str, "failure": str},
    "assumption": {"action": str},
    "end": {"items": dict},
}


@dataclass(frozen=True, slots=True)
class Trace:
    """The events of one trace that this reader knows, in order, and what reading it found.

    Invariant: ``events[0]`` is the ``start`` event; every event is a dict with a str ``kind``
    in ``KINDS``."""

    path: Path
    events: tuple[dict, ...]
    version: int  # the highest ``v`` seen
    skipped: int  # events of unknown kinds
    truncated: bool  # the last line was cut off and dropped
    warnings: tuple[Diagnostic, ...]

    def of(self, kind: str) -> list[dict]:
        return [e for e in self.events if e["kind"] == kind]

    def last(self, kind: str) -> dict | None:
        found = self.of(kind)
        return found[-1] if found else None

    @property
    def start(self) -> dict:
        return self.events[0]

    def beside(self, relative: str) -> Path:
        """A path the trace gives relative to its own folder (the PDDL files)."""
        return self.path.parent / relative


# ------------------------------------------------------------------ reading
def read_trace(path: str | os.PathLike) -> Trace:
    """Read and check a trace file; ``InputError`` (one line) if it is not one."""
    where = os.fspath(path)
    text = _text(where)
    lines = text.split("\n")
    numbered = [(n, line) for n, line in enumerate(lines, 1) if line.strip()]
    if not numbered:
        raise _not_a_trace(where, "the file is empty")
    events, truncated = [], False
    for i, (n, line) in enumerate(numbered):
        try:
            event = json.loads(line)
        except json.JSONDecodeError as e:
            if i == len(numbered) - 1 and events:  # a killed run: the last line is cut off
                truncated = True
                break
            raise _not_a_trace(where, f"line {n} is not JSON ({e.msg})") from None
        except RecursionError:  # JSON, but nested deeper than the decoder goes: no writer of ours
            raise _not_a_trace(where, f"line {n} is nested too deeply to read") from None
        except ValueError:  # JSON, but a whole number of more digits than int() takes (4,300)
            raise _not_a_trace(where, f"line {n} has a number of too many digits to read") from None
        if not isinstance(event, dict) or not isinstance(event.get("kind"), str):
            raise _not_a_trace(where, f'line {n} is not a trace event (no "kind")')
        if not events and event["kind"] != "start":
            raise _not_a_trace(where, f"it has no start event (the first is {event['kind']!r})")
        wrong = _malformed(event)
        if wrong:
            raise _not_a_trace(where, f"line {n}: a {event['kind']} event {wrong}")
        events.append(event)
    versions = [e["v"] for e in events if isinstance(e.get("v"), int)]
    version = max(versions, default=SCHEMA_VERSION)
    known = tuple(e for e in events if e["kind"] in KINDS)
    skipped = len(events) - len(known)
    warnings = []
    if truncated:
        last = known[-1] if known else events[-1]
        warnings.append(
            Diagnostic(
                where,
                None,
                None,
                f"cut off mid-line (a killed run?): read up to its last whole event, "
                f"seq {last.get('seq', '?')} ({last['kind']})",
                warning=True,
            )
        )
    if version > SCHEMA_VERSION:
        warnings.append(
            Diagnostic(
                where,
                None,
                None,
                f"written with trace schema v{version}, this tidyplan reads v{SCHEMA_VERSION}: "
                f"read as v{SCHEMA_VERSION}, {skipped} event{'' if skipped == 1 else 's'} "
                "of unknown kinds skipped",
                warning=True,
            )
        )
    return Trace(Path(where), known, version, skipped, truncated, tuple(warnings))


def _malformed(event: dict) -> str | None:
    """What a known event lacks that the readers rely on, or None (unknown kinds: None)."""
    if event["kind"] not in KINDS:
        return None
    fields = {"sim_s": NUMBER, "wall_s": NUMBER} | REQUIRED.get(event["kind"], {})
    for name, kind in fields.items():
        if not _is(event.get(name), kind):
            return f'whose "{name}" is missing or not {WHAT[kind]}'
    for name, kind in OPTIONAL.get(event["kind"], {}).items():
        value = event.get(name)
        if value is not None and not _is(value, kind):
            return f'whose "{name}" is not {WHAT[kind]}'
    if event["kind"] == "action" and not all(_is(p, POINT) for p in event.get("path") or []):
        return 'whose "path" is not a list of points [x, y]'
    return None


def _is(value, kind) -> bool:
    """Whether a JSON value is of ``kind``: a type (a bool is no number), or POINT, NAMES, COUNTS."""
    if kind == POINT:
        return isinstance(value, list) and len(value) == 2 and all(_is(v, NUMBER) for v in value)
    if kind == NAMES:
        return isinstance(value, list) and all(isinstance(v, str) for v in value)
    if kind == COUNTS:
        return isinstance(value, dict) and all(_is(v, NUMBER) for v in value.values())
    return isinstance(value, kind) and (kind is bool or not isinstance(value, bool))


def _text(where: str) -> str:
    if os.path.isdir(where):
        raise _not_a_trace(where, "it is a directory")
    try:
        with open(where, "rb") as fh:
            data = fh.read()
    except FileNotFoundError:
        raise InputError(Diagnostic(where, None, None, "no such file")) from None
    except OSError as e:
        raise InputError(Diagnostic(where, None, None, f"cannot read: {e.strerror}")) from None
    if b"\0" in data:
        raise _not_a_trace(where, "it is a binary file")
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as e:
        line = data[: e.start].count(b"\n") + 1
        raise _not_a_trace(where, f"line {line} is not UTF-8 text") from None


def _not_a_trace(where: str, why: str) -> InputError:
    return InputError(Diagnostic(where, None, None, f"not a tidyplan trace: {why}"))


# ------------------------------------------------------------------ plans
def adopted(trace: Trace) -> list[dict]:
    """The plan events whose plan the loop went on to execute: each solved one, except a last
    one whose probability was too low to act on (the mission ended instead)."""
    plans = trace.of("plan")
    end = trace.last("end")
    out = [p for p in plans if p.get("status") == "solved"]
    if out and out[-1] is plans[-1] and end and end.get("reason", "").startswith("best plan's"):
        out.pop()
    return out


def plan_rows(trace: Trace) -> list[dict]:
    """One row per planner call: when, why, which goal, the outcome, and the actions executed
    under it (0 unless adopted)."""
    chosen = {id(p) for p in adopted(trace)}
    rows, current, before = [], None, None
    for e in trace.events:
        if e["kind"] == "plan":
            steps = e.get("plan") or []
            row = {
                "replan": e.get("replan"),
                "sim_s": e.get("sim_s"),
                "wall_s": e.get("wall_s"),
                "cause": e.get("cause"),
                "why": e.get("why", ""),
                "goal_kind": e.get("goal_kind"),
                "goal": len(e.get("goal") or []),
                "status": e.get("status"),
                "stratum": e.get("stratum"),
                "transition": e.get("transition"),
                "steps": len(steps),
                "assumptions": e.get("assumptions", sum(_is_assumption(s) for s in steps)),
                "cost": e.get("cost"),
                "probability": e.get("probability"),
                "planning_time_s": e.get("planning_time_s"),
                "adopted": id(e) in chosen,
                "executed": 0,
                "again": before if before in ("explore_again", "look_again") else None,
            }
            rows.append(row)
            if row["adopted"]:
                current = row
        elif e["kind"] == "action" and current is not None:
            current["executed"] += 1
        if e["kind"] != "observe":  # a look_again's look comes between it and its plan
            before = e["kind"]
    return rows


def _is_assumption(step: str) -> bool:
    return step.startswith("(assume")


# ------------------------------------------------------------------ the story
def summarise(trace: Trace) -> dict:
    """The run in figures (the `tidyplan run --json` summary's fields and more), from the events;
    the run's own summary event, when there is one, has the last word on the shared fields."""
    s = _from_events(trace)
    own = trace.last("summary")
    if own is not None:
        for key, value in own.items():
            if key in s and key not in ("trace", "v", "seq", "kind", "wall_s", "sim_s"):
                s[key] = value
    s["complete"] = own is not None
    s["ended"] = (
        s["reason"]
        if own is not None
        else NO_SUMMARY + (f"; the loop's end: {s['reason']}" if trace.last("end") else "")
    )
    return s


def _from_events(trace: Trace) -> dict:
    start, end = trace.start, trace.last("end")
    actions = trace.of("action")
    groups = _replan_groups(trace)
    times = [p["planning_time_s"] for p in trace.of("plan") if "planning_time_s" in p]
    objects = sum(start.get("expected", {}).values()) or None
    places = (end or {}).get("items") or {}
    tidied = [a.get("delivered") or _arg(a, 1) for a in actions if delivers(a)]
    delivered = sum(str(v[0]).startswith("tidied") for v in places.values()) if places else len(tidied)
    checks = trace.of("assumption")
    last = trace.events[-1]

    limit = start.get("time_limit_s", TIME_LIMIT_S)
    return {
        "file": str(trace.path),
        "schema": trace.version,
        "scenario": start.get("scenario"),
        "strategy": start.get("strategy"),
        "seed": None,
        "success": bool(end and end.get("success")) and (objects is None or delivered == objects),
        "reason": end.get("reason", "") if end else "",
        "objects": objects,
        "delivered": delivered,
        "lost_objects": None,  # only the world knows: in the summary event
        "tidied": tidied,
        "actions": len(actions),
        "failed_actions": sum(not a.get("ok", True) for a in actions),
        "paper_actions": None,  # needs the belief's hand at each move: in the summary event
        "strata": _strata(actions),
        "replans": len(groups),
        "replan_causes": dict(sorted(Counter(groups.values()).items())),
        "replans_avoided": len(trace.of("plan_kept")),
        "recoveries": sum(a.get("recoveries", 0) for a in actions),
        "recovery_steps": _recovery_steps(trace),
        "assumptions": {
            "made": sum(p.get("assumptions", 0) for p in adopted(trace)),
            "passed": len(trace.of("assume")),
            "confirmed": sum(bool(c.get("holds")) for c in checks),
            "contradicted": sum(not c.get("holds") for c in checks),
        },
        "bound": [[b.get("virtual"), b.get("item")] for b in trace.of("bind")],
        "new_objects": sum(len(o.get("new") or []) for o in trace.of("observe")),
        "forgotten": sum(len(o.get("forgotten") or []) for o in trace.of("observe"))
        + len(trace.of("forget")),
        "distance_m": round(sum(a.get("metres", 0.0) for a in actions), 2),
        "sim_time_s": round(last.get("sim_s", 0.0), 1),
        "wall_time_s": round(last.get("wall_s", 0.0), 2),
        "replan_time_s": {"median": round(median(times), 3), "max": round(max(times), 3)}
        if times
        else {"median": 0.0, "max": 0.0},
        "wrs_score": wrs_score(trace.events, limit),
        "time_limit_s": limit,
        # what the same run would score had the referee no clock: how much the time limit cost
        "wrs_score_at_end": wrs_score(trace.events, math.inf),
        "plans": plan_rows(trace),
        "warnings": [str(w) for w in trace.warnings],
    }


def _replan_groups(trace: Trace) -> dict[int, str]:
    """Replan number -> its cause, for the replans that wrote a plan event (not the initial)."""
    groups: dict[int, str] = {}
    for p in trace.of("plan"):
        n = p.get("replan")
        if isinstance(n, int) and n > 0 and n not in groups:
            groups[n] = p.get("cause", "?")
    return groups


def _strata(actions: list[dict]) -> dict[str, int]:
    """Deliveries by the highest operator stratum executed since the previous delivery, failed
    actions included (as the loop counts them, Yan et al.'s Table II)."""
    strata, segment = {"P1": 0, "P2": 0, "P3": 0}, 1
    for a in actions:
        segment = max(segment, a.get("stratum") or 1)
        if delivers(a):
            strata[f"P{segment}"] = strata.get(f"P{segment}", 0) + 1
            segment = 1
    return strata


def _recovery_steps(trace: Trace) -> dict:
    steps = trace.of("recovery")
    counted = [r for r in steps if r.get("layer") != "error_layer"]

    def by(field: str) -> dict:  # a step without the field counts under None, listed last
        found = Counter(r.get(field) for r in counted)
        return dict(sorted(found.items(), key=lambda kv: (kv[0] is None, str(kv[0]))))

    return {
        "by_class": by("failure_class"),
        "by_layer": by("layer"),
        "by_failure": by("failure"),
        "exhausted": len(steps) - len(counted),
    }


def _arg(event: dict, i: int) -> str:
    """Argument ``i`` of an action event's step (a trace that does not name the item delivered)."""
    parts = event.get("action", "()").strip("()").split()
    return parts[i] if len(parts) > i else "?"


# ------------------------------------------------------------------ the track
def track(trace: Trace) -> list[dict]:
    """The robot's poses: where it started, then the path driven in each action (``path``, when
    the trace has it) and where it stood after it (``robot``), each with the simulated time at
    the action's end and the index (into ``adopted``) of the plan it was executing."""
    plans = {id(p): i for i, p in enumerate(adopted(trace))}
    start = trace.start.get("robot")
    points = [] if start is None else [{"sim_s": 0.0, "xy": tuple(start), "plan": 0}]
    current = 0
    for e in trace.events:
        if id(e) in plans:
            current = plans[id(e)]
        elif e["kind"] == "action":
            poses = [tuple(p) for p in e.get("path") or []]
            if e.get("robot") is not None and (not poses or poses[-1] != tuple(e["robot"])):
                poses.append(tuple(e["robot"]))
            points += [{"sim_s": e["sim_s"], "xy": xy, "plan": current} for xy in poses]
    return points


def replan_points(trace: Trace) -> list[dict]:
    """Where the robot stood at each replan (its last position before the first plan event of
    the replan) and why it replanned."""
    out, at, seen = [], trace.start.get("robot"), set()
    for e in trace.events:
        if e["kind"] == "action" and e.get("robot") is not None:
            at = e["robot"]
        elif e["kind"] == "plan" and e["replan"] > 0 and e["replan"] not in seen:
            seen.add(e["replan"])
            out.append({"replan": e["replan"], "cause": e.get("cause"), "sim_s": e["sim_s"], "xy": at})
    return out
