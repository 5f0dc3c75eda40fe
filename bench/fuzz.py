"""Real inputs mutated at random, through the command line in this process: does bad input always
get a located message and exit 2, never a traceback or a hang?

    nice -n 10 python bench/fuzz.py [--cases 10000] [--seed 0] [--alarm 10] [--out DIR] [--corpus DIR]

The inputs are real: the IPC corpus's domains and problems (``TIDYPLAN_PDDL_CORPUS``, default
../shared/pddl-corpus beside the clone), the project's ``domains/`` and ``problems/`` (PDDL and
scenario files) and a trace made here by a short symbolic mission. Each case takes one of them,
applies one to three mutations (tokens deleted, duplicated, swapped; lines deleted, duplicated,
swapped; the file cut; bytes that are not UTF-8; 100,000 open brackets; brackets nested 1,000
or 100,000 deep and closed; a number replaced by an odd one; for traces also a JSON line
corrupted and bytes dropped) and runs it through ``tidyplan.cli.main.main``: ``check`` for
PDDL, ``run --world symbolic`` with a 1 s simulated limit for scenarios, ``trace`` and ``trace
--html`` for traces. A per-case alarm (``--alarm`` seconds) stands for a hang. It prints cases
per input kind, exit statuses, tracebacks, hangs and errors without a location, and saves the
first offending inputs under ``--out``.

tests/test_fuzz.py drives the same generators (``mutate``, ``run_case``, ``faults``) through
hypothesis; here a seeded ``random.Random`` drives them, without shrinking, for many more cases.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import os
import random
import re
import signal
import sys
import tempfile
import time
import traceback
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
CORPUS_ENV = "TIDYPLAN_PDDL_CORPUS"

# Numbers that readers trip over: out of float range, below it, not numbers, too many digits for
# int() (Python's 4,300-digit limit), signs and forms some parsers take and others refuse.
ODD_NUMBERS = [
    b"0",
    b"-0",
    b"-1",
    b"-0.0",
    b"1e309",
    b"-1e309",
    b"1e-400",
    b"nan",
    b"NaN",
    b"inf",
    b"-inf",
    b"Infinity",
    b"1.",
    b".5",
    b"0x1F",
    b"1_000",
    b"00007",
    b"1e999999999",
    b"9" * 5000,
    b"-9223372036854775809",
    b"18446744073709551616",
    b"0.1e",
    b"3.4028236e38",
]
NOT_UTF8 = [
    b"\xff",
    b"\xfe\xff",
    b"\xc3",
    b"\x80",
    b"\xed\xa0\x80",
    b"\xf8\x88\x80\x80\x80",
    b"\xc0\xaf",
    b"\x00",
]
DEEP = 100_000  # open brackets in a row
TOKEN = re.compile(rb'\s+|[()\[\]{}=,:"]|[^\s()\[\]{}=,:"]+')
NUMBER = re.compile(rb"(?<![\w.-])-?\d+(?:\.\d+)?(?:[eE][-+]?\d+)?(?![\w.])")


# ------------------------------------------------------------------ the inputs
@dataclass(frozen=True)
class Seed:
    """One real input: its kind (``domain``, ``problem``, ``scenario``, ``trace``, ``html``), the
    file that is mutated, and for a problem the domain it is checked with."""

    kind: str
    path: Path
    domain: Path | None = None

    @property
    def name(self) -> str:
        return f"{self.path.parent.name}/{self.path.name}"


def corpus_root() -> Path:
    """Where the corpus is: the environment variable, else next to the repository (as the tests)."""
    configured = os.environ.get(CORPUS_ENV)
    return Path(configured) if configured else ROOT.parent / "shared" / "pddl-corpus"


def corpus_seeds(root: Path) -> list[Seed]:
    """Each corpus folder's domain, and each of its problems with that domain."""
    seeds = []
    for folder in sorted(p for p in root.iterdir() if p.is_dir()):
        domain = folder / "domain.pddl"
        seeds.append(Seed("domain", domain))
        seeds += [Seed("problem", p, domain) for p in sorted(folder.glob("*.pddl")) if p != domain]
    return seeds


