"""sim.scenario.model: the TOML scenario format, its defaults and every validation message."""

import pytest

from sim.grid import Box
from sim.scenario.model import (
    Deposit,
    DrawerSpec,
    Expect,
    Furniture,
    Item,
    Robot,
    Scenario,
    ScenarioError,
    Sensing,
    Viewpoint,
    drawer_layout,
)
from sim.scenario.read import load, loads

MINIMAL = """\
schema = 1
name = "mini"
title = "Mini room"

[room]
bounds = [0.0, 4.0, 0.0, 3.0]
entrance = [0.5, 0.5]
"""

FULL = (
    MINIMAL
    + """\
heading_deg = 90

[robot]
speed = 0.3

[sensing]
range_max = 3

[[furniture]]
name = "table"
center = [2.0, 2.0]
size = [1.0, 0.6]
height = 0.4
kind = "table"

[[deposit]]
name = "tray"
category = "food"
position = [3.5, 0.5, 0.0]
approach = [3.0, 0.5]

[[item]]
name = "apple"
category = "food"
position = [2.0, 2.0]
on = "table"

[[item]]
name = "pear"
category = "food"
position = [1.0, 1.5]
size = [0.1, 0.1, 0.2]

[[viewpoint]]
name = "vp"
position = [1.0, 1.0]

[expect]
unobservable_items = ["pear"]
"""
)


def errors(text: str) -> list[str]:
    with pytest.raises(ScenarioError) as info:
        loads(text, "s.toml")
    assert str(info.value) == "\n".join(info.value.messages)
    return info.value.messages


def edit(old: str, new: str, text: str = FULL) -> str:
    assert text.count(old) == 1, old
    return text.replace(old, new)


def test_minimal_loads_with_defaults():
    s = loads(MINIMAL, "m.toml")
    assert s == Scenario(
        "mini", "Mini room", "", (0.0, 4.0, 0.0, 3.0), (0.5, 0.5), 0.0, Robot(), Sensing(),
        (), (), (), (), Expect(), "m.toml",
    )  # fmt: skip
    assert s.robot == Robot(radius=0.22, nav_margin=0.05, speed=0.22)
    assert s.sensing == Sensing(0.8, 3.5, 58.0, 45.0, 0.2, 0.05, 1.0)
    assert s.categories() == [] and s.static_boxes() == []


def test_full_loads(tmp_path):
    path = tmp_path / "full.toml"
    path.write_text(FULL)
    s = load(path)
    assert s.path == str(path)
    assert s.heading_deg == 90.0
    assert s.robot == Robot(speed=0.3)
    assert s.sensing == Sensing(range_max=3.0)
    assert s.furniture == (Furniture("table", 2.0, 2.0, 1.0, 0.6, 0.4, "table"),)
    assert s.deposits == (Deposit("tray", "food", 3.5, 0.5, 0.0, (3.0, 0.5)),)
    assert s.items == (
        Item("apple", "food", 2.0, 2.0, "table", 0.08, 0.08, 0.10),
        Item("pear", "food", 1.0, 1.5, "floor", 0.1, 0.1, 0.2),
    )
    assert s.viewpoints == (Viewpoint("vp", 1.0, 1.0),)
    assert s.expect == Expect(unobservable_items=("pear",))
    assert s.furniture_named("table").height == 0.4
    assert [s.item_base_z(i) for i in s.items] == [0.4, 0.0]
    assert s.categories() == ["food"]
    assert s.static_boxes() == [Box(2.0, 2.0, 1.0, 0.6, "table")]
    assert s.items[1].box() == Box(1.0, 1.5, 0.1, 0.1, "pear")
    with pytest.raises(KeyError):
        s.furniture_named("sofa")


def test_deposit_without_approach():
    s = loads(edit("approach = [3.0, 0.5]\n", ""))
    assert s.deposits[0].approach is None


