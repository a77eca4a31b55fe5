"""The plant parameters a run uses: one object that ``params.toml``, a ``--plant`` file and a sweep
all set, by name.

The defaults are ``models/crs_arm/params.toml`` (the one home of physics numbers). A plant file
(``crslab identify`` writes one) is a TOML file with any of the same sections, ``[command]``,
``[drive]``, ``[rotor]``, ``[friction]`` and ``[friction.motorN]``, plus ``[variations]``: the
scales a sweep varies. Every value is also reachable by a flat name (:data:`NAMES`), which is how
sweeps and the fit address them:

>>> p = PlantParams.defaults()
>>> p.motor_gain
6.0
>>> q = p.with_values({"friction": 1.5, "payload_kg": 0.5, "stall_nm2": 18.0})
>>> q.friction_scale, q.payload_kg, q.stall_nm[1]
((1.5, 1.5, 1.5), 0.5, 18.0)
>>> q.value("friction2"), p.value("friction2")
(1.5, 1.0)

The worker applies them to the MuJoCo model (:func:`crslab.plant.model.apply_plant`) and to the C
drive (``crs_drive`` of ``csrc/board/board.h``) before the first tick.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

from crslab.plant.model_files import PARAMS
from crslab.toml_file import KeyPath, TomlFile, key_name, shown

Triple = tuple[float, float, float]
MOTORS = (1, 2, 3)


class PlantParamsError(ValueError):
    """A plant file or a named value that cannot be used; the message names the file or the name."""


@dataclass(frozen=True)
class Name:
    """One addressable plant value: ``field`` of :class:`PlantParams`, ``index`` into it for a per-motor
    value (None for a scalar), what it is (with its unit) and its bounds."""

    field: str
    index: int | None
    doc: str
    low: float = 0.0
    high: float = math.inf
    infinite_ok: bool = False
    """``inf`` is a meaningful value (no limit)."""


def _per_motor(stem: str, field: str, doc: str, low: float = 0.0, high: float = math.inf,
               infinite_ok: bool = False) -> dict[str, Name]:
    return {f"{stem}{m}": Name(field, m - 1, f"{doc}, motor {m}", low, high, infinite_ok) for m in MOTORS}


MAX_TORQUE_NM = 1000.0
"""The bound of every torque-like plant value (N.m, N.m s/rad): some 30 times the arm's own."""

NAMES: dict[str, Name] = {
    "motor_gain": Name("motor_gain", None, "joint torque of one command unit, N.m per unit", 0.0, 1000.0),
    **_per_motor("stall_nm", "stall_nm", "torque the drive delivers at standstill, at most, N.m (inf: no "
                 "limit)", high=MAX_TORQUE_NM, infinite_ok=True),
    **_per_motor("backemf", "backemf_nm_s_per_rad",
                 "what each rad/s of motor speed takes off the drive's torque, N.m s/rad",
                 high=MAX_TORQUE_NM),
    "drive_lag_s": Name("drive_lag_s", None, "first-order lag of the delivered torque, s", 0.0, 1.0),
    **_per_motor("coulomb_pos", "coulomb_pos_nm", "sliding friction against positive motion, where its line "
                 "meets zero speed (Cpos), N.m", high=MAX_TORQUE_NM),
    **_per_motor("coulomb_neg", "coulomb_neg_nm", "sliding friction against negative motion, where its line "
                 "meets zero speed (Cneg, a negative number), N.m", -MAX_TORQUE_NM, 0.0),
    **_per_motor("viscous_pos", "viscous_pos_nm_s_per_rad", "slope of the sliding friction moving positive "
                 "(Vpos), N.m s/rad", high=MAX_TORQUE_NM),
    **_per_motor("viscous_neg", "viscous_neg_nm_s_per_rad", "slope of the sliding friction moving negative "
                 "(Vneg), N.m s/rad", high=MAX_TORQUE_NM),
    **_per_motor("static_pos", "static_pos_nm", "static friction: the most torque a stuck joint resists "
                 "pushed positive (Spos), N.m", high=MAX_TORQUE_NM),
    **_per_motor("static_neg", "static_neg_nm", "static friction: the most torque a stuck joint resists "
                 "pushed negative (Sneg, a negative number), N.m", -MAX_TORQUE_NM, 0.0),
    **_per_motor("rotor_inertia", "rotor_inertia_kg_m2", "reflected rotor inertia (the motor, its "
                 "drive) about the motor angle, added to the links', kg.m^2", high=10.0),
    "friction_transition_rad_s": Name("friction_transition_rad_s", None, "motor speed over which sliding "
                                      "friction goes from the static band to its lines, rad/s", 0.005, 1.0),
    "friction": Name("friction_scale", 0, "scale of every motor's friction (dry and viscous)", 0.0, 100.0),
    **_per_motor("friction", "friction_scale", "scale of all friction (dry and viscous)", high=100.0),
    "payload_kg": Name("payload_kg", None, "mass clamped at the end effector, kg", 0.0, 10.0),
    "mass": Name("mass_scale", None, "scale of every link's mass and inertia (not the payload, not the "
                 "rotors)", 0.01, 100.0),
    "encoder_noise_counts": Name("encoder_noise_counts", None,
                                 "encoder noise, standard deviation in counts, every joint", 0.0, 1e6),
}
"""Every plant value by its flat name. ``friction`` (no number) scales every motor's friction."""

