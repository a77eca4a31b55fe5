"""Reading a world file: a built-in world's name or a TOML file, checked key by key by crslab's one
reader of input files (:mod:`crslab.toml_file`), then as a whole (the fixtures fit together, the
arm reaches them: :mod:`crslab.world.layout_checks`). Anything wrong is one :class:`WorldError`
line ``FILE:LINE: KEY: problem``; docs/worlds.md lists every key.

>>> w = load_world("contest")
>>> w.hole.center_xy_m, w.egg.breaking_force_n, w.contest.band_g
((0.034, 0.35), 25.0, (500.0, 1000.0))
>>> load_world("none").fixtures()
()
"""

from __future__ import annotations

from dataclasses import MISSING, dataclass, fields, replace
from pathlib import Path

from crslab import resources
from crslab.plant.model_files import REST_MOTOR_RAD
from crslab.toml_file import Table, TomlFile
from crslab.world.fixtures import (
    LONGEST_RUN_S,
    Contact,
    ContestRules,
    Egg,
    Groove,
    Hole,
    Obstacle,
    Peg,
    Triple,
    World,
)
from crslab.world.fixtures import (
    Table as TableFixture,
)
from crslab.world.layout_checks import arm_link_radius_m, check_layout, corner_turns_deg

WORLD_NAMES = ("none", "contest")
"""The worlds crslab carries (``crslab/worlds/NAME.toml``)."""
MAX_CORNER_TURN_DEG = 150.0
"""The groove's centre line may turn at most this much at a corner (more, and the channel's
mitre there runs out far past the corner)."""


class WorldError(ValueError):
    """A world file that cannot be used; its text is one line, ``FILE:LINE: KEY: problem``."""


@dataclass(frozen=True)
class _Kind:
    """What one key of a table holds: a number (``count`` 0), a list of ``count`` numbers, or
    (``points``) of ``count`` [x, y] points, or true/false (``boolean``); each number within
    ``minimum``..``maximum`` (above 0 when ``positive``)."""

    count: int = 0
    positive: bool = False
    minimum: float | None = None
    maximum: float | None = None
    points: bool = False
    boolean: bool = False

    def read(self, t: Table, key: str, default: object) -> object:
        """``key`` of ``t``, checked; ``default`` (the field's) when the table leaves it out."""
        if self.boolean:
            return t.boolean(key) if key in t else default
        if self.points:
            return t.points(key, self.count, minimum=self.minimum, maximum=self.maximum)
        kw = {"minimum": self.minimum, "maximum": self.maximum, "positive": self.positive}
        if self.count:
            return t.numbers(key, self.count, default=default, **kw)  # type: ignore[arg-type]
        return t.number(key, default=default, **kw)  # type: ignore[arg-type]


_Z = _Kind(minimum=-1.0, maximum=2.0)  # a height, m
_LENGTH = _Kind(positive=True, maximum=1.0)  # a size, m
_XY = _Kind(2, minimum=-1.0, maximum=1.0)  # a place on the table, m
_STIFFNESS = _Kind(minimum=100.0, maximum=1e8)  # N/m
_HOLD = _Kind(positive=True, maximum=LONGEST_RUN_S)  # s: a hold within the longest contest run
_FIELDS: dict[str, tuple[type, dict[str, _Kind]]] = {
    "table": (TableFixture, {"top_z_m": _Z, "size_m": _Kind(3, positive=True, maximum=10.0)}),
    "peg": (
        Peg,
        {
            "diameter_m": _LENGTH,
            "length_m": _LENGTH,
            "mass_kg": _Kind(minimum=0.001, maximum=1.0),
            "wrist_above_tip_m": _LENGTH,
            "gripper_diameter_m": _LENGTH,
        },
    ),
    "hole": (
        Hole,
        {
            "center_xy_m": _XY,
            "top_z_m": _Z,
            "diameter_m": _LENGTH,
            "depth_m": _LENGTH,
            "chamfer_m": _Kind(minimum=0.0, maximum=0.1),
            "block_size_xy_m": _Kind(2, positive=True, maximum=1.0),
        },
    ),
    "obstacle": (
        Obstacle,
        {"center_xy_m": _XY, "top_z_m": _Z, "size_xy_m": _Kind(2, positive=True, maximum=1.0)},
    ),
    "groove": (
        Groove,
        {
            "corners_xy_m": _Kind(4, points=True, minimum=-1.0, maximum=1.0),
            "top_z_m": _Z,
            "width_m": _LENGTH,
            "depth_m": _LENGTH,
            "rim_m": _LENGTH,
            "plate_thickness_m": _LENGTH,
        },
    ),
    "egg": (
        Egg,
        {
            "center_xy_m": _XY,
            "top_z_m": _Z,
            "diameter_m": _LENGTH,
            "height_m": _LENGTH,
            "shell_stiffness_n_per_m": _STIFFNESS,
            "breaking_force_n": _Kind(positive=True, maximum=1e4),
            "scale_diameter_m": _LENGTH,
            "scale_height_m": _LENGTH,
            "scale_stiffness_n_per_m": _STIFFNESS,
        },
    ),
    "contact": (
        Contact,
        {
            "friction": _Kind(minimum=0.0, maximum=2.0),
            "rigid_timeconst_s": _Kind(minimum=0.002, maximum=1.0),
            "rigid_impedance": _Kind(positive=True, maximum=0.9999),
            "egg_damping_ratio": _Kind(positive=True, maximum=10.0),
        },
    ),
    "contest": (
        ContestRules,
        {
            "band_g": _Kind(2, positive=True, maximum=1e5),
            "hold_s": _HOLD,
            "hold_tolerance_s": _Kind(minimum=0.0, maximum=LONGEST_RUN_S),
            "peg_min_depth_m": _Kind(minimum=0.0, maximum=1.0),
            "peg_hold_s": _HOLD,
            "groove_min_share": _Kind(positive=True, maximum=1.0),
            "obstacle_around": _Kind(boolean=True),
        },
    ),
}
"""Each table of a world file: the fixture it makes and what each of its keys holds, in the
fixture's field order (a key whose field has a default may be left out)."""
TOP_KEYS = ("name", *_FIELDS)


