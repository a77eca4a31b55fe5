"""What gdb is told in a ``crslab debug`` run on the terminal, and how gdbserver is started for
an IDE.

gdb attaches to the worker between two ticks with :data:`BEFORE_ATTACH` set (SIGSYS passes
through to the lab without a stop: the sandbox's trap is how a refused call is named; no debug
information is downloaded, no script of the user's or of a library is loaded), then reads
:func:`setup_script`: ``$tick`` and ``$t`` hold the tick being run and its time in seconds,
updated at every stop (a stop at a new tick says so in one line), and the commands ``tick``
and ``next-tick``. Then :mod:`crslab.debug.in_gdb` (gdb's Python) makes stepping skip crslab's
own C, arms the break and stops crashes at the lab's line.

>>> "define next-tick" in setup_script(Path("/crslab/csrc"))
True
>>> [line for line in setup_script(Path("/home/s/crslab/csrc")).splitlines() if "substitute" in line]
['set substitute-path /crslab/csrc "/home/s/crslab/csrc"']
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from crslab import resources
from crslab.framework_facts import TICKS_PER_S
from crslab.lab.firmware import DEBUG_INFO_CSRC

IN_GDB = Path(__file__).with_name("in_gdb.py")
"""The Python gdb runs to stop a crash at the lab's own line (:mod:`crslab.debug.in_gdb`)."""

BEFORE_ATTACH = (
    "set debuginfod enabled off",  # never download debug information (or ask whether to)
    "set debug-file-directory /nonexistent",  # nor load the system's: libc and libm are stepped over
    "set auto-load python-scripts off",
    "set auto-load gdb-scripts off",
    "set pagination off",
    "set confirm off",
    "set print thread-events off",
    "set print inferior-events off",
    "set print symbol-loading off",
    # the worker is one thread (the sandbox checks it): without libthread_db gdb prints no "[Thread
    # debugging using libthread_db enabled]" onto the transcript's stdout (one warning on stderr)
    "set libthread-db-search-path /nonexistent",
    "set suppress-cli-notifications on",  # no "stopped in read()" when it attaches: turned off after
)
"""Settings given before gdb attaches (``-iex``); one an older gdb lacks is only a warning."""

def _quote(text: str) -> str:
    """A gdb string literal.

    >>> print(_quote('C:\\\\lab "1".c'))
    "C:\\\\lab \\"1\\".c"
    """
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'


def setup_script(csrc: Path, *, lab_file: Path | None = None, sanitizer_report: Path | None = None,
                 batch: bool = False) -> str:
    """The gdb commands run once gdb has attached (see the module): the settings
    :mod:`crslab.debug.in_gdb` reads (crslab's C folder, the lab's file, a sanitizer's report,
    whether gdb runs ``-batch``), the tick display and the commands ``tick`` and ``next-tick``."""
    lines = [
        "# crslab debug: gdb's setup (docs/debugging.md)",
        f"set $crs_csrc = {_quote(str(csrc))}",
        # crslab's own C is named alike from every checkout in its debug information: here it is
        f"set substitute-path {DEBUG_INFO_CSRC} {_quote(str(csrc))}",
        f"set $crs_batch = {_quote('1' if batch else '')}",
        f"set $crs_lab_file = {_quote(str(lab_file) if lab_file else '')}",
        f"set $crs_sanitizer_report = {_quote(str(sanitizer_report) if sanitizer_report else '')}",
        f"set $crs_ticks_per_s = {TICKS_PER_S}",
        "set $crs_shown_tick = -1",
        "set $tick = crs_tick",
        "set $t = crs_tick / (double)$crs_ticks_per_s",
        "define hook-stop",
        "  set $tick = crs_tick",
        "  set $t = $tick / (double)$crs_ticks_per_s",
        "  if $tick >= 0 && $tick != $crs_shown_tick",
        "    set $crs_shown_tick = $tick",
        '    printf "crslab: tick %lld (t = %.3f s)\\n", $tick, $t',
        "  end",
        "end",
        "define tick",
        '  printf "tick %lld (t = %.3f s)\\n", crs_tick, crs_tick / (double)$crs_ticks_per_s',
        "end",
        "document tick",
        "Print the tick lab() is at (t = tick ms). Simulated time stands still while gdb holds the lab.",
        "end",
        "define next-tick",
        "  python crslab_stop_in_lab()",
        "  continue",
        "end",
        "document next-tick",
        "Run to the start of lab() at the next tick.",
        "end",
    ]
    return "\n".join(lines) + "\n"


def gdb_argv(gdb: str, script: Path, commands: Sequence[str] = (), *, batch: bool = False) -> list[str]:
    """How gdb is run: quiet, without the user's ``~/.gdbinit`` (every student gets the same
    gdb), :data:`BEFORE_ATTACH`, the setup ``script`` and :data:`IN_GDB` once attached, then
    ``continue`` and the user's ``commands`` (which run at the first stop). The worker's process
    id is appended after ``-p`` (:class:`crslab.debug.tracer.GatedTracer`).

    >>> gdb_argv("/usr/bin/gdb", Path("s.gdb"), ["print x"], batch=True)[-6:]
    ['-ex', 'continue', '-ex', 'print x', '-batch', '-p']
    """
    argv = [gdb, "-q", "-nx"]
    for command in BEFORE_ATTACH:
        argv += ["-iex", command]
    argv += ["-ex", "set suppress-cli-notifications off", "-x", str(script), "-x", str(IN_GDB),
             "-ex", "continue"]
    for command in commands:
        argv += ["-ex", command]
    return argv + (["-batch"] if batch else []) + ["-p"]


def gdbserver_argv(gdbserver: str) -> list[str]:
    """gdbserver for one IDE session over its standard input and output (crslab relays them to a
    port of localhost: :mod:`crslab.debug.local_port`), attaching to the worker whose process id
    is appended.

    >>> gdbserver_argv("gdbserver")
    ['gdbserver', '--once', '--attach', '-']
    """
    return [gdbserver, "--once", "--attach", "-"]


def csrc_dir() -> Path:
    """crslab's C folder, whose files gdb steps over."""
    return resources.path("csrc")
