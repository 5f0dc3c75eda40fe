"""Everything that turns a model into a plan: engines by name, Fast Downward run directly
(``fastdownward``), the loop's grounder straight into SAS (``grounding``, ``sas``, ``fragment``),
the O-FSM strata (``strata``, Table I), Algorithm 1 (``removal``), a domain's moves and their
metric (``moves``, ``move_metric``), the exact criterion optimum for measurements (``exact``)
and the plan's commitment to what it assumes (``commitment``); ``planner.plan`` puts them together.

Layer 2. Imports: tidyplan.errors, tidyplan.pddl.
"""
