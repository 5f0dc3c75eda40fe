"""The library: ``tidyplan.run`` does what ``tidyplan run`` does and returns a typed summary.

    import tidyplan
    s = tidyplan.run("case3", world="symbolic", seed=1)
    s.success, s.delivered, s.replans

A scenario is a ``sim.scenario.model.Scenario``, a scenario file, or the name of one the package ships
(``case1``, ``case2``, ``case3``). A trace is written only when ``trace`` names a file (never
over an existing one). Bad input raises ``tidyplan.InputError`` with the message the command
line prints; a mission that fails is a summary with ``success`` False, not an exception.

Layer 9, under the command line. Imports: tidyplan.errors, tidyplan.pddl, tidyplan.exec,
tidyplan.worlds, tidyplan.loop, sim.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, fields
from pathlib import Path

from tidyplan.errors import InputError
from tidyplan.loop.options import DEFAULTS, OptionError, Settings, cli_spelling
from tidyplan.loop.scenarios import DEFAULT_SCENARIO, DOMAIN, load_scenario
from tidyplan.worlds.rates import Rates


@dataclass(frozen=True, slots=True)
class Summary:
    """What a mission did: the fields of ``tidyplan run --json`` (docs/trace.md, the ``summary``
    event), typed."""

    scenario: str
    strategy: str
    world: str
    seed: int
    success: bool  # every object tidied, as the world (the referee) counts them
    reason: str
    objects: int
    delivered: int
    lost_objects: int
    escaped: list[str]  # objects physics moved out of the room (a simulation fault)
    given_up: list[str]  # the items of the belief it gave up on (none reached them)
    untidied: list[str]  # the true objects the room holds outside a deposit of their category
    actions: int
    paper_actions: int  # actions as Yan et al. count them
    strata: dict[str, int]  # deliveries by stratum, P1 P2 P3
    strata_unproven: int
    replans: int
    replan_causes: dict[str, int]
    replans_avoided: int
    recoveries: int
    distance_m: float
    sim_time_s: float
    wall_time_s: float
    replan_time_s: dict[str, float]  # median, max
    trace: str | None  # the trace's path; None when none was written
    wrs_score: float  # the WRS Tidy Up score (tidyplan.trace.score) within time_limit_s
    time_limit_s: float  # simulated seconds the WRS referee allows

    @classmethod
    def from_dict(cls, d: dict) -> Summary:
        return cls(**{f.name: d[f.name] for f in fields(cls)})

    def as_dict(self) -> dict:
        return asdict(self)


def run(
    scenario=DEFAULT_SCENARIO,
    *,
    world: str = DEFAULTS.world,
    seed: int = DEFAULTS.seed,
    strategy: str = DEFAULTS.strategy,
    planner: str = DEFAULTS.planner,
    faults: str = "",
    time_budget: float = DEFAULTS.time_budget,
    patience: float = DEFAULTS.patience,
    first_plan_limit: float = DEFAULTS.first_plan_limit,
    min_probability: float = DEFAULTS.min_probability,
    max_recovery: int = DEFAULTS.max_recovery,
    time_limit: float | None = DEFAULTS.time_limit,
    after_limit: str = DEFAULTS.after_limit,
    domain: str | Path | None = None,
    trace: str | Path | None = None,
    gui: bool = DEFAULTS.gui,
    on_event=None,
    options: str = "keywords",
) -> Summary:
    """Run one mission and return its ``Summary``. The options are ``tidyplan run``'s, with the
    same defaults (``tidyplan.loop.options``); ``faults`` as ``--faults`` takes them
    ("grasp_drop=0.2,..."); ``on_event`` is called with each trace event as it happens.
    ``domain``: a domain file in the dialect (by default the shipped ``domains/tidy.pddl``), read
    and checked before the world starts: the dialect, each action bound to units the worlds
    offer, the words the problems are written in (``tidyplan check DOMAIN`` prints the same).
    ``options="cli"`` names the options in messages as the command line spells them
    (``--max-recovery``)."""
    from sim.scenario.model import Scenario
    from tidyplan.loop.mission import run as run_mission

    spell = cli_spelling if options == "cli" else str
    try:
        settings = Settings(
            strategy,
            seed,
            planner=planner,
            time_budget=time_budget,
            patience=patience,
            first_plan_limit=first_plan_limit,
            min_probability=min_probability,
            rates=Rates.parse(faults, spell("faults")),
            max_recovery=max_recovery,
            world=world,
            gui=gui,
            time_limit=time_limit,
            after_limit=after_limit,
        )
    except OptionError as err:
        raise err.spelled(spell) from None
    if not isinstance(scenario, Scenario):
        scenario = load_scenario(scenario)
    domain_file = Path(domain) if domain is not None else DOMAIN
    _check_domain(domain_file, scenario)
    if trace is not None and (Path(trace).exists() or Path(trace).with_suffix(".pddl").exists()):
        raise InputError(f"{trace}: exists; a trace is never overwritten (choose another {spell('trace')})")
    return Summary.from_dict(run_mission(scenario, trace, settings, domain_file, on_event=on_event))


def _check_domain(path: Path, scenario) -> None:
    """The domain read and checked as ``tidyplan check`` does, and for running: every action
    bound to catalogue units with arguments of their kind, the problem words declared as the
    writer fills them, the scenario's facts in the domain's predicates. An InputError with
    each problem as ``path:line:col: what``."""
    from tidyplan.exec.binding_check import check_bindings, check_facts
    from tidyplan.pddl.reader import read_domain

    model = read_domain(path)
    errors = [d for d in check_bindings(model, for_run=True) if not d.warning] + check_facts(model, scenario)
    if errors:
        raise InputError(errors)
