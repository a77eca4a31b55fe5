"""Scopes of a running lab: rerun recordings, CSV files and plots of the same signals."""
