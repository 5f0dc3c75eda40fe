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
