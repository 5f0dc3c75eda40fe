"""A trace as a picture: the room with the robot's path, and a timeline of the run beneath it.

The map draws the scenario the trace names (``start.scenario_file``): walls, furniture,
deposits and items in the colour of their category, items hollow where they stood at the start
and filled where the world held them at the end (``end.items``; tidied ones are counted at
their deposit). The path joins the robot's believed positions after each action (``action``
``robot``) with straight lines, coloured by the plan being executed; the trace holds no pose
between two actions, so a line may cut a corner the robot drove around. Replans are marked
where the robot stood, by cause (i)-(v), with their number.

The timeline (simulated seconds) has a band per adopted plan in the path's colours, the
actions, and a row per behaviour unit, each run a bar (red edge: the run failed); recoveries
are crosses coloured by failure class, replans dashed lines coloured by cause.
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable

import matplotlib

matplotlib.use("Agg")  # files only: no display, whatever the environment says
import matplotlib.pyplot as plt  # noqa: E402 - after choosing the backend
from matplotlib.collections import LineCollection  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402
from matplotlib.patches import Rectangle  # noqa: E402

from tidyplan.exec import catalogue as cat  # noqa: E402
from tidyplan.trace.events import CAUSES  # noqa: E402
from tidyplan.trace.read import Trace, adopted, replan_points, summarise, track  # noqa: E402

# tab10: the path and the plan band; no other mark uses these colours (tests look for them)
PLAN_COLOURS = ("#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#17becf")
CATEGORY_COLOURS = ("#66c2a5", "#fc8d62", "#8da0cb", "#e78ac3", "#a6d854", "#ffd92f", "#e5c494")
CAUSE_STYLE = {  # cause -> (marker, colour)
    "precondition_failed": ("D", "#1b9e77"),
    "plan_invalid": ("s", "#d95f02"),
    "assumption_contradicted": ("X", "#7570b3"),
    "recovery_exhausted": ("P", "#e7298a"),
    "new_object": ("*", "#66a61e"),
}
CLASS_COLOURS = {"A": "#e6ab02", "B": "#a6761d", "C": "#e41a1c"}
# An action is coloured by the manipulation it ends with, the last unit it ran (its `units`,
# tidyplan.exec.catalogue): a domain of one's own is drawn the same way as tidy.pddl
ACTION_COLOURS = {
    cat.NAVIGATE: "#d0d0d0",
    cat.ADJUST_POSE: "#909090",
    cat.GRASP: "#fdb462",
    cat.PLACE: "#b3de69",
    cat.PUT_DOWN: "#fb8072",
    cat.PULL_HANDLE: "#80b1d3",
}
# the unit rows, in the order a take-and-deliver runs them
UNITS = (*cat.UNITS, cat.PUSH_DRAWER, cat.LOOK)
# traces written before actions named their units: tidy.pddl's actions by name
_OLD_LAST_UNIT = {
    "move": cat.NAVIGATE,
    "move_back": cat.NAVIGATE,
    "possible_ego_pose_adjustment": cat.ADJUST_POSE,
    "take_object": cat.GRASP,
    "deliver_it": cat.PLACE,
    "drop_object": cat.PUT_DOWN,
}

Warn = Callable[[str], None]


def plot(trace: Trace, out: str | os.PathLike, scenario=None, warn: Warn = lambda _: None) -> None:
    """Write the map and the timeline of ``trace`` as a PNG at ``out``. ``scenario`` (a
    ``sim.scenario.model.Scenario``) overrides the one the trace names; without either, the map has
    the path alone and ``warn`` says why."""
    if scenario is None:
        scenario = scenario_of(trace, warn)
    fig = plt.figure(figsize=(10, 11), dpi=100, layout="constrained")
    grid = fig.add_gridspec(2, 1, height_ratios=(2.6, 1.4))
    room, timeline = fig.add_subplot(grid[0]), fig.add_subplot(grid[1])
    try:
        _map(room, trace, scenario)
        _timeline(timeline, trace)
        s = summarise(trace)
        fig.suptitle(_title(s), fontsize=11)
        fig.savefig(out, bbox_inches="tight")
    finally:
        plt.close(fig)


def _title(s: dict) -> str:
    causes = ", ".join(f"{CAUSES.get(c, c)} {n}" for c, n in s["replan_causes"].items()) or "none"
    return (
        f"{s['scenario'] or '?'} · {s['strategy'] or '?'}: {s['delivered']}/{s['objects']} tidied, "
        f"{s['replans']} replans ({causes}), {s['actions']} actions, {s['recoveries']} recoveries, "
        f"{s['distance_m']:.1f} m, {s['sim_time_s']:.0f} s simulated\n{s['ended']}"
    )


def scenario_of(trace: Trace, warn: Warn):
    """The scenario the trace names (``start.scenario_file``), or None with ``warn`` saying why."""
    from sim.scenario.model import ScenarioError
    from sim.scenario.read import load

    path = trace.start.get("scenario_file")
    if not path:
        warn("the trace does not name its scenario file (give --scenario): the room is not drawn")
        return None
    try:
        return load(path)
    except ScenarioError as e:
        warn(f"{e.messages[0]}: the room is not drawn")
        return None


# ------------------------------------------------------------------ the map
def _map(ax, trace: Trace, scenario) -> None:
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    colours = {}
    points = track(trace)
    if not points and scenario is not None:
        points = [{"sim_s": 0.0, "xy": scenario.entrance, "plan": 0}]
    if scenario is not None and trace.start.get("robot") is None and points:
        points.insert(0, {"sim_s": 0.0, "xy": scenario.entrance, "plan": 0})
    if scenario is not None:
        colours = {
            c: CATEGORY_COLOURS[i % len(CATEGORY_COLOURS)] for i, c in enumerate(scenario.categories())
        }
        _room(ax, trace, scenario, colours, points)
    segments = [(a["xy"], b["xy"]) for a, b in zip(points, points[1:], strict=False)]
    plans = [PLAN_COLOURS[b["plan"] % len(PLAN_COLOURS)] for b in points[1:]]
    ax.add_collection(LineCollection(segments, colors=plans, linewidths=2.2, zorder=4))
    if points and (scenario is not None or trace.start.get("robot") is not None):  # the start is known
        ax.plot(*points[0]["xy"], marker="^", color="black", markersize=11, zorder=6)
        ax.annotate("start", points[0]["xy"], xytext=(6, -12), textcoords="offset points", fontsize=8)
    _replans(ax, trace)
    _legend(ax, colours)
    if scenario is None:
        ax.autoscale_view()
        ax.margins(0.1)


def _room(ax, trace: Trace, scenario, colours: dict, points: list[dict]) -> None:
    x0, x1, y0, y1 = scenario.bounds
    ax.add_patch(Rectangle((x0, y0), x1 - x0, y1 - y0, fill=False, linewidth=3, edgecolor="black", zorder=1))
    for f in scenario.furniture:
        ax.add_patch(
            Rectangle(
                (f.cx - f.sx / 2, f.cy - f.sy / 2),
                f.sx,
                f.sy,
                facecolor="#e4e4e4",
                edgecolor="#999999",
                zorder=1,
            )
        )
        ax.text(f.cx, f.cy, f.name, fontsize=6, ha="center", va="center", color="#555555", zorder=2)
    places = (trace.last("end") or {}).get("items") or {}
    tidied = {}
    for state, *_ in places.values():
        if str(state).startswith("tidied:"):
            tidied[state[7:]] = tidied.get(state[7:], 0) + 1
    for d in scenario.deposits:
        ax.plot(d.x, d.y, marker="s", markersize=13, color=colours[d.category], mec="black", zorder=3)
        label = f"{d.name} ({d.category})" + (f": {tidied[d.name]} tidied" if d.name in tidied else "")
        ax.annotate(label, (d.x, d.y), xytext=(9, -3), textcoords="offset points", fontsize=7, zorder=7)
    for item in scenario.items:
        c = colours[item.category]
        ax.plot(item.x, item.y, marker="o", markersize=8, mfc="none", mec=c, mew=2, zorder=3)
        state, *end = places.get(item.name, (None,))
        if state == "held" and points:  # in the hand: where the robot stopped
            end = list(points[-1]["xy"])
            ax.annotate("held", end, xytext=(6, 6), textcoords="offset points", fontsize=7, zorder=7)
        if state in ("placed", "held") and end:
            ax.plot(*end, marker="o", markersize=8, color=c, mec="black", zorder=5)
            if math.dist(end, (item.x, item.y)) > 0.05:
                ax.annotate(
                    "", end, (item.x, item.y), arrowprops={"arrowstyle": "->", "color": "#777777"}, zorder=3
                )
    ax.set_xlim(x0 - 0.2, x1 + 0.2)
    ax.set_ylim(y0 - 0.2, y1 + 0.2)


def _replans(ax, trace: Trace) -> None:
    for r in replan_points(trace):
        if r["xy"] is None:
            continue
        marker, colour = CAUSE_STYLE.get(r["cause"], ("o", "black"))
        ax.plot(*r["xy"], marker=marker, markersize=10, color=colour, mec="black", zorder=6, alpha=0.9)
        ax.annotate(
            str(r["replan"]), r["xy"], xytext=(5, 4), textcoords="offset points", fontsize=7, zorder=7
        )


def _legend(ax, colours: dict) -> None:
    handles = [
        Line2D([], [], marker=m, color=c, mec="black", linestyle="none", label=f"replan ({CAUSES[k]}) {k}")
        for k, (m, c) in CAUSE_STYLE.items()
    ]
    handles += [
        Line2D([], [], marker="s", color=c, mec="black", linestyle="none", label=f"category {k}")
        for k, c in colours.items()
    ]
    handles += [
        Line2D(
            [], [], marker="o", mfc="none", mec="#555555", mew=2, linestyle="none", label="item at the start"
        ),
        Line2D(
            [],
            [],
            marker="o",
            color="#555555",
            mec="black",
            linestyle="none",
            label="item at the end, untidied",
        ),
    ]
    handles.append(Line2D([], [], color=PLAN_COLOURS[0], linewidth=2.2, label="path, coloured by plan"))
    ax.legend(handles=handles, fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False)


# ------------------------------------------------------------------ the timeline
def _timeline(ax, trace: Trace) -> None:
    rows = ["plan", "action", *[u for u in UNITS if any(e.get("unit") == u for e in trace.of("unit"))]]
    y = {name: len(rows) - 1 - i for i, name in enumerate(rows)}
    end = trace.events[-1].get("sim_s", 0.0)
    plans = adopted(trace)
    for i, p in enumerate(plans):
        until = plans[i + 1]["sim_s"] if i + 1 < len(plans) else end
        ax.broken_barh([(p["sim_s"], max(until - p["sim_s"], 0.5))], (y["plan"] - 0.4, 0.8), color=_plan(i))
        if until - p["sim_s"] > 0.03 * max(end, 1.0):  # room for the replan number
            mid = (p["sim_s"] + until) / 2
            ax.text(mid, y["plan"], str(p.get("replan")), color="white", fontsize=7, ha="center", va="center")
    for a in trace.of("action"):
        name = a.get("action", "()").strip("()").split()[0]
        last = a["units"][-1] if a.get("units") else _OLD_LAST_UNIT.get(name)
        span = (a["sim_s"] - a.get("seconds", 0.0), max(a.get("seconds", 0.0), 0.3))
        edge = "#c00000" if not a.get("ok", True) else "white"
        ax.broken_barh(
            [span], (y["action"] - 0.4, 0.8), facecolor=ACTION_COLOURS.get(last, "#cccccc"), edgecolor=edge
        )
    for unit, start, stop, ok in unit_runs(trace):
        if unit in y:
            edge = "#c00000" if not ok else "#666666"
            ax.broken_barh(
                [(start, max(stop - start, 0.3))], (y[unit] - 0.35, 0.7), facecolor="#c6dbef", edgecolor=edge
            )
    for r in trace.of("recovery"):
        if r.get("unit") in y:
            ax.plot(
                r["sim_s"],
                y[r["unit"]],
                marker="x",
                markersize=8,
                mew=2,
                color=CLASS_COLOURS.get(r.get("failure_class"), "black"),
            )
    for r in replan_points(trace):
        colour = CAUSE_STYLE.get(r["cause"], ("o", "black"))[1]
        ax.axvline(r["sim_s"], color=colour, linestyle="--", linewidth=1)
        label = CAUSES.get(r["cause"], "?")
        ax.text(
            r["sim_s"], 1.01, label, fontsize=6, color=colour, ha="center", transform=ax.get_xaxis_transform()
        )
    ax.set_yticks(list(y.values()), list(y))
    ax.set_ylim(-0.6, len(rows) - 0.2)
    ax.set_xlim(0, max(end, 1.0))
    ax.set_xlabel("simulated time (s)")
    handles = [
        Line2D([], [], marker="x", color=c, mew=2, linestyle="none", label=f"recovery, class {k}")
        for k, c in CLASS_COLOURS.items()
    ]
    handles += [
        Rectangle((0, 0), 1, 1, facecolor=c, label=f"action ending in {k}") for k, c in ACTION_COLOURS.items()
    ]
    ax.legend(handles=handles, fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False)


def _plan(i: int) -> str:
    return PLAN_COLOURS[i % len(PLAN_COLOURS)]


def unit_runs(trace: Trace) -> list[tuple[str, float, float, bool]]:
    """Each run of a behaviour unit as (unit, start, stop, ok): it starts at the clock of the
    event before its ``check`` (a navigate retry's look, written as ``observe``, is part of its
    check) and stops at its ``do`` or at the function that failed."""
    runs, before, open_runs = [], 0.0, {}
    for e in trace.events:
        if e["kind"] == "unit":
            key = (e.get("unit"), e.get("depth"))
            if e.get("step") == "check":
                open_runs[key] = before
            start = open_runs.get(key, before)
            if e.get("step") == "do" or not e.get("ok", True):
                runs.append((e.get("unit"), start, e["sim_s"], bool(e.get("ok", True))))
                open_runs.pop(key, None)
        if e["kind"] != "observe":
            before = e.get("sim_s", before)
    return runs
