"""`tidyplan trace FILE --html OUT.html`: a run as one page that replays it in a browser.

Why a page: the story and the PNG say how many replans there were and why; a person debugging a
run wants to watch what the robot believed when it decided. One self-contained file (script,
style and data inline, nothing fetched) works offline and can be attached to a bug report.

Everything the page shows is computed here and embedded as JSON; the page's script
(``tidyplan/trace/replay/replay.js``) only draws it against the simulated clock. So the figures
are ``tidyplan.trace.read.summarise``'s, a replan's diff ``tidyplan.trace.diff.replan_diff``'s,
the colours and unit rows the PNG's (``tidyplan.trace.plot``), and tests hold the drawing to the
trace: ``pose_at`` is the script's interpolation. Invariants of the data:

- ``track``: keyframes ``[t, x, y, heading]``, t non-decreasing, joined by straight lines at
  constant speed. An action's ``path`` is spread by length over its motions (the ``do`` of the
  units that drive), so the robot stands still while it grasps and looks, and stands at the
  action's ``robot`` from its last motion to its end.
- ``belief``: each item the belief held, as ``[t, state, x, y]`` (``placed``, ``held``,
  ``tidied``, ``gone``; ``seen`` where its place is unknown): places from the problems written
  from the belief (``replan-NNN.pddl``'s header; older ones give only the grasp waypoint), an
  item seen in between placed by the next one; the hand's changes from the units.
"""

from __future__ import annotations

import json
import math
import os
import re
import tempfile
from bisect import bisect_right
from html import escape
from importlib import resources
from pathlib import Path

from sim.scenario.model import Sensing
from tidyplan.exec import catalogue as cat
from tidyplan.trace import plot  # its colours, unit rows and unit runs: the PNG's
from tidyplan.trace.diff import BULK, by_predicate, replan_diff
from tidyplan.trace.events import CAUSES
from tidyplan.trace.read import Trace, adopted, summarise

MOTIONS = frozenset(name for name, spec in cat.UNITS.items() if "follow" in spec.skills)
# a problem's header (tidyplan/belief/problem.py): waypoints "name kind x y", items "name category state x y"
_HEADER = re.compile(r"^;;\s+(\S+) (\S+)(?: (placed|held))? (-?\d+(?:\.\d+)?) (-?\d+(?:\.\d+)?)\s*$", re.M)
_FACT = re.compile(r"\((item-at|holding|of-category) ([^()\s]+)(?: ([^()\s]+))?\)")


def write_page(trace: Trace, out: str | os.PathLike, scenario=None, warn=lambda _: None) -> int:
    """Write the replay page of ``trace`` at ``out`` and return its size in bytes. ``scenario``
    overrides the one the trace names. Written beside ``out`` and renamed, so no reader sees
    half a page; whether ``out`` may be replaced is the caller's to decide."""
    data = page(trace, scenario, warn).encode("utf-8")
    fd, tmp = tempfile.mkstemp(dir=os.path.dirname(os.path.abspath(out)), prefix=".replay.", suffix=".tmp")
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
        os.chmod(tmp, 0o644)
        os.replace(tmp, out)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return len(data)


def page(trace: Trace, scenario=None, warn=lambda _: None) -> str:
    """The page's HTML: the template with the style, the script and the data inlined."""
    notes: list[str] = []  # what the page cannot show, said on it and to ``warn``
    if scenario is None:
        scenario = plot.scenario_of(trace, notes.append)
    data = page_data(trace, scenario, notes)
    for message in notes:
        warn(message)
    folder = resources.files("tidyplan.trace") / "replay"
    blob = json.dumps(data, separators=(",", ":")).replace("<", "\\u003c")  # no </script> nor <!-- inside
    html = (folder / "replay.html").read_text(encoding="utf-8")
    return (
        html.replace("{{TITLE}}", escape(data["title"]))
        .replace("{{CSS}}", (folder / "replay.css").read_text(encoding="utf-8"))
        .replace("{{JS}}", (folder / "replay.js").read_text(encoding="utf-8"))
        .replace("{{DATA}}", blob)
    )


