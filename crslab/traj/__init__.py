"""Trajectories: joint profiles from the C core (:mod:`crslab.traj.profiles`), Cartesian waypoint
files turned into joint-space paths (:mod:`crslab.traj.waypoints`), and their plots
(:mod:`crslab.traj.trajectory_plot`)."""