KNOWN_ITEM = "category, name, on, orientation, position, size, unknown"


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        ('name = "mini"', 'name = "mini"\ncolour = 1', "colour: unknown key (known: deposit, "
         "description, expect, facts, furniture, item, name, prior, robot, room, schema, sensing, "
         "time_limit_s, title, viewpoint)"),
        ('name = "mini"', 'name = "mini"\ntime_limit_s = 0', "time_limit_s: must be > 0, got 0"),
        ('name = "mini"', 'name = "mini"\ntime_limit_s = "15 min"', "time_limit_s: must be a finite number, "
         "got '15 min'"),
        ('on = "table"', 'on = "table"\ncolour = "red"',
         f'item "apple".colour: unknown key (known: {KNOWN_ITEM})'),
        ("speed = 0.3", "speed = 0.3\nwheels = 3",
         "robot.wheels: unknown key (known: nav_margin, radius, speed)"),
        ('title = "Mini room"\n', "", "title: missing required key"),
        ('kind = "table"\n', "", 'furniture "table".kind: missing required key'),
        ("heading_deg = 90", 'heading_deg = "north"',
         "room.heading_deg: must be a finite number, got 'north'"),
        ("height = 0.4", "height = true", 'furniture "table".height: must be a finite number, got True'),
        ("range_max = 3", "range_max = 3\nrange_min = false",
         "sensing.range_min: must be a finite number, got False"),
        ('name = "mini"', "name = 7", "name: must be a string, got 7"),
        ("entrance = [0.5, 0.5]", "entrance = [0.5]",
         "room.entrance: must be a list of 2 numbers [x, y], got [0.5]"),
        ("position = [3.5, 0.5, 0.0]", "position = [3.5, 0.5]",
         'deposit "tray".position: must be a list of 3 numbers [x, y, z], got [3.5, 0.5]'),
        ("bounds = [0.0, 4.0, 0.0, 3.0]", "bounds = [4.0, 0.0, 0.0, 3.0]",
         "room.bounds: needs x0 < x1 and y0 < y1, got (4, 0, 0, 3)"),
        ("bounds = [0.0, 4.0, 0.0, 3.0]", "bounds = [0.0, 4.0, 3.0, 3.0]",
         "room.bounds: needs x0 < x1 and y0 < y1, got (0, 4, 3, 3)"),
        ("entrance = [0.5, 0.5]", "entrance = [-0.5, 0.5]",
         "room.entrance: (-0.5, 0.5) is outside the room bounds (0, 4, 0, 3)"),
        ("center = [2.0, 2.0]", "center = [2.0, 3.2]",
         'furniture "table".center: (2, 3.2) is outside the room bounds (0, 4, 0, 3)'),
        ("position = [3.5, 0.5, 0.0]", "position = [4.5, 0.5, 0.0]",
         'deposit "tray".position: (4.5, 0.5) is outside the room bounds (0, 4, 0, 3)'),
        ("approach = [3.0, 0.5]", "approach = [3.0, 5.0]",
         'deposit "tray".approach: (3, 5) is outside the room bounds (0, 4, 0, 3)'),
        ("position = [1.0, 1.5]", "position = [1.0, -1.5]",
         'item "pear".position: (1, -1.5) is outside the room bounds (0, 4, 0, 3)'),
        ("position = [1.0, 1.0]", "position = [9.0, 1.0]",
         'viewpoint "vp".position: (9, 1) is outside the room bounds (0, 4, 0, 3)'),
        ("size = [1.0, 0.6]", "size = [1.0, 0.0]", 'furniture "table".size: sizes must be > 0, got (1, 0)'),
        ("height = 0.4", "height = -0.4", 'furniture "table".height: must be > 0, got -0.4'),
        ("size = [0.1, 0.1, 0.2]", "size = [0.1, 0.1, -0.2]",
         'item "pear".size: sizes must be > 0, got (0.1, 0.1, -0.2)'),
        ('name = "tray"', 'name = "vp"', "viewpoint[0].name: 'vp' is already the name of deposit[0]"),
        ('name = "vp"', 'name = "table"', "viewpoint[0].name: 'table' is already the name of furniture[0]"),
        ('on = "table"', 'on = "sofa"', "item \"apple\".on: no furniture named 'sofa' (nor \"floor\")"),
        ("position = [2.0, 2.0]\non", "position = [2.6, 2.0]\non",
         "item \"apple\".position: (2.6, 2) is outside the footprint of 'table' it stands on"),
        ("position = [1.0, 1.5]", "position = [1.46, 1.7]",
         "item \"pear\".position: on the floor but overlaps furniture 'table'"),
        ('category = "food"\nposition = [1.0', 'category = "toy"\nposition = [1.0',
         "item \"pear\".category: no deposit accepts category 'toy'"),
        ("range_max = 3", "false_positive = 1.5",
         "sensing.false_positive: must be a probability in [0, 1], got 1.5"),
        ("range_max = 3", "range_max = 0.8", "sensing.range_min: must be < range_max (0.8), got 0.8"),
        ("range_max = 3", "fov_h_deg = 400", "sensing.fov_h_deg: must be in (0, 360], got 400"),
        ("speed = 0.3", "speed = 0", "robot.speed: must be > 0, got 0"),
        ('unobservable_items = ["pear"]', 'unobservable_items = ["tray"]',
         "expect.unobservable_items[0]: 'tray': names a deposit, not an item"),
        ('unobservable_items = ["pear"]', 'unreachable_deposits = ["pear", "ghost"]',
         "expect.unreachable_deposits[0]: 'pear': names an item, not a deposit\n"
         "s.toml: expect.unreachable_deposits[1]: 'ghost': no deposit has this name"),
        ('unobservable_items = ["pear"]', "unreachable_items = 3",
         "expect.unreachable_items: must be a list of item names, got 3"),
        ('name = "vp"', 'name = "VP 1"',
         "viewpoint[0].name: 'VP 1' must match [a-z][a-z0-9_-]* (it becomes a PDDL name)"),
        ('name = "table"', 'name = "floor"',
         'furniture "floor".name: "floor" is reserved: it is what an item on the floor stands on\n'
         "s.toml: item \"apple\".on: no furniture named 'table' (nor \"floor\")"),
        ("[[viewpoint]]", "[viewpoint]",
         "viewpoint: must be an array of tables ([[viewpoint]]), got {'name': 'vp', 'position': [1.0, 1.0]}"),
    ],
)  # fmt: skip
def test_each_rule_has_its_message(old, new, message):
    assert errors(edit(old, new)) == [f"s.toml: {m}" for m in message.split("\ns.toml: ")]


