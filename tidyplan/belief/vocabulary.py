"""The words the worlds' problems are written in: the predicates and functions the problem
writer (``tidyplan.belief.problem``) fills from the belief and the map, with the types of their
arguments. A domain that declares one must declare it so (``tidyplan.exec.binding_check``); any
other predicate a domain declares comes from the scenario's facts or is false. Plain data, so
that checking a domain needs nothing of the map or the belief.
"""

from __future__ import annotations

COST = "total-cost"
GOAL = "tidied"  # the worlds' goal: (tidied ?o) for every item to tidy

# The words the writer fills from the belief and the map, with the types of their arguments:
# a domain that declares one must declare it so (``tidyplan.exec.binding_check``). Any other
# predicate a domain declares comes from the scenario's facts or is false.
VOCABULARY_TYPES = ("waypoint", "item", "deposit", "category")
VOCABULARY: dict[str, tuple[str, ...]] = {
    "robot-at": ("waypoint",),
    "hand-empty": (),
    "holding": ("item",),
    "item-at": ("item", "waypoint"),
    "located": ("item",),
    "of-category": ("item", "category"),
    "deposit-at": ("deposit", "waypoint"),
    "accepts": ("deposit", "category"),
    "closed": ("deposit",),  # a drawer not open (the WRS drawer)
    "pull-blocked": ("deposit",),  # a floor item lies where the base backs off to pull it open
    "blocks-pull": ("item", "deposit"),
    "removal-waypoint": ("item", "waypoint"),
    "unexplored": ("waypoint",),
    "path": ("waypoint", "waypoint"),
    "blocked": ("waypoint", "waypoint"),
    "blocks": ("item", "waypoint", "waypoint"),
    "pose-adjustment": ("waypoint", "waypoint"),
    GOAL: ("item",),
}
VOCABULARY_FUNCTIONS: dict[str, tuple[str, ...]] = {
    "distance": ("waypoint", "waypoint"),  # metres along the path
    "travel-time": ("waypoint", "waypoint"),  # seconds along it at the robot's speed
    "p-item-near": ("waypoint",),
    COST: (),
}
