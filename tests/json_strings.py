"""Every text inside a decoded JSON value: what the hostile-text tests read out of a report or a
page message, wherever it is nested."""

from __future__ import annotations


def json_strings(value: object) -> list[str]:
    """The strings in ``value`` (dicts' values and lists' items, at any depth), in order.

    >>> json_strings({"a": ["x", {"b": "y"}, 3], "c": None})
    ['x', 'y']
    """
    if isinstance(value, str):
        return [value]
    if isinstance(value, dict):
        return [s for v in value.values() for s in json_strings(v)]
    if isinstance(value, list):
        return [s for v in value for s in json_strings(v)]
    return []
