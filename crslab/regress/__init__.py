"""Regression checks on what a lab prints: golden transcripts, a number-aware comparison, JUnit
reports, and grading a folder of submissions against a reference lab."""
