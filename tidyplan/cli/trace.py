"""`tidyplan trace`: the story of a run from its trace, its plot, its replay page, a replan's
diff, runs compared.

Reading and figures are tidyplan/trace/read.py, the replan diff tidyplan/trace/diff.py, the
picture tidyplan/trace/plot.py, the page tidyplan/trace/html.py; this module parses the options
and prints. A file that is not a trace is bad input (exit 2, one line); a damaged trace is read
with a warning on stderr. The page never replaces a file unless asked to (``--force``).
"""

from __future__ import annotations

import argparse
import json
import os
import sys
from typing import TYPE_CHECKING

from tidyplan.errors import Diagnostic, InputError
from tidyplan.trace.events import CAUSES

if TYPE_CHECKING:
    from rich.console import Console
    from rich.table import Table

    from tidyplan.trace.read import Trace

# rich and the trace reader are imported where they are used: every command builds this module's
# parser, and `tidyplan plan` and `check` should not pay for them (tests/test_house.py)

KEPT_SHOWN = 2  # a run of kept steps longer than twice this is shown by its ends


def add_parser(sub) -> None:
    t = sub.add_parser("trace", help="the story of a run from its trace: replans and why, plots, plan diffs")
    t.add_argument("files", nargs="+", metavar="FILE", help="a trace; two or more: the runs side by side")
    t.add_argument("--json", action="store_true", help="print one JSON object")
    t.add_argument("--plot", metavar="PNG", help="draw the room with the robot's path, and a timeline")
    t.add_argument(
        "--replan", type=_count, metavar="N", help="the problem and plan of replan N, and what changed"
    )
    t.add_argument(
        "--html",
        metavar="OUT",
        help="write one self-contained page that replays the run in a browser (works offline)",
    )
    t.add_argument("--force", action="store_true", help="with --html: replace OUT if it exists")
    t.add_argument(
        "--scenario", metavar="FILE", help="the scenario to draw (default: the one the trace names)"
    )


def _count(text: str) -> int:
    if not text.isdigit():
        raise argparse.ArgumentTypeError(f"a replan number is a whole number from 0, not {text!r}")
    return int(text)


def cmd_trace(args) -> int:
    if len(args.files) > 1 and (args.plot or args.html or args.replan is not None):
        raise InputError("--plot, --html and --replan: give one trace (several are compared side by side)")
    from tidyplan.trace.diff import replan_diff
    from tidyplan.trace.read import read_trace, summarise

    traces = [read_trace(f) for f in args.files]
    for t in traces:
        for w in t.warnings:
            print(w, file=sys.stderr)
    if args.html:  # first: a page or plot that cannot be written is bad input, before anything is printed
        _html(traces[0], args.html, args.scenario, args.force)
    if args.plot:
        _plot(traces[0], args.plot, args.scenario)
    out = _console()
    if len(traces) > 1:
        summaries = [summarise(t) for t in traces]
        _print_json({"runs": summaries}) if args.json else _print_comparison(out, summaries)
    elif args.replan is not None:
        diff = replan_diff(traces[0], args.replan)
        _print_json(diff) if args.json else _print_diff(out, traces[0], diff)
    else:
        s = summarise(traces[0])
        _print_json(s) if args.json else _print_story(out, s)
    return 0


def _plot(trace: Trace, out: str, scenario_file: str | None) -> None:
    from tidyplan.trace.plot import plot  # matplotlib loads only when a plot is asked for

    scenario = _scenario(scenario_file)
    try:
        plot(trace, out, scenario, warn=lambda m: print(f"{trace.path}: warning: {m}", file=sys.stderr))
    except OSError as e:
        raise InputError(Diagnostic(out, None, None, f"cannot write the plot: {e.strerror or e}")) from None
    print(f"wrote {out}", file=sys.stderr)


