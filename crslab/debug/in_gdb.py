"""Run by gdb itself (``gdb -x in_gdb.py``) once it has attached, in ``crslab debug`` on the
terminal. It reads the settings of crslab's setup script (``$crs_csrc``, ``$crs_lab_file``,
``$crs_sanitizer_report``, ``$crs_batch``, ``$crs_ticks_per_s``) and:

- makes stepping skip crslab's own C (``serial_printf`` is one step);
- breaks on ``crs_debug_break``, which the worker calls when the run reaches the break: there
  it arms a temporary breakpoint on ``lab()`` and goes on, so gdb stops inside ``lab()`` at that
  very tick (:func:`crslab_stop_in_lab`, also behind the ``next-tick`` command);
- quits when the lab's process has ended (the run is over), unless in ``-batch``;
- shows, in ``bt``, the lab's frames and the framework's down to its loop (``crs_board_run``), not
  the hundred-odd frames of CPython and cffi below it (:class:`LabFrames`, a gdb frame filter;
  ``bt -no-filters`` shows them all);
- when the lab crashes, stops at the lab's own line: a segfault stops in the lab's code
  already, but a sanitizer finding or an ``abort()`` stops deep in a runtime library, and a NaN
  made inside ``sqrt`` in libm. It selects the innermost frame in the lab's file
  (:func:`lab_frame_index`), prints it, and names the crash, the tick and, for a sanitizer, its
  one-line summary.

gdb's own Python runs this, not crslab's: it imports nothing of crslab and keeps to the Python
3.8 that older distributions' gdb embed. Imported anywhere else (the doctests) it only defines
functions.

>>> fpe_kind(7)
'an invalid operation made a NaN'
>>> lab_frame_index(["/usr/lib/libc.so.6", None, "/home/s/lab.c", "/home/s/lab.c"], "/home/s/lab.c")
2
>>> class Frame:
...     def __init__(self, name): self.name = name
...     def function(self): return self.name
>>> [f.name for f in LabFrames().filter(iter(map(Frame, ["lab", "lab_tick", "crs_board_run", "ffi_call"])))]
['lab', 'lab_tick', 'crs_board_run']
"""

from __future__ import annotations

import os

try:
    import gdb  # type: ignore[import-not-found]
except ImportError:  # imported outside gdb: only the functions
    gdb = None

CRASHES = {
    "SIGSEGV": "a memory access outside what the lab owns (SIGSEGV)",
    "SIGBUS": "a misaligned or unmapped memory access (SIGBUS)",
    "SIGILL": "an illegal instruction (SIGILL)",
    "SIGABRT": "abort() (SIGABRT)",
    "SIGFPE": "a floating-point exception (SIGFPE)",
}
_FPE = {1: "an integer division by zero", 2: "an integer overflow",
        3: "a division by zero made an infinity", 4: "an overflow made an infinity",
        7: "an invalid operation made a NaN"}


def fpe_kind(si_code: int) -> str:
    """What a SIGFPE's ``si_code`` (``FPE_*``) means."""
    return _FPE.get(si_code, "a floating-point exception")


def lab_frame_index(files: list[str | None], lab_file: str) -> int | None:
    """The innermost frame (0 = innermost) whose source file is ``lab_file``, else the innermost
    with any source, else None; ``files`` lists each frame's source file (None: unknown)."""
    same = [i for i, f in enumerate(files) if f and os.path.realpath(f) == os.path.realpath(lab_file)]
    if same:
        return same[0]
    known = [i for i, f in enumerate(files) if f]
    return known[0] if known else None


def _setting(name: str) -> str:
    value = gdb.convenience_variable(name)
    return value.string() if value is not None else ""


def _sanitizer_summary(path: str) -> str | None:
    try:
        with open(path, errors="replace") as f:
            lines = f.read().splitlines()
    except OSError:
        return None
    for line in lines:
        if line.startswith("SUMMARY: "):
            return line[len("SUMMARY: "):]
    return next((line for line in lines if "ERROR: " in line or "runtime error:" in line), None)


def _frames() -> list:
    """(frame, its source file or None), innermost first."""
    frames, frame = [], gdb.newest_frame()
    while frame is not None and len(frames) < 64:
        symtab = frame.find_sal().symtab
        frames.append((frame, symtab.fullname() if symtab is not None else None))
        frame = frame.older()
    return frames


