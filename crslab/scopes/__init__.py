"""Scopes of a running lab: the signals named once (CSV columns, plot panels, rerun entities), the
arm in 3D, plots of a ``--csv`` file. The rerun and CSV sinks that write them are in
:mod:`crslab.sinks`."""