def _html(trace: Trace, out: str, scenario_file: str | None, force: bool) -> None:
    from tidyplan.trace.html import write_page

    if os.path.isdir(out):
        raise InputError(Diagnostic(out, None, None, "is a directory; --html names the page's file"))
    if os.path.exists(out) and os.path.samefile(out, trace.path):
        raise InputError(Diagnostic(out, None, None, "is the trace itself; choose another --html file"))
    if os.path.exists(out) and not force:
        raise InputError(Diagnostic(out, None, None, "exists; --force replaces it"))
    folder = os.path.dirname(os.path.abspath(out))
    if not os.path.isdir(folder) or not os.access(folder, os.W_OK):  # said before the page is made
        why = "no such folder" if not os.path.isdir(folder) else "the folder is not writable"
        raise InputError(Diagnostic(out, None, None, f"cannot write the page: {why}"))
    scenario = _scenario(scenario_file)
    try:
        size = write_page(
            trace, out, scenario, warn=lambda m: print(f"{trace.path}: warning: {m}", file=sys.stderr)
        )
    except OSError as e:
        raise InputError(Diagnostic(out, None, None, f"cannot write the page: {e.strerror or e}")) from None
    print(f"wrote {out} ({size / 1e6:.2f} MB): open it in a browser", file=sys.stderr)


def _scenario(scenario_file: str | None):
    """The scenario ``--scenario`` names (a file, or a shipped one's name), or None (the trace's own)."""
    from tidyplan.loop.scenarios import load_scenario

    return load_scenario(scenario_file) if scenario_file else None


def _console() -> Console:
    from rich.console import Console

    # Piped output keeps a readable width; markup off: plan steps and reasons are printed as is.
    return Console(
        width=None if sys.stdout.isatty() else 120, markup=False, highlight=False, emoji=False, soft_wrap=True
    )


def _print_json(obj: dict) -> None:
    print(json.dumps(obj))


# ------------------------------------------------------------------ one run
def _print_story(out: Console, s: dict) -> None:
    out.print(
        f"{s['scenario'] or '?'} · {s['strategy'] or '?'}"
        + (f" · seed {s['seed']}" if s["seed"] is not None else "")
        + f": {s['file']} (schema v{s['schema']})"
    )
    verdict = "success" if s["success"] else "FAILED" if s["complete"] else "unfinished"
    lost = "" if s["lost_objects"] is None else f", {s['lost_objects']} lost"
    out.print(f"ended: {s['ended']}: {verdict}, {s['delivered']}/{s['objects']} tidied{lost}")
    out.print(
        f"replans: {s['replans']} ({_causes(s['replan_causes'])}); "
        f"{s['replans_avoided']} plans kept after recoveries or new objects"
    )
    out.print(_plans_table(s["plans"]) if s["plans"] else "plans: none yet")
    paper = "" if s["paper_actions"] is None else f", {s['paper_actions']} as Yan et al. count"
    out.print(
        f"actions: {s['actions']} executed ({s['failed_actions']} failed{paper}); "
        f"deliveries by stratum: {_strata(s['strata'])}"
    )
    r = s["recovery_steps"]
    out.print(
        f"recoveries: {s['recoveries']} steps; by failure class {_pairs(r['by_class'])}; "
        f"by layer {_pairs(r['by_layer'])}; "
        f"by failure {_pairs(r['by_failure'])}; exhausted {r['exhausted']} (each a replan (iv))"
    )
    a = s["assumptions"]
    bound = ", ".join(f"{v} → {i}" for v, i in s["bound"]) or "none"
    out.print(
        f"assumptions: {a['made']} in the plans executed; {a['confirmed']} confirmed, "
        f"{a['contradicted']} contradicted, the rest dropped with their plan or never checked; "
        f"virtual objects bound: {bound}"
    )
    out.print(
        f"objects: {s['new_objects']} seen anew, {s['forgotten']} forgotten; "
        f"tidied in order: {' '.join(s['tidied']) or 'none'}"
    )
    out.print(
        f"WRS score {s['wrs_score']:g} within {s['time_limit_s']:g} s simulated "
        f"({s['wrs_score_at_end']:g} at the end, had there been no time limit)"
    )
    t = s["replan_time_s"]
    out.print(
        f"distance {s['distance_m']:.2f} m; simulated time {s['sim_time_s']:.1f} s; "
        f"wall time {s['wall_time_s']:.2f} s; "
        f"planning median {t['median']:.2f} s, max {t['max']:.2f} s"
    )


SHORT = {
    "initial": "initial",
    "precondition_failed": "(i) precondition",
    "plan_invalid": "(ii) plan invalid",
    "assumption_contradicted": "(iii) assumption",
    "recovery_exhausted": "(iv) recovery",
    "new_object": "(v) new object",
}


