"""Typed getters over a parsed TOML scenario, each problem said as ``path: key path: what``
and collected (``sim.scenario.read`` reads the document with them).

A getter returns None for a missing or malformed value after saying so, so later checks that
need the value skip instead of piling consequential messages on the first one.
"""

from __future__ import annotations

import dataclasses
from typing import Any

from sim.scenario.checks import REQUIRED, Check, fmt, is_number, key_path
from sim.scenario.model import NAME_RE


class FieldReader:
    """The messages of one file (``messages``) and the getters that add to them."""

    def __init__(self, path: str) -> None:
        self.path = path
        self.messages: list[str] = []

    def error(self, where: str, what: str) -> None:
        self.messages.append(f"{self.path}: {where}: {what}" if where else f"{self.path}: {what}")

    # ------------------------------------------------------------------ values
    def keys(self, table: dict[str, Any], where: str, known: tuple[str, ...]) -> None:
        for k in table:
            if k not in known:
                self.error(key_path(where, k), f"unknown key (known: {', '.join(sorted(known))})")

    def value(self, table: dict[str, Any], where: str, key: str, default: Any) -> tuple[bool, Any]:
        """(True, value) when the key is there; else (False, default), saying so when it is required."""
        if key in table:
            return True, table[key]
        if default is REQUIRED:
            self.error(key_path(where, key), "missing required key")
            return False, None
        return False, default

    def number(self, table: dict, where: str, key: str, default: Any = REQUIRED, check: Check | None = None):
        present, v = self.value(table, where, key, default)
        if not present:
            return v
        if not is_number(v):
            self.error(key_path(where, key), f"must be a finite number, got {v!r}")
            return None
        problem = check(v) if check else None
        if problem:
            self.error(key_path(where, key), f"{problem}, got {v:g}")
            return None
        return float(v)

    def vector(self, table: dict, where: str, key: str, shape: str, default: Any = REQUIRED, positive=False):
        """A list of numbers; ``shape`` such as "[x, y]" says how many and what they mean."""
        present, v = self.value(table, where, key, default)
        if not present:
            return v
        n = shape.count(",") + 1
        if not isinstance(v, list) or len(v) != n or not all(is_number(x) for x in v):
            self.error(key_path(where, key), f"must be a list of {n} numbers {shape}, got {v!r}")
            return None
        if positive and min(v) <= 0:
            self.error(key_path(where, key), f"sizes must be > 0, got {fmt(tuple(v))}")
            return None
        return tuple(float(x) for x in v)

    def string(self, table: dict, where: str, key: str, default: Any = REQUIRED, name: bool = False):
        present, v = self.value(table, where, key, default)
        if not present:
            return v
        if not isinstance(v, str):
            self.error(key_path(where, key), f"must be a string, got {v!r}")
            return None
        if name and not NAME_RE.fullmatch(v):
            self.error(key_path(where, key), f"{v!r} must match [a-z][a-z0-9_-]* (it becomes a PDDL name)")
            return None
        return v

    def table(self, doc: dict, key: str, required: bool) -> dict | None:
        present, v = self.value(doc, "", key, REQUIRED if required else {})
        if present and not isinstance(v, dict):
            self.error(key, f"must be a table ([{key}]), got {v!r}")
            return None
        return v

    def entries(self, doc: dict, key: str) -> list[tuple[int, str, dict]]:
        """(index, label, table) per [[key]] entry; the label names the entry in messages."""
        v = doc.get(key, [])
        if not isinstance(v, list):
            self.error(key, f"must be an array of tables ([[{key}]]), got {v!r}")
            return []
        out = []
        for i, t in enumerate(v):
            if not isinstance(t, dict):
                self.error(f"{key}[{i}]", f"must be a table ([[{key}]]), got {t!r}")
                continue
            n = t.get("name")
            out.append(
                (i, f'{key} "{n}"' if isinstance(n, str) and NAME_RE.fullmatch(n) else f"{key}[{i}]", t)
            )
        return out

    def inside(self, where: str, p: tuple[float, ...] | None, bounds: tuple | None) -> None:
        if p is None or bounds is None:
            return
        x0, x1, y0, y1 = bounds
        if not (x0 <= p[0] <= x1 and y0 <= p[1] <= y1):
            self.error(where, f"{fmt(p[:2])} is outside the room bounds {fmt(bounds)}")

    def settings(self, doc: dict, key: str, cls: type, checks: dict[str, Check]) -> Any:
        """A [robot] or [sensing] table: every field optional, defaults from ``cls``."""
        t = self.table(doc, key, required=False)
        if t is None:
            return cls()
        self.keys(t, key, tuple(checks))
        before = len(self.messages)
        values = {
            f.name: self.number(t, key, f.name, f.default, checks[f.name]) for f in dataclasses.fields(cls)
        }
        return cls(**values) if len(self.messages) == before else None
