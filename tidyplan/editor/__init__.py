"""The dialect in an editor (docs/editor.md): a forgiving s-expression reader (``sexpr``), the
symbol index of a file (``index``), ``tidyplan check``'s diagnostics with ranges and several
syntax errors at once (``diagnose``), a domain read section by section (``sections``), the open
files and the answers to an editor's questions (``workspace``, ``hover``, ``outline``,
``complete``), the Language Server Protocol over stdio (``server``, pygls) and the HTTP planner
service of ``tidyplan serve`` (``service``, which plans through ``tidyplan plan`` in a child).

Layer 6, beside the loop. Imports: tidyplan.errors, tidyplan.pddl, tidyplan.exec.
"""
