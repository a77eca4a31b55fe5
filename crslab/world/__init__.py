"""The world the arm touches: the fixtures of a world file (``crslab/worlds/*.toml``) and the MuJoCo
scene made from them (:mod:`crslab.world.layout`, :mod:`crslab.world.scene`); docs/worlds.md."""
