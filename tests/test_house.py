"""The house's rules, held by the code itself: each package's docstring says what it may import
(its ``Imports:`` line), every import keeps to it, nothing imports in a circle, ``sim`` imports
nothing of tidyplan, and ``tidyplan check`` loads neither a world nor the numeric stack.
"""

from __future__ import annotations

import ast
import re
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parent.parent
PACKAGES = ("tidyplan", "sim")


def _modules() -> dict[str, Path]:
    out = {}
    for top in PACKAGES:
        for path in (REPO / top).rglob("*.py"):
            parts = path.relative_to(REPO).with_suffix("").parts
            out[".".join(p for p in parts if p != "__init__")] = path
    return out


MODULES = _modules()


def _imports(path: Path) -> set[str]:
    """Every module of ours that ``path`` imports, at its top or inside a function."""
    found = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            for alias in node.names:
                full = f"{node.module}.{alias.name}"
                found.add(full if full in MODULES else node.module)
        elif isinstance(node, ast.Import):
            found.update(a.name for a in node.names)
    return {m for m in found if m.split(".")[0] in PACKAGES and m in MODULES}


def _unit(module: str) -> str:
    """The unit a module belongs to for the layer rules: its package below the top, or the
    top-level module itself (``tidyplan.errors``, ``tidyplan.library``)."""
    parts = module.split(".")
    if parts[0] == "sim":
        # the bottom of sim: the footprint (box), the grid over it (and the lengths a changed
        # grid keeps, carried), the scenario format over both
        if parts[1:2] in (["scenario"], ["grid"], ["box"], ["carried"]):
            return f"sim.{parts[1]}"
        return "sim"
    if len(parts) == 1:
        return "tidyplan"
    return ".".join(parts[:2])


def _declared(unit: str) -> set[str] | None:
    """The units a unit's docstring allows (``Imports: a, b.``); None where it states none."""
    path = MODULES[unit]
    doc = ast.get_docstring(ast.parse(path.read_text())) or ""
    match = re.search(r"Imports:\s*(.*?)(?:\.\s*$|\.\s*\n|\Z)", doc, re.S)
    if match is None:
        return None
    text = match.group(1)
    if text.strip().startswith("anything below"):
        return {"*"}
    return set(re.findall(r"\b(?:tidyplan|sim)(?:\.\w+)?\b", text))


UNITS = sorted({_unit(m) for m in MODULES})


@pytest.mark.parametrize("unit", [u for u in UNITS if u != "tidyplan"])
def test_each_package_says_what_it_may_import(unit):
    assert _declared(unit) is not None, f"{MODULES[unit]}: its docstring has no 'Imports:' line"


@pytest.mark.parametrize("unit", [u for u in UNITS if u != "tidyplan"])
def test_every_import_keeps_to_what_its_package_declares(unit):
    allowed = _declared(unit) or set()
    if "*" in allowed:
        return
    wrong = []
    for module, path in MODULES.items():
        if _unit(module) != unit:
            continue
        for target in sorted(_imports(path)):
            t = _unit(target)
            if t != unit and t not in allowed and not any(t.startswith(a + ".") for a in allowed):
                wrong.append(f"{path.relative_to(REPO)} imports {target} ({t} is not in its Imports)")
    assert not wrong, "\n".join(wrong)


def test_the_declared_layers_have_no_circle():
    import networkx as nx

    graph = nx.DiGraph()
    for unit in UNITS:
        for to in _declared(unit) or set():
            if to not in ("*", unit):
                graph.add_edge(unit, _unit(to) if to in MODULES else to)
    assert list(nx.simple_cycles(graph)) == []


def test_no_module_imports_in_a_circle():
    import networkx as nx

    graph = nx.DiGraph((m, t) for m, p in MODULES.items() for t in _imports(p) if t != m)
    cycles = [c for c in nx.simple_cycles(graph) if not all(m == "tidyplan" for m in c)]
    assert cycles == [], cycles[:5]


def test_sim_imports_nothing_of_tidyplan():
    for module, path in MODULES.items():
        if module.split(".")[0] == "sim":
            assert not [t for t in _imports(path) if t.startswith("tidyplan")], path


def test_checking_a_domain_loads_no_world_and_no_numeric_stack(tmp_path):
    domain = REPO / "domains" / "tidy.pddl"
    script = (
        "import sys\n"
        "from tidyplan.cli.main import main\n"
        f"assert main(['check', {str(domain)!r}]) == 0\n"
        "print(' '.join(sorted(sys.modules)))\n"
    )
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    loaded = set(done.stdout.split())
    for heavy in ("scipy", "networkx", "pybullet", "numpy", "matplotlib"):
        assert heavy not in loaded, f"tidyplan check loaded {heavy}"
    worlds = {m for m in loaded if m.startswith(("tidyplan.worlds.", "sim"))} - {
        "tidyplan.worlds.registry",
        "tidyplan.worlds.rates",
    }
    assert worlds == set(), f"tidyplan check loaded the worlds: {sorted(worlds)}"


def test_every_package_ships():
    """pyproject.toml lists the packages by name: a new one left out would be missing from an
    installed tidyplan, though the tests, run from the clone, would still find it."""
    import tomllib

    listed = set(tomllib.loads((REPO / "pyproject.toml").read_text())["tool"]["setuptools"]["packages"])
    found = {m for m, path in MODULES.items() if path.name == "__init__.py"}
    assert found - listed == set()


def test_planning_loads_no_world_no_trace_reader_and_no_terminal_styling(tmp_path):
    """`tidyplan plan` on a small task: its whole call is mostly the interpreter and its imports
    (docs/planner.md, against Fast Downward's driver), so it imports what planning needs only."""
    script = (
        "import sys\n"
        "from tidyplan.cli.main import main\n"
        f"assert main(['plan', {str(REPO / 'domains' / 'tidy.pddl')!r}, "
        f"{str(REPO / 'problems' / 'tidy-p1.pddl')!r}, '--json']) == 0\n"
        "print(' '.join(sorted(sys.modules)), file=sys.stderr)\n"
    )
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    loaded = set(done.stderr.split())
    for heavy in ("rich", "numpy", "scipy", "networkx", "pybullet", "matplotlib", "tidyplan.trace.read"):
        assert heavy not in loaded, f"tidyplan plan loaded {heavy}"
    assert not {m for m in loaded if m.startswith(("tidyplan.belief", "sim."))}