def test_a_name_or_category_that_is_a_list_is_one_message_not_a_traceback():
    """Found by bench/fuzz.py: a furniture's name (or a deposit's category) given as a list made
    the checks between entries fail on an unhashable value."""
    assert errors(edit('name = "table"', "name = [-2.7, -1.7]")) == [
        "s.toml: furniture[0].name: must be a string, got [-2.7, -1.7]",
        's.toml: item "apple".on: no furniture named \'table\' (nor "floor")',
    ]
    messages = errors(edit('category = "food"\nposition = [3.5', "category = [1]\nposition = [3.5"))
    assert messages[0] == 's.toml: deposit "tray".category: must be a string, got [1]'


def test_tables_of_the_wrong_shape():
    no_room = MINIMAL.split("[room]")[0]
    assert errors(no_room) == ["s.toml: room: missing required key"]
    assert errors(no_room + "room = 3\n") == ["s.toml: room: must be a table ([room]), got 3"]
    assert errors(no_room + "item = [1]\n[room]" + MINIMAL.split("[room]")[1]) == [
        "s.toml: item[0]: must be a table ([[item]]), got 1"
    ]


def test_touching_footprints_do_not_overlap():
    # pear spans x in [1.25, 1.5], the table [1.5, 2.5]: exact in binary, so really touching
    s = loads(edit("position = [1.0, 1.5]\nsize = [0.1,", "position = [1.375, 1.7]\nsize = [0.25,"))
    assert (s.items[1].x, s.items[1].sx) == (1.375, 0.25)


