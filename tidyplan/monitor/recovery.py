"""Layered failure recovery and the error-handling layer (Yamazaki et al., Section VII-C, Fig. 7).

The runner executes an action's units in order, each as check -> plan -> do, and answers a
failure by its class:

- (A), found at check or plan (or while approaching): check again in the same unit; if that does
  not give an adequate result, run an earlier unit of the action again (``Unit.earlier``);
- (B), found after ``do``: go back from do to check in the same unit; if that fails too, an
  earlier unit, as for (A);
- (C): insert the units the failure calls for (pick the dropped object up), run them, then return
  to the unit that was running, from its check.

The error-handling layer counts the iterations of each recovery (per failing unit, until that
unit succeeds) and, past ``max_iterations``, stops it: the action ends "recovery exhausted" and
the continual planner reworks the task from the belief (replan cause (iv)).

Layers, as the trace names them: ``same_unit`` (A: check again; B: do -> check), ``earlier_unit``,
``insert_unit`` (C), ``error_layer`` (the cap reached: hand over to the planner).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from tidyplan.monitor.unit import Failure, FailureClass, StateMonitor, Unit

LAYERS = ("same_unit", "earlier_unit", "insert_unit", "error_layer")


@dataclass(frozen=True, slots=True)
class RecoveryConfig:
    max_iterations: int = 3  # recoveries of one failing unit before the planner takes over
    retries_in_unit: int = 1  # same-unit retries before an earlier unit is tried
    max_depth: int = 2  # inserted units may themselves insert, this deep


@dataclass(frozen=True, slots=True)
class RunResult:
    ok: bool
    failure: Failure | None = None
    unit: str | None = None  # the unit whose recovery was exhausted
    recoveries: int = 0
    where: Unit | None = None  # that unit itself, to learn from its failure

    @property
    def exhausted(self) -> bool:
        return not self.ok


Emit = Callable[..., None]  # emit(kind, **fields): the trace


class Runner:
    """Runs units with layered recovery; ``emit`` receives a ``unit`` event per function run and a
    ``recovery`` event per recovery step."""

    def __init__(self, config: RecoveryConfig | None = None, emit: Emit | None = None) -> None:
        self.config = config or RecoveryConfig()
        self.emit = emit or (lambda kind, **fields: None)
        self.recoveries = 0

    def run(self, units: list[Unit], depth: int = 0) -> RunResult:
        iterations = [0] * len(units)  # recoveries of the failure at unit i, since it last succeeded
        in_unit = [0] * len(units)
        i = 0
        while i < len(units):
            unit = units[i]
            failure = self._once(unit, iterations[i] + 1, depth)
            if failure is None:
                iterations[i] = in_unit[i] = 0
                i += 1
                continue
            iterations[i] += 1
            attempt = iterations[i]
            if attempt > self.config.max_iterations:
                self._recovery(unit, failure, "error_layer", attempt, depth, None)
                return RunResult(False, failure, unit.name, self.recoveries, unit)
            self.recoveries += 1
            if failure.klass is FailureClass.C:
                inserted = unit.insert_for(failure) if depth < self.config.max_depth else []
                if inserted:
                    self._recovery(unit, failure, "insert_unit", attempt, depth, [u.name for u in inserted])
                    sub = self.run(inserted, depth + 1)
                    if not sub.ok:
                        return sub
                    continue  # back to the unit that was running, from its check
            if in_unit[i] < self.config.retries_in_unit:
                in_unit[i] += 1
                self._recovery(unit, failure, "same_unit", attempt, depth, [unit.name])
                continue
            j = _index(units, unit.earlier, before=i)
            if j is None:  # nothing earlier in this action: check again until the cap
                self._recovery(unit, failure, "same_unit", attempt, depth, [unit.name])
                continue
            units[j].again_differently()
            self._recovery(unit, failure, "earlier_unit", attempt, depth, [units[j].name])
            i = j
        return RunResult(True, recoveries=self.recoveries)

    def _once(self, unit: Unit, attempt: int, depth: int) -> Failure | None:
        """check -> plan -> do; the first failure ends the unit's run."""
        for phase in ("check", "plan", "do"):
            if phase == "do":
                monitor = StateMonitor()
                failure = unit.do(monitor)
            else:
                failure = getattr(unit, phase)()
            self.emit(
                "unit",
                unit=unit.name,
                unit_phase=unit.phase,
                step=phase,
                ok=failure is None,
                failure=failure.what if failure else None,
                failure_class=failure.klass.value if failure else None,
                interrupted=bool(failure and failure.interrupted),
                attempt=attempt,
                depth=depth,
            )
            if failure is not None:
                return failure
        return None

    def _recovery(self, unit: Unit, failure: Failure, layer: str, attempt: int, depth: int, then) -> None:
        self.emit(
            "recovery",
            unit=unit.name,
            failure=failure.what,
            failure_class=failure.klass.value,
            layer=layer,
            attempt=attempt,
            depth=depth,
            then=then,
        )


def _index(units: list[Unit], name: str | None, before: int) -> int | None:
    if name is None:
        return None
    for j in range(before - 1, -1, -1):
        if units[j].name == name:
            return j
    return None
