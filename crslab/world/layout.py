"""World files: where the fixtures the arm touches stand, how big they are, what they are made of.

A world file is TOML (``crslab/worlds/none.toml``, ``crslab/worlds/contest.toml``; docs/worlds.md):
a table per fixture (``[table]``, ``[peg]``, ``[hole]``, ``[obstacle]``, ``[groove]``, ``[egg]``),
the contact materials (``[contact]``) and the contest's rules (``[contest]``). Units are SI (m, kg,
N, N/m); positions are in the arm's base frame, the frame of the course's forward kinematics
(:mod:`crslab.crs`). :func:`load_world` reads one by name or path and checks it: anything wrong is
one :class:`WorldError` line ``FILE:LINE: KEY: problem``, and so is a fixture that overlaps the
arm at its resting pose or that the peg cannot reach.

>>> w = load_world("contest")
>>> w.hole.center_xy_m, w.egg.breaking_force_n, w.contest.band_g
((0.034, 0.35), 20.0, (500.0, 1000.0))
>>> load_world("none").fixtures()
()
"""

from __future__ import annotations

import re
import tomllib
import xml.etree.ElementTree as ET
from dataclasses import MISSING, dataclass, field, fields, replace
from pathlib import Path

import numpy as np

from crslab import crs, resources
from crslab.plant.model_files import ARM_XML, REST_MOTOR_RAD

WORLD_NAMES = ("none", "contest")
"""The worlds crslab carries (``crslab/worlds/NAME.toml``)."""
DEFAULT_WORLD = "none"
"""The world of every command but ``crslab contest``: free air, as crslab always simulated."""

Pair = tuple[float, float]
Triple = tuple[float, float, float]


class WorldError(ValueError):
    """A world file that cannot be used; its text is one line, ``FILE:LINE: KEY: problem``."""


@dataclass(frozen=True)
class Table:
    """The table the arm and the fixtures stand on; its top is at ``top_z_m``."""

    top_z_m: float
    size_m: Triple


@dataclass(frozen=True)
class Peg:
    """The peg the arm holds, always vertical (a wrist keeps it so): its tip is the course's
    end-effector point plus ``tip_offset_m`` (m, in the world frame at waist angle 0: it turns with
    the waist); it rises ``length_m`` from the tip."""

    diameter_m: float
    length_m: float
    mass_kg: float
    tip_offset_m: Triple = (0.0, 0.0, 0.0)


@dataclass(frozen=True)
class Hole:
    """A block with a vertical round hole ``diameter_m`` wide and ``depth_m`` deep from its top,
    its mouth widened by a 45-degree chamfer ``chamfer_m`` wide; the block stands on the table."""

    center_xy_m: Pair
    top_z_m: float
    diameter_m: float
    depth_m: float
    chamfer_m: float
    block_size_m: Triple


@dataclass(frozen=True)
class Obstacle:
    """A box: its centre and full extents."""

    center_m: Triple
    size_m: Triple


@dataclass(frozen=True)
class Groove:
    """A Z-shaped channel ``width_m`` wide and ``depth_m`` deep cut into the top of a plate, along the
    segments entrance -> corner 1 -> corner 2 -> exit; the plate (``plate_size_m``, centred on the
    corners) stands on the table."""

    corners_xy_m: tuple[Pair, Pair, Pair, Pair]
    top_z_m: float
    width_m: float
    depth_m: float
    plate_size_m: Triple

    @property
    def plate_center_xy_m(self) -> Pair:
        """The plate's centre: the middle of the corners' bounding box."""
        c = np.asarray(self.corners_xy_m)
        mid = (c.min(axis=0) + c.max(axis=0)) / 2
        return (float(mid[0]), float(mid[1]))