def test_schema_version():
    assert errors(edit("schema = 1", "schema = 2")) == [
        "s.toml: schema: unknown schema version 2; this tidyplan reads 1"
    ]
    assert errors(edit("schema = 1\n", "")) == ["s.toml: schema: missing required key"]


def test_several_errors_all_reported():
    text = edit(
        "height = 0.4", "height = 0", edit('on = "table"', 'on = "sofa"', edit("speed = 0.3", "speed = -1"))
    )
    text = text.replace('name = "vp"', 'name = "pear"')
    assert errors(text) == [
        "s.toml: robot.speed: must be > 0, got -1",
        's.toml: furniture "table".height: must be > 0, got 0',
        "s.toml: viewpoint[0].name: 'pear' is already the name of item[1]",
        's.toml: item "apple".on: no furniture named \'sofa\' (nor "floor")',
    ]


def test_toml_syntax_error_has_line_and_column(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text('schema = 1\nname = "x"\nname = "y"\n')
    with pytest.raises(ScenarioError) as info:
        load(path)
    assert info.value.messages == [f"{path}:3:11: Cannot overwrite a value"]
    assert errors("schema = 1\nname =") == ["s.toml:2:7: Invalid value (at end of document)"]


def test_missing_file_and_directory(tmp_path):
    with pytest.raises(ScenarioError) as info:
        load(tmp_path / "nope.toml")
    assert info.value.messages == [f"{tmp_path / 'nope.toml'}: no such file"]
    with pytest.raises(ScenarioError) as info:
        load(tmp_path)
    assert info.value.messages == [f"{tmp_path}: is a directory, not a scenario file"]


def test_not_utf8(tmp_path):
    path = tmp_path / "latin.toml"
    path.write_bytes(b'schema = 1\ntitle = "caf\xe9"\n')
    with pytest.raises(ScenarioError) as info:
        load(path)
    assert info.value.messages == [f"{path}: not UTF-8 text (bad byte at offset 23)"]


def test_prior_is_what_the_robot_is_told_and_never_the_items():
    told = loads(FULL + "\n[prior]\ncount = { food = 5 }\n", "s.toml")
    assert told.prior_counts() == {"food": 5}  # two food items in the room: the prior is not a count of them
    assert loads(FULL, "s.toml").prior_counts() is None
    blind = told.without_items()
    assert blind.items == () and blind.prior == told.prior and blind.furniture == told.furniture


def test_prior_messages():
    assert errors(FULL + "\n[prior]\ncount = { tool = 1, food = -1, Food = 2 }\n") == [
        "s.toml: prior.count.tool: no deposit accepts category 'tool'",
        "s.toml: prior.count.food: must be a whole number >= 0, got -1",
        "s.toml: prior.count.Food: 'Food' must match [a-z][a-z0-9_-]* (it becomes a PDDL name)",
    ]
    assert errors(FULL + "\n[prior]\ntotal = 3\n") == [
        "s.toml: prior.total: unknown key (known: count)",
        "s.toml: prior.count: must be a table of category = count, got None",
    ]


# A chest of drawers against the west wall (its front face at x = 0.52), its drawer sliding out
# 0.25 m towards the approach: closed flush with the face, 0.25 m deep.
DRAWER = (
    MINIMAL
    + """\

[[furniture]]
name = "chest"
center = [0.3, 1.5]
size = [0.44, 0.99]
height = 0.94
kind = "drawer"

[[deposit]]
name = "drawer"
category = "tool"
position = [0.645, 1.5, 0.3]
approach = [1.12, 1.5]

[deposit.drawer]
closed = true
travel = 0.25
"""
)


def test_a_drawer_deposit_loads_with_its_defaults_and_its_layout():
    s = loads(DRAWER, "s.toml")
    (d,) = s.deposits
    assert d.drawer == DrawerSpec(closed=True, travel=0.25, width=0.40, rim=0.10, handle_height=None)
    layout = drawer_layout(s.furniture, d)
    assert layout.carcass.name == "chest" and (layout.k, layout.sign) == (0, 1.0)
    assert (layout.front, layout.depth, layout.floor_z) == pytest.approx((0.52, 0.25, 0.3))
    assert layout.handle(0.0) == pytest.approx((0.5375, 1.5, 0.344))
    assert layout.interior(0.25) == pytest.approx((0.532, 0.758, 1.3, 1.7))
    # a deposit without a drawer has none
    assert loads(FULL).deposits[0].drawer is None


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        ("travel = 0.25", "travel = -0.1", 'deposit "drawer".drawer.travel: must be > 0, got -0.1'),
        ("travel = 0.25", "travel = 0.25\nhandle = 3",
         'deposit "drawer".drawer.handle: unknown key (known: closed, handle_height, rim, travel, width)'),
        ("closed = true", 'closed = "yes"',
         "deposit \"drawer\".drawer.closed: must be true or false, got 'yes'"),
        ("[deposit.drawer]\nclosed = true\ntravel = 0.25\n", "drawer = 3\n",
         'deposit "drawer".drawer: must be a table ([deposit.drawer]), got 3'),
        ("approach = [1.12, 1.5]\n", "",
         'deposit "drawer".approach: missing required key (a drawer is pulled open from there)'),
        ("center = [0.3, 1.5]", "center = [0.3, 2.5]",
         'deposit "drawer".position: no furniture piece holds the closed drawer (0.25 m back from it '
         "towards the approach)"),
        ("approach = [1.12, 1.5]", "approach = [0.9, 1.5]",
         "deposit \"drawer\".approach: the open drawer and its handle reach 0.285 m out of 'chest': the "
         "base (0.22 m) at the approach would touch them"),
        ("travel = 0.25", "travel = 0.25\nwidth = 1.0",
         "deposit \"drawer\".drawer.width: the drawer (1 m inside) does not fit across 'chest'"),
        ("travel = 0.25", "travel = 0.25\nhandle_height = 0.6",
         "deposit \"drawer\".drawer.handle_height: the handle at 0.6 m is not on the drawer's front"),
        ("position = [0.645, 1.5, 0.3]", "position = [0.645, 1.5, 0.9]",
         "deposit \"drawer\".position: z: a drawer floor at 0.9 m leaves it outside 'chest' (0 to 0.94 m)"),
        ("position = [0.645, 1.5, 0.3]", "position = [0.4, 1.5, 0.3]",
         "deposit \"drawer\".position: closed, the drawer (0.74 m deep) would not fit in 'chest'"),
    ],
)  # fmt: skip
def test_each_drawer_rule_has_its_message(old, new, message):
    assert errors(edit(old, new, DRAWER)) == [f"s.toml: {message}"]


def test_a_drawer_and_facts_are_written_out_and_read_back_unchanged():
    from dataclasses import replace

    from sim.scenario.write import dumps
    from tidyplan.loop.scenarios import project_file

    s = replace(
        load(project_file("problems/wrs-drawer.toml")), facts=(("fragile", "tray"), ("shortest-paths",))
    )
    back = loads(dumps(s), s.path)
    assert back.deposits == s.deposits and back.facts == s.facts
    assert back.time_limit_s is None
    limited = replace(s, time_limit_s=900.0)  # the referee's clock, where a scenario has one
    assert loads(dumps(limited), s.path).time_limit_s == 900.0
    assert any(d.drawer is not None and d.drawer.closed for d in back.deposits)
