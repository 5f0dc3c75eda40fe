"""The command line: ``main`` parses and dispatches (check, plan, compile), ``run`` (run and
reproduce), ``trace`` and ``sweep`` their commands. It alone turns errors into exit statuses.

Layer 10, the top. Imports: anything below.
"""
