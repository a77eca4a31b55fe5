"""A report said once the run has ended: ``crslab sim`` and ``crslab debug`` end their fan-out with
these, so the waypoint tracking's report, the C28x check's findings and the run's summary come
after everything the other sinks say, in that order.

>>> from crslab.sinks.sink import FanOut
>>> said = []
>>> out = FanOut([AtEnd(lambda result: said.append(("tracking", result))),
...               AtEnd(lambda result: said.append(("summary", result)))])
>>> out.on_serial(4100, b"0.00\\n\\r"); out.on_end("ok"); said
[('tracking', 'ok'), ('summary', 'ok')]
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from crslab.sinks.sink import Ended, Sink


class AtEnd(Sink):
    """An output said when the run ends: ``say(result)`` (after the sinks before it)."""

    def __init__(self, say: Callable[[Any], None]) -> None:
        """``say`` takes how the run ended (a :class:`crslab.run.status.RunResult` for a
        ``BoardRun``'s run)."""
        self.say = say

    def on_end(self, result: Ended) -> None:
        self.say(result)
