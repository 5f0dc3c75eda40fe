"""The execution monitor (Yamazaki et al.): the behaviour unit's check / plan / do with its
status and failure class (A, B, C) (``unit``), and the layered recovery that retries, inserts
a unit or goes back to an earlier one and caps its iterations (``recovery``).

Layer 3. Imports: none (it runs the units it is given).
"""
