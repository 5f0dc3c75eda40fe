"""The simulated world the robot stands on, importing nothing of tidyplan: the scenario format
(``scenario``), the occupancy grid whose path lengths are the move costs (``grid``, over the
footprints of ``box``; the lengths a changed grid keeps, ``carried``; what taking a box away
joins, ``joins``), line of
sight (``visibility``), and the pybullet physics: the HSR (``robot``, ``hsr.urdf``), the room
(``room``), the head camera (``camera``), the base's collision checks (``motion``) and the
drawers' joints (``drawer``).

Imports: sim only; ``box`` and ``carried`` import nothing of sim, ``grid`` only those two,
``joins`` only ``box`` and ``grid``, ``scenario`` only ``grid``.
"""
