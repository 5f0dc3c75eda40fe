"""The dialect: its grammar, the reader (text to a model that keeps file positions), the
model's frozen values, the checks, the compilation to plain PDDL with action costs, the writer,
and Goebelbecker's criterion c(pi) + R(1 - p(pi)) with its -ln p compilation (``criterion``).

Layer 1. Imports: tidyplan.errors.
"""
