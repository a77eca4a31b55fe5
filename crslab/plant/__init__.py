"""The simulated CRS arm: its MuJoCo model and the physics plant built on it."""
