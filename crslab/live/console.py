"""Live variables: read and write a running lab's watched variables, as the course's MATLAB tools do.

The course lists (``ME446_serial_ListVars``), reads (``ME446_serialread``) and writes
(``ME446_serialwrite``) the variables that the lab file places with ``#pragma DATA_SECTION``
while the DSP runs. While ``crslab sim`` runs, these commands typed on its standard input do the
same, between two ticks (replies go to stderr, so stdout stays the Tera Term view)::

    list                  the watched variables: name, C type, array length, current value
    get NAME              the value (all elements of an array)
    get NAME[i]           one element
    set NAME VALUE        write a scalar (integers are rounded)
    set NAME[i] VALUE     write one element of an array
    help                  these commands

>>> parse_command("set theta1array[3] 2.5")
Command(verb='set', name='theta1array', index=3, value=2.5)
>>> parse_command("get  whattoprint ")
Command(verb='get', name='whattoprint', index=None, value=None)
>>> parse_command("set whattoprint")
Traceback (most recent call last):
...
crslab.live.console.CommandError: set needs a value: set NAME VALUE or set NAME[i] VALUE
"""

from __future__ import annotations

import math
import queue
import re
import sys
import threading
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import TextIO

from crslab.framework_facts import TICKS_PER_S
from crslab.lab.watched import WatchedError, WatchedVar, watched_var
from crslab.run.running import RunningLab

HELP = "commands: list, get NAME, get NAME[i], set NAME VALUE, set NAME[i] VALUE, help"
_TARGET = re.compile(r"^([A-Za-z_]\w*)(?:\[\s*(\d+)\s*\])?$")

class CommandError(Exception):
    """A command that cannot be carried out; its message is the one-line reply."""


@dataclass(frozen=True)
class Command:
    """One typed command: ``verb`` (list, get, set, help), the variable, its index and the value."""

    verb: str
    name: str | None = None
    index: int | None = None
    value: float | None = None


def parse_command(line: str) -> Command:
    """Parse one typed line (see the module's table)."""
    words = re.sub(r"\s*\[\s*(\d+)\s*\]", r"[\1]", line).split()
    if not words:
        raise CommandError(HELP)
    verb = words[0].lower()
    if verb in ("list", "help"):
        return Command(verb)
    if verb not in ("get", "set"):
        raise CommandError(f"unknown command '{words[0]}'; {HELP}")
    if len(words) < 2:
        raise CommandError(f"{verb} needs a variable: {verb} NAME" + (" VALUE" if verb == "set" else ""))
    m = _TARGET.match(words[1])
    if not m:
        raise CommandError(f"'{words[1]}' is not a variable name (NAME or NAME[i])")
    name, index = m.group(1), (int(m.group(2)) if m.group(2) is not None else None)
    if verb == "get":
        if len(words) > 2:
            raise CommandError(f"get takes one variable, got '{line.strip()}'")
        return Command("get", name, index)
    if len(words) != 3:
        raise CommandError("set needs a value: set NAME VALUE or set NAME[i] VALUE")
    try:
        value = float(words[2])
    except ValueError:
        raise CommandError(f"'{words[2]}' is not a number") from None
    if not math.isfinite(value):
        raise CommandError(f"'{words[2]}' is not a finite number")
    return Command("set", name, index, value)


def format_value(var: WatchedVar, value: float) -> str:
    """A value as the lab's type holds it: integers without a decimal point, floats to 7 digits.

    >>> format_value(WatchedVar("n", "long", None, None, ".my_vars", 1), 3.0)
    '3'
    >>> format_value(WatchedVar("x", "float", None, None, ".my_vars", 1), -0.41999998688697815)
    '-0.42'
    """
    return str(int(value)) if var.is_integer else f"{value:.7g}"


def describe(var: WatchedVar) -> str:
    """``name  type[length]  = initial`` for listings.

    >>> describe(WatchedVar("theta1array", "float", 100, None, ".my_arrs", 30))
    'theta1array  float[100]'
    """
    dims = f"[{var.length}]" if var.length is not None else ""
    init = f"  = {var.initial}" if var.initial is not None else ""
    return f"{var.name}  {var.ctype}{dims}{init}"


class VarConsole:
    """Typed commands on ``stream`` (a reader thread queues them); :meth:`serve` runs them on a sim.

    ``reply(line)`` receives every answer (default: stderr).
    """

    def __init__(self, watched: Sequence[WatchedVar], *, stream: TextIO | None = None,
                 reply: Callable[[str], None] | None = None) -> None:
        self.watched = {v.name: v for v in watched}
        self.reply = reply or (lambda line: print(line, file=sys.stderr, flush=True))
        self.lines: queue.Queue[str] = queue.Queue()
        self._stream = stream
        self._thread: threading.Thread | None = None

    def start(self) -> None:
        """Start reading the stream (standard input by default) in a daemon thread."""
        stream = self._stream if self._stream is not None else sys.stdin

        def read() -> None:
            try:
                for line in stream:
                    self.lines.put(line)
            except (OSError, ValueError):  # closed or not readable: no more commands
                pass

        self._thread = threading.Thread(target=read, name="crslab-vars", daemon=True)
        self._thread.start()

    def serve(self, lab: RunningLab) -> None:
        """Carry out every command typed so far on the running ``lab`` (between ticks)."""
        while True:
            try:
                line = self.lines.get_nowait()
            except queue.Empty:
                return
            if not line.strip():
                continue
            try:
                self.reply(self.execute(lab, parse_command(line)))
            except CommandError as exc:
                self.reply(f"vars: {exc}")

    @staticmethod
    def _now(lab: RunningLab, var: WatchedVar) -> str:
        """``name  type[length]`` and, for a scalar, its value in the running lab."""
        if var.length is not None:
            return f"{var.name}  {var.ctype}[{var.length}]"
        value = lab.get(var.name)
        assert not isinstance(value, list)
        return f"{var.name}  {var.ctype}  = {format_value(var, value)}"

    def execute(self, lab: RunningLab, cmd: Command) -> str:
        """Run one command on the running ``lab`` and return its reply line."""
        at = f"t = {lab.tick / TICKS_PER_S:.3f} s"
        if cmd.verb == "help":
            return f"vars: {HELP}"
        if cmd.verb == "list":
            if not self.watched:
                return "vars: this lab has no watched (#pragma DATA_SECTION) variables"
            return "\n".join(f"vars: {self._now(lab, v)}" for v in self.watched.values())
        lab_name = lab.config.build.source.name
        try:
            var = watched_var(self.watched.values(), cmd.name or "", cmd.index, lab_name,
                              whole=cmd.verb == "get")
            if cmd.value is not None:
                var.check_value(cmd.value, lab_name)
        except WatchedError as exc:
            raise CommandError(str(exc)) from None
        target = var.name if cmd.index is None else f"{var.name}[{cmd.index}]"
        if cmd.verb == "get":
            value = lab.get(var.name)
            if isinstance(value, list):
                if cmd.index is not None:
                    return f"{target} = {format_value(var, value[cmd.index])}   ({at})"
                return f"{target} = [{' '.join(format_value(var, v) for v in value)}]   ({at})"
            return f"{target} = {format_value(var, value)}   ({at})"
        new = cmd.value
        assert new is not None  # parse_command gives every set a value
        try:
            lab.set(var.name, new, index=cmd.index)
        except KeyError as exc:
            raise CommandError(str(exc.args[0])) from None
        shown = format_value(var, round(new) if var.is_integer else new)
        return f"{target} = {shown}   (from {at} on)"