@dataclass(frozen=True)
class Egg:
    """An egg standing on a scale (``scale_size_m``), the scale on a stand on the table. The egg's
    contact with what presses it is a spring of ``stiffness_n_per_m`` (shell and scale in series);
    past ``breaking_force_n`` it breaks, for the rest of the run."""

    center_xy_m: Pair
    top_z_m: float
    diameter_m: float
    height_m: float
    stiffness_n_per_m: float
    breaking_force_n: float
    scale_size_m: Triple

    @property
    def scale_top_z_m(self) -> float:
        """Where the egg stands: the scale's top."""
        return self.top_z_m - self.height_m


@dataclass(frozen=True)
class Contact:
    """The contact materials: Coulomb ``friction`` of the peg on every fixture; the rigid fixtures'
    MuJoCo time constant and impedance; the egg's damping ratio (docs/worlds.md)."""

    friction: float = 0.4
    rigid_timeconst_s: float = 0.004
    rigid_impedance: float = 0.99
    egg_damping_ratio: float = 1.0


@dataclass(frozen=True)
class ContestRules:
    """The final project's contest: the egg's force band (grams on the scale) held ``hold_s``; the
    peg at least ``peg_min_depth_m`` in the hole for ``peg_hold_s``; the share of the groove's path
    the peg must stay inside."""

    band_g: Pair = (500.0, 1000.0)
    hold_s: float = 2.0
    peg_min_depth_m: float = 0.02
    peg_hold_s: float = 0.5
    groove_min_share: float = 0.9


@dataclass(frozen=True)
class World:
    """One world: the fixtures the arm may touch (None: not there). ``source`` is the file's path,
    or the built-in world's name."""

    name: str
    source: str
    table: Table | None = None
    peg: Peg | None = None
    hole: Hole | None = None
    obstacle: Obstacle | None = None
    groove: Groove | None = None
    egg: Egg | None = None
    contest: ContestRules | None = None
    contact: Contact = field(default_factory=Contact)

    @property
    def is_free_air(self) -> bool:
        """True for a world with nothing in it (``none``): the arm's own scene, unchanged."""
        return not self.fixtures() and self.peg is None

    def fixtures(self) -> tuple[str, ...]:
        """The names of the fixtures this world has, in file order."""
        return tuple(
            n for n in ("table", "hole", "obstacle", "groove", "egg") if getattr(self, n) is not None
        )


FREE_AIR = World(name="none", source="none")
"""World ``none``: nothing but the arm, as ``crslab/worlds/none.toml`` says."""


# -- reading -----------------------------------------------------------------------------------

_HEADER = re.compile(r"^\s*\[\s*([A-Za-z_]+)\s*\]\s*(#.*)?$")


class _Reader:
    """The tables of one world file and the lines they stand on, for errors naming both."""

    def __init__(self, source: str, text: str) -> None:
        self.source = source
        self.lines = text.splitlines()
        self.headers = {m.group(1): i for i, line in enumerate(self.lines) if (m := _HEADER.match(line))}

    def line_of(self, table: str | None, key: str | None) -> int | None:
        """1-based line of ``key`` in ``table`` (None: the top level), else of the table's header."""
        if table is None and key in self.headers:  # a table: its header
            return self.headers[key] + 1
        start = 0 if table is None else self.headers.get(table)
        if start is None:
            return None
        if key is not None:
            pattern = re.compile(rf'^\s*"?{re.escape(key)}"?\s*=')
            for i in range(start, len(self.lines)):
                if i > start and self.lines[i].lstrip().startswith("["):
                    break
                if pattern.match(self.lines[i]):
                    return i + 1
        return start + 1 if table is not None else None

    def fail(self, table: str | None, key: str | None, why: str) -> WorldError:
        line = self.line_of(table, key)
        where = f"{self.source}:{line}" if line else self.source
        name = ".".join(k for k in (table, key) if k)
        return WorldError(f"{where}: {name}: {why}" if name else f"{where}: {why}")


