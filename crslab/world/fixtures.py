"""What a world holds: its fixtures, the peg, the contact materials and the contest's rules, as
plain data (a world file's tables, :mod:`crslab.world.world_file`; docs/worlds.md says each key).

Positions are in the world file's frame, which is the lab's: a point is where the peg's tip is when
the course's forward kinematics (:mod:`crslab.crs`) reads that point. The arm itself stands
``peg.wrist_above_tip_m`` higher than the course's frame says: its wrist, where its forearm ends,
is that far above the tip (the peg and its gripper hang below it). Every fixture stands on the
table (or on z = 0 without one): a fixture's height is that of its top.

>>> Peg(0.01, 0.065, 0.03, 0.1).top_above_tip_m
0.065
>>> round(Egg((0.2, 0.2), 0.3, 0.044, 0.057, 3e5, 25.0, 0.076, 0.02, 1e5).stiffness_n_per_m)
75000
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from crslab.world import world_facts

Pair = tuple[float, float]
Triple = tuple[float, float, float]


@dataclass(frozen=True)
class Table:
    """The table the arm and the fixtures stand on: its top at ``top_z_m``, ``size_m`` its extents."""

    top_z_m: float
    size_m: Triple


@dataclass(frozen=True)
class Peg:
    """The peg the arm holds, always vertical (a wrist keeps it so): ``length_m`` from its tip up to
    its gripper; the arm's wrist (the forearm's end) is ``wrist_above_tip_m`` above the tip, the
    gripper (``gripper_diameter_m`` across) between. The course's forward kinematics names the tip."""

    diameter_m: float
    length_m: float
    mass_kg: float
    wrist_above_tip_m: float
    gripper_diameter_m: float = 0.024

    @property
    def top_above_tip_m(self) -> float:
        """Where the peg ends and its gripper begins, above the tip."""
        return self.length_m


@dataclass(frozen=True)
class Hole:
    """A block with a vertical round hole ``diameter_m`` wide and ``depth_m`` deep from its top,
    its mouth widened by a 45-degree chamfer ``chamfer_m`` wide; the block (``block_size_xy_m``)
    stands on the table, up to ``top_z_m``."""

    center_xy_m: Pair
    top_z_m: float
    diameter_m: float
    depth_m: float
    chamfer_m: float
    block_size_xy_m: Pair


@dataclass(frozen=True)
class Obstacle:
    """A post standing on the table: its centre, its footprint (x, y) and its top."""

    center_xy_m: Pair
    top_z_m: float
    size_xy_m: Pair


@dataclass(frozen=True)
class Groove:
    """A Z-shaped channel ``width_m`` wide and ``depth_m`` deep cut into the top of a plate
    (``plate_thickness_m``), along the segments entrance -> corner 1 -> corner 2 -> exit (closed at
    both ends); the plate's top reaches ``rim_m`` beyond the channel all round. It stands on the
    table."""

    corners_xy_m: tuple[Pair, Pair, Pair, Pair]
    top_z_m: float
    width_m: float
    depth_m: float
    rim_m: float
    plate_thickness_m: float

    @property
    def floor_z_m(self) -> float:
        """The channel's floor."""
        return self.top_z_m - self.depth_m

    @property
    def length_m(self) -> float:
        """The Z's centre line, entrance to exit."""
        return float(np.sum(np.linalg.norm(np.diff(np.asarray(self.corners_xy_m), axis=0), axis=1)))


@dataclass(frozen=True)
class Egg:
    """An egg standing on a kitchen scale's round platform, the scale on a stand on the table. The
    egg's contact with what presses it is its shell (``shell_stiffness_n_per_m``) and the scale's
    platform (``scale_stiffness_n_per_m``) in series; past ``breaking_force_n`` it breaks, for the
    rest of the run."""

    center_xy_m: Pair
    top_z_m: float
    diameter_m: float
    height_m: float
    shell_stiffness_n_per_m: float
    breaking_force_n: float
    scale_diameter_m: float
    scale_height_m: float
    scale_stiffness_n_per_m: float

    @property
    def scale_top_z_m(self) -> float:
        """Where the egg stands: the scale's top."""
        return self.top_z_m - self.height_m

    @property
    def stiffness_n_per_m(self) -> float:
        """The egg's contact: shell and scale in series."""
        return 1.0 / (1.0 / self.shell_stiffness_n_per_m + 1.0 / self.scale_stiffness_n_per_m)


@dataclass(frozen=True)
class Contact:
    """The contact materials: Coulomb ``friction`` of the peg on every fixture; the rigid fixtures'
    MuJoCo time constant and impedance; the egg's damping ratio (docs/worlds.md)."""

    friction: float = 0.4
    rigid_timeconst_s: float = 0.004
    rigid_impedance: float = 0.99
    egg_damping_ratio: float = 0.2


LONGEST_RUN_S = 60.0
"""The longest contest run (simulated s, the 4.1 s start-up included) unless ``--duration``: twice
the 30 s crslab used to give every run, three times crslab's own starter's 21 s. A world's holds
last at most this long."""


@dataclass(frozen=True)
class ContestRules:
    """The final project's contest (``crslab contest``): the egg's force band (grams on the scale)
    held ``hold_s``; the peg at least ``peg_min_depth_m`` in the hole for ``peg_hold_s`` (of each
    hold a TA times, ``hold_tolerance_s`` short of it passes); the share of the groove's path the
    peg must stay inside; whether passing beside the obstacle avoids it too (``obstacle_around``). The
    defaults are C's (``csrc/plant/world_facts.h``)."""

    band_g: Pair = world_facts.CONTEST_BAND_G
    hold_s: float = world_facts.CONTEST_HOLD_S
    hold_tolerance_s: float = world_facts.CONTEST_HOLD_TOLERANCE_S
    peg_min_depth_m: float = world_facts.CONTEST_PEG_MIN_DEPTH_M
    peg_hold_s: float = world_facts.CONTEST_PEG_HOLD_S
    groove_min_share: float = world_facts.CONTEST_GROOVE_MIN_SHARE
    obstacle_around: bool = world_facts.CONTEST_OBSTACLE_AROUND


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
    contest: ContestRules = field(default_factory=ContestRules)
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

    @property
    def arm_raised_m(self) -> float:
        """How much higher the arm's base stands than the course's frame puts it: the wrist is this
        far above the tip the forward kinematics names (0 without a peg)."""
        return self.peg.wrist_above_tip_m if self.peg is not None else 0.0

    @property
    def floor_z_m(self) -> float:
        """What the fixtures stand on: the table's top, else z = 0."""
        return self.table.top_z_m if self.table is not None else 0.0


FREE_AIR = World(name="none", source="none")
"""World ``none``: nothing but the arm, as ``crslab/worlds/none.toml`` says."""