ALL_FRICTION = "friction"


@dataclass(frozen=True)
class PlantParams:
    """The physical numbers of one run's simulated arm that can change without regenerating the
    model: the motor gain, the drive, friction, and the variations a sweep applies. Per-motor
    values are motors 1, 2, 3, about their motor angles, in N.m: a command unit asks for
    ``motor_gain`` N.m, which the drive delivers within its torque-speed envelope (``stall_nm``,
    ``backemf_nm_s_per_rad``) after its lag; friction acts on the motor angles (the rules are
    :meth:`friction_nm`'s).
    """

    motor_gain: float
    stall_nm: Triple
    backemf_nm_s_per_rad: Triple
    drive_lag_s: float
    coulomb_pos_nm: Triple
    coulomb_neg_nm: Triple
    viscous_pos_nm_s_per_rad: Triple
    viscous_neg_nm_s_per_rad: Triple
    static_pos_nm: Triple
    static_neg_nm: Triple
    friction_transition_rad_s: float
    rotor_inertia_kg_m2: Triple
    friction_scale: Triple = (1.0, 1.0, 1.0)
    mass_scale: float = 1.0
    payload_kg: float = 0.0
    encoder_noise_counts: float = 0.0

    @classmethod
    def defaults(cls) -> PlantParams:
        """The arm of ``models/crs_arm/params.toml``."""
        return cls.from_model_tables(PARAMS)

    @classmethod
    def from_model_tables(cls, params: Mapping, where: str = "models/crs_arm/params.toml") -> PlantParams:
        """The plant values of a whole ``params.toml`` (as read by ``tomllib``): the generator of the
        MJCF uses this too, so the compiled model and a run agree by construction."""
        plant = _from_tables(params, where, cls(**_DEFAULT_FIELDS), whole_model=True)
        unset = [name for name, v in plant.values().items() if math.isnan(v)]
        if unset:
            raise PlantParamsError(f"{where}: sets no value for {', '.join(unset)}")
        return plant

    @classmethod
    def load(cls, path: str | Path, base: PlantParams | None = None) -> PlantParams:
        """A plant file's values over ``base`` (default: :meth:`defaults`). Raises
        :class:`PlantParamsError` naming the file for anything unreadable or unknown."""
        doc = TomlFile.read(Path(path), "plant file", PlantParamsError)
        return _from_tables(doc.data, str(path), base or cls.defaults(), doc=doc)

    def value(self, name: str) -> float:
        """The value called ``name`` (:data:`NAMES`); ``friction`` is motor 1's friction scale."""
        spec = _name(name)
        v = getattr(self, spec.field)
        return float(v if spec.index is None else v[spec.index])

    def with_values(self, values: Mapping[str, float]) -> PlantParams:
        """A copy with ``values`` set by name. ``friction`` sets every motor's friction scale; given
        with it, ``friction1..3`` multiply it (a sweep's overall scale times a joint's). Raises
        :class:`PlantParamsError` for an unknown name or a value outside its bounds."""
        fields: dict[str, object] = {}
        overall = 1.0
        if ALL_FRICTION in values:
            overall = _checked(ALL_FRICTION, values[ALL_FRICTION], NAMES[f"{ALL_FRICTION}1"])
            fields["friction_scale"] = (overall,) * 3
        for name, raw in values.items():
            if name == ALL_FRICTION:
                continue
            spec = _name(name)
            v = _checked(name, raw, spec)
            if spec.index is None:
                fields[spec.field] = v
                continue
            if spec.field == "friction_scale":
                v *= overall
            current = list(fields.get(spec.field, getattr(self, spec.field)))  # type: ignore[call-overload]
            current[spec.index] = v
            fields[spec.field] = tuple(current)
        return dataclasses.replace(self, **fields)  # type: ignore[arg-type]

    def values(self) -> dict[str, float]:
        """Every value by its flat name (``friction`` left out: it is ``friction1..3``)."""
        return {name: self.value(name) for name in NAMES if name != ALL_FRICTION}

    # -- the friction law ----------------------------------------------------------------------
    def friction_nm(self, motor: int, speed_rad_s: float) -> float:
        """The friction torque (N.m, against the motion) on ``motor`` (1..3) sliding at
        ``speed_rad_s`` (motor angle), scaled; at zero speed see :meth:`static_band_nm`.

        Moving positive it rises from the static band's edge ``Spos`` to the course's line
        ``Cpos + Vpos w`` over ``friction_transition_rad_s``:
        ``Spos + (Cpos - Spos)(1 - exp(-w / w_t)) + Vpos w``; moving negative likewise with
        ``Sneg``, ``Cneg`` and ``Vneg`` (negative numbers). This is the rule the board applies
        (``csrc/plant/friction.c`` for the sliding part, MuJoCo's friction constraint for the band).

        >>> p = PlantParams.defaults().with_values({"coulomb_pos1": 2.0, "viscous_pos1": 1.5,
        ...     "static_pos1": 1.2, "coulomb_neg1": -1.8, "viscous_neg1": 1.4, "static_neg1": -1.8})
        >>> round(p.friction_nm(1, 1.0), 6), round(p.friction_nm(1, -1.0), 6)   # the lines, far above w_t
        (3.5, -3.2)
        >>> round(p.friction_nm(1, 1e-9), 6)                                    # the static band's edge
        1.2
        """
        m = motor - 1
        w, scale = float(speed_rad_s), self.friction_scale[m]
        if w == 0.0:
            return 0.0
        if w > 0:
            static, coulomb = self.static_pos_nm[m], self.coulomb_pos_nm[m]
            viscous = self.viscous_pos_nm_s_per_rad[m]
        else:
            static, coulomb = self.static_neg_nm[m], self.coulomb_neg_nm[m]
            viscous = self.viscous_neg_nm_s_per_rad[m]
        rise = -math.expm1(-abs(w) / self.friction_transition_rad_s)
        return scale * (static + (coulomb - static) * rise + viscous * w)

    def static_band_nm(self, motor: int) -> tuple[float, float]:
        """``(Sneg, Spos)`` of ``motor`` (1..3), scaled: a stuck joint stays stuck while the other
        torques on it (N.m, about its motor angle) lie within this band."""
        m = motor - 1
        return self.static_neg_nm[m] * self.friction_scale[m], self.static_pos_nm[m] * self.friction_scale[m]

    # -- what the model and the C board are given -----------------------------------------------
    def band_half_nm(self) -> tuple[float, ...]:
        """MuJoCo's symmetric dry friction per motor (N.m): half the width of the static band
        ``[Sneg, Spos]``, scaled."""
        return tuple(0.5 * (hi - lo) for lo, hi in map(self.static_band_nm, MOTORS))

    def friction_bias_nm(self) -> tuple[float, ...]:
        """The constant torque per motor (N.m) that shifts MuJoCo's symmetric band onto ``[Sneg, Spos]``:
        ``-(Spos + Sneg) / 2``, scaled. With it, a stuck joint stays stuck while the other torques on
        it lie within ``[Sneg, Spos]``, and meets ``Spos`` (moving positive) or ``Sneg`` as it starts
        to slide. The model carries it as its motor actuators' constant bias."""
        return tuple(-0.5 * (hi + lo) for lo, hi in map(self.static_band_nm, MOTORS))

    def friction_bias_units(self) -> tuple[float, ...]:
        """:meth:`friction_bias_nm` in actuator force (before the gear of ``motor_gain`` N.m per
        unit): the motor actuators' constant bias that carries it."""
        return tuple(b / self.motor_gain for b in self.friction_bias_nm())

    def sliding_units(self) -> dict[str, tuple[float, ...]]:
        """What the C board's sliding friction (``crs_friction`` of ``csrc/board/board.h``) is given, in
        command units (N.m over the motor gain), scaled: how far each line's intercept lies beyond
        the static band's edge (``Cpos - Spos``, ``Cneg - Sneg``) and the two slopes."""
        def per_motor(values: Triple) -> tuple[float, ...]:
            return tuple(v * s / self.motor_gain for v, s in zip(values, self.friction_scale))

        gap_pos = tuple(c - b for c, b in zip(self.coulomb_pos_nm, self.static_pos_nm))
        gap_neg = tuple(c - b for c, b in zip(self.coulomb_neg_nm, self.static_neg_nm))
        return {
            "slide_pos_units": per_motor(gap_pos),
            "slide_neg_units": per_motor(gap_neg),
            "viscous_pos_units_s_per_rad": per_motor(self.viscous_pos_nm_s_per_rad),
            "viscous_neg_units_s_per_rad": per_motor(self.viscous_neg_nm_s_per_rad),
        }

    def to_toml(self, header: str = "") -> str:
        """This arm as a plant file (every value written, so the file does not depend on the
        defaults of the crslab that reads it). ``header`` lines become comments at the top.

        >>> p = PlantParams.defaults()
        >>> import tempfile, os
        >>> path = os.path.join(tempfile.mkdtemp(), "arm.toml")
        >>> _ = open(path, "w").write(p.with_values({"viscous_neg2": 0.5}).to_toml("my arm"))
        >>> PlantParams.load(path).value("viscous_neg2")
        0.5
        """
        def arr(xs: Triple) -> str:
            return "[" + ", ".join(_num(x) for x in xs) + "]"

        lines = [f"# {line}" if line else "#" for line in header.splitlines()]
        lines += ["", "[command]", f"newton_metre_per_unit = {_num(self.motor_gain)}",
                  "", "[drive]", f"stall_nm = {arr(self.stall_nm)}",
                  f"backemf_nm_s_per_rad = {arr(self.backemf_nm_s_per_rad)}",
                  f"lag_s = {_num(self.drive_lag_s)}"]
        lines += ["", "[rotor]"] + [f"motor{m} = {_num(self.rotor_inertia_kg_m2[m - 1])}" for m in MOTORS]
        lines += ["", "[friction]", f"transition_rad_s = {_num(self.friction_transition_rad_s)}"]
        for j in range(3):
            lines += ["", f"[friction.motor{j + 1}]"]
            lines += [f"{key} = {_num(self.value(name.format(m=j + 1)))}"
                      for key, name in _TABLE_KEYS["friction.motor"].items() if key != "V_nm_s_per_rad"]
        lines += ["", "[variations]"] + [f"{name} = {_num(self.value(name))}" for name in VARIATIONS]
        return "\n".join(lines).lstrip("\n") + "\n"