def project_seeds() -> list[Seed]:
    """The project's own domains, problems (each with the domain it names) and scenario files."""
    domains = sorted((ROOT / "domains").glob("*.pddl"))
    by_name = {_defined_name(d, "domain"): d for d in domains}
    seeds = [Seed("domain", d) for d in domains]
    for p in sorted((ROOT / "problems").glob("*.pddl")):
        seeds.append(Seed("problem", p, by_name[_defined_name(p, ":domain")]))
    seeds += [Seed("scenario", s) for s in sorted((ROOT / "problems").glob("*.toml"))]
    return seeds


def _defined_name(path: Path, keyword: str) -> str:
    found = re.search(rf"\({re.escape(keyword)}\s+([^\s()]+)", path.read_text(), re.IGNORECASE)
    assert found, f"{path}: no ({keyword} NAME)"
    return found.group(1).lower()


def make_trace(folder: Path) -> Path:
    """A short symbolic mission's trace (case I, faults, seed 1: replans and recoveries in it),
    with its PDDL folder beside it as a run leaves them."""
    import tidyplan

    trace = folder / "mission.jsonl"
    tidyplan.run(
        "case1",
        world="symbolic",
        seed=1,
        planner="lama-first",  # deterministic: the same trace on every machine
        faults="grasp_drop=0.2,perception_miss=0.2",
        time_limit=300,
        after_limit="stop",
        trace=trace,
    )
    return trace


# ------------------------------------------------------------------ the mutations
def _tokens(data: bytes) -> tuple[list[bytes], list[int]]:
    """The data's tokens (whitespace kept, so that joining them gives the data back) and the
    indices of those that are not whitespace."""
    tokens = TOKEN.findall(data)
    return tokens, [i for i, t in enumerate(tokens) if not t.isspace()]


def delete_tokens(data: bytes, rnd) -> bytes:
    tokens, solid = _tokens(data)
    if not solid:
        return data
    start = rnd.randrange(len(solid))
    for i in solid[start : start + rnd.choice([1, 1, 2, 5])]:
        tokens[i] = b""
    return b"".join(tokens)


def duplicate_tokens(data: bytes, rnd) -> bytes:
    tokens, solid = _tokens(data)
    if not solid:
        return data
    i = rnd.choice(solid)
    tokens[i] = tokens[i] + b" " + tokens[i]
    return b"".join(tokens)


def swap_tokens(data: bytes, rnd) -> bytes:
    tokens, solid = _tokens(data)
    if len(solid) < 2:
        return data
    i, j = rnd.choice(solid), rnd.choice(solid)
    tokens[i], tokens[j] = tokens[j], tokens[i]
    return b"".join(tokens)


def mutate_lines(data: bytes, rnd) -> bytes:
    lines = data.split(b"\n")
    i, j = rnd.randrange(len(lines)), rnd.randrange(len(lines))
    how = rnd.choice(["delete", "duplicate", "swap"])
    if how == "delete":
        del lines[i]
    elif how == "duplicate":
        lines.insert(i, lines[i])
    else:
        lines[i], lines[j] = lines[j], lines[i]
    return b"\n".join(lines)


def cut(data: bytes, rnd) -> bytes:
    return data[: rnd.randrange(len(data) + 1)]


def not_utf8(data: bytes, rnd) -> bytes:
    i = rnd.randrange(len(data) + 1)
    return data[:i] + rnd.choice(NOT_UTF8) + data[i:]


def deep(data: bytes, rnd, opener: bytes = b"(") -> bytes:
    """100,000 open brackets, at a random point or where a number was (a value's place)."""
    numbers = list(NUMBER.finditer(data))
    if numbers and rnd.random() < 0.5:
        m = rnd.choice(numbers)
        return data[: m.start()] + opener * DEEP + data[m.end() :]
    i = rnd.randrange(len(data) + 1)
    return data[:i] + opener * DEEP + data[i:]