def _on_interrupt() -> None:
    """Ctrl-C: show the lab's line if it was running its own code (a loop that never ends)."""
    lab_file = _setting("crs_lab_file")
    frames = _frames()
    index = lab_frame_index([f for _, f in frames], lab_file) if lab_file else None
    in_lab = index is not None and os.path.realpath(frames[index][1] or "") == os.path.realpath(lab_file)
    if index is not None and in_lab:
        frames[index][0].select()
        gdb.execute("frame")
    else:
        print("crslab: the lab is between two ticks, waiting for crslab; 'next-tick' runs to the next "
              "lab() call, 'continue' goes on")


def _on_stop(event: object) -> None:
    if isinstance(event, gdb.SignalEvent) and event.stop_signal == "SIGINT":
        _on_interrupt()
        return
    if not isinstance(event, gdb.SignalEvent) or event.stop_signal not in CRASHES:
        return
    what = CRASHES[event.stop_signal]
    if event.stop_signal == "SIGFPE":
        try:
            what = f"{fpe_kind(int(gdb.parse_and_eval('$_siginfo')['si_code']))} (SIGFPE)"
        except gdb.error:
            pass
    report = _setting("crs_sanitizer_report")
    found = _sanitizer_summary(report) if report and event.stop_signal == "SIGABRT" else None
    if found:
        what = found
    frames = _frames()
    index = lab_frame_index([f for _, f in frames], _setting("crs_lab_file"))
    tick = int(gdb.parse_and_eval("crs_tick"))
    ticks_per_s = int(gdb.parse_and_eval("$crs_ticks_per_s"))  # the setup script's (framework_facts.h)
    print(f"crslab: the lab stopped at tick {tick} (t = {tick / ticks_per_s:.3f} s): {what}; 'bt' shows the "
          "calls that led there, 'continue' ends the run as crslab sim would")
    if index is not None:
        frames[index][0].select()
        gdb.execute("frame")


FRAMEWORK_LOOP = "crs_board_run"
"""The framework's loop: the outermost frame ``bt`` shows (below it: cffi and CPython)."""


class LabFrames:
    """A gdb frame filter: the frames up to :data:`FRAMEWORK_LOOP`, innermost first (all of them
    when it is not on the stack, as in a constructor of the lab)."""

    name = "crslab-lab-frames"
    priority = 100
    enabled = True

    def filter(self, frames: object) -> object:
        return _up_to_the_loop(frames)


def _up_to_the_loop(frames: object) -> object:
    for frame in frames:  # type: ignore[attr-defined]
        yield frame
        if frame.function() == FRAMEWORK_LOOP:
            return


def crslab_stop_in_lab() -> None:
    """Stop at the next ``lab()`` call (a temporary breakpoint, set without a word)."""
    gdb.execute("tbreak lab", to_string=True)


def process_ended(pid: int) -> bool:
    """Whether process ``pid`` has ended (gone, or a zombie its parent has not reaped yet).

    >>> process_ended(os.getpid())
    False
    """
    try:
        with open(f"/proc/{pid}/stat") as f:
            state = f.read().rpartition(")")[2].split()[0]
    except (OSError, IndexError):
        return True
    return state in ("Z", "X")


_lab_pid = 0


def _quit_after(event: object) -> None:
    """The lab's process has ended (the run is over, or the lab died): so is this session. gdb
    reports a detach the same way (``quit``, ``detach``, the end of ``-batch``); then the
    process lives on without gdb, and gdb stays or quits as the user asked."""
    if _lab_pid and process_ended(_lab_pid) and not _setting("crs_batch"):  # -batch ends by itself
        gdb.post_event(lambda: gdb.execute("quit"))


def _setup() -> None:
    global _lab_pid
    _lab_pid = gdb.selected_inferior().pid
    # the sandbox's trap is how a refused call is named: it must reach the lab, unseen
    gdb.execute("handle SIGSYS nostop noprint pass", to_string=True)
    csrc = _setting("crs_csrc")
    if csrc:
        for root in (csrc, "/crslab/csrc"):  # the folder, and its name in the debug information
            for folder in ("board", "plant", "port", "kin", "firmware/include"):
                gdb.execute(f"skip -gfile {root}/{folder}/*", to_string=True)
    armed = gdb.Breakpoint("crs_debug_break", internal=True)
    armed.silent = True
    armed.commands = "python crslab_stop_in_lab()\ncontinue"
    gdb.frame_filters[LabFrames.name] = LabFrames()
    gdb.events.stop.connect(_on_stop)
    gdb.events.exited.connect(_quit_after)


if gdb is not None:
    _setup()
