"""The pybullet world of the HSR and the WRS room. Knows nothing of planning."""
