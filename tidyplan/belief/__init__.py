"""What the robot knows of the room (Goebelbecker's belief state): the map of waypoints, paths
and what blocks them (``geometry`` works them out, each item's grasp pose chosen by ``grasp``
over the cells of its ``ring``, a plan's waypoints picked out by ``focus``; ``mapfacts`` holds
them: the placed items, the facts, the waypoints' names), the belief itself (``state``: items
seen, their places, since when, one item's record in ``known``; virtual objects; where unseen
items may be and each viewpoint's chance of revealing one; where to look again for an item it
forgot, ``revisit``), the viewpoints generated where the scenario's do not cover the room
(``viewpoints``), the words the problems are written in
(``vocabulary``) and the belief written as a PDDL problem (``problem``). Never the true items:
only a world's referee knows those.

Layer 3. Imports: tidyplan.errors, tidyplan.pddl, tidyplan.planning, sim.
"""
