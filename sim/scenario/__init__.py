"""The scenario format: the room, furniture, deposits, items, viewpoints and prior of one mission
(``model``), read from TOML with every problem located (``read``, its typed getters in ``fields``,
the cross-checks in ``checks``) and written back (``write``).

Imports: sim.grid.
"""
