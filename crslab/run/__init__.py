"""The simulator: a lab's lab() at 1 kHz in lockstep with the MuJoCo arm, in a worker process.

This package is the crslab process's half of a run: it starts the worker (:mod:`crslab.worker`,
the other half), runs it in chunks, watches it and reports what it did."""
