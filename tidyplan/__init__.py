"""tidyplan: continual task planning for a service robot that tidies a room.

``tidyplan.run(scenario, ...)`` runs a mission and returns a ``tidyplan.Summary``
(``tidyplan.library``); bad input raises ``tidyplan.InputError``.
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