def page_data(trace: Trace, scenario, notes: list[str]) -> dict:
    """Everything the page draws, as plain JSON values (see the module's doc); what it cannot
    show is added to ``notes``."""
    s = summarise(trace)
    keys = keyframes(trace, scenario.heading_deg if scenario is not None else 90.0)
    snaps = _snapshots(trace)
    if trace.of("plan") and not snaps:
        gone = any(p.get("problem") for p in trace.of("plan"))
        why = "the trace's PDDL folder is gone" if gone else "the plan events name no problem file"
        notes.append(f"{why}: the believed places of the items are not drawn")
    waypoints = {n: w for snap in snaps.values() for n, w in snap["waypoints"].items()}
    waypoints |= {n: (*xy, "viewpoint") for n, xy in (trace.start.get("generated_viewpoints") or {}).items()}
    room = _room(scenario)
    categories = sorted({*(room["categories"] if room else []), *(trace.start.get("expected") or {}).keys()})
    sensing = scenario.sensing if scenario is not None else Sensing()
    palette = plot.CATEGORY_COLOURS
    seed = "" if s["seed"] is None else f" · seed {s['seed']}"
    return {
        "title": f"{s['scenario'] or '?'} · {s['strategy'] or '?'}{seed}: {trace.path.name}",
        "summary": s,
        "notes": [*map(str, trace.warnings), *notes],
        "t_end": trace.events[-1]["sim_s"],
        "room": room,
        "camera": {"near": sensing.range_min, "range": sensing.range_max, "fov": sensing.fov_h_deg},
        "colours": {
            "category": {c: palette[i % len(palette)] for i, c in enumerate(categories)},
            "cause": {c: colour for c, (_, colour) in plot.CAUSE_STYLE.items()},
            "class": plot.CLASS_COLOURS,
            "plan": plot.PLAN_COLOURS,
            "action": plot.ACTION_COLOURS,
        },
        "causes": CAUSES,
        "track": keys,
        "waypoints": {n: [round(x, 3), round(y, 3), kind] for n, (x, y, kind) in waypoints.items()},
        "end_items": (trace.last("end") or {}).get("items") or {},
        "belief": _belief(trace, keys, snaps, room),
        "plans": _plans(trace),
        "timeline": _timeline(trace),
        "observe": [[e["sim_s"], e.get("new") or []] for e in trace.of("observe")],
        "assumptions": [[e["sim_s"], e.get("action", ""), e["holds"]] for e in trace.of("assumption")],
        "replans": _replans(trace),
    }


# ------------------------------------------------------------------ the robot
def keyframes(trace: Trace, heading: float = 90.0) -> list[list[float]]:
    """The robot's track as keyframes ``[t, x, y, heading]`` (see the module's doc)."""
    keys: list[list[float]] = []
    start = trace.start.get("robot")
    if start is not None:
        keys.append([0.0, start[0], start[1], heading])
    windows, before, look = [], 0.0, None
    for e in trace.events:
        kind = e["kind"]
        if kind == "unit" and e["step"] == "do" and e["unit"] in MOTIONS and e["sim_s"] > before:
            windows.append((before, e["sim_s"]))
        if kind == "unit" and e["unit"] == cat.LOOK and e["step"] == "check" and e.get("depth", 0) == 0:
            look = before
        if kind == "action":
            t0 = e["sim_s"] - e.get("seconds", 0.0)
            if sum(b - a for a, b in windows) < 1e-6:
                windows = [(t0, look if look is not None and look > t0 else e["sim_s"])]
            _drive(keys, e, windows)
            windows, look = [], None
        if kind != "observe":
            before = e["sim_s"]
    return [[round(v, 3) for v in k] for k in keys]


