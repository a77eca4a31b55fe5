"""``crslab debug``: a lab under gdb with simulated time frozen, as Code Composer Studio debugs
it on the board (docs/debugging.md).

The run is the one ``crslab sim`` makes (same build of the board, scenario, sinks and
transcript); the lab is built ``-O0 -g``. The debugger is a process of crslab's that the worker
names as its one allowed tracer before its sandbox closes (:mod:`~crslab.debug.tracer`); it
attaches between two ticks (:mod:`~crslab.debug.debugged_run`), so while it holds ``lab()`` the
plant, the scenario and every sink wait: simulated time stands still by construction.

- :mod:`~crslab.debug.programs`: finding gdb and gdbserver (a missing one is one line);
- :mod:`~crslab.debug.gdb_commands`: what gdb is told (the break, SIGSYS, the tick);
- :mod:`~crslab.debug.in_gdb`: the Python gdb runs to stop a crash at the lab's own line;
- :mod:`~crslab.debug.tracer`: the debugger process, started before the worker, held until
  the worker is ready;
- :mod:`~crslab.debug.debugged_run`: where the run stops and who attaches when.
"""
