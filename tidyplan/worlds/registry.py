"""The worlds a mission runs in, by name. A new world is one class that implements the contract of
``tidyplan.worlds.base`` (``Skills``, ``Referee``) with a ``for_mission`` constructor, and one
entry here. Named by ``module:class``, so that the command line lists them without loading
numpy or pybullet."""

from __future__ import annotations

import ctypes
import os
import sys
from contextlib import contextmanager
from importlib import import_module

WORLDS = {
    "pybullet": "tidyplan.worlds.pybullet.world:BulletWorld",  # the HSR in the physics world (the default)
    "symbolic": "tidyplan.worlds.symbolic:SymbolicWorld",  # the grid world: fast, no physics
}


def world_class(name: str):
    """The class of the world ``name``; a ``KeyError`` for a name not in WORLDS."""
    module, _, cls = WORLDS[name].partition(":")
    return getattr(import_module(module), cls)


@contextmanager
def quiet_import():
    """Standard error closed at the file descriptor while a world's module loads: pybullet's C
    library prints its build time there on import, noise in ``tidyplan check``'s report.
    Exceptions still propagate; only what C code writes is dropped."""
    sys.stderr.flush()
    saved = os.dup(2)
    try:
        with open(os.devnull, "w") as null:
            os.dup2(null.fileno(), 2)
        yield
    finally:
        ctypes.CDLL(None).fflush(None)  # what C's stdio buffered goes to the null device too
        os.dup2(saved, 2)
        os.close(saved)