def _builtin_path(name: str) -> Path:
    return resources.path("worlds", f"{name}.toml")


def world_file(name_or_path: str | Path) -> tuple[Path, str]:
    """The file of a built-in world's name (``none``, ``contest``) or of a path, and the name errors
    give it (the built-in's name, or the path as given)."""
    text = str(name_or_path)
    if text in WORLD_NAMES:
        return _builtin_path(text), text
    path = Path(name_or_path)
    if not path.is_file():
        raise WorldError(
            f"{text}: no such world file or built-in world (built-ins: {', '.join(WORLD_NAMES)})"
        )
    return path, text


def load_world(name_or_path: str | Path, *, rest_motor_rad: Triple = REST_MOTOR_RAD) -> World:
    """Read and check a world (a built-in's name or a TOML file): :class:`WorldError` names file,
    line and key for anything wrong, a fixture that overlaps the arm at ``rest_motor_rad`` or that
    the peg cannot reach included.

    >>> load_world("mars")
    Traceback (most recent call last):
    ...
    crslab.world.world_file.WorldError: mars: no such world file or built-in world (built-ins: none, contest)
    """
    path, source = world_file(name_or_path)
    doc = TomlFile.read(path, "world file", WorldError, shown_as=source)
    world = _world(doc)
    check_layout(world, rest_motor_rad, lambda table, why: doc.fail((table,), why))
    return world


def parse_world(text: str, source: str, *, rest_motor_rad: Triple = REST_MOTOR_RAD) -> World:
    """The world in TOML ``text`` (``source`` names it in errors), checked as :func:`load_world`
    checks a file.

    >>> parse_world('name = "w"\\n[obstacle]\\ncenter_xy_m = [0.2, 0.1]\\n', "w.toml")
    Traceback (most recent call last):
    ...
    crslab.world.world_file.WorldError: w.toml:2: obstacle.top_z_m: missing
    >>> parse_world('name = "w"\\n[egg]\\nheight = 2\\n', "w.toml")
    Traceback (most recent call last):
    ...
    crslab.world.world_file.WorldError: w.toml:3: egg.height: unknown key (allowed: breaking_force_n, ...)
    """
    doc = TomlFile.parse(text, source, WorldError)
    world = _world(doc)
    check_layout(world, rest_motor_rad, lambda table, why: doc.fail((table,), why))
    return world


def _world(doc: TomlFile) -> World:
    """The world of a checked TOML file, each table's values and their fit checked."""
    doc.table().check_keys(TOP_KEYS)
    name = doc.data.get("name", Path(doc.source).stem)
    if not isinstance(name, str) or not name:
        raise doc.fail(("name",), f"must be a non-empty string, got {name!r}")
    world = World(name=name, source=doc.source)
    for key, (cls, kinds) in _FIELDS.items():
        if key not in doc.data:
            continue
        t = doc.table((key,), key)
        optional = {
            f.name for f in fields(cls) if f.default is not MISSING or f.default_factory is not MISSING
        }
        t.check_keys(set(kinds), required=[k for k in kinds if k not in optional])
        defaults = {f.name: f.default for f in fields(cls) if f.default is not MISSING}
        world = replace(
            world, **{key: cls(**{k: kind.read(t, k, defaults.get(k)) for k, kind in kinds.items()})}
        )
    _check_fit(world, doc)
    return world


