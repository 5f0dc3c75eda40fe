"""Algorithm 1 (Yan et al.): the waypoint for removing a blocking object."""

from tidyplan.planning.removal import Waypoint, removal_waypoint

# The situation of the paper's Fig. 3, as its text describes it: the robot holds
# the closest blocking object; around it are waypoints used for grasping and for
# delivery, one it has not been to yet, and the ones it passed on the way in from
# the entrance. The answer is the nearest waypoint it has passed that serves
# neither grasping nor delivery.
FIG3 = [
    Waypoint("grasp-o3", 1.0, 0.2, for_grasping=True, reached=True),  # nearest, but for grasping
    Waypoint("deposit-tray", 0.6, 0.9, for_delivery=True, reached=True),  # for delivery
    Waypoint("unexplored", 1.2, -0.3),  # free and near, but never reached
    Waypoint("corridor", 2.0, 0.5, reached=True),  # the answer
    Waypoint("entrance", 3.0, 0.0, reached=True),  # eligible, farther
]
ROBOT = (1.1, 0.0)


def test_algorithm_1_on_the_fig3_situation():
    assert removal_waypoint(FIG3, ROBOT).name == "corridor"


def test_a_waypoint_for_grasping_is_never_chosen():
    only = [Waypoint("g", 1.1, 0.0, for_grasping=True, reached=True), Waypoint("far", 9, 9, reached=True)]
    assert removal_waypoint(only, ROBOT).name == "far"


def test_a_waypoint_for_delivery_is_never_chosen():
    only = [Waypoint("d", 1.1, 0.0, for_delivery=True, reached=True), Waypoint("far", 9, 9, reached=True)]
    assert removal_waypoint(only, ROBOT).name == "far"


def test_a_waypoint_not_yet_reached_is_never_chosen():
    only = [Waypoint("new", 1.1, 0.0), Waypoint("far", 9, 9, reached=True)]
    assert removal_waypoint(only, ROBOT).name == "far"


def test_no_eligible_waypoint_gives_none():
    assert (
        removal_waypoint([w for w in FIG3 if not w.reached or w.for_grasping or w.for_delivery], ROBOT)
        is None
    )
    assert removal_waypoint([], ROBOT) is None


def test_nearest_by_path_length_when_given_one():
    """With a wall in the way, the Euclidean nearest is not the nearest by path."""
    near_behind_wall = Waypoint("behind-wall", 1.1, 0.5, reached=True)
    farther_open = Waypoint("open", 1.1, -1.0, reached=True)

    def path_length(a, b):
        return 4.0 if b == (1.1, 0.5) else 1.0

    assert removal_waypoint([near_behind_wall, farther_open], ROBOT).name == "behind-wall"
    assert removal_waypoint([near_behind_wall, farther_open], ROBOT, path_length).name == "open"


def test_unreachable_by_path_is_not_eligible():
    ws = [Waypoint("cut-off", 1.1, 0.1, reached=True), Waypoint("open", 2, 0, reached=True)]
    assert removal_waypoint(ws, ROBOT, lambda a, b: None if b == (1.1, 0.1) else 1.0).name == "open"


def test_ties_go_to_the_name():
    ws = [Waypoint("b", 1.1, 1.0, reached=True), Waypoint("a", 1.1, -1.0, reached=True)]
    assert removal_waypoint(ws, ROBOT).name == "a"
    assert removal_waypoint(list(reversed(ws)), ROBOT).name == "a"


def test_the_item_in_hand_goes_down_beside_the_robot_when_no_removal_waypoint_is_open():
    # Case III under load: holding a tool at a grasp pose, a box on the floor shut both the way to
    # the drawer and the way to the one removal waypoint. Taking the box needs a free hand.
    from types import SimpleNamespace

    from tidyplan.belief.mapfacts import MapFacts
    from tidyplan.belief.problem import removal_choices

    facts = MapFacts(
        points={
            "wp-entrance": (0.0, 0.0),
            "vp-north": (0.0, 2.0),
            "wp-tool-1": (1.0, 1.0),
            "wp-box-1": (1.5, 1.0),
        },
        kind={"wp-entrance": "entrance", "vp-north": "viewpoint", "wp-tool-1": "grasp", "wp-box-1": "grasp"},
        grasp={"tool-1": "wp-tool-1", "box-1": "wp-box-1"},
    )
    facts.path = {("wp-tool-1", "wp-box-1"): 0.5, ("wp-box-1", "wp-tool-1"): 0.5}
    facts.blocked = {
        (a, b): 1.5 for a in facts.points for b in facts.points if a != b and (a, b) not in facts.path
    }
    belief = SimpleNamespace(reached={"wp-entrance", "vp-north", "wp-tool-1"}, holding="tool-2")
    assert removal_choices(facts, belief, "wp-tool-1")["tool-2"] == "wp-tool-1"
    facts.path[("wp-tool-1", "vp-north")] = facts.blocked.pop(("wp-tool-1", "vp-north"))
    assert removal_choices(facts, belief, "wp-tool-1")["tool-2"] == "vp-north"  # Algorithm 1 when open


def test_the_removal_waypoints_are_algorithm_1s_over_every_waypoint_of_the_map():
    """``removal_choices`` hands Algorithm 1 only the waypoints it may choose; on maps of every
    kind of waypoint, some reached, some paths open, its answers are those of Algorithm 1 over
    all of them with their flags (grasp, deposit, reached)."""
    import random
    from types import SimpleNamespace

    from tidyplan.belief.mapfacts import MapFacts
    from tidyplan.belief.problem import NOT_FOR_REMOVAL, _length, removal_choices

    kinds = ["entrance", "viewpoint", "deposit", "grasp", "adjust", "robot"]
    chosen = 0
    for seed in range(40):
        rng = random.Random(seed)
        names = [f"w{k}" for k in range(rng.randint(3, 14))]
        facts = MapFacts(
            points={n: (rng.uniform(0, 5), rng.uniform(0, 5)) for n in names},
            kind={n: rng.choice(kinds) for n in names},
        )
        grasps = [n for n in names if facts.kind[n] == "grasp"]
        facts.grasp = {f"item-{n}": n for n in grasps}
        facts.path = {
            (a, b): round(rng.uniform(0.5, 6), 2)
            for a in names
            for b in names
            if a != b and rng.random() < 0.7
        }
        belief = SimpleNamespace(reached={n for n in names if rng.random() < 0.6}, holding=None)
        robot_wp = rng.choice(names)
        want = {}
        every = [
            Waypoint(
                n,
                *facts.points[n],
                for_grasping=facts.kind[n] == "grasp",
                for_delivery=facts.kind[n] == "deposit",
                reached=n in belief.reached and facts.kind[n] not in NOT_FOR_REMOVAL,
            )
            for n in sorted(names)
        ]
        for item, origin in sorted(facts.grasp.items()):
            length = lambda a, b, o=origin, f=facts: _length(f, o, b)  # noqa: E731
            w = removal_waypoint(every, facts.points[origin], length)
            if w is not None:
                want[item] = w.name
        assert removal_choices(facts, belief, robot_wp) == want, seed
        chosen += len(want)
    assert chosen  # some item had a removal waypoint: the test is of something