VARIATIONS = ("friction1", "friction2", "friction3", "mass", "payload_kg", "encoder_noise_counts")
"""The names of a plant file's ``[variations]`` table."""

_UNSET = (math.nan,) * 3
_DEFAULT_FIELDS = dict(motor_gain=math.nan, stall_nm=_UNSET, backemf_nm_s_per_rad=_UNSET,
                       drive_lag_s=math.nan, coulomb_pos_nm=_UNSET, coulomb_neg_nm=_UNSET,
                       viscous_pos_nm_s_per_rad=_UNSET, viscous_neg_nm_s_per_rad=_UNSET,
                       static_pos_nm=_UNSET, static_neg_nm=_UNSET, friction_transition_rad_s=math.nan,
                       rotor_inertia_kg_m2=_UNSET)


def _num(x: float) -> str:
    return format(float(x), ".6g") if math.isfinite(x) else repr(float(x))


def _name(name: str) -> Name:
    try:
        return NAMES[name]
    except KeyError:
        raise PlantParamsError(f"no plant value called {name!r}; the names are {', '.join(NAMES)}") from None


def _problem(raw: object, spec: Name) -> str | None:
    """What is wrong with ``raw`` as the value ``spec`` names (None: nothing)."""
    if isinstance(raw, bool | str | list | dict):
        return f"must be a number, got {shown(raw)}"
    try:
        v = float(raw)  # type: ignore[arg-type]
    except (TypeError, ValueError, OverflowError):
        return f"must be a number, got {shown(raw)}"
    if math.isinf(v) and v > 0 and spec.infinite_ok:
        return None
    if math.isnan(v) or not spec.low <= v <= spec.high:
        return f"{shown(raw)} is outside {spec.low:g} .. {spec.high:g} ({spec.doc})"
    return None


