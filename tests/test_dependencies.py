"""Every package that tidyplan/ and sim/ import is a declared dependency of pyproject.toml (or of one of
its extras): a package that only arrives through another's dependencies can change or vanish with
that one's next release. The versions allowed are tried by .ci/bounds."""

from __future__ import annotations

import ast
import importlib.metadata
import re
import sys
import tomllib
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent


def _normal(name: str) -> str:
    return re.sub(r"[-_.]+", "-", name).lower()


def _declared() -> set[str]:
    project = tomllib.loads((REPO / "pyproject.toml").read_text())["project"]
    specs = [
        *project["dependencies"],
        *(s for extra in project["optional-dependencies"].values() for s in extra),
    ]
    return {_normal(re.split(r"[\s<>=~!;\[]", s, maxsplit=1)[0]) for s in specs}


def _imports() -> dict[str, str]:
    """Top-level module imported -> where it is first imported (path:line)."""
    found: dict[str, str] = {}
    for top in ("tidyplan", "sim"):
        for path in sorted((REPO / top).rglob("*.py")):
            for node in ast.walk(ast.parse(path.read_text(), str(path))):
                if isinstance(node, ast.Import):
                    names = [alias.name for alias in node.names]
                elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
                    names = [node.module]
                else:
                    continue
                for name in names:
                    found.setdefault(name.split(".")[0], f"{path.relative_to(REPO)}:{node.lineno}")
    return {
        m: w for m, w in found.items() if m not in sys.stdlib_module_names and m not in ("tidyplan", "sim")
    }


def test_every_imported_package_is_declared():
    distributions = importlib.metadata.packages_distributions()
    declared = _declared()
    undeclared = []
    for module, where in sorted(_imports().items()):
        # an extra's package not installed here is looked for under its own name
        names = {_normal(d) for d in distributions.get(module, [module])}
        if not names & declared:
            undeclared.append(f"{where}: {module} (from {', '.join(sorted(names))})")
    assert not undeclared, "imported but not declared in pyproject.toml: " + "; ".join(undeclared)


def test_the_translator_is_its_own_distribution_with_a_compatible_release_bound():
    # tidyplan/planning/fastdownward.py imports fast_downward.translate's internals: the bound keeps
    # to the releases tried (.ci/bounds runs the lowest and the newest)
    assert importlib.metadata.packages_distributions()["fast_downward"] == ["fast-downward.translate"]
    deps = tomllib.loads((REPO / "pyproject.toml").read_text())["project"]["dependencies"]
    for name in ("fast-downward.translate", "up-fast-downward", "unified-planning"):
        (spec,) = [d for d in deps if d.startswith(name)]
        assert "~=" in spec, spec
