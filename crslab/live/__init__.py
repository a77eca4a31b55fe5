"""Windows into a running lab, served between chunks of ticks (each a ``LiveControl`` of
:mod:`crslab.run.running`): typed commands on its watched variables (``console``), MuJoCo's viewer
whose mouse pushes the arm (``viewer``, also a sink), and the bridge that carries the host ports'
bytes to and from the board (``bridge``)."""
