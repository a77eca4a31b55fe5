"""The WebSocket protocol between the page and ``crslab serve``: what the browser may ask, checked.

Every message is one JSON object with a ``type``. The browser sends:

=============  =====================================================================================
``build``      ``lab`` (``{"name": "lab1.c", "text": "..."}``): compile it; the answer is ``built``
``run``        ``lab``, ``scenario`` (``{"name": "tour"}`` or ``{"file": {"name", "text"}}``),
               ``speed`` (1, 2, 10, ... or null: as fast as possible), ``offsets`` ([O2, O3] rad or
               null), ``no_startup_delay``, ``duration`` (simulated s or null), ``record``
               (``{"csv": bool, "rrd": bool}``), ``world`` (a built-in world's name: ``none``, the
               default, or ``contest``), ``contest`` (true: run it as ``crslab contest`` does, in
               the contest world unless ``world`` names another with fixtures, hands off, resting
               where the lab's offsets say, until the arm comes to rest unless ``duration``; a
               ``scorecard`` before ``ended``): build, then run, streaming ``chunk`` messages
``stop``       end the run now
``speed``      ``speed``: change the pace of the running lab
``vars``       ``cmd`` (``list``, ``get``, ``set``), ``name``, ``index``, ``value``: the lab's
               watched variables, as ``crslab sim``'s typed commands (the answer is ``vars``)
``hand``       ``body`` (a link), ``anchor`` (the grabbed point in the link's frame, m), ``target``
               (where the mouse holds it, world frame, m): pull the link there, as a hand does
``release``    let go of the arm
``check``      ``lab``, ``golden`` (``{"name", "text"}``): run the lab as ``crslab check`` does and
               compare with the golden file (the answer is ``checked``)
=============  =====================================================================================

The server answers with ``hello``, ``building``, ``built``, ``started``, ``chunk``, ``event``,
``scorecard``, ``ended``, ``vars``, ``checked`` and ``error`` (docs/serve.md lists their fields). A
message that is not one of the above, or whose fields are wrong, gets one ``error`` naming the
problem, and nothing else happens.

>>> parse_message('{"type": "stop"}')
{'type': 'stop'}
>>> parse_message('{"type": "speed", "speed": 0}')
Traceback (most recent call last):
...
crslab.serve.page_messages.ProtocolError: speed: must be a number > 0 (x real time) or null (as fast as ...)
>>> parse_message('{"type": "launch"}')  # doctest: +ELLIPSIS
Traceback (most recent call last):
...
crslab.serve.page_messages.ProtocolError: unknown message type 'launch' (build, run, stop, speed, vars, ...)
"""

from __future__ import annotations

import json
import math
import re
from typing import Any

from crslab.world import WORLD_NAMES

MAX_MESSAGE_BYTES = 1_000_000
"""The largest message the page may send (a lab file or a golden file with room to spare)."""
MAX_FILE_CHARS = 500_000
MAX_SPEED = 1000.0
BODIES = ("waist", "upper_arm", "forearm")
"""The links a hand may grab (the arm's moving bodies, crslab.scopes.arm3d)."""
_FILE_NAME = re.compile(r"^[A-Za-z0-9_][A-Za-z0-9_.\- ]{0,99}$")
TYPES = ("build", "run", "stop", "speed", "vars", "hand", "release", "check")


class ProtocolError(ValueError):
    """A message the server refuses; its text is the one-line ``error`` sent back."""


def _number(
    msg: dict, key: str, *, low: float | None = None, high: float | None = None, positive: bool = False
) -> float:
    value = msg.get(key)
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise ProtocolError(f"{key}: must be a number")
    if positive and value <= 0:
        raise ProtocolError(f"{key}: must be > 0")
    if low is not None and value < low or high is not None and value > high:
        raise ProtocolError(f"{key}: must be within {low:g}..{high:g}")
    return float(value)


def _vector(value: object, key: str) -> list[float]:
    if (
        not isinstance(value, list)
        or len(value) != 3
        or not all(
            isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) and abs(v) < 10.0
            for v in value
        )
    ):
        raise ProtocolError(f"{key}: must be three numbers (m, within 10 m)")
    return [float(v) for v in value]