def _drive(keys: list[list[float]], action: dict, windows: list[tuple[float, float]]) -> None:
    """Append the keyframes of one action: its path spread by length over its motion windows."""
    poses = [tuple(p) for p in action.get("path") or []]
    robot = action.get("robot")
    if robot is not None and (not poses or poses[-1] != tuple(robot)):
        poses.append(tuple(robot))
    if not poses:
        return
    if not keys:  # a trace without start.robot: the track starts where the first action drove from
        keys.append([windows[0][0], *poses[0], 90.0])
    points = [tuple(keys[-1][1:3]), *poses]
    lengths = [0.0]
    for a, b in zip(points, points[1:], strict=False):
        lengths.append(lengths[-1] + math.dist(a, b))
    total, span = lengths[-1], sum(b - a for a, b in windows)
    if total < 1e-9 or span <= 0:
        _key(keys, max(keys[-1][0], windows[-1][1]), points[-1])
        _key(keys, action["sim_s"], points[-1])
        return
    done = 0.0  # time of the windows before the current one
    for a, b in windows:
        s0, s1 = total * done / span, total * (done + b - a) / span
        _key(keys, a, _along(points, lengths, s0))
        for p, s in zip(points, lengths, strict=True):
            if s0 < s < s1:
                _key(keys, a + (s - s0) / total * span, p)
        _key(keys, b, _along(points, lengths, s1))
        done += b - a
    _key(keys, action["sim_s"], points[-1])


def _along(points: list[tuple], lengths: list[float], s: float) -> tuple[float, float]:
    i = min(max(bisect_right(lengths, s) - 1, 0), len(points) - 2)
    d = lengths[i + 1] - lengths[i]
    f = 0.0 if d <= 0 else min(max((s - lengths[i]) / d, 0.0), 1.0)
    (x0, y0), (x1, y1) = points[i], points[i + 1]
    return x0 + f * (x1 - x0), y0 + f * (y1 - y0)


def _key(keys: list[list[float]], t: float, xy: tuple[float, float]) -> None:
    t = max(t, keys[-1][0])
    x0, y0, h = keys[-1][1], keys[-1][2], keys[-1][3]
    if math.dist((x0, y0), xy) > 1e-3:
        h = math.degrees(math.atan2(xy[1] - y0, xy[0] - x0))
    keys.append([t, xy[0], xy[1], h])


def pose_at(keys: list[list[float]], t: float) -> tuple[float, float, float]:
    """(x, y, heading) at simulated time ``t``: what replay.js's ``poseAt`` draws."""
    i = bisect_right([k[0] for k in keys], t) - 1
    if i < 0:
        return tuple(keys[0][1:4])
    if i >= len(keys) - 1:
        return tuple(keys[-1][1:4])
    (t0, x0, y0, _), (t1, x1, y1, h1) = keys[i], keys[i + 1]
    f = 0.0 if t1 <= t0 else (t - t0) / (t1 - t0)
    return x0 + f * (x1 - x0), y0 + f * (y1 - y0), h1


# ------------------------------------------------------------------ the room and the belief
def _room(scenario) -> dict | None:
    if scenario is None:
        return None
    return {
        "bounds": list(scenario.bounds),
        "entrance": list(scenario.entrance),
        "robot_radius": scenario.robot.radius,
        "furniture": [[f.name, f.cx, f.cy, f.sx, f.sy, f.kind] for f in scenario.furniture],
        "deposits": [[d.name, d.category, d.x, d.y] for d in scenario.deposits],
        "viewpoints": [[v.name, v.x, v.y] for v in scenario.viewpoints],
        "items": [[i.name, i.category, i.x, i.y] for i in scenario.items],
        "categories": sorted({i.category for i in scenario.items} | {d.category for d in scenario.deposits}),
    }


