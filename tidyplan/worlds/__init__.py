"""The worlds the robot acts in: the typed contract every world implements (``contract``: the
skills the behaviour units call and the referee that alone knows the truth), the registry by
name (``registry``), what the worlds share (``base``: fault rates, outcomes, the simulated
clock's rules), the symbolic world with a hidden true state (``symbolic``) and the pybullet world
of the HSR (``pybullet``: its skills over the physics in ``sim``).

Layer 4. Imports: tidyplan.errors, tidyplan.belief, sim.
"""