NESTS = {"domain": b"(and ", "problem": b"(and ", "scenario": b"[", "trace": b"["}
CLOSES = {b"(and ": b")", b"[": b"]"}


def nest(data: bytes, rnd, opener: bytes = b"(and ") -> bytes:
    """Nesting that is well formed but deep (1,000 or 100,000 levels), where a formula or a value
    goes: inside an ``(and`` for PDDL, in a number's place for TOML and JSON."""
    depth = rnd.choice([1000, DEEP])
    deep_value = opener * depth + CLOSES[opener] * depth
    places = [m.end() for m in re.finditer(rb"\(and\b", data)] if opener == b"(and " else []
    if places:
        i = rnd.choice(places)
        return data[:i] + b" " + deep_value + data[i:]
    numbers = list(NUMBER.finditer(data))
    if numbers:
        m = rnd.choice(numbers)
        return data[: m.start()] + deep_value + data[m.end() :]
    i = rnd.randrange(len(data) + 1)
    return data[:i] + deep_value + data[i:]


def odd_number(data: bytes, rnd) -> bytes:
    numbers = list(NUMBER.finditer(data))
    if not numbers:
        return data
    m = rnd.choice(numbers)
    return data[: m.start()] + rnd.choice(ODD_NUMBERS) + data[m.end() :]


def drop_bytes(data: bytes, rnd) -> bytes:
    if not data:
        return data
    i = rnd.randrange(len(data))
    return data[:i] + data[i + rnd.choice([1, 1, 3, 40, 1000]) :]


ODD_VALUES = [None, "", "?", -1, 0, 1e308, -1e308, True, [], {}, [None], {"kind": 1}, "x" * 10_000]


def corrupt_json_line(data: bytes, rnd) -> bytes:
    """One JSON line made wrong: a field dropped, or given a value of another kind; else cut."""
    lines = data.split(b"\n")
    i = rnd.randrange(len(lines))
    try:
        event = json.loads(lines[i])
    except ValueError:
        event = None
    if isinstance(event, dict) and event and rnd.random() < 0.8:
        key = rnd.choice(sorted(event))
        if rnd.random() < 0.3:
            del event[key]
        else:
            event[key] = rnd.choice(ODD_VALUES)
        lines[i] = json.dumps(event).encode()
    else:
        lines[i] = lines[i][: rnd.randrange(len(lines[i]) + 1)]
    return b"\n".join(lines)


MUTATIONS = {
    "delete": delete_tokens,
    "duplicate": duplicate_tokens,
    "swap": swap_tokens,
    "lines": mutate_lines,
    "cut": cut,
    "not-utf8": not_utf8,
    "deep": deep,
    "nest": nest,
    "number": odd_number,
}
TRACE_MUTATIONS = MUTATIONS | {"json-line": corrupt_json_line, "drop-bytes": drop_bytes}
OPENERS = {"domain": [b"("], "problem": [b"("], "scenario": [b"[", b"{"], "trace": [b"[", b"{"]}


def mutations_for(kind: str) -> list[str]:
    return sorted(TRACE_MUTATIONS if kind in ("trace", "html") else MUTATIONS)


def mutate(kind: str, data: bytes, rnd, names: list[str] | None = None) -> tuple[list[str], bytes]:
    """``names`` (default: one to three chosen by ``rnd``) applied to ``data`` in turn, each
    mutation's places chosen by ``rnd`` (a ``random.Random``, or hypothesis' ``st.randoms()``):
    the names and the mutated bytes."""
    table = TRACE_MUTATIONS if kind in ("trace", "html") else MUTATIONS
    if names is None:
        names = [rnd.choice(sorted(table)) for _ in range(rnd.choice([1, 1, 1, 2, 3]))]
    for name in names:
        if name == "deep":
            data = deep(data, rnd, rnd.choice(OPENERS.get(kind, [b"["])))
        elif name == "nest":
            data = nest(data, rnd, NESTS.get(kind, b"["))
        else:
            data = table[name](data, rnd)
    return names, data