def _snapshots(trace: Trace) -> dict[str, dict]:
    """The problem files the plan events name (those still there), read for the belief they
    were written from: the waypoints, and each item's category and place or the hand."""
    out = {}
    for p in trace.of("plan"):
        rel = p.get("problem")
        if not rel or rel in out:
            continue
        try:  # a name the OS refuses (too long, say) is a file not there, not the page's fault
            text = trace.beside(rel).read_text(encoding="utf-8", errors="replace")
        except OSError:
            continue
        lines = _HEADER.findall(text)
        waypoints = {n: (float(x), float(y), kind) for n, kind, state, x, y in lines if not state}
        believed = {n: (float(x), float(y)) for n, _, state, x, y in lines if state == "placed"}
        items, kinds = {}, {}
        for name, a, b in _FACT.findall(text):
            if name == "item-at" and b in waypoints:  # where believed, else at its grasp waypoint
                items[a] = ("placed", *believed.get(a, waypoints[b][:2]))
            elif name == "holding":
                items[a] = ("held", None, None)
            elif name == "of-category":
                kinds[a] = b
        out[rel] = {"waypoints": waypoints, "items": items, "categories": kinds}
    return out


def _belief(trace: Trace, keys: list[list[float]], snaps: dict, room: dict | None) -> dict:
    """Item name -> {"category", "keys": [[t, state, x, y], ...]} (see the module's doc)."""
    items: dict[str, dict] = {}
    deposits = {d[0]: (d[2], d[3]) for d in (room or {}).get("deposits", [])}
    held = dropped = None

    def put(name: str | None, t: float, state: str, xy=(None, None)) -> None:
        if name is None:
            return
        entry = items.setdefault(name, {"category": name.rsplit("-", 1)[0], "keys": []})
        key = [t, state, *(None if v is None else round(v, 3) for v in xy)]
        if not entry["keys"] or entry["keys"][-1][1:] != key[1:]:
            entry["keys"].append(key)

    for e in trace.events:
        kind, t = e["kind"], e["sim_s"]
        if kind == "observe":
            for n in e.get("new") or []:
                put(n, t, "seen")
            for n in e.get("forgotten") or []:
                put(n, t, "gone")
        elif kind == "plan" and e.get("problem") in snaps:
            snap = snaps[e["problem"]]
            for n, (state, x, y) in snap["items"].items():
                put(n, t, state, (x, y))
                items[n]["category"] = snap["categories"].get(n, items[n]["category"])
            held = next((n for n, v in snap["items"].items() if v[0] == "held"), None)
        elif kind == "inspect_deposit":
            for n in e.get("lost") or []:
                put(n, t, "gone")
        elif kind == "unit" and e["step"] == "do":
            args = e.get("action", "()").strip("()").split()[1:]
            here = pose_at(keys, t)[:2] if keys else (None, None)
            if e["unit"] == cat.GRASP and e["ok"]:
                held = next((a for a in args if a in items), dropped)
                put(held, t, "held")
            elif e.get("failure") == "grasp_drop" and held:
                put(held, t, "placed", here)
                held, dropped = None, held
            elif e["unit"] == cat.PLACE and e["ok"] and held:
                put(held, t, "tidied", next((deposits[a] for a in args if a in deposits), here))
                held = None
            elif e["unit"] == cat.PUT_DOWN and e["ok"] and held:
                put(held, t, "placed", here)
                held = None
    for ks in (entry["keys"] for entry in items.values()):  # seen between two problems: the next's place
        for i, k in enumerate(ks):
            later = next((j for j in ks[i + 1 :] if j[1] == "placed" and j[2] is not None), None)
            if k[1] == "seen" and later is not None:
                ks[i] = [k[0], "placed", *later[2:]]
    return items


