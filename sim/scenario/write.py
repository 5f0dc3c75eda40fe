"""Scenario files written from a ``Scenario``: the inverse of ``sim.scenario.read.loads``.

Why: generators of rooms (``bench/wrs.py``) write scenarios that must read back as the very
values generated, so every number is written as the shortest text that reads back as the same
float, and strings only where TOML needs no escape.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import fields

from sim.scenario.model import Scenario


def dumps(s: Scenario) -> str:
    """The scenario as a self-contained file of docs/scenario.md's format, read back unchanged."""
    x0, x1, y0, y1 = s.bounds
    lines = [
        f"# {s.title}",
        "schema = 1",
        f"name = {_str(s.name)}",
        f"title = {_str(s.title)}",
        f"description = '''\n{s.description}'''",
        *([f"time_limit_s = {_num(s.time_limit_s)}"] if s.time_limit_s is not None else []),
        *([f"facts = [{', '.join(_str('(' + ' '.join(a) + ')') for a in s.facts)}]"] if s.facts else []),
        "",
        "[room]",
        f"bounds = {_list((x0, x1, y0, y1))}",
        f"entrance = {_list(s.entrance)}",
        f"heading_deg = {_num(s.heading_deg)}",
        "",
        "[robot]",
        *(f"{f.name} = {_num(getattr(s.robot, f.name))}" for f in fields(s.robot)),
        "",
        "[sensing]",
        *(f"{f.name} = {_num(getattr(s.sensing, f.name))}" for f in fields(s.sensing)),
    ]
    if s.prior is not None:
        lines += ["", "[prior]", "count = { " + ", ".join(f"{c} = {n}" for c, n in s.prior) + " }"]
    for f in s.furniture:
        lines += ["", "[[furniture]]", f"name = {_str(f.name)}", f"center = {_list((f.cx, f.cy))}"]
        lines += [f"size = {_list((f.sx, f.sy))}", f"height = {_num(f.height)}", f"kind = {_str(f.kind)}"]
    for d in s.deposits:
        lines += ["", "[[deposit]]", f"name = {_str(d.name)}", f"category = {_str(d.category)}"]
        lines += [f"position = {_list((d.x, d.y, d.z))}"]
        lines += [f"approach = {_list(d.approach)}"] if d.approach is not None else []
        lines += [f"container = {_list(d.container)}"] if d.container is not None else []
        if d.drawer is not None:
            spec = d.drawer
            lines += ["", "[deposit.drawer]", f"closed = {str(spec.closed).lower()}"]
            lines += [f"{k} = {_num(getattr(spec, k))}" for k in ("travel", "width", "rim")]
            lines += [f"handle_height = {_num(spec.handle_height)}"] if spec.handle_height is not None else []
    for v in s.viewpoints:
        lines += ["", "[[viewpoint]]", f"name = {_str(v.name)}", f"position = {_list((v.x, v.y))}"]
    for i in s.items:
        lines += ["", "[[item]]", f"name = {_str(i.name)}", f"category = {_str(i.category)}"]
        lines += [
            f"position = {_list((i.x, i.y))}",
            f"on = {_str(i.on)}",
            f"size = {_list((i.sx, i.sy, i.sz))}",
        ]
        lines += ["unknown = true"] if i.unknown else []
        if i.orientation is not None:
            o = i.orientation
            lines += [f"orientation = {{ axis = {_list(o.axis)}, down = {_str(o.down)} }}"]
    return "\n".join(lines) + "\n"


def _num(v: float) -> str:
    return repr(float(v))  # the shortest text that reads back as the same float


def _list(vs: Sequence[float]) -> str:
    return "[" + ", ".join(_num(v) for v in vs) + "]"


def _str(s: str) -> str:
    if not s.isprintable() or '"' in s or "\\" in s:
        raise ValueError(f"not written as a plain TOML string: {s!r}")
    return f'"{s}"'