# ------------------------------------------------------------------ one case
@dataclass
class Outcome:
    """What one call of the command line did: its exit status (None: it raised, or the alarm
    rang), what it printed, the traceback if one escaped, and whether it hung."""

    argv: list[str]
    status: int | None
    out: str
    err: str
    traceback: str | None = None
    hung: bool = False
    files: list[Path] = field(default_factory=list)  # the inputs its messages may name


class Hang(BaseException):
    """The per-case alarm rang. A BaseException: the command line's own handlers let it through."""


def _ring(signum, frame):
    raise Hang


@contextlib.contextmanager
def _alarm(seconds: float | None):
    if not seconds:
        yield
        return
    previous = signal.signal(signal.SIGALRM, _ring)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)


@contextlib.contextmanager
def _tracebacks_escape():
    """TIDYPLAN_TRACEBACK=1: a bug of ours raises out of ``main`` instead of becoming exit 4."""
    before = os.environ.get("TIDYPLAN_TRACEBACK")
    os.environ["TIDYPLAN_TRACEBACK"] = "1"
    try:
        yield
    finally:
        if before is None:
            del os.environ["TIDYPLAN_TRACEBACK"]
        else:
            os.environ["TIDYPLAN_TRACEBACK"] = before


def argv_for(seed: Seed, path: Path, folder: Path) -> list[str]:
    """The command a mutated file goes through: never ``plan`` (a search may rightly be long)."""
    if seed.kind == "domain":
        return ["check", str(path)]
    if seed.kind == "problem":
        return ["check", str(seed.domain), str(path)]
    if seed.kind == "scenario":
        run = ["run", str(path), "--world", "symbolic", "--planner", "lama-first", "--quiet"]
        # a 1 s simulated limit: the mission stops after its first plan; the first plan's own limit
        # keeps a mutated room that is hard to plan for from taking long
        limits = ["--time-limit", "1", "--after-limit", "stop", "--first-plan-limit", "5"]
        return run + limits + ["--trace", str(folder / f"{path.stem}.run.jsonl")]
    if seed.kind == "trace":
        return ["trace", str(path)]
    return ["trace", str(path), "--html", str(folder / f"{path.stem}.html")]


def run_case(seed: Seed, data: bytes, folder: Path, name: str, alarm: float | None = None) -> Outcome:
    """Write ``data`` as ``folder/name`` (a trace beside its original, whose PDDL folder it names)
    and run its command in this process."""
    from tidyplan.cli.main import main

    path = (seed.path.parent if seed.kind in ("trace", "html") else folder) / name
    path.write_bytes(data)
    argv = argv_for(seed, path, folder)
    files = [path] + ([seed.domain] if seed.domain else [])
    out, err = io.StringIO(), io.StringIO()
    outcome = Outcome(argv, None, "", "", files=files)
    try:
        with _tracebacks_escape(), contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            with _alarm(alarm):
                outcome.status = main(argv)
    except Hang:
        outcome.hung = True
    except SystemExit as e:  # argparse's: our argv is fixed, so this would be a finding too
        outcome.status = e.code if isinstance(e.code, int) else 2
    except BaseException:  # noqa: BLE001 - what the command line let escape is the finding
        outcome.traceback = traceback.format_exc()
    outcome.out, outcome.err = out.getvalue(), err.getvalue()
    if outcome.status == 4 and outcome.traceback is None:  # `run` keeps the traceback beside its trace
        saved = sorted(folder.glob("*.traceback.txt"))
        outcome.traceback = saved[-1].read_text() if saved else outcome.err
    return outcome