def _plans_table(rows: list[dict]) -> Table:
    from rich.table import Table

    table = Table(title="plans and replans", title_justify="left", show_edge=False, pad_edge=False)
    columns = "# sim_s cause why goal status P steps cost p plan_s run".split()
    for name in columns:
        left = name in ("cause", "why", "goal", "status", "P")
        table.add_column(
            name.replace("_", " "),
            justify="left" if left else "right",
            overflow="fold",
            max_width=52 if name == "why" else None,
            no_wrap=name != "why",
        )
    for r in rows:
        table.add_row(
            str(r["replan"]),
            _num(r["sim_s"], 1),
            SHORT.get(r["cause"], r["cause"]),
            (f"{r['again'].replace('_', ' ')}: " if r["again"] else "") + (r["why"] or ""),
            ("" if r["goal_kind"] == "all" else f"{r['goal_kind']} ") + str(r["goal"]),
            r["status"] + ("" if r["adopted"] or r["status"] != "solved" else " (not adopted)"),
            f"P{r['stratum']}" if r["stratum"] else "-",
            f"{r['steps']}" + (f" ({r['assumptions']})" if r["assumptions"] else ""),
            _num(r["cost"], 1),
            "-" if r["probability"] is None else f"{r['probability']:.3g}",
            _num(r["planning_time_s"], 2),
            str(r["executed"]) if r["adopted"] else "",
            style=None if r["status"] == "solved" else "dim",
        )
    table.caption = (
        "goal: items and virtual objects to tidy; P: highest stratum; steps (assumptions); "
        "p: success probability; plan s: planning time; run: actions executed under the plan"
    )
    table.caption_justify = "left"
    return table


def _num(x, digits: int) -> str:
    return "-" if x is None else f"{x:.{digits}f}"


def _causes(causes: dict) -> str:
    return ", ".join(f"{k} ({CAUSES.get(k, '?')}) {n}" for k, n in causes.items()) or "none"


def _strata(strata: dict) -> str:
    return " · ".join(f"{k} {v}" for k, v in strata.items())


def _pairs(d: dict) -> str:
    return ", ".join(f"{k} {v}" for k, v in d.items()) or "none"


# ------------------------------------------------------------------ one replan
def _print_diff(out: Console, trace: Trace, d: dict) -> None:
    cause = d["cause"] if d["cause"] == "initial" else f"{d['cause']} ({CAUSES.get(d['cause'], '?')})"
    out.print(
        f"replan {d['replan']} of {trace.path}, at {d['sim_s']} s simulated: {cause}"
        + (f": {d['why']}" if d["why"] else "")
    )
    for a in d["attempts"]:
        p = "-" if a["probability"] is None else f"{a['probability']:.3g}"
        out.print(
            f"  goal {a['goal_kind']}: {a['status']}, "
            + (f"P{a['stratum']}, " if a["stratum"] else "")
            + f"{a['steps']} steps, cost {_num(a['cost'], 2)}, p {p}, {_num(a['planning_time_s'], 2)} s"
            + (f" ({a['message']})" if a["message"] else "")
        )
    out.print(
        f"problem: {trace.beside(d['problem']) if d['problem'] else '-'}"
        + ("" if d["adopted"] else " (plan not adopted)")
    )
    prev = d["previous"]
    if prev is None:
        out.print(f"{d['facts_note']}; its plan:")
        _print_steps(out, d["diff"])
        return
    ex = d["executed"]
    out.print(
        f"executed since replan {prev['replan']}: {len(ex)} action{_s(ex)}"
        + (f": {' '.join(ex)}" if len(ex) <= 4 else f", the last {ex[-1]}")
    )
    out.print(
        f"plan against the rest of replan {prev['replan']} ({len(d['rest'])} steps left): "
        f"{len(d['kept'])} kept, {len(d['dropped'])} dropped, {len(d['added'])} added"
    )
    _print_steps(out, d["diff"])
    if d["facts"] is None:
        out.print(d["facts_note"])
    else:
        _print_facts(out, d["facts"])


