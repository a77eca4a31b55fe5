"""lab()'s cost against its budget (``--budget``), the one reading of it: the board counts each
call's cost and the calls over the budget in its own unit (WebAssembly instructions; natively the
ns they take), and says that budget in the run's counters (``RunStats.budget``); every report of it
(``crslab sim``'s summary, ``record`` and ``check``'s line, ``grade``'s and ``sweep``'s columns)
reads it from there, so none says another number than the one the calls were counted against.
"""

from __future__ import annotations

from crslab._bindings import constants
from crslab.worker.run_stats import RunStats

NEAR_BUDGET = 0.8
"""A run whose slowest lab() call took this share of the budget, and none more, is warned of it."""


def lab_cost(stats: RunStats) -> dict:
    """lab()'s cost per call, in the firmware's unit: WebAssembly instructions, or (native) the
    microseconds it took, with the budget the board counted against (``stats.budget``, in that unit:
    ``--budget``'s instructions, or the ns they take at one per cycle of the 150 MHz F28335).

    >>> native = lab_cost(RunStats(lab_calls=2, lab_cost_total=3000, cost_unit=0, budget=500_000))
    >>> native["lab_cost_unit"], native["lab_cost_mean"], native["budget"]
    ('us', 1.5, 500.0)
    """
    calls = stats.lab_calls
    instructions = stats.cost_unit == constants.CRS_COST_INSTRUCTIONS
    scale = 1.0 if instructions else 1e-3  # ns to us
    return {
        "lab_cost_unit": "instructions" if instructions else "us",
        "lab_cost_mean": round(stats.lab_cost_total * scale / calls, 1) if calls else 0.0,
        "lab_cost_max": round(stats.lab_cost_max * scale, 1),
        "lab_max_tick": stats.lab_max_tick,
        "budget": stats.budget if instructions else round(stats.budget * scale, 1),
        "over_budget": stats.over_budget,
        "over_budget_ticks": list(stats.first_over_tick),
    }


def _count(value: float) -> str:
    return f"{value:,.0f}" if value >= 100 else f"{value:.1f}"


def cost_text(info: dict) -> str:
    """lab()'s calls, their cost and those over the budget (a :func:`summary`'s or
    :func:`lab_cost`'s numbers, with ``lab_calls``), as the summary line says them."""
    unit = info["lab_cost_unit"]
    text = (f"lab() x{info['lab_calls']}: mean {_count(info['lab_cost_mean'])} {unit}, "
            f"max {_count(info['lab_cost_max'])} {unit} (tick {info['lab_max_tick']})")
    if "hung_tick" in info:  # the lab() call that hung never finished, so was never measured
        return text + f"; the call at tick {info['hung_tick']} did not return (not counted above)"
    budget = info["budget"]
    budget_text = f"{budget:,.0f}" if float(budget).is_integer() else _count(budget)
    text += f"; {info['over_budget']} over the budget of {budget_text} {unit}"
    if info["over_budget"]:
        text += f" (ticks {', '.join(map(str, info['over_budget_ticks']))})"
    return text


def budget_line(stats: RunStats) -> str | None:
    """What a command that runs a lab without the summary line (``record``, ``check``) says of its
    budget (``--budget``): lab()'s calls, their cost and those over it; None when lab() never ran.

    >>> budget_line(RunStats(lab_calls=3, lab_cost_total=300, lab_cost_max=120, lab_max_tick=4102,
    ...                      over_budget=1, first_over_tick=(4102,), budget=110)).split("; ")[1]
    '1 over the budget of 110 instructions (ticks 4102)'
    """
    if not stats.lab_calls:
        return None
    return cost_text({"lab_calls": stats.lab_calls, **lab_cost(stats)})


def near_budget_warning(lab_name: str, info: dict) -> str | None:
    """A warning when no lab() call went over the budget but the slowest came close."""
    if info.get("over_budget", 0) or not info.get("lab_calls"):
        return None
    if info["lab_cost_max"] <= NEAR_BUDGET * info["budget"]:
        return None
    return (f"warning: {lab_name}'s slowest lab() call cost {_count(info['lab_cost_max'])} "
            f"{info['lab_cost_unit']}, close to the budget of {_count(info['budget'])}")