# ------------------------------------------------------------------ the properties
STOPPED = {130, 128 + signal.SIGTERM, 128 + signal.SIGHUP}  # main's statuses for a signal
STATUSES = {"domain": {0, 2}, "problem": {0, 2}, "scenario": {0, 1, 2}, "trace": {0, 2}, "html": {0, 2}}
PLACE = re.compile(r"(?P<path>.+?):(?P<line>\d+):(?P<col>\d+): ")


def _lines_of(path: Path) -> list[bytes]:
    # bytes: a column is at most the line's length in bytes plus one, however it is counted
    return path.read_bytes().split(b"\n")


def unlocated(kind: str, err: str, files: list[Path]) -> list[str]:
    """The stderr lines that are not one located message about one of ``files``.

    PDDL: ``path:line:col: `` with the line in the file (1..its lines; the line after a last
    newline is where the file ends) and the column within that line or just past it (in bytes,
    which bounds a column counted in characters too). Scenarios
    and traces: ``path: `` (with a key path, or a line in words) or ``path:line:col: `` as for
    PDDL. A file's messages may name the output the command could not write, too."""
    names = {str(f): f for f in files}
    bad = []
    for text in err.splitlines():
        m = PLACE.match(text)
        if m and m.group("path") in names:
            lines = _lines_of(names[m.group("path")])
            line, col = int(m.group("line")), int(m.group("col"))
            if not (1 <= line <= len(lines) and 1 <= col <= len(lines[line - 1]) + 1):
                bad.append(f"outside the file ({len(lines)} lines): {text}")
            continue
        if kind in ("domain", "problem") or not any(text.startswith(f"{n}: ") for n in names):
            bad.append(text)
    return bad


def faults(seed: Seed, o: Outcome) -> list[tuple[str, str]]:
    """What is wrong with an outcome: (``traceback``|``hang``|``status``|``unlocated``|``repeated``,
    detail); empty when the command behaved."""
    if o.hung:
        return [("hang", " ".join(o.argv))]
    if o.traceback is not None:
        return [("traceback", o.traceback.strip().splitlines()[-1])]
    found = []
    if o.status not in STATUSES[seed.kind]:
        found.append(("status", f"exit {o.status}: {o.err.strip()[:300]}"))
    if o.status == 2 and not o.err.strip():
        found.append(("unlocated", "exit 2 with nothing on stderr"))
    if o.status == 2 or seed.kind in ("domain", "problem"):  # PDDL warnings are located too
        found += [("unlocated", line) for line in unlocated(seed.kind, o.err, o.files)]
    repeated = [line for line, n in Counter(o.err.splitlines()).items() if n > 1]
    found += [("repeated", line) for line in repeated]
    return found