def _print_steps(out: Console, lines: list[list[str]]) -> None:
    from rich.text import Text

    i = 0
    while i < len(lines):
        j = i
        while j < len(lines) and lines[j][0] == " ":
            j += 1
        run = lines[i:j] if j > i else [lines[i]]
        if j - i > 2 * KEPT_SHOWN + 1:
            shown = run[:KEPT_SHOWN] + [["", f"… {j - i - 2 * KEPT_SHOWN} kept steps …"]] + run[-KEPT_SHOWN:]
        else:
            shown = run
        for mark, step in shown:
            style = {"-": "red", "+": "green"}.get(mark)
            out.print(Text(f"  {mark} {step}", style=style or ""))
        i = j if j > i else i + 1


def _print_facts(out: Console, f: dict) -> None:
    from rich.text import Text

    from tidyplan.trace.diff import BULK, by_predicate

    out.print(
        f"belief ({f['from']} → {f['to']}): {len(f['added'])} facts added, {len(f['removed'])} removed, "
        f"{len(f['values'])} values changed"
    )
    added, removed = by_predicate(f["added"]), by_predicate(f["removed"])
    for name in sorted(added.keys() | removed.keys(), key=lambda n: (n in BULK, n)):
        plus, minus = added.get(name, []), removed.get(name, [])
        if name in BULK:
            out.print(f"  {name}: {len(plus)} added, {len(minus)} removed")
            continue
        for fact in minus:
            out.print(Text(f"  - {fact}", style="red"))
        for fact in plus:
            out.print(Text(f"  + {fact}", style="green"))
    values = by_predicate([v[0] for v in f["values"]])
    for name, terms in values.items():
        if name in BULK:
            out.print(f"  {name}: {len(terms)} values changed")
            continue
        for term, old, new in (v for v in f["values"] if v[0] in terms):
            out.print(f"  {term}: {'-' if old is None else old} → {'-' if new is None else new}")


# ------------------------------------------------------------------ runs side by side
ROWS = (
    ("scenario", lambda s: s["scenario"] or "?"),
    ("strategy", lambda s: s["strategy"] or "?"),
    ("seed", lambda s: "?" if s["seed"] is None else str(s["seed"])),
    ("ended", lambda s: ("success: " if s["success"] else "FAILED: ") + _cut(s["ended"], 40)),
    ("tidied", lambda s: f"{s['delivered']}/{s['objects']}"),
    ("lost objects", lambda s: "?" if s["lost_objects"] is None else str(s["lost_objects"])),
    ("simulated time (s)", lambda s: f"{s['sim_time_s']:.1f}"),
    ("WRS score (at the end)", lambda s: f"{s['wrs_score']:g} ({s['wrs_score_at_end']:g})"),
    ("wall time (s)", lambda s: f"{s['wall_time_s']:.2f}"),
    ("distance (m)", lambda s: f"{s['distance_m']:.2f}"),
    ("replans", lambda s: str(s["replans"])),
    *((f"  ({n}) {c}", lambda s, c=c: str(s["replan_causes"].get(c, 0))) for c, n in CAUSES.items()),
    ("actions", lambda s: str(s["actions"])),
    ("  as Yan et al. count", lambda s: "?" if s["paper_actions"] is None else str(s["paper_actions"])),
    ("deliveries P1/P2/P3", lambda s: "/".join(str(s["strata"].get(k, 0)) for k in ("P1", "P2", "P3"))),
    ("recoveries", lambda s: str(s["recoveries"])),
    ("  exhausted", lambda s: str(s["recovery_steps"]["exhausted"])),
    (
        "assumptions made/contradicted",
        lambda s: f"{s['assumptions']['made']}/{s['assumptions']['contradicted']}",
    ),
    (
        "planning median/max (s)",
        lambda s: f"{s['replan_time_s']['median']:.2f}/{s['replan_time_s']['max']:.2f}",
    ),
)


def _print_comparison(out: Console, summaries: list[dict]) -> None:
    from rich.table import Table

    table = Table(
        title="runs side by side (Yan et al., Table III figures)", title_justify="left", show_edge=False
    )
    table.add_column("")
    for s in summaries:
        table.add_column(s["file"], justify="right", overflow="fold", max_width=40)
    for name, value in ROWS:
        table.add_row(name, *(value(s) for s in summaries))
    out.print(table)


def _s(items: list) -> str:
    return "" if len(items) == 1 else "s"


def _cut(text: str, n: int) -> str:
    return text if len(text) <= n else text[: n - 1] + "…"