def file_field(value: object, key: str, suffixes: tuple[str, ...]) -> dict:
    """``{"name": ..., "text": ...}``: a file the page sends, its name a plain file name.

    >>> file_field({"name": "mylab.c", "text": "void lab(){}"}, "lab", (".c", ".cpp"))["name"]
    'mylab.c'
    >>> file_field({"name": "../etc/passwd.c", "text": ""}, "lab", (".c",))
    Traceback (most recent call last):
    ...
    crslab.serve.page_messages.ProtocolError: lab: '../etc/passwd.c' is not a plain file name (letters, ...)
    """
    if not isinstance(value, dict) or set(value) != {"name", "text"}:
        raise ProtocolError(f'{key}: must be {{"name": ..., "text": ...}}')
    name, text = value["name"], value["text"]
    if not isinstance(name, str) or not _FILE_NAME.match(name) or name in (".", ".."):
        raise ProtocolError(f"{key}: {name!r} is not a plain file name (letters, digits, _ . - and spaces)")
    if not name.endswith(suffixes):
        raise ProtocolError(f"{key}: {name} must end in {' or '.join(suffixes)}")
    if not isinstance(text, str):
        raise ProtocolError(f"{key}: text must be a string")
    if len(text) > MAX_FILE_CHARS:
        raise ProtocolError(f"{key}: {name} is longer than {MAX_FILE_CHARS} characters")
    return {"name": name, "text": text}


def _speed(msg: dict) -> float | None:
    value = msg.get("speed")
    if value is None:
        return None
    if (
        isinstance(value, bool)
        or not isinstance(value, (int, float))
        or not math.isfinite(value)
        or not 0 < value <= MAX_SPEED
    ):
        raise ProtocolError("speed: must be a number > 0 (x real time) or null (as fast as possible)")
    return float(value)


def _only(msg: dict, allowed: set[str]) -> None:
    extra = sorted(set(msg) - allowed - {"type"})
    if extra:
        raise ProtocolError(f"{msg['type']}: unknown field{'s' * (len(extra) > 1)} {', '.join(extra)}")


def _run(msg: dict) -> dict:
    _only(msg, {"lab", "scenario", "speed", "offsets", "no_startup_delay", "duration", "record", "world",
                "contest"})
    out: dict[str, Any] = {"type": "run", "lab": file_field(msg.get("lab"), "lab", (".c", ".cpp"))}
    scenario = msg.get("scenario", {"name": "tour"})
    if not isinstance(scenario, dict) or len(scenario) != 1 or not ({"name", "file"} & set(scenario)):
        raise ProtocolError('scenario: must be {"name": NAME} or {"file": {"name": ..., "text": ...}}')
    if "name" in scenario:
        if not isinstance(scenario["name"], str) or not re.match(r"^\w{1,64}$", scenario["name"]):
            raise ProtocolError("scenario: name must be a built-in scenario's name")
        out["scenario"] = {"name": scenario["name"]}
    else:
        out["scenario"] = {"file": file_field(scenario["file"], "scenario", (".toml",))}
    out["speed"] = _speed(msg)
    offsets = msg.get("offsets")
    if offsets is not None:
        if (
            not isinstance(offsets, list)
            or len(offsets) != 2
            or not all(
                isinstance(v, (int, float))
                and not isinstance(v, bool)
                and math.isfinite(v)
                and abs(v) <= 2 * math.pi
                for v in offsets
            )
        ):
            raise ProtocolError("offsets: must be two motor angles [O2, O3] in rad (within 2 pi)")
        offsets = [float(v) for v in offsets]
    out["offsets"] = offsets
    delay = msg.get("no_startup_delay", False)
    if not isinstance(delay, bool):
        raise ProtocolError("no_startup_delay: must be true or false")
    out["no_startup_delay"] = delay
    out["duration"] = None if msg.get("duration") is None else _number(msg, "duration", positive=True)
    record = msg.get("record", {})
    if (
        not isinstance(record, dict)
        or set(record) - {"csv", "rrd"}
        or not all(isinstance(v, bool) for v in record.values())
    ):
        raise ProtocolError('record: must be {"csv": true|false, "rrd": true|false}')
    out["record"] = {"csv": record.get("csv", False), "rrd": record.get("rrd", False)}
    world = msg.get("world", "none")
    if world not in WORLD_NAMES:
        raise ProtocolError(f"world: must be one of {', '.join(WORLD_NAMES)}")
    out["world"] = world
    contest = msg.get("contest", False)
    if not isinstance(contest, bool):
        raise ProtocolError("contest: must be true or false")
    out["contest"] = contest
    return out


