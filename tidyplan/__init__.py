"""tidyplan: continual task planning for a service robot that tidies a room.

``tidyplan.run(scenario, ...)`` runs a mission and returns a ``tidyplan.Summary``
(``tidyplan.library``); bad input raises ``tidyplan.InputError``.

The packages, from the bottom up; each imports only what its docstring's ``Imports:`` line
names, all of it below (tests/test_house.py holds it):

    errors     the one exception tree
    pddl       the dialect: reader, model, checks, compilation, writer, criterion
    planning   model to plan: engines, Fast Downward, grounding, strata, Algorithm 1
    belief     what the robot knows: the map, the belief state, the problem written from it
    monitor    Yamazaki's behaviour unit and layered recovery
    worlds     the contract, the registry, the symbolic world, the pybullet world's skills
    exec       the unit catalogue, the units, the bindings of actions to units
    trace      the events: writer, reader, diff, plot, HTML replay, WRS score
    loop       the continual loop, the options record, one mission
    sweep      campaigns of missions, a process each, locally or on Ray
    library    tidyplan.run
    cli        the command line

``sim`` beside it (the scenario format, the grid, the pybullet physics) imports nothing of
tidyplan.
"""

__version__ = "0.1.0"

__all__ = ["InputError", "Summary", "run"]


def __getattr__(name: str):
    # the library loads the planner stack: only when asked for, not for `tidyplan check`
    if name in ("run", "Summary"):
        from tidyplan import library

        return getattr(library, name)
    if name == "InputError":
        from tidyplan.errors import InputError

        return InputError
    raise AttributeError(f"module 'tidyplan' has no attribute {name!r}")
