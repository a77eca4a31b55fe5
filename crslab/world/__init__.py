"""The world the arm touches (docs/worlds.md): what a world file holds
(:mod:`crslab.world.fixtures`), reading and checking one (:mod:`crslab.world.world_file`,
:mod:`crslab.world.layout_checks`, the groove's plate in :mod:`crslab.world.groove_plate`, solids
in :mod:`crslab.world.shapes`), the MuJoCo scene made from it (:mod:`crslab.world.scene`) and the
world's facts that C holds (:mod:`crslab.world.world_facts`: the world row's columns, the egg's
break, the contest's rules).

The rest of crslab uses a world through what this package names:

>>> from crslab.world import load_world
>>> load_world("contest").name
'contest'
"""

from crslab.world.fixtures import FREE_AIR, World
from crslab.world.world_file import WORLD_NAMES, WorldError, load_world, world_file

__all__ = ["FREE_AIR", "WORLD_NAMES", "World", "WorldError", "load_world", "world_file"]