def _check_fit(world: World, doc: TomlFile) -> None:
    """What each table's values must satisfy together, and with the peg and the table."""

    def fail(table: str, key: str | None, why: str) -> WorldError:
        return doc.fail((table, key) if key else (table,), why)  # type: ignore[return-value]

    peg, floor = world.peg, world.floor_z_m
    needing = [n for n in ("hole", "groove", "egg") if getattr(world, n) is not None]
    if peg is None and needing:
        raise fail(needing[0], None, "needs a [peg] table (the peg is what goes in it)")
    if peg is not None:
        if peg.length_m <= peg.diameter_m:
            raise fail("peg", "length_m", f"{peg.length_m:g} m is not longer than the peg is wide")
        forearm = arm_link_radius_m("forearm")
        if peg.wrist_above_tip_m < peg.length_m + forearm:
            raise fail(
                "peg",
                "wrist_above_tip_m",
                f"{peg.wrist_above_tip_m:g} m leaves the forearm ({1000 * forearm:.0f} mm round its "
                f"axis) lower than the peg's top ({peg.length_m:g} m above the tip): at least "
                f"{peg.length_m + forearm:g} m, nothing of the arm below the tip",
            )
    if (h := world.hole) is not None:
        assert peg is not None
        if h.diameter_m <= peg.diameter_m:
            raise fail(
                "hole", "diameter_m", f"{h.diameter_m:g} m is not wider than the peg ({peg.diameter_m:g} m)"
            )
        mouth = h.diameter_m + 2 * h.chamfer_m
        if mouth >= min(h.block_size_xy_m):
            raise fail(
                "hole",
                "block_size_xy_m",
                f"the block ({h.block_size_xy_m[0]:g} x {h.block_size_xy_m[1]:g}"
                f" m) is not wider than the hole's mouth ({mouth:g} m)",
            )
        if h.chamfer_m >= h.depth_m:
            raise fail("hole", "chamfer_m", f"{h.chamfer_m:g} m is not smaller than the hole is deep")
        if h.top_z_m - h.depth_m <= floor:
            raise fail(
                "hole",
                "depth_m",
                f"{h.depth_m:g} m reaches the table (the block's top is {h.top_z_m - floor:g} m above it)",
            )
    if (o := world.obstacle) is not None and o.top_z_m <= floor:
        raise fail("obstacle", "top_z_m", f"{o.top_z_m:g} m is not above the table ({floor:g} m)")
    if (g := world.groove) is not None:
        assert peg is not None
        if g.width_m <= peg.diameter_m:
            raise fail(
                "groove", "width_m", f"{g.width_m:g} m is not wider than the peg ({peg.diameter_m:g} m)"
            )
        if g.depth_m >= g.plate_thickness_m:
            raise fail(
                "groove",
                "depth_m",
                f"{g.depth_m:g} m is not shallower than the plate is thick ({g.plate_thickness_m:g} m)",
            )
        if g.top_z_m - g.plate_thickness_m < floor - 1e-9:
            raise fail(
                "groove",
                "plate_thickness_m",
                f"the plate ({g.plate_thickness_m:g} m thick) would reach "
                f"below the table from its top at {g.top_z_m:g} m",
            )
        c = g.corners_xy_m
        for i in range(3):
            length = ((c[i + 1][0] - c[i][0]) ** 2 + (c[i + 1][1] - c[i][1]) ** 2) ** 0.5
            if length < g.width_m:
                raise fail(
                    "groove",
                    "corners_xy_m",
                    f"segment {i + 1} ({list(c[i])} to {list(c[i + 1])}) is shorter than the groove is wide",
                )
        for i, turn in enumerate(corner_turns_deg(c)):
            if turn > MAX_CORNER_TURN_DEG:
                raise fail(
                    "groove",
                    "corners_xy_m",
                    f"the centre line turns {turn:.0f} degrees at corner {i + 1}"
                    f" (at most {MAX_CORNER_TURN_DEG:.0f}): the channel would fold over itself",
                )
    if (e := world.egg) is not None:
        if e.scale_top_z_m - e.scale_height_m < floor - 1e-9:
            raise fail(
                "egg",
                "scale_height_m",
                "the scale would stand below the table: the egg's top is lower "
                "than the egg and the scale are tall",
            )
        if e.diameter_m >= e.scale_diameter_m:
            raise fail(
                "egg",
                "scale_diameter_m",
                f"{e.scale_diameter_m:g} m is not wider than the egg ({e.diameter_m:g} m)",
            )
    ru = world.contest
    if ru.band_g[0] >= ru.band_g[1]:
        raise fail("contest", "band_g", f"must be [low, high] with low < high, got {list(ru.band_g)}")
    if world.hole is not None and ru.peg_min_depth_m >= world.hole.depth_m:
        raise fail(
            "contest",
            "peg_min_depth_m",
            f"{ru.peg_min_depth_m:g} m is not shallower than the hole ({world.hole.depth_m:g} m deep)",
        )
    if ru.hold_tolerance_s >= ru.hold_s:
        raise fail(
            "contest",
            "hold_tolerance_s",
            f"{ru.hold_tolerance_s:g} s is not shorter than the hold ({ru.hold_s:g} s)",
        )
    if ru.peg_hold_s <= ru.hold_tolerance_s:
        raise fail(
            "contest",
            "peg_hold_s",
            f"{ru.peg_hold_s:g} s is not longer than hold_tolerance_s ({ru.hold_tolerance_s:g} s), what a "
            "TA lets pass short of each hold",
        )
