"""The `tidyplan` command: check, plan, compile (here), run and reproduce (cli_run.py), trace
(cli_trace.py), sweep (cli_sweep.py), lsp and serve
(cli/editor.py).

Only this module turns errors into exit statuses: 0 success, 1 no plan (proven, or an incomplete
search ended without one: the message says which), 2 bad input (a file, an option), 3 no plan
found within the first-plan limit (nothing proven), 4 the planner failed; never a traceback.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import signal
import sys
import tempfile
import time
from pathlib import Path

from tidyplan.cli import editor as cli_editor
from tidyplan.cli import run as cli_run
from tidyplan.cli import sweep as cli_sweep
from tidyplan.cli import trace as cli_trace
from tidyplan.errors import Diagnostic, InputError, InternalError, PlannerError, TidyplanError

COMPILED_HEADER = "; plain PDDL compiled by tidyplan"


class _Parser(argparse.ArgumentParser):
    """argparse, but a bad option is one line and exit 2."""

    def error(self, message: str) -> None:  # type: ignore[override]
        self.exit(2, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


def _parser() -> argparse.ArgumentParser:
    p = _Parser(
        prog="tidyplan", description="Continual task planning for a service robot that tidies a room."
    )
    sub = p.add_subparsers(dest="command", required=True, parser_class=_Parser)

    c = sub.add_parser("check", help="read and check a domain (and a problem)")
    c.add_argument("domain")
    c.add_argument("problem", nargs="?")

    pl = sub.add_parser("plan", help="one plan: steps, cost, success probability, strata")
    pl.add_argument("domain")
    pl.add_argument("problem")
    pl.add_argument(
        "--planner",
        default=None,
        help="engine: lama-optimal (default), lama, lama-first, optimal, or any unified-planning engine name",
    )
    pl.add_argument(
        "--time-budget",
        type=_positive,
        default=None,
        metavar="S",
        help="seconds an anytime planner improves its first plan (default 1)",
    )
    pl.add_argument(
        "--first-plan-limit",
        type=_positive,
        default=None,
        metavar="S",
        help="seconds to find a first plan, for the whole call (default 60); past it: exit 3",
    )
    pl.add_argument(
        "--max-stratum", type=_stratum, default=None, metavar="K", help="plan with strata 1..K only"
    )
    pl.add_argument(
        "--no-strata", action="store_true", help="all operators at once, ranked by the criterion only"
    )
    pl.add_argument("--json", action="store_true", help="print one JSON object")

    co = sub.add_parser("compile", help="write the task as plain PDDL with action costs")
    co.add_argument("domain")
    co.add_argument("problem")
    co.add_argument("--out", required=True, metavar="DIR")
    co.add_argument("--max-stratum", type=_stratum, default=None, metavar="K", help="keep strata 1..K only")
    co.add_argument("--force", action="store_true", help="overwrite files there that tidyplan did not write")
    cli_run.add_parsers(sub, _positive)
    cli_trace.add_parser(sub)
    cli_sweep.add_parser(sub, _positive)
    cli_editor.add_parsers(sub, _positive)
    return p


def _positive(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: {text!r}") from None
    if not value > 0:
        raise argparse.ArgumentTypeError(f"must be positive: {text!r}")
    return value


def _stratum(text: str) -> int:
    if not text.isdigit() or int(text) < 1:
        raise argparse.ArgumentTypeError(f"a stratum is a whole number of at least 1, not {text!r}")
    return int(text)


# ------------------------------------------------------------------ commands
def _read(domain: str, problem: str | None):
    from tidyplan.pddl.reader import read

    return read(domain, problem, warn=lambda d: print(d, file=sys.stderr))


def cmd_check(args) -> int:
    from tidyplan.exec.binding_check import check_bindings, offered

    domain, problem = _read(args.domain, args.problem)
    found = check_bindings(domain)
    for d in found:
        if d.warning:
            print(d, file=sys.stderr)
    errors = [d for d in found if not d.warning]
    if errors:
        raise InputError(errors)
    strata = ", ".join(f"P{k}" for k in domain.strata)
    n_assumptions = sum(a.is_assumption for a in domain.actions)
    bound = sum(a.units is not None for a in domain.actions)
    print(
        f"{args.domain}: ok, domain {domain.name}: {len(domain.actions) - n_assumptions} actions, "
        f"{n_assumptions} assumptions, strata {strata}, "
        + (
            f"{bound} actions bound to behaviour units"
            if bound
            else "a planning domain (no :units: not runnable)"
        )
    )
    if bound:
        print("behaviour units the worlds offer (:units):")
        for spec, worlds in offered():
            print(f"  {spec.signature:<46} {', '.join(worlds) or 'no world'}: {spec.summary}")
    if problem is not None:
        print(
            f"{args.problem}: ok, problem {problem.name}: {len(problem.objects)} objects, "
            f"{len(problem.virtual_objects)} virtual objects, {len(problem.init)} facts"
        )
    return 0


def cmd_plan(args) -> int:
    from tidyplan.planning import translator
    from tidyplan.planning.planner import (
        DEFAULT_ENGINE,
        DEFAULT_FIRST_PLAN_LIMIT,
        DEFAULT_TIME_BUDGET,
        ENGINES,
        Status,
        plan,
    )

    started = time.perf_counter()  # the first-plan limit counts the reading too
    if (args.planner or DEFAULT_ENGINE) in ENGINES:
        translator.warm()  # Fast Downward's translator starts up on the other core while we read
    limit = args.first_plan_limit or DEFAULT_FIRST_PLAN_LIMIT
    try:
        with _alarm(limit):
            domain, problem = _read(args.domain, args.problem)
    except _Late:
        message = f"no plan found within {limit:g} s, nothing proven (the files were still being read)"
        if args.json:
            print(json.dumps({"status": Status.TIMEOUT.value, "plan": [], "message": message}))
        else:
            print(f"tidyplan: {message}", file=sys.stderr)
        return 3
    result = plan(
        domain,
        problem,
        planner=args.planner or DEFAULT_ENGINE,
        time_budget=args.time_budget or DEFAULT_TIME_BUDGET,
        max_stratum=args.max_stratum,
        strata=not args.no_strata,
        first_plan_limit=limit,
        started=started,
    )
    if args.json:
        print(json.dumps(result.to_json()))
    else:
        _print_plan(result)
    if result.status is Status.SOLVED:
        return 0
    if not args.json:
        print(f"tidyplan: {result.message}", file=sys.stderr)
    return {Status.TIMEOUT: 3, Status.ERROR: 4}.get(result.status, 1)


class _Late(Exception):
    """The first-plan limit ran out while this process itself was busy (reading a file)."""


@contextlib.contextmanager
def _alarm(seconds: float):
    """Raise _Late in this (the main) thread after `seconds`: our reader cannot be stopped from
    outside, and a file may be large enough to take the whole limit."""

    def late(signum, frame):
        raise _Late

    previous = signal.signal(signal.SIGALRM, late)
    signal.setitimer(signal.ITIMER_REAL, max(seconds, 1e-3))
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)


def _print_plan(result) -> None:
    for i, step in enumerate(result.steps, 1):
        mark = "assume" if step.assumption else "      "
        print(f"{i:3d} {mark} P{step.stratum} {step}  cost {step.cost:g}  p {step.probability:g}")
    if result.score is not None:
        s = result.score
        print(
            f"cost {s.cost:g}, success probability {s.probability:.4g}, "
            f"criterion c + R(1 - p) = {s.criterion:.4g} (R = {s.reward:g})"
        )
        print(
            f"stratum P{result.stratum}; operators from {', '.join(f'P{k}' for k in result.strata) or 'none'}"
        )
    tried = ", ".join(f"P{a.stratum} {a.outcome.value} {a.seconds:.2f}s" for a in result.attempts)
    print(f"planning time {result.planning_time_s:.2f}s ({result.engine}; {tried})")


def cmd_compile(args) -> int:
    from tidyplan.pddl.compile import compile_task
    from tidyplan.pddl.writer import domain_text, problem_text

    domain, problem = _read(args.domain, args.problem)
    task = compile_task(domain, problem)
    if args.max_stratum is not None:
        task = task.restrict(args.max_stratum)
    out = Path(args.out)
    targets = {
        out / "domain.pddl": domain_text(task.domain),
        out / "problem.pddl": problem_text(task.problem),
    }
    _refuse_overwrite(targets, [args.domain, args.problem], args.force)
    header = _compiled_header(task)
    try:
        out.mkdir(parents=True, exist_ok=True)
        for path, text in targets.items():
            _write_atomically(path, header + text)
    except OSError as e:
        raise InputError(Diagnostic(str(args.out), None, None, f"cannot write there: {e.strerror}")) from None
    written = " and ".join(str(p) for p in targets)
    print(f"wrote {written} (cost scale {task.scale}, R = {task.reward:g})")
    return 0


def _write_atomically(path: Path, text: str) -> None:
    """Write beside the target under a fresh name, then rename: a reader never
    sees half a file, and no file of the user's is touched but the target."""
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "w") as f:
            f.write(text)
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise


def _compiled_header(task) -> str:
    lines = [
        COMPILED_HEADER,
        f"; cost(a) = round({task.scale} * (c(a) + {task.reward:g} * -ln p(a)))",
    ]
    for name, info in sorted(task.info.items()):
        if name not in {a.name for a in task.domain.actions}:
            continue
        kind = "assumption" if info.is_assumption else "action"
        renamed = f" (was {info.name})" if info.name != name else ""
        lines.append(f"; {kind} {name}{renamed}: stratum {info.stratum}")
    return "\n".join(lines) + "\n"


def _refuse_overwrite(targets: dict[Path, str], inputs: list[str], force: bool) -> None:
    """Never overwrite an input, nor a file tidyplan did not write (unless --force)."""
    input_paths = {Path(p).resolve() for p in inputs}
    for path in targets:
        if path.resolve() in input_paths:
            raise InputError(Diagnostic(str(path), None, None, "is an input file; choose another --out"))
        if path.exists() and not force:
            with open(path, errors="replace") as f:
                first = f.readline().rstrip("\n")
            if first != COMPILED_HEADER:
                raise InputError(
                    Diagnostic(
                        str(path),
                        None,
                        None,
                        "exists and was not written by tidyplan; --force replaces it",
                    )
                )


COMMANDS = {
    "check": cmd_check,
    "plan": cmd_plan,
    "compile": cmd_compile,
    "run": cli_run.cmd_run,
    "reproduce": cli_run.cmd_reproduce,
    "trace": cli_trace.cmd_trace,
    "sweep": cli_sweep.cmd_sweep,
    "lsp": cli_editor.cmd_lsp,
    "serve": cli_editor.cmd_serve,
}


