"""The summary of a sweep by condition (every configuration field but the seed, or those
``--by`` names): success rate
with its Wilson 95 % interval, mean and standard deviation of simulated time, distance, replans,
recoveries and the WRS score; the same drawn with ``--plot``.

Crashed and timed-out missions count as failures in the success rate (a mission that did not
finish tidied nothing the table can show) and are left out of the means, which describe the
missions that ended.
"""

from __future__ import annotations

import math
import statistics
from pathlib import Path

from tidyplan.errors import InputError
from tidyplan.loop.options import DEFAULTS
from tidyplan.sweep.grid import MissionConfig

Z95 = 1.959963984540054
MEASURES = (  # (row field, heading, format)
    ("sim_time_s", "sim time (s)", "{:.0f}"),
    ("distance_m", "distance (m)", "{:.1f}"),
    ("replans", "replans", "{:.1f}"),
    ("recoveries", "recoveries", "{:.1f}"),
    ("wrs_score", "WRS score", "{:.0f}"),
)


def wilson(successes: int, n: int, z: float = Z95) -> tuple[float, float]:
    """Wilson's score interval for a binomial proportion: sound at 0 and n successes and for
    few missions, where the normal approximation gives bounds outside [0, 1]."""
    if n == 0:
        return (0.0, 1.0)
    p = successes / n
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    return (max(0.0, centre - half), min(1.0, centre + half))


# What ``--by`` may name: a configuration field (``scenario`` for the scenario file), in the
# order a label lists them.
BY_FIELDS = {
    "scenario": "scenario_file",
    "strategy": "strategy",
    "planner": "planner",
    "faults": "faults",
    "world": "world",
    "time_limit": "time_limit",
    "after_limit": "after_limit",
    "time_budget": "time_budget",
    "patience": "patience",
}


def parse_by(text: str | None) -> tuple[str, ...] | None:
    """``--by strategy,faults``: the fields that make a condition (the rest pooled); None: all."""
    if not text:
        return None
    names = tuple(dict.fromkeys(n.strip() for n in text.split(",") if n.strip()))
    for n in names:
        if n not in BY_FIELDS:
            raise InputError(f"--by: {n!r} is not one of {', '.join(BY_FIELDS)}")
    if not names:
        raise InputError("--by: no field given")
    return names


def conditions(rows: list[dict], by: tuple[str, ...] | None = None) -> list[dict]:
    """One entry per condition, in the order the table first has them. A condition is every
    configuration field but the seed, or only the fields ``by`` names (the others pooled: a
    strategy over many rooms, say)."""
    groups: dict[tuple, list[dict]] = {}
    for r in rows:
        config = MissionConfig.from_row(r)
        key = config.condition if by is None else tuple(getattr(config, BY_FIELDS[f]) for f in by)
        groups.setdefault(key, []).append(r)
    out = []
    for rs in groups.values():
        config = MissionConfig.from_row(rs[0])
        ended = [r for r in rs if r.get("status") == "done"]
        k = sum(bool(r.get("success")) for r in ended)
        entry = {
            "label": label(config) if by is None else pooled_label(config, by),
            "config": config,
            "missions": len(rs),
            "success": k,
            "success_rate": k / len(rs),
            "interval": wilson(k, len(rs)),
            "crashed": sum(r.get("status") == "crashed" for r in rs),
            "timeout": sum(r.get("status") == "timeout" for r in rs),
        }
        for key, _, _ in MEASURES:
            values = [float(r[key]) for r in ended if r.get(key) is not None]
            entry[key] = (
                statistics.mean(values) if values else math.nan,
                statistics.stdev(values) if len(values) > 1 else 0.0 if values else math.nan,
            )
        out.append(entry)
    return out


def label(config: MissionConfig) -> str:
    faults = config.faults or "baseline"
    extra = "" if config.time_limit == DEFAULTS.time_limit else f" limit {config.time_limit:g}s"
    extra += "" if config.after_limit == DEFAULTS.after_limit else f" then {config.after_limit}"
    scenario = Path(config.scenario_file).stem
    return f"{scenario} {config.strategy} {config.planner} {faults} {config.world}{extra}"


def pooled_label(config: MissionConfig, by: tuple[str, ...]) -> str:
    words = {
        "scenario": Path(config.scenario_file).stem,
        "faults": config.faults or "baseline",
        "time_limit": f"limit {config.time_limit:g}s" if config.time_limit else "the scenario's limit",
        "after_limit": f"then {config.after_limit}",
        "time_budget": f"budget {config.time_budget:g}s",
        "patience": f"patience {config.patience:g}s",
    }
    return " ".join(words.get(f, str(getattr(config, BY_FIELDS[f]))) for f in BY_FIELDS if f in by)


def report_lines(rows: list[dict], by: tuple[str, ...] | None = None) -> list[str]:
    entries = conditions(rows, by)
    if not entries:
        return ["no missions in the table"]
    width = max(len("condition"), *(len(e["label"]) for e in entries))
    head = f"{'condition':{width}} {'n':>3} {'success (95% CI)':>22} {'crash':>5} {'t/o':>3}"
    head += "".join(f" {h + ' mean±sd':>22}" for _, h, _ in MEASURES)
    lines = [head]
    for e in entries:
        lo, hi = e["interval"]
        line = (
            f"{e['label']:{width}} {e['missions']:3d} "
            f"{e['success']:3d} {e['success_rate']:4.0%} [{lo:4.0%},{hi:4.0%}] "
            f"{e['crashed']:5d} {e['timeout']:3d}"
        )
        for key, _, fmt in MEASURES:
            mean, sd = e[key]
            line += f" {(fmt.format(mean) + ' ± ' + fmt.format(sd)) if not math.isnan(mean) else '-':>22}"
        lines.append(line)
    return lines


def plot(rows: list[dict], path: str | Path, by: tuple[str, ...] | None = None) -> None:
    """One panel per figure, one bar per condition: success with its interval, means with ±sd."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    entries = conditions(rows, by)
    names = [e["label"] for e in entries]
    x = list(range(len(entries)))
    fig, axes = plt.subplots(2, 3, figsize=(15, 8), constrained_layout=True)
    ax = axes[0][0]
    rates = [e["success_rate"] for e in entries]
    errors = [
        [r - e["interval"][0] for r, e in zip(rates, entries, strict=True)],
        [e["interval"][1] - r for r, e in zip(rates, entries, strict=True)],
    ]
    ax.bar(x, rates, yerr=errors, capsize=4, color="tab:green")
    ax.set_ylim(0, 1.05)
    ax.set_title("success rate (Wilson 95% interval)")
    for ax, (key, heading, _) in zip(axes.flat[1:], MEASURES, strict=True):
        means = [e[key][0] for e in entries]
        sds = [e[key][1] for e in entries]
        ax.bar(x, means, yerr=sds, capsize=4, color="tab:blue")
        ax.set_title(f"{heading}: mean ± sd")
    for ax in axes.flat:
        ax.set_xticks(x, names, rotation=30, ha="right", fontsize=7)
    fig.savefig(path, dpi=110)
    plt.close(fig)
