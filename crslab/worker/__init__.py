"""The worker's half of a run: the process that owns the MuJoCo plant, the board and the lab's
firmware and runs chunks of ticks, and what it is told over its pipe (the run's configuration, the
messages both sides read). The crslab process's half, which starts it, is :mod:`crslab.run`."""
