"""Campaigns: one mission's configuration, the key of its row (``config``), the grid of missions
and its resumable table (``grid``), each mission in a process of its own on a local pool or on
Ray (``missions``), and the summary by condition (``report``).

Layer 8. Imports: tidyplan.errors, tidyplan.planning, tidyplan.worlds, tidyplan.loop,
tidyplan.trace, sim.
"""