# ------------------------------------------------------------------ the benchmark
# Each kind's share of the cases: a scenario's mission costs the most, a trace's page the next.
KIND_SHARE = {"domain": 0.25, "problem": 0.25, "scenario": 0.2, "trace": 0.15, "html": 0.15}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--cases", type=int, default=10_000)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--alarm", type=float, default=10.0, metavar="S", help="seconds before a case is a hang")
    ap.add_argument(
        "--out", type=Path, default=None, help="folder for offending inputs (default: a temp one)"
    )
    ap.add_argument("--keep", type=int, default=20, help="offending inputs saved, at most")
    ap.add_argument("--corpus", type=Path, default=None)
    ap.add_argument(
        "--kinds", default=",".join(KIND_SHARE), help="input kinds to draw from (comma-separated)"
    )
    args = ap.parse_args(argv)
    out = args.out or Path(tempfile.mkdtemp(prefix="tidyplan-fuzz-"))
    out.mkdir(parents=True, exist_ok=True)
    work = Path(tempfile.mkdtemp(prefix="tidyplan-fuzz-work-"))
    corpus = args.corpus or corpus_root()
    seeds = project_seeds() + (corpus_seeds(corpus) if corpus.is_dir() else [])
    if not corpus.is_dir():
        print(f"corpus not found at {corpus} (set {CORPUS_ENV}): the project's files only", file=sys.stderr)
    trace = make_trace(work)
    seeds += [Seed("trace", trace), Seed("html", trace)]
    originals = {s: s.path.read_bytes() for s in seeds}
    rnd = random.Random(args.seed)
    cases, statuses, found, seconds = Counter(), Counter(), Counter(), Counter()
    kept = 0
    share = {k: KIND_SHARE[k] for k in args.kinds.split(",")}
    by_kind = {k: [s for s in seeds if s.kind == k] for k in share}
    for n in range(args.cases):
        kind = rnd.choices(list(share), weights=list(share.values()))[0]
        seed = rnd.choice(by_kind[kind])
        names, data = mutate(seed.kind, originals[seed], rnd)
        folder = work / f"c{n}"
        folder.mkdir()
        began = time.perf_counter()
        o = run_case(seed, data, folder, f"c{n}{seed.path.suffix}", alarm=args.alarm)
        seconds[seed.kind] += time.perf_counter() - began
        if o.status in STOPPED:  # the command line turned our own Ctrl-C or SIGTERM into a status
            print(f"stopped at case {n} ({o.err.strip()})", file=sys.stderr)
            break
        cases[seed.kind] += 1
        statuses[seed.kind, "hang" if o.hung else "raised" if o.status is None else o.status] += 1
        wrong = faults(seed, o)
        for what, _ in wrong:
            found[seed.kind, what] += 1
        if wrong and kept < args.keep:
            kept += 1
            _save(out / f"case{n:05d}-{seed.kind}", seed, names, data, o, wrong)
        _clean(seed, folder, n)
        if (n + 1) % 500 == 0:
            print(f"{n + 1} cases, {sum(found.values())} findings", file=sys.stderr, flush=True)
    _table(cases, statuses, found, seconds, args, out, kept)
    return 1 if found else 0


def _save(where: Path, seed: Seed, names, data: bytes, o: Outcome, wrong) -> None:
    where.mkdir(parents=True, exist_ok=True)
    (where / f"input{seed.path.suffix}").write_bytes(data)
    about = {"seed": str(seed.path), "domain": str(seed.domain) if seed.domain else None}
    about |= {"mutations": names, "argv": o.argv, "status": o.status, "stderr": o.err, "faults": wrong}
    (where / "case.json").write_text(json.dumps(about, indent=1) + "\n")
    if o.traceback:
        (where / "traceback.txt").write_text(o.traceback)


def _clean(seed: Seed, folder: Path, n: int) -> None:
    import shutil

    shutil.rmtree(folder, ignore_errors=True)
    if seed.kind in ("trace", "html"):
        (seed.path.parent / f"c{n}{seed.path.suffix}").unlink(missing_ok=True)


def _table(
    cases: Counter, statuses: Counter, found: Counter, seconds: Counter, args, out: Path, kept: int
) -> None:
    kinds = sorted(cases)
    codes = sorted({c for _, c in statuses}, key=str)
    print(f"\n{sum(cases.values())} cases, seed {args.seed}, alarm {args.alarm:g} s")
    head = ["kind", "cases", *(f"exit {c}" for c in codes), "tracebacks", "hangs", "unlocated", "other", "s"]
    rows = []
    for k in kinds:
        other = sum(
            v for (kk, w), v in found.items() if kk == k and w not in ("traceback", "hang", "unlocated")
        )
        rows.append(
            [k, cases[k], *(statuses[k, c] for c in codes)]
            + [found[k, "traceback"], found[k, "hang"], found[k, "unlocated"], other, round(seconds[k])]
        )
    rows.append(["all", *(sum(r[i] for r in rows) for i in range(1, len(head)))])
    print("other: an exit status the command does not define, or a message said twice; s: seconds")
    widths = [max(len(str(x)) for x in col) for col in zip(head, *rows, strict=True)]
    for r in [head, *rows]:
        print("  ".join(str(x).rjust(w) for x, w in zip(r, widths, strict=True)))
    print(f"offending inputs saved: {kept} under {out}")


if __name__ == "__main__":
    sys.exit(main())
