"""The course's own host tools against the simulated board: the C28x data memory and its linker
map (for the MATLAB scripts), the serial ports a host program opens (pseudo-terminals, TCP), the
bridge that carries their bytes to the board between chunks of ticks, and crslab's own client of
the MATLAB and Simulink protocols (``crslab serial``). See docs/host-tools.md."""
