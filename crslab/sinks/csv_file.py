"""``--csv FILE``: the scope signals of a run, one row per tick, for a spreadsheet or ``crslab plot``.

The header names every column with its unit (``theta1motor [rad]``, ``tau1 [command units]``;
see :mod:`crslab.scopes.signals`). Values are written in full precision (shortest text that reads
back to the same double). The Simulink_PlotVar columns hold the lab's variables at every tick,
before Simulink's 5 ms sampling and 1e-4 quantization (the rerun scope shows those).

>>> import io
>>> from crslab.scopes.signals import csv_header
>>> out = io.BytesIO()
>>> sink = CsvSink(out)
>>> log = {"tick": np.array([[0], [1]]), "enc_rad": np.zeros((2, 3)), "tau_lab": np.zeros((2, 3)),
...        "tau_applied": np.zeros((2, 3)), "plot": np.full((2, 4), 0.5),
...        "safety": np.zeros((2, 1), np.int32),
...        "leds": np.array([[0], [3]], np.uint32), "motor_board_off": np.array([[0], [1]], np.int32),
...        "qpos_dh_rad": np.zeros((2, 3)), "ee": np.zeros((2, 3)), "push_force": np.zeros((2, 3))}
>>> sink.on_log(log); sink.close()
>>> text = out.getvalue().decode().splitlines()
>>> text[0].split(",")[:3], text[2].split(",")[:2], text[2].split(",")[15:19]
(['tick', 't [s]', 'theta1motor [rad]'], ['1', '0.001'], ['0', '1', '1', '1'])
"""

from __future__ import annotations

from pathlib import Path
from typing import BinaryIO

import numpy as np

from crslab.framework_facts import TICKS_PER_S
from crslab.output_paths import with_parent
from crslab.scopes.signals import SIGNALS, WORLD_SIGNALS, csv_header, signal_values
from crslab.sinks.sink import Sink


def preload() -> None:
    """Import pyarrow's CSV writer in a background thread now (about 0.1 s), for the next
    :class:`CsvSink` of this process: call it once the worker was forked, so that the import
    overlaps the worker's start-up (an import in progress makes a second one wait for it)."""
    import threading

    threading.Thread(target=__import__, args=("pyarrow.csv",), name="crslab-pyarrow-import",
                     daemon=True).start()


class CsvSink(Sink):
    """Write every scope row to ``target`` (a path or a binary stream), header first."""

    def __init__(self, target: Path | BinaryIO, *, world: bool = False) -> None:
        """``world``: the run's world has fixtures, so its rows carry the world's columns too."""
        self.signals = SIGNALS + WORLD_SIGNALS if world else SIGNALS
        if isinstance(target, (str, Path)):
            self.file = open(with_parent(target), "wb")  # noqa: SIM115 - closed in close()
            self._own = True
        else:
            self.file, self._own = target, False
        self.file.write((",".join(csv_header(self.signals)) + "\n").encode())
        self._writer = None

    def on_log(self, columns: dict[str, np.ndarray]) -> None:
        import pyarrow as pa
        import pyarrow.csv as pacsv

        tick = columns["tick"][:, 0]
        if not len(tick):
            return
        arrays = [pa.array(tick), pa.array(tick / TICKS_PER_S)]
        arrays += [pa.array(signal_values(columns, s)) for s in self.signals]
        table = pa.Table.from_arrays(arrays, names=csv_header(self.signals))
        if self._writer is None:
            options = pacsv.WriteOptions(include_header=False, quoting_style="none")
            self._writer = pacsv.CSVWriter(self.file, table.schema, write_options=options)
        self._writer.write_table(table)

    def flush(self) -> None:
        """Push what was written to disk."""
        self.file.flush()

    def close(self) -> None:
        if self._writer is not None:
            self._writer.close()
            self._writer = None
        if self._own:
            self.file.close()
        else:
            self.file.flush()