class Terminated(BaseException):
    """SIGTERM or SIGHUP: stop like Ctrl-C, so that clean-up code runs.

    Python's default for these signals is to die at once, skipping `finally`;
    the planning engine runs in a session of its own and would be orphaned.
    """

    def __init__(self, signum: int) -> None:
        super().__init__(signum)
        self.signum = signum


def _raise_terminated(signum, _frame) -> None:
    raise Terminated(signum)


def main(argv: list[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    previous = {s: signal.signal(s, _raise_terminated) for s in (signal.SIGTERM, signal.SIGHUP)}
    try:
        return COMMANDS[args.command](args)
    except InputError as e:
        for d in e.diagnostics:
            print(d, file=sys.stderr)
        return 2
    except PlannerError as e:
        print(f"tidyplan: {e}", file=sys.stderr)
        return 2
    except InternalError as e:
        print(f"tidyplan: {e}", file=sys.stderr)
        return 4
    except TidyplanError as e:
        print(f"tidyplan: {e}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print("tidyplan: interrupted", file=sys.stderr)
        return 130
    except Terminated as e:
        print(f"tidyplan: stopped by {signal.Signals(e.signum).name}", file=sys.stderr)
        return 128 + e.signum
    except BrokenPipeError:
        return 0
    except Exception as e:  # noqa: BLE001 - a bug of ours: one line, never a traceback
        if os.environ.get("TIDYPLAN_TRACEBACK"):
            raise
        what = f"{type(e).__name__}: {e}".splitlines()[0][:300]
        print(f"tidyplan: internal error: {what} (TIDYPLAN_TRACEBACK=1 shows where)", file=sys.stderr)
        return 4
    finally:
        for s, handler in previous.items():
            signal.signal(s, handler)


if __name__ == "__main__":
    sys.exit(main())
