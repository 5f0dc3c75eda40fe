"""The trace of a run: one JSON event a line (``writer``), read back (``read``), a replan's diff
(``diff``), the map and timeline plot (``plot``), the self-contained HTML replay (``html`` and its
page in ``replay/``) and the WRS Tidy Up score tallied over the events (``score``).

Layer 6. Imports: tidyplan.errors, tidyplan.pddl, tidyplan.exec, sim.
"""