class _Table:
    """One table of a world file, each value read with its type checked."""

    def __init__(
        self,
        reader: _Reader,
        name: str,
        values: object,
        keys: tuple[str, ...],
        optional: tuple[str, ...] = (),
    ) -> None:
        self.r, self.name = reader, name
        if not isinstance(values, dict):
            raise reader.fail(None, name, f"must be a table ([{name}])")
        self.values = values
        for key in values:
            if key not in keys:
                raise reader.fail(name, key, f"unknown key (allowed: {', '.join(keys)})")
        for key in keys:
            if key not in values and key not in optional:
                raise reader.fail(name, key, "missing")

    def fail(self, key: str, why: str) -> WorldError:
        return self.r.fail(self.name, key, why)

    def number(
        self, key: str, *, positive: bool = False, minimum: float | None = None, default: float | None = None
    ) -> float:
        if key not in self.values and default is not None:
            return default
        v = self.values[key]
        if isinstance(v, bool) or not isinstance(v, int | float) or not np.isfinite(v):
            raise self.fail(key, f"must be a number, got {v!r}")
        if positive and not v > 0:
            raise self.fail(key, f"must be > 0, got {v!r}")
        if minimum is not None and v < minimum:
            raise self.fail(key, f"must be at least {minimum:g}, got {v!r}")
        return float(v)

    def numbers(self, key: str, n: int, *, positive: bool = False, default: tuple | None = None) -> tuple:
        if key not in self.values and default is not None:
            return default
        v = self.values[key]
        if (
            not isinstance(v, list)
            or len(v) != n
            or not all(isinstance(x, int | float) and not isinstance(x, bool) and np.isfinite(x) for x in v)
        ):
            raise self.fail(key, f"must be a list of {n} numbers, got {v!r}")
        if positive and not all(x > 0 for x in v):
            raise self.fail(key, f"must be {n} numbers > 0, got {v!r}")
        return tuple(float(x) for x in v)

    def points(self, key: str, n: int) -> tuple:
        v = self.values[key]
        if not isinstance(v, list) or len(v) != n:
            raise self.fail(key, f"must be a list of {n} [x, y] points, got {v!r}")
        out = []
        for p in v:
            if (
                not isinstance(p, list)
                or len(p) != 2
                or not all(
                    isinstance(x, int | float) and not isinstance(x, bool) and np.isfinite(x) for x in p
                )
            ):
                raise self.fail(key, f"must be a list of {n} [x, y] points, got {v!r}")
            out.append((float(p[0]), float(p[1])))
        return tuple(out)


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
    crslab.world.layout.WorldError: mars: no such world file or built-in world (built-ins: none, contest)
    """
    path, source = world_file(name_or_path)
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise WorldError(f"{source}: cannot be read ({exc})") from None
    world = parse_world(text, source)
    check_world(world, text, rest_motor_rad)
    return world


def parse_world(text: str, source: str) -> World:
    """The world in TOML ``text`` (``source`` names it in errors), each value's type and range checked.

    >>> parse_world('name = "w"\\n[obstacle]\\ncenter_m = [0.2, 0.1, 0.1]\\n', "w.toml")
    Traceback (most recent call last):
    ...
    crslab.world.layout.WorldError: w.toml:2: obstacle.size_m: missing
    >>> parse_world('name = "w"\\n[egg]\\nheight = 2\\n', "w.toml")
    Traceback (most recent call last):
    ...
    crslab.world.layout.WorldError: w.toml:3: egg.height: unknown key (allowed: center_xy_m, top_z_m, ...)
    """
    r = _Reader(source, text)
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        m = re.search(r"\(at line (\d+)", str(exc))
        where = f"{source}:{m.group(1)}" if m else source
        raise WorldError(f"{where}: not valid TOML: {str(exc).split(' (at line')[0]}") from None
    top_keys = ("name", "table", "peg", "hole", "obstacle", "groove", "egg", "contact", "contest")
    for key in doc:
        if key not in top_keys:
            raise r.fail(None, key, f"unknown key (allowed: {', '.join(top_keys)})")
    name = doc.get("name", Path(source).stem)
    if not isinstance(name, str) or not name:
        raise r.fail(None, "name", f"must be a non-empty string, got {name!r}")

    world = World(name=name, source=source)
    for key, (cls, kinds) in _FIXTURE_FIELDS.items():  # in file order: a hole's check needs the peg
        if key not in doc:
            continue
        optional = tuple(f.name for f in fields(cls) if f.default is not MISSING)
        t = _Table(r, key, doc[key], tuple(kinds), optional)
        value = cls(**{name: kind.read(t, name, getattr(cls, name, None)) for name, kind in kinds.items()})
        _CHECKS.get(key, _no_check)(t, value, world.peg)
        world = replace(world, **{key: value})
    if world.peg is None:
        needing = [n for n in ("hole", "groove", "egg") if getattr(world, n) is not None]
        if needing:
            raise r.fail(needing[0], None, "needs a [peg] table (the peg is what goes in it)")
    return world


@dataclass(frozen=True)
class _Kind:
    """What one key of a fixture's table holds: a number (``count`` 0), a list of ``count``
    numbers, or (``points``) of ``count`` [x, y] points; above 0 when ``positive``, at least
    ``minimum``."""

    count: int = 0
    positive: bool = False
    minimum: float | None = None
    points: bool = False

    def read(self, t: _Table, key: str, default: object) -> object:
        """``key`` of ``t``, checked; ``default`` (the field's) when the table leaves it out."""
        if self.points:
            return t.points(key, self.count)
        if self.count:
            return t.numbers(key, self.count, positive=self.positive, default=default)  # type: ignore[arg-type]
        return t.number(key, positive=self.positive, minimum=self.minimum, default=default)  # type: ignore[arg-type]


_NUMBER, _POSITIVE, _AT_LEAST_0 = _Kind(), _Kind(positive=True), _Kind(minimum=0.0)
_XY, _XYZ, _SIZE = _Kind(2), _Kind(3), _Kind(3, positive=True)
_FIXTURE_FIELDS: dict[str, tuple[type, dict[str, _Kind]]] = {
    "table": (Table, {"top_z_m": _NUMBER, "size_m": _SIZE}),
    "peg": (Peg, {"diameter_m": _POSITIVE, "length_m": _POSITIVE, "mass_kg": _POSITIVE,
                  "tip_offset_m": _XYZ}),
    "hole": (Hole, {"center_xy_m": _XY, "top_z_m": _POSITIVE, "diameter_m": _POSITIVE, "depth_m": _POSITIVE,
                    "chamfer_m": _AT_LEAST_0, "block_size_m": _SIZE}),
    "obstacle": (Obstacle, {"center_m": _XYZ, "size_m": _SIZE}),
    "groove": (Groove, {"corners_xy_m": _Kind(4, points=True), "top_z_m": _POSITIVE, "width_m": _POSITIVE,
                        "depth_m": _POSITIVE, "plate_size_m": _SIZE}),
    "egg": (Egg, {"center_xy_m": _XY, "top_z_m": _POSITIVE, "diameter_m": _POSITIVE, "height_m": _POSITIVE,
                  "stiffness_n_per_m": _POSITIVE, "breaking_force_n": _POSITIVE, "scale_size_m": _SIZE}),
    "contact": (Contact, {"friction": _AT_LEAST_0, "rigid_timeconst_s": _POSITIVE,
                          "rigid_impedance": _POSITIVE, "egg_damping_ratio": _POSITIVE}),
    "contest": (ContestRules, {"band_g": _Kind(2, positive=True), "hold_s": _POSITIVE,
                               "peg_min_depth_m": _POSITIVE, "peg_hold_s": _POSITIVE,
                               "groove_min_share": _POSITIVE}),
}
"""Each table of a world file: the fixture it makes and what each of its keys holds, in the
fixture's field order (a key with a default in the fixture's class may be left out)."""


def _no_check(t: _Table, value: object, peg: Peg | None) -> None:
    pass


def _check_peg(t: _Table, peg: Peg, _: Peg | None) -> None:
    if peg.length_m <= peg.diameter_m:
        raise t.fail("length_m", f"{peg.length_m:g} m is not longer than the peg is wide")


def _check_egg(t: _Table, egg: Egg, _: Peg | None) -> None:
    if egg.scale_top_z_m - egg.scale_size_m[2] < 0:
        raise t.fail("scale_size_m", "the scale would stand below the table: the egg's top is lower than "
                     "the egg and the scale are tall")


def _check_contact(t: _Table, contact: Contact, _: Peg | None) -> None:
    if contact.rigid_impedance >= 1:
        raise t.fail("rigid_impedance", f"must be below 1 (MuJoCo's solimp), got {contact.rigid_impedance!r}")
    if contact.rigid_timeconst_s < 0.002:
        raise t.fail("rigid_timeconst_s",
                     f"must be at least 0.002 s, twice the 1 ms step, got {contact.rigid_timeconst_s!r}")


def _check_contest(t: _Table, rules: ContestRules, _: Peg | None) -> None:
    if rules.band_g[0] >= rules.band_g[1]:
        raise t.fail("band_g", f"must be [low, high] with low < high, got {list(rules.band_g)}")
    if rules.groove_min_share > 1:
        raise t.fail("groove_min_share", f"must be at most 1, got {rules.groove_min_share!r}")


def _check_hole(t: _Table, hole: Hole, peg: Peg | None) -> None:
    if peg is not None and hole.diameter_m <= peg.diameter_m:
        raise t.fail("diameter_m", f"{hole.diameter_m:g} m is not wider than the peg ({peg.diameter_m:g} m)")
    mouth = hole.diameter_m + 2 * hole.chamfer_m
    if mouth >= min(hole.block_size_m[:2]):
        raise t.fail(
            "block_size_m",
            f"the block ({hole.block_size_m[0]:g} x {hole.block_size_m[1]:g} m) is "
            f"not wider than the hole's mouth ({mouth:g} m)",
        )
    if hole.depth_m + hole.chamfer_m >= hole.block_size_m[2]:
        raise t.fail(
            "depth_m",
            f"{hole.depth_m:g} m (with the chamfer) is not shallower than the block is "
            f"tall ({hole.block_size_m[2]:g} m)",
        )
    if hole.chamfer_m >= hole.depth_m:
        raise t.fail("chamfer_m", f"{hole.chamfer_m:g} m is not smaller than the hole is deep")
    if hole.top_z_m - hole.block_size_m[2] < -1e-9:
        raise t.fail(
            "block_size_m",
            f"the block ({hole.block_size_m[2]:g} m tall) would reach below the table "
            f"from its top at {hole.top_z_m:g} m",
        )


def _check_groove(t: _Table, groove: Groove, peg: Peg | None) -> None:
    if peg is not None and groove.width_m <= peg.diameter_m:
        raise t.fail("width_m", f"{groove.width_m:g} m is not wider than the peg ({peg.diameter_m:g} m)")
    if groove.depth_m >= groove.plate_size_m[2]:
        raise t.fail(
            "depth_m",
            f"{groove.depth_m:g} m is not shallower than the plate is thick ({groove.plate_size_m[2]:g} m)",
        )
    c = np.asarray(groove.corners_xy_m)
    for i in range(3):
        if np.linalg.norm(c[i + 1] - c[i]) < groove.width_m:
            raise t.fail(
                "corners_xy_m",
                f"segment {i + 1} ({c[i].tolist()} to {c[i + 1].tolist()}) is shorter "
                f"than the groove is wide",
            )
    half = np.asarray(groove.plate_size_m[:2]) / 2 - groove.width_m / 2
    centre = np.asarray(groove.plate_center_xy_m)
    if np.any(np.abs(c - centre) > half + 1e-12):
        raise t.fail(
            "plate_size_m",
            f"the plate ({groove.plate_size_m[0]:g} x {groove.plate_size_m[1]:g} m) "
            "does not hold the groove's corners and its width",
        )


def peg_depth_m(world: World, tip_m: Triple) -> float:
    """How deep the peg's tip (``tip_m``, m) is in the hole: below the hole's top while within its
    radius of the hole's axis (m); 0 when out, or in a world without a hole.

    >>> w = load_world("contest")
    >>> round(peg_depth_m(w, (0.034, 0.35, 0.12)), 6), peg_depth_m(w, (0.1, 0.35, 0.12))
    (0.04, 0.0)
    """
    h = world.hole
    if h is None:
        return 0.0
    off = float(np.hypot(tip_m[0] - h.center_xy_m[0], tip_m[1] - h.center_xy_m[1]))
    depth = h.top_z_m - float(tip_m[2])
    return depth if depth > 0 and off <= h.diameter_m / 2 else 0.0


# -- the fixtures as boxes, the arm as capsules: overlap and reach -------------------------------


@dataclass(frozen=True)
class Box:
    """An axis-aligned box of a fixture (what, and where: lower and upper corners, m)."""

    what: str
    table: str
    lo: Triple
    hi: Triple

    def distance(self, points: np.ndarray) -> np.ndarray:
        """Distance (m) from each point (rows) to the box; 0 inside."""
        d = np.maximum(np.maximum(np.asarray(self.lo) - points, points - np.asarray(self.hi)), 0.0)
        return np.linalg.norm(d, axis=-1)

    def where(self) -> str:
        return (
            f"x {self.lo[0]:.3f}..{self.hi[0]:.3f}, y {self.lo[1]:.3f}..{self.hi[1]:.3f}, "
            f"z {self.lo[2]:.3f}..{self.hi[2]:.3f} m"
        )


def _box(what: str, table: str, center: object, size: object) -> Box:
    c, s = np.asarray(center, float), np.asarray(size, float) / 2
    return Box(what, table, tuple(map(float, c - s)), tuple(map(float, c + s)))


@dataclass(frozen=True)
class Stand:
    """A block under a plate that stands higher than the table (the groove plate, the egg's
    scale): half the plate's footprint, from the table (or the floor, z = 0) up to the plate."""

    name: str
    """Its body's name in the scene (``groove_stand``)."""
    what: str
    """What a message calls it."""
    center_m: Triple
    size_m: Triple
    """Its full extents."""


def stands(world: World) -> dict[str, Stand]:
    """The stands of ``world``, by the table they belong to (``groove``, ``egg``)."""
    floor = world.table.top_z_m if world.table is not None else 0.0
    plates = {}  # table: (name, what, the plate's centre x y, the plate's bottom z, the plate's size)
    if (g := world.groove) is not None:
        plates["groove"] = ("groove_stand", "the groove plate's stand", g.plate_center_xy_m,
                            g.top_z_m - g.plate_size_m[2], g.plate_size_m)
    if (e := world.egg) is not None:
        plates["egg"] = ("scale_stand", "the scale's stand", e.center_xy_m,
                         e.scale_top_z_m - e.scale_size_m[2], e.scale_size_m)
    return {
        table: Stand(name, what, (*xy, (floor + bottom) / 2), (size[0] * 0.5, size[1] * 0.5, bottom - floor))
        for table, (name, what, xy, bottom, size) in plates.items()
        if bottom > floor
    }


def fixture_boxes(world: World) -> list[Box]:
    """Every fixture's solid parts as axis-aligned boxes (stands included; the table is left out:
    the arm stands on it). A box bounds the fixture; the egg's is its bounding box."""
    out = []
    under = stands(world)
    if (h := world.hole) is not None:
        out.append(
            _box(
                "the hole block", "hole", (*h.center_xy_m, h.top_z_m - h.block_size_m[2] / 2), h.block_size_m
            )
        )
    if (o := world.obstacle) is not None:
        out.append(_box("the obstacle", "obstacle", o.center_m, o.size_m))
    if (g := world.groove) is not None:
        top, size = g.top_z_m, g.plate_size_m
        out.append(_box("the groove plate", "groove", (*g.plate_center_xy_m, top - size[2] / 2), size))
        if (stand := under.get("groove")) is not None:
            out.append(_box(stand.what, "groove", stand.center_m, stand.size_m))
    if (e := world.egg) is not None:
        out.append(
            _box(
                "the egg",
                "egg",
                (*e.center_xy_m, e.top_z_m - e.height_m / 2),
                (e.diameter_m, e.diameter_m, e.height_m),
            )
        )
        scale = e.scale_size_m
        out.append(_box("the egg's scale", "egg", (*e.center_xy_m, e.scale_top_z_m - scale[2] / 2), scale))
        if (stand := under.get("egg")) is not None:
            out.append(_box(stand.what, "egg", stand.center_m, stand.size_m))
    return out


def _arm_link_radii_m() -> dict[str, float]:
    """The radii of the arm's links, as the arm's model draws them (models/crs_arm/crs_arm.xml)."""
    sizes = {g.get("name"): float(g.get("size", "0").split()[0]) for g in ET.parse(ARM_XML).iter("geom")}
    return {
        "pedestal": sizes["pedestal"],
        "waist": sizes["waist_column"],
        "upper arm": sizes["upper_arm_link"],
        "forearm": sizes["forearm_link"],
    }


def arm_points_m(motor_rad: object) -> dict[str, np.ndarray]:
    """The arm's joint centres (m) at motor angles ``motor_rad``: base, shoulder, elbow and the
    end-effector point (the course's forward kinematics, :func:`crslab.crs.fk`).

    >>> p = arm_points_m([0.0, 0.0, 0.0])      # motor zero: upper arm up, forearm level
    >>> [np.round(p[k], 4).tolist() for k in ("shoulder", "elbow", "ee")]
    [[0.0, 0.0, 0.254], [0.0, 0.0, 0.508], [0.254, 0.0, 0.508]]
    """
    q = np.asarray(motor_rad, dtype=float)
    m = crs.M_PER_IN
    shoulder = np.array([0.0, 0.0, crs.BASE_HEIGHT_IN * m])
    ee = crs.fk(q) * m
    # the upper arm: from the shoulder at motor angle 2 from the vertical, in the waist's plane
    up = (
        crs.UPPER_ARM_IN
        * m
        * np.array([np.sin(q[1]) * np.cos(q[0]), np.sin(q[1]) * np.sin(q[0]), np.cos(q[1])])
    )
    elbow = shoulder + up
    assert abs(np.linalg.norm(ee - elbow) - crs.FOREARM_IN * m) < 1e-9  # the FK's own forearm
    return {"base": np.zeros(3), "shoulder": shoulder, "elbow": elbow, "ee": ee}


def _segment(a: np.ndarray, b: np.ndarray, n: int = 400) -> np.ndarray:
    return a + np.linspace(0.0, 1.0, n)[:, None] * (b - a)


def reach_points(world: World) -> list[tuple[str, str, np.ndarray]]:
    """The points the peg's tip must reach for each fixture (what, table, xyz m): the hole at its
    top and its bottom, the groove's corners at half its depth, the egg's top, the top of the
    obstacle (passed over)."""
    out = []
    if (h := world.hole) is not None:
        out.append(("the hole's mouth", "hole", np.array([*h.center_xy_m, h.top_z_m])))
        out.append(("the hole's bottom", "hole", np.array([*h.center_xy_m, h.top_z_m - h.depth_m])))
    if (g := world.groove) is not None:
        for name, c in zip(("entrance", "first corner", "second corner", "exit"), g.corners_xy_m):
            out.append((f"the groove's {name}", "groove", np.array([*c, g.top_z_m - g.depth_m / 2])))
    if (e := world.egg) is not None:
        out.append(("the egg's top", "egg", np.array([*e.center_xy_m, e.top_z_m])))
    if (o := world.obstacle) is not None:
        out.append(
            (
                "the top of the obstacle",
                "obstacle",
                np.array([o.center_m[0], o.center_m[1], o.center_m[2] + o.size_m[2] / 2]),
            )
        )
    return out


def peg_tip_m(world: World, motor_rad: object) -> np.ndarray:
    """Where the peg's tip is (m) at motor angles ``motor_rad``: the course's end-effector point plus
    the peg's ``tip_offset_m``, which turns with the waist (it is given at waist angle 0).

    >>> peg_tip_m(load_world("contest"), [0.0, 0.0, 0.0]).round(4).tolist()
    [0.254, 0.0, 0.508]
    """
    q = np.asarray(motor_rad, dtype=float)
    offset = np.asarray(world.peg.tip_offset_m if world.peg is not None else (0.0, 0.0, 0.0))
    c, s = np.cos(q[0]), np.sin(q[0])
    turned = np.array([c * offset[0] - s * offset[1], s * offset[0] + c * offset[1], offset[2]])
    return crs.fk(q) * crs.M_PER_IN + turned


def check_world(world: World, text: str, rest_motor_rad: Triple = REST_MOTOR_RAD) -> None:
    """Refuse a world whose fixtures overlap each other, overlap the arm at its resting pose, or
    hold a point the peg cannot reach (:class:`WorldError`, naming the fixture and where)."""
    r = _Reader(world.source, text)
    boxes = fixture_boxes(world)
    for i, a in enumerate(boxes):
        for b in boxes[i + 1 :]:
            if a.table != b.table and all(
                a.lo[k] < b.hi[k] - 1e-9 and b.lo[k] < a.hi[k] - 1e-9 for k in range(3)
            ):
                raise r.fail(b.table, None, f"{b.what} ({b.where()}) overlaps {a.what} ({a.where()})")
    rest = np.asarray(rest_motor_rad, float)
    p = arm_points_m(rest)
    radii = _arm_link_radii_m()
    links = [
        ("pedestal", _segment(p["base"], p["base"] + [0, 0, 0.12]), radii["pedestal"]),
        ("waist", _segment(p["base"], p["shoulder"]), radii["waist"]),
        ("upper arm", _segment(p["shoulder"], p["elbow"]), radii["upper arm"]),
        ("forearm", _segment(p["elbow"], p["ee"]), radii["forearm"]),
    ]
    if world.peg is not None:
        tip = peg_tip_m(world, rest)  # the peg hangs vertical from its tip (crslab/world/scene.py)
        links.append(("peg", _segment(tip, tip + (0.0, 0.0, world.peg.length_m)), world.peg.diameter_m / 2))
    for box in boxes:
        for link, points, radius in links:
            d = box.distance(points)
            k = int(np.argmin(d))
            if d[k] < radius:
                near = points[k]
                raise r.fail(
                    box.table,
                    None,
                    f"{box.what} ({box.where()}) overlaps the arm's {link} at its resting "
                    f"pose (near ({near[0]:.3f}, {near[1]:.3f}, {near[2]:.3f}) m)",
                )
    for what, table, point in reach_points(world):
        offset = np.asarray(world.peg.tip_offset_m if world.peg else (0.0, 0.0, 0.0))
        q, status = crs.ik_with_status((point - offset) / crs.M_PER_IN, elbow="up")
        where = f"({point[0]:.3f}, {point[1]:.3f}, {point[2]:.3f}) m"
        if int(status) != crs.IK_OK:
            raise r.fail(
                table,
                None,
                f"{what} at {where} is out of the arm's reach ({crs.IK_STATUS_TEXT[int(status)]})",
            )
        if bool(crs.outside_envelope(q)):
            raise r.fail(
                table,
                None,
                f"{what} at {where} is out of the arm's reach (outside the framework's safety envelope)",
            )


_CHECKS = {"peg": _check_peg, "hole": _check_hole, "groove": _check_groove, "egg": _check_egg,
           "contact": _check_contact, "contest": _check_contest}
"""What is checked of a fixture beyond each value's own range (against the peg, where it goes in)."""
