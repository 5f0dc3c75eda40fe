"""Execution: the catalogue of behaviour units by name (``catalogue``), the units themselves
(``units``, ``drawer_units``, ``put_down``), what a unit sees of the mission (``context``),
each action's units built from its ``:units`` declaration (``bindings``) and the check of a
domain's bindings against the catalogue before a mission starts (``binding_check``).

Layer 5. Imports: tidyplan.errors, tidyplan.pddl, tidyplan.planning, tidyplan.belief,
tidyplan.monitor, tidyplan.worlds, sim.
"""
