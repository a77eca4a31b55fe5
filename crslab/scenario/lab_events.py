"""Writes to the lab while it runs: a watched variable (``set``), what Simulink sends (``simulink``)."""

from __future__ import annotations

import re
from dataclasses import dataclass

from crslab.framework_facts import SIMULINK_INPUTS
from crslab.scenario.event import Event, RandomFaults
from crslab.toml_file import Table

INT16_MIN, INT16_MAX = -32768, 32767
_IDENTIFIER = re.compile(r"[A-Za-z_]\w*\Z")


@dataclass(frozen=True)
class SetVariable(Event):
    """Write ``value`` to the lab's watched variable ``name`` (element ``index`` of an array), as
    the course's ``ME446_serialwrite`` does while the DSP runs. Integer variables get the value
    rounded.

    >>> SetVariable(tick=5000, name="table", value=-7.0, index=2).describe()
    'set table[2] = -7'
    """

    name: str
    value: float
    index: int | None = None
    kinds = ("set",)

    @classmethod
    def parse(cls, r: Table, at: int, line: int, faults: RandomFaults) -> list[Event]:
        r.check_keys({"at", "kind", "var", "value", "index"})
        name = r.text("var")
        if not _IDENTIFIER.match(name):
            raise r.fail("var", f"must be a C variable name, got {name!r}")
        index = r.integer("index", minimum=0) if "index" in r.table else None
        line = r.line_of("var") or line  # what check_lab's errors point at
        return [cls(tick=at, name=name, value=r.number("value"), index=index, line=line)]

    def describe(self) -> str:
        where = self.name if self.index is None else f"{self.name}[{self.index}]"
        return f"set {where} = {self.value:g}"


@dataclass(frozen=True)
class SimulinkInput(Event):
    """Simulink sends values down: ``values`` holds ``(input, value)`` pairs, input 1..7, value an
    int16. The lab sees them in ``int SIMU_Var1_fromSIMU_16bit`` .. ``SIMU_Var7_fromSIMU_16bit``
    (declared ``extern`` in the lab file); inputs not named keep their value."""

    values: tuple[tuple[int, int], ...]
    kinds = ("simulink",)

    @classmethod
    def parse(cls, r: Table, at: int, line: int, faults: RandomFaults) -> list[Event]:
        r.check_keys({"at", "kind", "values", "input", "value"})
        if "values" in r.table:
            if "input" in r.table or "value" in r.table:
                raise r.fail("values", "give values, or input and value, not both")
            values = r.table["values"]
            if (not isinstance(values, list) or not 1 <= len(values) <= SIMULINK_INPUTS
                    or not all(isinstance(v, int) and not isinstance(v, bool) and INT16_MIN <= v <= INT16_MAX
                               for v in values)):
                raise r.fail("values", f"must be a list of 1 to {SIMULINK_INPUTS} whole numbers from "
                             f"{INT16_MIN} to {INT16_MAX} (int16), got {values!r}")
            pairs = tuple((i + 1, v) for i, v in enumerate(values))
        else:
            pairs = ((r.integer("input", minimum=1, maximum=SIMULINK_INPUTS),
                      r.integer("value", minimum=INT16_MIN, maximum=INT16_MAX)),)
        return [cls(tick=at, values=pairs, line=line)]

    def describe(self) -> str:
        return "simulink " + ", ".join(f"input {i} = {v}" for i, v in self.values)
