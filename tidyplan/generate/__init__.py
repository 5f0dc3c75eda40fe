"""Seeded inputs for measurements and tests, drawn from the published facts: WRS tidy-up rooms
laid out by the competition's object spawner (``rooms``; ``python bench/wrs.py``) and tidy-up
PDDL tasks in the WRS room with their exact optimum, found apart from the planner (``tasks``;
``python bench/tidygen.py``).

Layer 8. Imports: tidyplan.loop, sim.
"""
