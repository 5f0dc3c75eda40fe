"""One exception tree for the whole program.

Library code raises; only the command line turns an error into a message and
exit status 2. Every error about a file carries where it happened.

Layer 0. Imports: none.
"""

from __future__ import annotations

from dataclasses import dataclass


class TidyplanError(Exception):
    """Root of every error tidyplan raises on purpose."""


@dataclass(frozen=True, slots=True)
class Diagnostic:
    """One problem in one file: `path:line:col: message` when printed."""

    path: str
    line: int | None
    col: int | None
    message: str
    warning: bool = False

    def __str__(self) -> str:
        text = f"warning: {self.message}" if self.warning else self.message
        if not text:  # a message that carries its own place, e.g. "--faults: ..."
            return self.path
        if self.line is None:
            return f"{self.path}: {text}"
        return f"{self.path}:{self.line}:{self.col}: {text}"


class InputError(TidyplanError):
    """Bad input from the user: a file, a scenario, an option. Exit status 2."""

    def __init__(self, diagnostics: list[Diagnostic] | Diagnostic | str) -> None:
        if isinstance(diagnostics, str):
            diagnostics = [Diagnostic(diagnostics, None, None, "")]
        elif isinstance(diagnostics, Diagnostic):
            diagnostics = [diagnostics]
        self.diagnostics: list[Diagnostic] = diagnostics
        super().__init__("\n".join(str(d) for d in diagnostics))


class PddlError(InputError):
    """A PDDL file that cannot be read or does not make sense."""


class PlannerError(TidyplanError):
    """A planning engine that cannot be found, or that failed unexpectedly."""


class InternalError(TidyplanError):
    """A fault of tidyplan's own (a bug), not of the input: exit status 4. ``trace`` is the run's
    trace, kept and readable up to its last whole event; ``details`` where the traceback went."""

    def __init__(self, what: str, trace: str | None = None, details: str | None = None) -> None:
        self.what, self.trace, self.details = what, trace, details
        parts = [f"internal error: {what}"]
        if trace:
            parts.append(f"the trace so far is {trace}")
        if details:
            parts.append(f"the traceback is in {details}; please report it")
        super().__init__("; ".join(parts))