def _checked(name: str, raw: object, spec: Name) -> float:
    problem = _problem(raw, spec)
    if problem is not None:
        raise PlantParamsError(f"{name} {problem}" if problem.startswith("must") else f"{name} = {problem}")
    return float(raw)  # type: ignore[arg-type]


# The tables a plant file may hold: section -> key -> flat name pattern ("{m}" is the motor).
_TABLE_KEYS: dict[str, dict[str, str]] = {
    "command": {"newton_metre_per_unit": "motor_gain"},
    "drive": {"stall_nm": "stall_nm{m}", "backemf_nm_s_per_rad": "backemf{m}",
              "lag_s": "drive_lag_s"},
    "rotor": {"motor1": "rotor_inertia1", "motor2": "rotor_inertia2", "motor3": "rotor_inertia3"},
    "friction": {"transition_rad_s": "friction_transition_rad_s"},
    "friction.motor": {"Cpos_nm": "coulomb_pos{m}", "Cneg_nm": "coulomb_neg{m}",
                       "Vpos_nm_s_per_rad": "viscous_pos{m}", "Vneg_nm_s_per_rad": "viscous_neg{m}",
                       "Spos_nm": "static_pos{m}", "Sneg_nm": "static_neg{m}",
                       "V_nm_s_per_rad": "viscous_pos{m} viscous_neg{m}"},
    "variations": {name: name for name in VARIATIONS},
}


