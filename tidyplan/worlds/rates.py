"""The faults a world injects, as rates (``--faults K=V,...``): the execution monitor recovers
from them. Plain values, read once here for the command line, the library and the sweep alike.
"""

from __future__ import annotations

from dataclasses import dataclass

from tidyplan.errors import InputError

# Faults the world injects, as rates; the execution monitor recovers from them.
FAULTS = {
    "grasp_fail": "a grasp closes on nothing (take_object; default 0.05)",
    "grasp_drop": "the item in the hand falls near the robot while it drives (per motion; default 0)",
    "place_fail": "a placement fails, the item stays in the hand (deliver_it, drop_object; default 0.02)",
    "path_blocked": "a transient obstacle stops a motion on its way (per motion; default 0)",
    "perception_miss": "a visible object is not detected (false negative)",
    "perception_false": "a look reports an object that is not there (false positive)",
    "handle_slip": "the handle slips out of the hand part-way through a pull (open_drawer; default 0.05)",
    "drawer_jam": "a drawer sticks part-way out until pushed back closed (per pull; default 0)",
}


@dataclass(frozen=True, slots=True)
class Rates:
    """Success rates of the manipulation actions and the camera's error rates.

    Defaults: the domain's probabilities (take 0.95, deliver 0.98, drop 0.98, a pull of a drawer's
    handle 0.95) and Goebelbecker's
    false negative 0.2 and false positive 0.05 (the scenario's [sensing] may set its own); no
    drops in transit and no transient obstacles unless asked for (``--faults``)."""

    take: float = 0.95
    deliver: float = 0.98
    drop: float = 0.98
    false_negative: float | None = None  # None: the scenario's
    false_positive: float | None = None
    grasp_drop: float = 0.0  # per carrying motion: the item falls near the robot
    path_blocked: float = 0.0  # per motion: a transient obstacle stops the robot on its way
    handle_slip: float = 0.05  # per pull: the handle slips out of the hand part-way (open_drawer 0.95)
    drawer_jam: float = 0.0  # per pull: the drawer sticks part-way until pushed back closed

    @classmethod
    def parse(cls, text: str, what: str = "faults") -> Rates:
        """The rates ``K=V,...`` names (``FAULTS``; the rest at their defaults). Bad text is an
        ``InputError`` whose message starts with ``what``: each caller names the option in its
        own words (``--faults`` on the command line, ``faults`` for ``tidyplan.run``)."""
        rates: dict[str, float] = {}
        for part in filter(None, (p.strip() for p in text.split(","))):
            key, sep, value = part.partition("=")
            if not sep:
                raise InputError(f"{what}: {part!r} is not NAME=RATE")
            if key not in FAULTS:
                raise InputError(f"{what}: unknown fault {key!r}; known: {', '.join(FAULTS)}")
            try:
                rate = float(value)
            except ValueError:
                raise InputError(f"{what}: {key}={value!r}: the rate is not a number") from None
            if not 0.0 <= rate <= 1.0:
                raise InputError(f"{what}: {key}={value}: the rate must be in [0, 1]")
            rates[key] = rate
        default = cls()
        return cls(
            take=1.0 - rates.get("grasp_fail", 1.0 - default.take),
            deliver=1.0 - rates.get("place_fail", 1.0 - default.deliver),
            drop=1.0 - rates.get("place_fail", 1.0 - default.drop),
            false_negative=rates.get("perception_miss"),
            false_positive=rates.get("perception_false"),
            grasp_drop=rates.get("grasp_drop", default.grasp_drop),
            path_blocked=rates.get("path_blocked", default.path_blocked),
            handle_slip=rates.get("handle_slip", default.handle_slip),
            drawer_jam=rates.get("drawer_jam", default.drawer_jam),
        )