def _vars(msg: dict) -> dict:
    _only(msg, {"cmd", "name", "index", "value"})
    cmd = msg.get("cmd")
    if cmd not in ("list", "get", "set"):
        raise ProtocolError("vars: cmd must be list, get or set")
    out: dict[str, Any] = {"type": "vars", "cmd": cmd, "name": None, "index": None, "value": None}
    if cmd == "list":
        return out
    name = msg.get("name")
    if not isinstance(name, str) or not re.match(r"^[A-Za-z_]\w{0,127}$", name):
        raise ProtocolError("vars: name must be a C identifier")
    out["name"] = name
    index = msg.get("index")
    if index is not None and (isinstance(index, bool) or not isinstance(index, int) or index < 0):
        raise ProtocolError("vars: index must be a whole number >= 0")
    out["index"] = index
    if cmd == "set":
        out["value"] = _number(msg, "value")
    return out


def parse_message(text: str | bytes) -> dict:
    """One message from the page, checked and normalized; :class:`ProtocolError` otherwise."""
    if len(text) > MAX_MESSAGE_BYTES:
        raise ProtocolError(f"message longer than {MAX_MESSAGE_BYTES} bytes")
    try:
        msg = json.loads(text)
    except (ValueError, UnicodeDecodeError):
        raise ProtocolError("not JSON: every message is one JSON object with a type") from None
    if not isinstance(msg, dict) or not isinstance(msg.get("type"), str):
        raise ProtocolError("every message is one JSON object with a type")
    kind = msg["type"]
    if kind not in TYPES:
        raise ProtocolError(f"unknown message type {kind[:40]!r} ({', '.join(TYPES)})")
    if kind in ("stop", "release"):
        _only(msg, set())
        return {"type": kind}
    if kind == "build":
        _only(msg, {"lab"})
        return {"type": "build", "lab": file_field(msg.get("lab"), "lab", (".c", ".cpp"))}
    if kind == "run":
        return _run(msg)
    if kind == "speed":
        _only(msg, {"speed"})
        return {"type": "speed", "speed": _speed(msg)}
    if kind == "vars":
        return _vars(msg)
    if kind == "hand":
        _only(msg, {"body", "anchor", "target"})
        if msg.get("body") not in BODIES:
            raise ProtocolError(f"hand: body must be one of {', '.join(BODIES)}")
        return {
            "type": "hand",
            "body": msg["body"],
            "anchor": _vector(msg.get("anchor"), "anchor"),
            "target": _vector(msg.get("target"), "target"),
        }
    _only(msg, {"lab", "golden"})  # check
    return {"type": "check", "lab": file_field(msg.get("lab"), "lab", (".c", ".cpp")),
            "golden": file_field(msg.get("golden"), "golden", (".txt", ".golden"))}


def compile_diagnostics(text: str, file_name: str) -> list[dict]:
    """The compiler's messages about ``file_name`` as editor markers: line, column, severity, text.

    >>> marks = compile_diagnostics("/tmp/x/lab.c: In function 'lab':\\n"
    ...     "/tmp/x/lab.c:12:5: error: 'tau' undeclared (first use in this function)\\n"
    ...     "/tmp/x/lab.c:20:1: warning: unused variable 'k' [-Wunused-variable]\\n"
    ...     "/usr/include/math.h:3:1: note: elsewhere\\n", "lab.c")
    >>> [(m["line"], m["column"], m["severity"]) for m in marks]
    [(12, 5, 'error'), (20, 1, 'warning')]
    >>> marks[0]["message"]
    "'tau' undeclared (first use in this function)"
    """
    pattern = re.compile(
        r"^(?:.*/)?" + re.escape(file_name) + r":(\d+):(?:(\d+):)?\s*(fatal error|error|warning):\s*(.*)$"
    )
    out = []
    for line in text.splitlines():
        m = pattern.match(line)
        if m:
            severity = "error" if "error" in m.group(3) else "warning"
            out.append(
                {
                    "line": int(m.group(1)),
                    "column": int(m.group(2) or 1),
                    "severity": severity,
                    "message": m.group(4).strip(),
                }
            )
    return out


def habit_diagnostics(habits: tuple[str, ...] | list[str], file_name: str) -> list[dict]:
    """The C89 habits a lab built with (``file:line: what the board does``, :mod:`crslab.lab.c89_habits`)
    as warning markers at their lines, each saying it as ``crslab sim`` does (the file by its name).

    >>> [m] = habit_diagnostics(["/tmp/s/lab.c:24: malloc() is called with no declaration"], "lab.c")
    >>> (m["line"], m["severity"], m["message"])
    (24, 'warning', 'lab.c:24: malloc() is called with no declaration')
    """
    out = []
    for habit in habits:
        m = re.match(r"^.*?:(\d+): (.*)$", habit)
        if m:
            line = int(m.group(1))
            out.append({"line": line, "column": 1, "severity": "warning",
                        "message": f"{file_name}:{line}: {m.group(2)}"})
    return out
