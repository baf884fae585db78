"""Timed joint trajectories: time from (angle, velocity), resampling, limits."""
