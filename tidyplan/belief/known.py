"""What the belief holds of one item it has seen (``Known``: its category, believed place and
state, the looks that showed it), of them all (``Items``), and what one look changed
(``Update``).
``tidyplan.belief.state.Belief`` keeps the items and updates them."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from tidyplan.belief.mapfacts import Placed, Point

SEEN_FROM_KEPT = 4  # poses an item was seen from, kept with it (Known.seen_from)
_EDITS = [0]  # changes to what the belief's views of its items read, on any Known so far
# what those views read (Belief.untidied: who is put away, by name; Belief.placed: each one's
# Placed record; Belief.item_boxes: each one's box): a look that confirms an item sets its
# misses, its size and its last look, and changes none of them unless the size differs (counted,
# every frame's look made the views and the map's key anew)
_VIEWED = frozenset(("name", "category", "x", "y", "on", "sx", "sy", "sz", "spread", "state", "aside"))
_UNSET = object()


def edits() -> int:
    """How many times a field the belief's views read has changed on any ``Known``: the same
    count, the same views."""
    return _EDITS[0]


@dataclass(slots=True)
class Known:
    """A seen item. ``state`` is placed, held or tidied; (x, y, on) is where it was last seen or
    put down; ``misses`` counts looks in a row that should have seen it."""

    name: str
    category: str
    x: float
    y: float
    on: str = "floor"
    sx: float = 0.08
    sy: float = 0.08
    sz: float = 0.10
    state: str = "placed"
    misses: int = 0
    deposit: str | None = None
    spread: float = 0.0  # m it may lie from (x, y): 0 where seen; more where it fell unseen
    aside: bool = False  # the robot's last put-down of it was out of the way (Placed.aside)
    oriented: bool = False  # an orientation item (the detector reported its down end)
    # where the camera stood when it found or confirmed the item, the latest last (a few kept):
    # a pose known to show it, for the looks after it is forgotten
    seen_from: list[Point] = field(default_factory=list)
    seen_look: int = -1  # the belief's look (``Belief.looks``) that last showed it
    # the last ``placed()``: the same record while the item stays, so the belief's keys of many
    # items compare by identity (a new record per item, several times a turn, grew with the room)
    _placed: Placed | None = field(default=None, repr=False, compare=False)

    def __setattr__(self, name: str, value) -> None:
        if name in _VIEWED and getattr(self, name, _UNSET) != value:
            _EDITS[0] += 1
        object.__setattr__(self, name, value)

    def placed(self) -> Placed:
        p = self._placed
        loose = self.spread > 0
        now = (self.name, self.category, self.x, self.y, self.on, self.sx, self.sy, loose, self.aside)
        if p is None or (p.name, p.category, p.x, p.y, p.on, p.sx, p.sy, p.loose, p.aside) != now:
            p = self._placed = Placed(*now)
        return p

    def saw(self, at: Point, look: int) -> None:
        """Remember that look number ``look``, from ``at``, showed it (the last SEEN_FROM_KEPT
        places, no repeats)."""
        self.seen_look = look
        if not self.seen_from or math.dist(self.seen_from[-1], at) > 0.1:
            self.seen_from.append((float(at[0]), float(at[1])))
            del self.seen_from[:-SEEN_FROM_KEPT]


class Items(dict):
    """The belief's items by name (``Belief.items``), counting the changes of who is in it
    (``edits``): with ``edits()``, what the belief's views of its items are kept by."""

    edits = 0

    def __setitem__(self, name, item) -> None:
        super().__setitem__(name, item)
        self.edits += 1

    def __delitem__(self, name) -> None:
        super().__delitem__(name)
        self.edits += 1

    def pop(self, *args):
        self.edits += 1
        return super().pop(*args)

    def popitem(self):
        self.edits += 1
        return super().popitem()

    def clear(self) -> None:
        self.edits += 1
        super().clear()

    def update(self, *args, **kwargs) -> None:
        self.edits += 1
        super().update(*args, **kwargs)

    def setdefault(self, name, item=None):
        self.edits += 1
        return super().setdefault(name, item)


@dataclass(slots=True)
class Update:
    """What one observation changed, for the monitor and the trace."""

    new: list[str] = field(default_factory=list)
    confirmed: list[str] = field(default_factory=list)
    forgotten: list[str] = field(default_factory=list)
    # believed items a detection of another kind lay on: the same object seen twice, not added
    overlapping: list[str] = field(default_factory=list)
