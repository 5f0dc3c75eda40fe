"""The continual loop (Goebelbecker et al., Brenner and Nebel): plan, execute, monitor, replan.
The loop itself (``loop``), the goals it tries in turn (``goals``), the replanning triggers
(i)-(v) (``triggers``), the planner calls (``replanning``), looking around (``looking``), the
papers' counts (``counting``) and one mission assembled from a scenario (``mission``).

Layer 7. Imports: tidyplan.errors, tidyplan.pddl, tidyplan.planning, tidyplan.belief,
tidyplan.monitor, tidyplan.worlds, tidyplan.exec, tidyplan.trace, sim.
"""
