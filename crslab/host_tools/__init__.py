"""The course's own host tools against the simulated board: the linker map of the C28x data
memory (for the MATLAB scripts; the layout itself is :mod:`crslab.lab.c28x_memory`), the serial
ports a host program opens (pseudo-terminals, TCP), and crslab's own client of the MATLAB and
Simulink protocols (``crslab serial``). The bridge that carries the ports' bytes to the running
board is a live control (:mod:`crslab.live.bridge`). See docs/host-tools.md."""
