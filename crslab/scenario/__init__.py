"""Scenarios: a timeline of what happens to the arm and the lab during a run (TOML files)."""