def _from_tables(tables: Mapping, where: str, base: PlantParams, whole_model: bool = False,
                 doc: TomlFile | None = None) -> PlantParams:
    """``base`` with every value ``tables`` gives (in params.toml's layout) set by name; with
    ``whole_model`` (params.toml itself) the tables that describe the model are passed over. Each
    error names the file (``where``), and with ``doc`` (the checked file) the line, and the key."""
    values: dict[str, object] = {}
    origin: dict[str, KeyPath] = {}

    def bad(path: KeyPath, what: str) -> PlantParamsError:
        if doc is not None:
            return doc.fail(path, what)  # type: ignore[return-value]
        return PlantParamsError(f"{where}: {key_name(path)}: {what}")

    def given(name: str, value: object, path: KeyPath) -> None:
        values[name], origin[name] = value, path

    for section, body in tables.items():
        if section == "friction" and isinstance(body, Mapping):
            for motor, row in body.items():
                if motor in _TABLE_KEYS["friction"]:
                    given(_TABLE_KEYS["friction"][motor], row, ("friction", motor))
                    continue
                if not isinstance(row, Mapping):
                    holds = ", ".join(_TABLE_KEYS["friction"])
                    raise bad(("friction", motor), f"unknown key ([friction] holds {holds}, and the tables "
                                                   "[friction.motor1..3])")
                if motor not in ("motor1", "motor2", "motor3"):
                    raise bad(("friction", motor), "unknown table (motor1, motor2 or motor3)")
                for key, v in row.items():
                    if key not in _TABLE_KEYS["friction.motor"]:
                        known = ", ".join(_TABLE_KEYS["friction.motor"])
                        raise bad(("friction", motor, key), f"unknown key ({known})")
                    for name in _TABLE_KEYS["friction.motor"][key].split():
                        given(name.format(m=motor[-1]), v, ("friction", motor, key))
                # an older plant file (or one that leaves it out) has no static band: the joint
                # sticks within [Cneg, Cpos], as plain dry friction does
                for side in ("pos", "neg"):
                    if f"C{side}_nm" in row and f"S{side}_nm" not in row:
                        given(f"static_{side}{motor[-1]}", row[f"C{side}_nm"],
                              ("friction", motor, f"C{side}_nm"))
            continue
        keys = _TABLE_KEYS.get(section)
        if keys is None:
            if whole_model:
                continue
            raise bad((section,), f"unknown table (a plant file holds {', '.join(_PLANT_TABLES)})")
        if not isinstance(body, Mapping):
            raise bad((section,), "must be a table")
        for key, v in body.items():
            if key not in keys:
                raise bad((section, key), f"unknown key ([{section}] holds {', '.join(keys)})")
            pattern = keys[key]
            if "{m}" in pattern:
                if not isinstance(v, list) or len(v) != 3:
                    raise bad((section, key), f"must be three numbers (motors 1, 2, 3), got {shown(v)}")
                for m, x in zip(MOTORS, v):
                    given(pattern.format(m=m), x, (section, key, m - 1))
            else:
                given(pattern, v, (section, key))
    for name, raw in values.items():
        problem = _problem(raw, NAMES[name])
        if problem is not None:
            raise bad(origin[name], problem)
    return base.with_values(values)  # type: ignore[arg-type]


_PLANT_TABLES = ("[command]", "[drive]", "[rotor]", "[friction]", "[friction.motor1..3]", "[variations]")