# ------------------------------------------------------------------ plans, timeline, replans
def _plans(trace: Trace) -> list[dict]:
    """The adopted plans, each with when its steps were passed (an ``assume``, an ``action``
    or, for assumptions on a bound item, the ``bind``), begun, the binds that renamed its
    virtual objects, and when the loop dropped it (the next plan event)."""
    chosen = {id(p) for p in adopted(trace)}
    out, cur, steps, names = [], None, [], {}
    for e in trace.events:
        kind = e["kind"]
        if id(e) in chosen:
            steps = [tuple(s.strip("()").split()) for s in e["plan"]]
            names = {}
            cur = {
                **{k: e.get(k) for k in ("replan", "sim_s", "cause", "why", "goal_kind", "stratum")},
                **{k: e.get(k) for k in ("cost", "probability")},
                "goal": len(e.get("goal") or []),
                "steps": list(e["plan"]),
                "passed": [None] * len(steps),
                "began": [None] * len(steps),
                "binds": [],
                "until": None,
            }
            out.append(cur)
        elif cur is None or cur["until"] is not None:
            continue
        elif kind == "plan":
            cur["until"] = e["sim_s"]
        elif kind == "bind":
            names[e["virtual"]] = e["item"]
            cur["binds"].append([e["sim_s"], e["virtual"], e["item"]])
            for i, s in enumerate(steps):
                if cur["passed"][i] is None and s[0].startswith("assume") and e["virtual"] in s[1:]:
                    cur["passed"][i] = cur["began"][i] = e["sim_s"]
        elif kind in ("assume", "action"):
            done = tuple(e["action"].strip("()").split())
            for i, s in enumerate(steps):
                if cur["passed"][i] is None and tuple(names.get(a, a) for a in s) == done:
                    cur["passed"][i] = e["sim_s"]
                    cur["began"][i] = round(e["sim_s"] - e.get("seconds", 0.0), 3)
                    break
    return out


def _timeline(trace: Trace) -> dict:
    runs = plot.unit_runs(trace)
    rows = [u for u in plot.UNITS if any(r[0] == u for r in runs)]
    rows += sorted({r[0] for r in runs} - set(rows))
    return {
        "units": rows,
        "runs": [[rows.index(u), round(a, 3), round(b, 3), ok] for u, a, b, ok in runs],
        "actions": [  # [start, end, step, ok, last unit (its colour), the loop's purpose]
            [round(a["sim_s"] - a.get("seconds", 0.0), 3), a["sim_s"], a["action"], a["ok"], *_last(a)]
            for a in trace.of("action")
        ],
        "recoveries": [
            [r["sim_s"], r["unit"], r.get("failure"), r.get("failure_class"), r.get("layer"), r.get("then")]
            for r in trace.of("recovery")
        ],
    }


def _last(action: dict) -> tuple[str | None, str | None]:
    return (action.get("units") or [None])[-1], action.get("purpose")


def _replans(trace: Trace) -> list[dict]:
    """Each replan (0: the initial plan) with its diff, as ``tidyplan trace --replan N --json``
    gives it, the map's facts counted rather than listed (as the text view does)."""
    numbers = sorted({p["replan"] for p in trace.of("plan")})
    out = []
    for n in numbers:
        d = replan_diff(trace, n)
        d.update({key: len(d[key]) for key in ("kept", "dropped", "added", "rest")})
        if d["facts"] is not None:
            d["facts"] = _facts(d["facts"])
        out.append(d)
    return out


def _facts(f: dict) -> dict:
    groups = [by_predicate(f["added"]), by_predicate(f["removed"]), by_predicate([v[0] for v in f["values"]])]
    counted = {n: [len(g.get(n, [])) for g in groups] for n in BULK if any(n in g for g in groups)}

    def bulk(fact: str) -> bool:
        return fact.strip("()").split()[0] in BULK

    return {
        "from": f["from"],
        "to": f["to"],
        "added": [x for x in f["added"] if not bulk(x)],
        "removed": [x for x in f["removed"] if not bulk(x)],
        "values": [v for v in f["values"] if not bulk(v[0])],
        "counted": counted,  # predicate -> [added, removed, values changed]
    }
