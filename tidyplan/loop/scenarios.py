"""What the package ships (``domains/``, ``problems/``) and the one way every caller finds a
scenario: a file, or the name of a shipped one (``case1``, ``wrs-drawer``) where no file of that
name is here. ``tidyplan.run``, ``tidyplan run``, ``tidyplan sweep`` and ``tidyplan trace
--scenario`` all look a scenario up here, so they find the same one.
"""

from __future__ import annotations

from importlib.resources import files
from pathlib import Path

from tidyplan.errors import Diagnostic, InputError


def project_file(relative: str) -> Path:
    """A file the project ships (``domains/NAME``, ``problems/NAME``): from the package, which
    carries both folders as ``tidyplan.domains`` and ``tidyplan.problems`` (pyproject.toml), or
    from beside the package where a clone runs without being installed."""
    folder, _, name = relative.partition("/")
    try:
        shipped = Path(str(files(f"tidyplan.{folder}") / name))
    except ModuleNotFoundError:
        shipped = None
    if shipped is not None and shipped.exists():
        return shipped
    return Path(__file__).resolve().parents[2] / relative


DOMAIN = project_file("domains/tidy.pddl")  # the O-FSM tidy-up domain
DEFAULT_SCENARIO = "case3"  # the O-FSM paper's case III


def scenario_path(text: str | Path) -> Path:
    """A scenario file, or the shipped ``problems/<name>.toml`` where no file of that name is here."""
    path = Path(text)
    if not path.exists() and "/" not in str(text):
        shipped = project_file(f"problems/{str(text).removesuffix('.toml')}.toml")
        path = shipped if shipped.exists() else path
    return path


def load_scenario(text: str | Path):
    """The scenario ``text`` names (``scenario_path``), read and checked: a ``sim.scenario.model.
    Scenario``, or an ``InputError`` with each of the file's problems."""
    from sim.scenario.model import ScenarioError
    from sim.scenario.read import load

    try:
        return load(scenario_path(text))
    except ScenarioError as e:
        raise InputError([Diagnostic(m, None, None, "") for m in e.messages]) from None
