"""The simulator: a lab's lab() at 1 kHz in lockstep with the MuJoCo arm, in a worker process."""
