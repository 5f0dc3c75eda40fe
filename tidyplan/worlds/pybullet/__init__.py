"""The HSR in the pybullet world: the world behind the skills (``world``), the head camera's
looks (``look``), the arm and hand (``hand``), where the hand lets go (``put``) and the WRS
drawers (``drawer``). The physics itself (robot, room, camera, drawer joints) is in ``sim``.

Layer 4 (in tidyplan.worlds). Imports: tidyplan.errors, tidyplan.belief, sim.
"""
