"""Fuzzing of the Python module: thousands of random bad calls to billiard.Simulation's methods,
to the containers (the shape functions and Container's add_ calls), to billiard.Settings and to
the six course functions, from a fixed seed (BILLIARD_FUZZ_SEED=k explores another).

The rule for errors, checked on every call:
  - a wrong value (nan, infinities, beyond the documented 1e50 / 1e-50, a negative count, an
    array of the wrong shape, complex, boolean, text or object numbers, a read-only,
    non-contiguous or non-float64 array where a course function writes in place): ValueError whose
    message names the argument (a field of the settings as "settings.<field>", when
    Simulation(container, settings) checks them);
  - a wrong Python type for a scalar (None, a string or a list for a number, a float for an int),
    an int beyond the C++ parameter's range (n >= 2**31, a negative seed for add_random_discs), or
    anything but a numpy array for a course function's array: TypeError from pybind11, whose
    message lists the signature with the argument's name;
  - adding discs after the first advance(): RuntimeError (std::logic_error). Arguments are
    converted first, so a conversion error (the two above) wins over it; a convertible but bad
    value after the start is the RuntimeError.
After every refusal the simulation, the container or the settings are unchanged (bit for bit),
and a simulation still advances exactly like an untouched twin (one made from the refused
container or settings, like one made from a twin); the course functions leave their in-place
arrays untouched. Valid calls with extreme values must keep the simulation valid and finite."""

import math
import os
import random
import struct
import sys
from collections import Counter, namedtuple

import numpy as np
import pytest

import billiard

SEED = int(os.environ.get("BILLIARD_FUZZ_SEED", "24301"))
NAN, INF = math.nan, math.inf
HUGE = sys.float_info.max
DENORMAL = 5e-324


# ---- Values ---------------------------------------------------------------------------------

class Unreadable:
    """numpy cannot turn it into an array: its __array__ raises."""

    def __array__(self, *args, **kwargs):
        raise RuntimeError("no array here")


NOT_FINITE_OR_HUGE = [NAN, -NAN, INF, -INF, 1e308, -1e308, HUGE, 1e51, -1e51]
BAD_SCALES = NOT_FINITE_OR_HUGE + [0.0, -0.0, -1.0, -DENORMAL, DENORMAL, 1e-308, 1e-51]  # radius, mass, inertia
BAD_NONNEGATIVE = [NAN, INF, -INF, -1.0, -DENORMAL, -1e308]
NOT_FLOATS = [None, "1.0", [1.0], (1.0,), {}, object(), 1j, b"1", 10**400]
NOT_INTS = [2.5, "3", None, [3], 3.0, np.float64(3.0)]
BEYOND_INT = [2**31, -2**31 - 1, 2**63, 2**100, -2**100]
BEYOND_INT64 = [2**63, -2**63 - 1, 2**100]
BEYOND_UINT64 = [-1, 2**64, -2**70]
NOT_POINTS = [None, "ab", [1.0, 2.0, 3.0], [1.0], [], [[1, 2], [3, 4]], {"x": 1}, object(), Unreadable(),
              np.array([1 + 1j, 2]), np.array([True, False]), np.array(["1", "2"]), [1.0, None], [[1, 2], [3]]]
NOT_ARRAYS = [None, "abc", np.zeros(3), np.zeros((3, 3)), np.zeros((2, 2, 2)), np.zeros(0), 5.0, [[1, 2], [3]],
              np.zeros((3, 2), complex), np.zeros((3, 2), bool), np.array([["1", "2"]]),
              np.array([[1.0, None]], dtype=object), Unreadable()]


def bad_point(rng):
    good = rng.uniform(-3, 3)
    bad = rng.choice(NOT_FINITE_OR_HUGE)
    return rng.choice([(bad, good), (good, bad), (bad, bad)])


def bits(x):
    """x as exact bits, to compare states bit for bit (nan == nan, 0.0 != -0.0)."""
    if isinstance(x, np.ndarray):
        return ("array", x.dtype.str, x.shape, x.tobytes())
    if isinstance(x, float):
        return ("float", struct.pack("<d", x))
    if isinstance(x, dict):
        return {key: bits(value) for key, value in x.items()}
    if isinstance(x, (list, tuple)):
        return tuple(bits(value) for value in x)
    return x


def first_difference(before, after):
    for key in before:
        if before[key] != after.get(key):
            return key
    return None


# ---- Simulations --------------------------------------------------------------------------------

Start = namedtuple("Start", "name make started")


def _table():
    sim = billiard.Simulation(billiard.circular_table(10.0))
    sim.add_random_discs(20, 0.5, seed=1)
    return sim


def _box():
    sim = billiard.Simulation(billiard.box((0.0, 0.0), (20.0, 10.0)))
    sim.add_disc((1.0, 1.0), (1.0, 0.0), radius=0.3, mass=0.5)
    sim.add_random_discs(25, 0.4, mass=2.0, seed=2)
    return sim


def _periodic():
    sim = billiard.Simulation(billiard.periodic_box(20.0, 15.0))
    sim.add_random_discs(30, 0.5, seed=3)
    return sim


def _hexagon():
    angles = np.arange(6) * np.pi / 3
    container = billiard.polygon(10 * np.column_stack([np.cos(angles), np.sin(angles)]))
    container.add_segment((-2.0, -2.0), (2.0, 3.0))
    return container


def _polygon():
    sim = billiard.Simulation(_hexagon())
    sim.add_random_discs(15, 0.6, seed=4)
    return sim


def _gravity():
    sim = billiard.Simulation(billiard.box((0.0, 0.0), (15.0, 15.0)), billiard.Settings(gravity=(0.1, -2.0)))
    sim.add_random_discs(20, 0.5, seed=5)
    return sim


def _started():
    sim = billiard.Simulation(billiard.box((0.0, 0.0), (20.0, 20.0)))
    sim.add_random_discs(30, 0.5, seed=6)
    sim.set_log_events(True)
    sim.advance(events=200)
    return sim


def _rough_periodic_started():
    sim = billiard.Simulation(billiard.periodic_box(15.0, 15.0), billiard.Settings(restitution=(0.9, 0.5)))
    sim.add_random_discs(25, 0.5, seed=7)
    sim.set_log_events(True)
    sim.advance(events=100)
    return sim


def _one_disc_in_a_box():
    sim = billiard.Simulation(billiard.box((0.0, 0.0), (5.0, 4.0)))
    sim.add_disc((1.0, 2.0), (0.5, -1.0))
    return sim


def _empty_table_started():
    sim = billiard.Simulation(billiard.circular_table(3.0))
    sim.advance(events=10, time=1.0)
    return sim


STARTS = [
    Start("box without discs", lambda: billiard.Simulation(billiard.box((-6.0, -6.0), (6.0, 6.0))), False),
    Start("one disc in a box", _one_disc_in_a_box, False),
    Start("table", _table, False),
    Start("box", _box, False),
    Start("periodic box", _periodic, False),
    Start("polygon and a segment", _polygon, False),
    Start("box with gravity", _gravity, False),
    Start("box after 200 collisions, event log on", _started, True),
    Start("rough periodic box after 100 collisions", _rough_periodic_started, True),
    Start("table without discs, started", _empty_table_started, True),
]


def snapshot(sim):
    container = sim.container
    return bits({
        "len": len(sim), "time": sim.time, "current_state": sim.current_state, "initial_state": sim.initial_state,
        "walls": container.walls, "period": container.period, "table_radius": container.table_radius,
        "periodic": container.periodic, "container": repr(container), "gravity": sim.gravity,
        "restitution": sim.restitution, "exchange_velocities": sim.exchange_velocities,
        "totals": sim.totals, "event_log": sim.event_log, "kinetic_energy": sim.kinetic_energy(),
        "potential_energy": sim.potential_energy(), "contact_duration": sim.contact_duration,
        "elastic_impact_speed": sim.elastic_impact_speed, "sleep_speed": sim.sleep_speed,
        "sleeping_discs": sim.sleeping_discs,
    })


def finite(sim):
    state = sim.current_state
    return all(np.isfinite(state[key]).all() for key in ("position", "velocity", "spin")) and math.isfinite(sim.time)


# ---- Calls ----------------------------------------------------------------------------------------

# kind: "value" (the library refuses it: ValueError, or RuntimeError when a setup call comes after
# the start), "convert" (the binding cannot read it: ValueError before any check of the state),
# "type" (pybind11 finds no overload: TypeError), "either" (valid, maybe extreme: accepted or
# refused for the state, e.g. a disc outside the table). names: one must be in the message.
Call = namedtuple("Call", "text run kind names setup", defaults=(True,))


def call(text, run, kind, names, setup=True):
    return Call(text, run, kind, [names] if isinstance(names, str) else names, setup)


def float_argument(rng, bad_values, optional=False):
    """A bad value for a float parameter: (value, kind). (None is valid where it means "automatic".)"""
    if rng.random() < 0.25:
        return rng.choice([x for x in NOT_FLOATS if not (optional and x is None)]), "type"
    return rng.choice(bad_values), "value"


def point_argument(rng):
    return (rng.choice(NOT_POINTS), "convert") if rng.random() < 0.4 else (bad_point(rng), "value")


def array_argument(rng, rows=3):
    """A bad (n, 2) array for the Simulation (copied, so any layout or writability is fine)."""
    if rng.random() < 0.5:
        return rng.choice(NOT_ARRAYS), "convert"
    array = np.array([[rng.uniform(-3, 3), rng.uniform(-3, 3)] for _ in range(max(rows, 1))])
    array[rng.randrange(len(array)), rng.randrange(2)] = rng.choice(NOT_FINITE_OR_HUGE)
    return array, "value"


def bad_restitution(rng):
    """A bad value for Settings.restitution and set_restitution: (value, kind, names)."""
    choice = rng.randrange(3)
    if choice == 0:
        return rng.choice(["0.9", None, [1.0, 2.0, 3.0], [], True, object(), 1j, Unreadable(), [0.5, None],
                           np.array([True, False]), (0.9, (1.0,))]), "convert", ["settings.restitution"]
    if choice == 1:
        normal = rng.choice([NAN, INF, -INF, -0.1, 1.5, 1.0000000000000002, -DENORMAL, 1e308])
        return rng.choice([normal, (normal, -1.0), np.array([normal, 0.5])]), "value", ["settings.restitution.normal"]
    tangential = rng.choice([NAN, INF, -INF, -1.0000000000000002, 1.5, -2.0, 1e308])
    return (0.9, tangential), "value", ["settings.restitution.tangential"]


def bad_simulation_call(rng, start):
    choice = rng.randrange(9)
    if choice == 0:  # (given as Settings.restitution is: a number or a pair)
        value, kind, names = bad_restitution(rng)
        return call(f"set_restitution({value!r})", lambda s: s.set_restitution(value), kind,
                    [name.replace("settings.", "set_restitution: ") for name in names], setup=False)
    if choice in (1, 2):
        return bad_disc(rng, start)
    if choice == 3:
        return bad_discs(rng)
    if choice == 4:
        return bad_random_discs(rng, start)
    if choice == 5:
        if rng.random() < 0.5:
            events = rng.choice([-1, -2**31, -2**62] + BEYOND_INT64 + NOT_INTS[:2])
            kind = "value" if isinstance(events, int) and -2**63 <= events < 2**63 else "type"
            return call(f"advance(events={events!r})", lambda s: s.advance(events=events), kind, "events", setup=False)
        duration, kind = float_argument(rng, [NAN, -INF, -1.0, -DENORMAL, -1e308], optional=True)
        return call(f"advance(10, time={duration!r})", lambda s: s.advance(events=10, time=duration), kind, "time",
                    setup=False)
    if choice == 6:
        tolerance, kind = float_argument(rng, BAD_NONNEGATIVE + [INF])
        return call(f"validate({tolerance!r})", lambda s: s.validate(tolerance), kind, "tolerance", setup=False)
    if choice == 7:
        if rng.random() < 0.5:
            dt = rng.choice([NAN, 0.0, -0.0, -1.0, -INF, None, "0.1"])
            kind = "type" if dt is None or isinstance(dt, str) else "value"
            return call(f"replay_by_time({dt!r})", lambda s: next(s.replay_by_time(dt)), kind, "dt", setup=False)
        until = rng.choice([NAN, INF, -INF, "later"])
        kind = "type" if isinstance(until, str) else "value"
        return call(f"replay_by_time(0.1, until={until!r})", lambda s: next(s.replay_by_time(0.1, until)), kind, "until",
                    setup=False)
    value, kind = float_argument(rng, BAD_NONNEGATIVE, optional=True)
    if rng.random() < 0.5:
        return call(f"set_contact_duration({value!r})", lambda s: s.set_contact_duration(value), kind, "duration",
                    setup=False)
    if rng.random() < 0.5:
        return call(f"set_sleep_speed({value!r})", lambda s: s.set_sleep_speed(value), kind, "speed", setup=False)
    return call(f"set_elastic_impact_speed({value!r})", lambda s: s.set_elastic_impact_speed(value), kind, "speed",
                setup=False)


def bad_disc(rng, start):
    args = {"position": (rng.uniform(-3, 3), rng.uniform(-3, 3)), "velocity": (rng.uniform(-2, 2), 0.5),
            "radius": rng.uniform(0.1, 1), "mass": rng.uniform(0.5, 2), "inertia": None, "spin": 0.0}
    field = rng.choice(list(args))
    if field in ("position", "velocity"):
        args[field], kind = point_argument(rng)
    elif field == "spin":
        args[field], kind = float_argument(rng, NOT_FINITE_OR_HUGE)
    else:
        args[field], kind = float_argument(rng, BAD_SCALES, optional=field == "inertia")
    return call(f"add_disc(**{args!r})", lambda s: s.add_disc(**args), kind, field)


def bad_discs(rng):
    rows = rng.randrange(0, 5)
    positions = np.array([[rng.uniform(-4, 4), rng.uniform(-4, 4)] for _ in range(rows)]).reshape(rows, 2)
    velocities = np.zeros((rows, 2))
    radius, mass = 0.1, 1.0
    choice = rng.randrange(5)
    if choice == 0:
        velocities, kind, names = np.zeros((rows + rng.randrange(1, 3), 2)), "value", "velocities has"
    elif choice == 1:
        (radius, kind), names = float_argument(rng, BAD_SCALES), "radius"
    elif choice == 2:
        (mass, kind), names = float_argument(rng, BAD_SCALES), "mass"
    elif choice == 3:
        positions, kind = array_argument(rng, rows)
        velocities = np.zeros((len(positions) if kind == "value" else rows, 2))
        # (an earlier row may conflict with the state first: overlapping, outside, too small)
        names = "positions" if kind == "convert" else ["position", "overlaps", "outside", "too small"]
    else:
        velocities, kind = array_argument(rng, rows)
        positions = np.zeros((len(velocities) if kind == "value" else rows, 2))
        names = "velocities" if kind == "convert" else ["velocity", "overlaps", "outside", "too small"]
    return call(f"add_discs({positions!r}, {velocities!r}, {radius!r}, {mass!r})",
                lambda s: s.add_discs(positions, velocities, radius, mass), kind, names)


def bad_random_discs(rng, start):
    args = {"n": rng.randrange(1, 40), "radius": rng.uniform(0.05, 0.3), "mass": 1.0, "kT": 1.0, "seed": rng.randrange(2**64)}
    choice = rng.randrange(6)
    if choice == 0:
        args["n"] = rng.choice([-1, -2**31, -rng.randrange(1, 2**31)] + BEYOND_INT + NOT_INTS)
        kind, names = ("value", "n must") if isinstance(args["n"], int) and -2**31 <= args["n"] < 2**31 else ("type", "n")
    elif choice in (1, 2):
        field = "radius" if choice == 1 else "mass"
        args[field], kind = float_argument(rng, BAD_SCALES)
        names = field
    elif choice == 3:
        args["kT"], kind = float_argument(rng, BAD_NONNEGATIVE + [1e308])
        names = "kT"
    elif choice == 4:
        args["seed"] = rng.choice(BEYOND_UINT64 + NOT_INTS)
        kind, names = "type", "seed"
    else:  # impossible packings: refused at once, however large n is
        args["n"], args["radius"] = rng.choice([2**31 - 1, 2**30, 10**6, 10**5]), rng.uniform(0.5, 2)
        kind, names = "value", ["fit", "too small"]
    return call(f"add_random_discs(**{args!r})", lambda s: s.add_random_discs(**args), kind, names)


def extreme_value(rng, typical):
    """A coordinate: typical, or one of the documented limits, -0.0 or a denormal."""
    if rng.random() < 0.5:
        return rng.uniform(-typical, typical)
    return rng.choice([0.0, -0.0, DENORMAL, -1e-308, 1e50, -1e50, 1e-50, typical])


def extreme_length(rng, typical):
    """A length or mass: typical, or one of the documented limits."""
    return rng.uniform(0.1, 1) * typical if rng.random() < 0.5 else rng.choice([1e-50, 1e50, 1e-20, 1e20, typical])


def plausible_simulation_call(rng):
    """A valid call, sometimes with extreme values (the documented limits, -0.0, denormals)."""
    def extreme(typical):
        return extreme_value(rng, typical)

    def extreme_scale(typical):
        return extreme_length(rng, typical)

    choice = rng.randrange(6)
    if choice <= 2:
        position, velocity = (extreme(10), extreme(10)), (extreme(3), extreme(3))
        radius, mass = extreme_scale(0.5), extreme_scale(1.0)
        layout = rng.choice(["tuple", "array", "read-only", "strided"])
        if layout != "tuple":
            position = np.array([position[0], 7.0, position[1]])[::2] if layout == "strided" else np.array(position)
            position.flags.writeable = layout != "read-only"
        return call(f"add_disc({position!r}, {velocity!r}, {radius!r}, {mass!r})",
                    lambda s: s.add_disc(position, velocity, radius, mass), "either", [])
    if choice == 3:
        n, radius, kT = rng.randrange(0, 30), rng.choice([1e-50, 1e-10, 0.1, 0.3]), rng.choice([0.0, 1e-300, 1.0, 1e50])
        seed = rng.randrange(2**64)
        positions = np.zeros((0, 2))[:, ::-1]  # (a valid empty, non-contiguous array)
        return call(f"add_random_discs({n}, {radius!r}, kT={kT!r}) and add_discs(empty)",
                    lambda s: (s.add_random_discs(n, radius, kT=kT, seed=seed), s.add_discs(positions, positions, 0.1)),
                    "either", [])
    if choice == 4:
        normal, tangential = rng.choice([0.0, 1e-3, 0.5, 0.9, 1.0]), rng.choice([-1.0, 0.0, -0.0, 1.0])
        return call(f"set_restitution(({normal!r}, {tangential!r}))", lambda s: s.set_restitution((normal, tangential)),
                    "either", [], setup=False)
    events, duration = rng.choice([None, 0, 1, 50]), rng.choice([None, 0.0, -0.0, DENORMAL, 0.5, INF])
    if events is None and (duration is None or duration == INF):  # (no limit at all would never end)
        events = 5
    return call(f"advance({events!r}, {duration!r})", lambda s: s.advance(events=events, time=duration), "either", [],
                setup=False)


def expected(start, c):
    """The exception the call must raise (None: any outcome) and the names one of which it shows."""
    if c.kind == "type":
        return TypeError, [f"{name.strip()}:" for name in c.names] + [f"{name.strip()}=" for name in c.names]
    if c.kind == "convert":
        return ValueError, c.names
    if c.setup and start.started:
        return RuntimeError, ["started"]
    if c.kind == "value":
        return ValueError, c.names
    return None, []


def accepted(where, error, names, run, counts):
    """Runs run(); a refusal must be the expected error (a ValueError when either may come) naming
    one of `names`, an acceptance must be expected. Counts the outcome; returns whether accepted."""
    try:
        run()
    except (ValueError, TypeError, RuntimeError) as raised:
        message = str(raised)
        counts[type(raised).__name__] += 1
        if error is not None:
            assert type(raised) is error, f"{where}: {type(raised).__name__} instead of {error.__name__}: {message}"
            assert any(name in message for name in names), f"{where}: the message names none of {names}: {message}"
        else:
            assert type(raised) is ValueError, f"{where}: {type(raised).__name__}: {message}"
        return False
    assert error is None, f"{where}: accepted, expected {error.__name__}"
    counts["accepted"] += 1
    return True


def check(start, c, counts):
    where = f"{start.name}: {c.text}"
    sim, twin = start.make(), start.make()
    before = snapshot(sim)
    error, names = expected(start, c)
    if accepted(where, error, names, lambda: c.run(sim), counts):
        assert sim.validate() is None, where
        assert finite(sim), where
        sim.advance(events=20)
        assert sim.validate() is None and finite(sim), where
        return
    # Refused: the same simulation as before, bit for bit, valid, and it goes on like its twin.
    changed = first_difference(before, snapshot(sim))
    assert changed is None, f"{where}: the refused call changed {changed}"
    assert sim.validate() is None, where
    sim.advance(events=20)
    twin.advance(events=20)
    changed = first_difference(snapshot(twin), snapshot(sim))
    assert changed is None, f"{where}: after the refused call, advancing gives a different {changed}"


needs_simulation = pytest.mark.skipif(not hasattr(billiard, "Simulation"),
                                      reason="this build has no billiard.Simulation (the engine library is not built)")


@needs_simulation
def test_bad_calls_to_the_simulation_raise_naming_the_argument_and_change_nothing(capsys):
    rng = random.Random(SEED)
    counts = Counter()
    calls = 4000
    for k in range(calls):
        start = rng.choice(STARTS)
        c = plausible_simulation_call(rng) if k % 5 == 4 else bad_simulation_call(rng, start)
        check(start, c, counts)
    refused = counts["ValueError"] + counts["TypeError"] + counts["RuntimeError"]
    with capsys.disabled():  # (the counts belong in the test command's log, pass or fail)
        print(f"python Simulation fuzz (seed {SEED}): {calls} calls, {counts['ValueError']} ValueError, "
              f"{counts['TypeError']} TypeError, {counts['RuntimeError']} RuntimeError, {counts['accepted']} accepted; "
              "every refusal left the simulation unchanged")
    assert refused + counts["accepted"] == calls
    assert counts["ValueError"] > calls // 3 and counts["TypeError"] > calls // 20 and counts["RuntimeError"] > calls // 20
    assert counts["accepted"] > calls // 20


# ---- Containers -----------------------------------------------------------------------------------
# The shape functions and Container's add_ calls. A container is a value: after a refusal it is
# the same bit for bit (its walls, its kind, and what its repr counts: outlines and obstacles), and
# a simulation made of it runs exactly like one made of an untouched twin.

Shape = namedtuple("Shape", "name make periodic")


def _stadium_with_an_arc():
    container = billiard.stadium((0.0, 0.0), 5.0, 4.0)
    container.add_arc((0.0, 0.0), 2.0, 0.0, np.pi)
    return container


def _box_with_a_triangle():
    container = billiard.box((-10.0, -10.0), (10.0, 10.0))
    container.add_obstacle(billiard.polygon([[0.0, 0.0], [3.0, 0.0], [0.0, 3.0]]))
    return container


SHAPES = [
    Shape("circular table", lambda: billiard.circular_table(10.0), False),
    Shape("box", lambda: billiard.box((0.0, 0.0), (20.0, 10.0)), False),
    Shape("periodic box", lambda: billiard.periodic_box(20.0, 15.0), True),
    Shape("polygon and a segment", _hexagon, False),
    Shape("Sinai billiard", lambda: billiard.sinai_billiard((0.0, 0.0), (10.0, 10.0), 2.0), False),
    Shape("stadium with an arc", _stadium_with_an_arc, False),
    Shape("box with a triangle obstacle", _box_with_a_triangle, False),
    Shape("mushroom", lambda: billiard.mushroom((0.0, 0.0), 5.0, 2.0, 4.0), False),
    Shape("union of circles", lambda: billiard.union_of_circles([[0.0, 0.0], [4.0, 0.0]], [3.0, 2.5]), False),
]
BAD_LENGTHS = NOT_FINITE_OR_HUGE + [0.0, -0.0, -1.0, -DENORMAL]
BAD_ANGLES = [NAN, INF, -INF, 1e7, -1e7, 1e308]


def container_snapshot(container):
    return bits({"walls": container.walls, "period": container.period, "table_radius": container.table_radius,
                 "periodic": container.periodic, "repr": repr(container)})


def run_in(container):
    """A simulation of the container with a few random discs, after 50 collisions (as a snapshot)."""
    sim = billiard.Simulation(container)
    sim.add_random_discs(10, 0.2, seed=1)
    sim.advance(events=50)
    return snapshot(sim)


def bad_shape_call(rng):
    """A shape function with one bad argument: (text, run, kind, names); run ignores its container."""
    choice = rng.randrange(8)
    if choice == 0:
        r, kind = float_argument(rng, BAD_LENGTHS)
        return call(f"circular_table({r!r})", lambda c: billiard.circular_table(r), kind, "radius")
    if choice == 1:
        bad, kind = float_argument(rng, NOT_FINITE_OR_HUGE + [0.0, -0.0, -1.0])
        if rng.random() < 0.5:
            return call(f"periodic_box({bad!r}, 20)", lambda c: billiard.periodic_box(bad, 20.0), kind, "width")
        return call(f"periodic_box(20, {bad!r})", lambda c: billiard.periodic_box(20.0, bad), kind, "height")
    if choice == 2:
        p, kind = point_argument(rng)
        if rng.random() < 0.5:
            return call(f"box({p!r}, (30, 30))", lambda c: billiard.box(p, (30.0, 30.0)), kind, "lower")
        return call(f"box((-30, -30), {p!r})", lambda c: billiard.box((-30.0, -30.0), p), kind, "upper")
    if choice == 3:
        vertices, kind = array_argument(rng, rows=rng.choice([2, 4, 5]))
        names = ["vertices", "vertex"] if kind == "value" else "vertices"
        return call(f"polygon({vertices!r})", lambda c: billiard.polygon(vertices), kind, names)
    if choice == 4:
        field = rng.choice(["centre", "radius", "length"])
        args = {"centre": (1.0, 2.0), "radius": 3.0, "length": 4.0}
        args[field], kind = point_argument(rng) if field == "centre" else float_argument(rng, BAD_LENGTHS)
        return call(f"stadium(**{args!r})", lambda c: billiard.stadium(**args), kind, field)
    if choice == 5:
        field = rng.choice(["lower", "upper", "obstacle_radius"])
        args = {"lower": (0.0, 0.0), "upper": (10.0, 8.0), "obstacle_radius": 2.0}
        if field == "obstacle_radius":
            args[field], kind = float_argument(rng, BAD_LENGTHS + [4.0, 5.0])  # (at least half the smaller side)
        else:
            args[field], kind = point_argument(rng)
        return call(f"sinai_billiard(**{args!r})", lambda c: billiard.sinai_billiard(**args), kind, field)
    if choice == 6:
        field = rng.choice(["centre", "cap_radius", "stem_width", "stem_height"])
        args = {"centre": (0.0, 0.0), "cap_radius": 5.0, "stem_width": 2.0, "stem_height": 4.0}
        if field == "centre":
            args[field], kind = point_argument(rng)
        else:
            args[field], kind = float_argument(rng, BAD_LENGTHS + ([10.0, 12.0] if field == "stem_width" else []))
        return call(f"mushroom(**{args!r})", lambda c: billiard.mushroom(**args), kind, field)
    centres, radii = [[0.0, 0.0], [4.0, 0.0]], [3.0, 2.5]
    if rng.random() < 0.5:
        centres, kind = array_argument(rng, rows=2)
        # (centres of another length than the radii: the radii's count is refused)
        names = "centres" if kind == "convert" else ["centre", "circle", "radii"]
    else:
        radii = rng.choice([[3.0], [3.0, 2.5, 1.0], "wide", [[3.0, 2.5]], [3.0, None], np.array([1 + 1j, 2]),
                            np.array([True, False]), [3.0, rng.choice(BAD_LENGTHS)]])
        kind, names = ("value", ["radius", "circle 1"]) if isinstance(radii, list) and len(radii) == 2 and \
            isinstance(radii[1], float) else ("convert", "radii")
        if isinstance(radii, list) and len(radii) != 2 and all(isinstance(r, float) for r in radii):
            kind, names = "value", "radii"
    return call(f"union_of_circles({centres!r}, {radii!r})", lambda c: billiard.union_of_circles(centres, radii), kind,
                names)


def bad_container_call(rng, shape):
    """An add_ call with one bad argument, or any wall in a periodic box."""
    choice = rng.randrange(6)
    if choice == 0:
        (p, kind), q = point_argument(rng), (1.0, 1.0)
        if rng.random() < 0.5:
            return call(f"add_segment({p!r}, {q})", lambda c: c.add_segment(p, q), kind, "a ")
        return call(f"add_segment({q}, {p!r})", lambda c: c.add_segment(q, p), kind, "b ")
    if choice in (1, 2):
        method = "add_arc" if choice == 1 else "add_obstacle"
        args = {"centre": (1.0, 1.0), "radius": 1.0}
        if method == "add_arc":
            args.update(start_angle=0.0, end_angle=1.0)
        field = rng.choice(list(args) + (["sweep"] if method == "add_arc" else []))
        if field == "centre":
            args[field], kind = point_argument(rng)
        elif field == "radius":
            args[field], kind = float_argument(rng, BAD_LENGTHS)
        elif field == "sweep":  # end_angle - start_angle not in (0, 2 pi]
            args["end_angle"], kind, field = rng.choice([0.0, -0.0, -1.0, 7.0, 2 * math.pi + 1e-9]), "value", \
                "end_angle - start_angle"
        else:
            args[field], kind = float_argument(rng, BAD_ANGLES)
        return call(f"{method}(**{args!r})", lambda c: getattr(c, method)(**args), kind, field)
    if choice == 3:
        other = rng.choice(["table", "periodic", "free walls", "not a container"])
        if other == "not a container":
            bad = rng.choice([None, 5.0, "box", [[0, 0], [1, 0], [0, 1]]])
            return call(f"add_obstacle({bad!r})", lambda c: c.add_obstacle(bad), "type", "shape")
        if other == "free walls":
            bad = billiard.box((0.0, 0.0), (1.0, 1.0))
            bad.add_segment((0.2, 0.5), (0.8, 0.5))
        else:
            bad = billiard.circular_table(1.0) if other == "table" else billiard.periodic_box(1.0, 1.0)
        return call(f"add_obstacle({bad!r})", lambda c: c.add_obstacle(bad), "value", ["shape", "periodic box"])
    if choice == 4 and shape.periodic:  # a good wall, in the wrong place
        wall = rng.choice([lambda c: c.add_segment((1.0, 1.0), (2.0, 2.0)), lambda c: c.add_arc((5.0, 5.0), 1.0, 0.0, 1.0),
                           lambda c: c.add_obstacle((5.0, 5.0), 1.0),
                           lambda c: c.add_obstacle(billiard.box((1.0, 1.0), (2.0, 2.0)))])
        return call("a wall in a periodic box", wall, "value", "periodic box")
    return bad_shape_call(rng)


def plausible_container_call(rng):
    """A valid add_ call, sometimes with extreme values (a periodic box refuses it)."""
    choice = rng.randrange(4)
    if choice == 0:
        a, b = (extreme_value(rng, 20), extreme_value(rng, 20)), (extreme_value(rng, 20), extreme_value(rng, 20))
        return call(f"add_segment({a!r}, {b!r})", lambda c: c.add_segment(a, b), "either", [])
    centre, radius = (extreme_value(rng, 10), extreme_value(rng, 10)), extreme_length(rng, 2.0)
    if choice == 1:
        start = rng.uniform(-10, 10)
        end = start + rng.choice([rng.uniform(1e-9, 2 * math.pi), 2 * math.pi])
        return call(f"add_arc({centre!r}, {radius!r}, {start!r}, {end!r})", lambda c: c.add_arc(centre, radius, start, end),
                    "either", [])
    if choice == 2:
        return call(f"add_obstacle({centre!r}, {radius!r})", lambda c: c.add_obstacle(centre, radius), "either", [])
    lower = np.array([extreme_value(rng, 10), extreme_value(rng, 10)])
    size = extreme_length(rng, 2.0)
    return call(f"add_obstacle(box({tuple(lower)!r}, + {size!r}))",
                lambda c: c.add_obstacle(billiard.box(lower, lower + size)), "either", [])


def check_container(shape, c, counts):
    where = f"{shape.name}: {c.text}"
    container, twin = shape.make(), shape.make()
    before = container_snapshot(container)
    error, names = expected(Start(shape.name, shape.make, False), c)  # (never after a start)
    if accepted(where, error, names, lambda: c.run(container), counts):
        sim = billiard.Simulation(container)
        assert container_snapshot(sim.container) == container_snapshot(container), where
        try:
            sim.add_random_discs(10, 0.2, seed=1)  # (the new wall may leave no room)
        except ValueError:
            pass
        assert sim.validate() is None and finite(sim), where
        sim.advance(events=20)
        assert sim.validate() is None and finite(sim), where
        return
    # Refused: the same container, bit for bit, and it makes the same simulation as its twin.
    changed = first_difference(before, container_snapshot(container))
    assert changed is None, f"{where}: the refused call changed the container's {changed}"
    changed = first_difference(run_in(twin), run_in(container))
    assert changed is None, f"{where}: after the refused call, a simulation of it has a different {changed}"


@needs_simulation
def test_bad_calls_to_the_containers_raise_naming_the_argument_and_change_nothing(capsys):
    rng = random.Random(SEED + 2)
    counts = Counter()
    calls = 2000
    for k in range(calls):
        shape = rng.choice(SHAPES)
        c = plausible_container_call(rng) if k % 5 == 4 else bad_container_call(rng, shape)
        check_container(shape, c, counts)
    with capsys.disabled():
        print(f"python Container fuzz (seed {SEED + 2}): {calls} calls, {counts['ValueError']} ValueError, "
              f"{counts['TypeError']} TypeError, {counts['accepted']} accepted; every refusal left the container unchanged")
    assert counts["ValueError"] + counts["TypeError"] + counts["accepted"] == calls
    assert counts["ValueError"] > calls // 2 and counts["TypeError"] > calls // 20 and counts["accepted"] > calls // 20


# ---- Settings -------------------------------------------------------------------------------------
# billiard.Settings converts what it is given when it is given (ValueError or TypeError naming the
# field); Simulation(container, settings) checks the values (ValueError naming "settings.<field>").
# A refused assignment leaves the settings as they were.

SETTINGS_STARTS = [
    Start("table", lambda settings: _with_discs(billiard.circular_table(10.0), settings, 20, 0.5), False),
    Start("box", lambda settings: _with_discs(billiard.box((0.0, 0.0), (20.0, 10.0)), settings, 25, 0.4), False),
    Start("periodic box", lambda settings: _with_discs(billiard.periodic_box(20.0, 15.0), settings, 30, 0.5), False),
    Start("polygon and a segment", lambda settings: _with_discs(_hexagon(), settings, 15, 0.6), False),
]
SETTINGS_FIELDS = ["gravity", "restitution", "exchange_velocities", "contact_duration", "elastic_impact_speed",
                   "sleep_speed", "cell_size", "prefetch"]


def _with_discs(container, settings, n, radius):
    sim = billiard.Simulation(container, settings)
    sim.add_random_discs(n, radius, seed=n)
    return sim


def settings_snapshot(settings):
    return bits({field: getattr(settings, field) for field in SETTINGS_FIELDS})


def bad_settings_value(rng):
    """(field, value, kind, names) for one bad field."""
    field = rng.choice(SETTINGS_FIELDS)
    if field == "gravity":
        if rng.random() < 0.2:
            return field, rng.choice([(DENORMAL, 0.0), (0.0, -1e-51)]), "value", "settings.gravity"  # |g|^2 underflows
        value, kind = point_argument(rng)
        return field, value, kind, "settings.gravity"
    if field == "restitution":
        value, kind, names = bad_restitution(rng)
        return field, value, kind, names[0]
    if field == "exchange_velocities":
        return field, rng.choice(["yes", [True], object()]), "type", field  # (pybind11 takes numbers, None as False)
    if field == "prefetch":
        return field, rng.choice(["sometimes", "", "ON", "Auto", " on", None, 1, True]), "convert", "settings.prefetch"
    value, kind = float_argument(rng, BAD_NONNEGATIVE, optional=field != "cell_size")
    return field, value, kind, (f"settings.{field}" if kind == "value" else field)


def plausible_settings_value(rng):
    field = rng.choice(["gravity", "restitution", "cell_size", "prefetch", "granular", "exchange_velocities"])
    if field == "gravity":
        return field, (extreme_value(rng, 5), extreme_value(rng, 5))
    if field == "restitution":
        normal, tangential = rng.choice([0.0, 1e-3, 0.5, 0.9, 1.0]), rng.choice([-1.0, 0.0, -0.0, 1.0])
        return field, rng.choice([normal, (normal, tangential)])
    if field == "cell_size":
        return field, rng.choice([0.0, -0.0, DENORMAL, 1e-300, 0.5, 3.0, 1e50, 1e308, HUGE])
    if field == "prefetch":
        return field, rng.choice(["auto", "on", "off"])
    if field == "exchange_velocities":
        return field, rng.choice([True, False])
    return rng.choice(["contact_duration", "elastic_impact_speed", "sleep_speed"]), \
        rng.choice([None, 0.0, DENORMAL, 1e-3, 1.0, 1e50])


def check_settings(start, rng, plausible, counts):
    if plausible:
        (field, value), kind, names = plausible_settings_value(rng), "either", []
    else:
        field, value, kind, names = bad_settings_value(rng)
    given = rng.choice(["keyword", "attribute"])
    where = f"{start.name}: settings {field}={value!r} ({given})"
    error, names = expected(start, call(where, None, kind, names, setup=False))
    settings = billiard.Settings()
    before = settings_snapshot(settings)
    made = {}

    def make():
        if given == "keyword":
            made["settings"] = billiard.Settings(**{field: value})
        else:
            setattr(settings, field, value)
        made["sim"] = start.make(made.get("settings", settings))

    if not accepted(where, error, names, make, counts):
        if kind in ("convert", "type") and given == "attribute":
            # Refused as it was given: the settings are as they were and make the same simulation.
            changed = first_difference(before, settings_snapshot(settings))
            assert changed is None, f"{where}: the refused assignment changed {changed}"
            sim, twin = start.make(settings), start.make(billiard.Settings())
            sim.advance(events=20)
            twin.advance(events=20)
            changed = first_difference(snapshot(twin), snapshot(sim))
            assert changed is None, f"{where}: after the refused assignment, a simulation has a different {changed}"
        return
    sim = made["sim"]
    assert sim.validate() is None and finite(sim), where
    sim.advance(events=20)
    assert sim.validate() is None and finite(sim), where


@needs_simulation
def test_bad_settings_raise_naming_the_field_and_change_nothing(capsys):
    rng = random.Random(SEED + 3)
    counts = Counter()
    calls = 1500
    for k in range(calls):
        check_settings(rng.choice(SETTINGS_STARTS), rng, k % 5 == 4, counts)
    with capsys.disabled():
        print(f"python Settings fuzz (seed {SEED + 3}): {calls} calls, {counts['ValueError']} ValueError, "
              f"{counts['TypeError']} TypeError, {counts['accepted']} accepted; every refused assignment left the "
              "settings unchanged")
    assert counts["ValueError"] + counts["TypeError"] + counts["accepted"] == calls
    assert counts["ValueError"] > calls // 2 and counts["TypeError"] > calls // 20 and counts["accepted"] > calls // 20


# ---- Course functions -----------------------------------------------------------------------------

R, A = 10.0, 1.0
CIRCLES = np.array([[0.0, 0.0], [3.0, 0.0], [-3.0, 4.0]])
SPEEDS = np.array([[1.0, 0.5], [-1.0, 0.0], [0.0, -1.0]])


def course_array(rng, name, in_place):
    """A bad array for a course function: (value, kind, names)."""
    choice = rng.randrange(5 if in_place else 3)
    if choice == 0:  # not a numpy array at all
        return rng.choice([None, "abc", [[1.0, 2.0]], 5.0, Unreadable()]), "type", [f"{name}:"]
    if choice == 1:
        return rng.choice([x for x in NOT_ARRAYS if isinstance(x, np.ndarray)]), "value", [name]
    if choice == 2:  # finite numbers only, at most 1e50
        array = (CIRCLES if name == "coordinates" else SPEEDS).copy()
        array[rng.randrange(3), rng.randrange(2)] = rng.choice(NOT_FINITE_OR_HUGE)
        return array, "value", [name]
    base = (CIRCLES if name == "coordinates" else SPEEDS).copy()
    if choice == 3:  # not writable in place
        layout = rng.choice(["read-only", "strided", "fortran", "float32", "int"])
        if layout == "read-only":
            base.flags.writeable = False
        elif layout == "strided":
            base = np.repeat(base, 2, axis=0)[::2]
        elif layout == "fortran":
            base = np.asfortranarray(base)
        else:
            base = base.astype(np.float32 if layout == "float32" else np.int64)
        return base, "value", [name]
    return base[:2], "value", [name, "rows"]  # one row too few for the other array


def bad_course_call(rng, tmp_path):
    coordinates, velocities = CIRCLES.copy(), SPEEDS.copy()
    svg = tmp_path / "fuzz.svg"
    radius_bad = BAD_SCALES + [None, "10", [10.0], 10**400]

    def radius_kind(value):
        return "type" if value is None or isinstance(value, (str, list)) or value == 10**400 else "value"

    function = rng.choice(["init_billiard", "init_velocities", "visualize_table", "propagate", "movie",
                           "kinetic_energy", "correct_energy_drift"])
    choice = rng.randrange(4)
    if function == "init_billiard":
        args = {"table_radius": R, "circle_radius": A, "n": 5, "rng": 1}
        if choice == 0:
            field = rng.choice(["table_radius", "circle_radius"])
            args[field] = rng.choice(radius_bad)
            kind, names = radius_kind(args[field]), [field, f"{field}:"]
        elif choice == 1:
            args["n"] = rng.choice([-1, -2**31, 10**6, 2**31 - 1] + BEYOND_INT + NOT_INTS)
            in_range = isinstance(args["n"], int) and -2**31 <= args["n"] < 2**31
            kind, names = ("value", ["n ="]) if in_range else ("type", ["n:"])
        elif choice == 2:
            args["rng"] = rng.choice(BEYOND_UINT64 + [2.5, "seed", None, np.int64(3)])
            kind, names = "value", ["rng"]
        else:
            args["circle_radius"] = rng.choice([R, 2 * R, 1e50])
            kind, names = "value", ["circle_radius"]
        return function, args, kind, names, []
    if function == "init_velocities":
        args = {"coordinates": coordinates, "rng": 1}
        if choice < 3:
            args["coordinates"], kind, names = course_array(rng, "coordinates", False)
        else:
            args["rng"] = rng.choice(BEYOND_UINT64 + [2.5, "seed", None, Unreadable()])
            kind, names = "value", ["rng"]
        return function, args, kind, names, []
    if function == "kinetic_energy":
        velocities, kind, names = course_array(rng, "velocities", False)
        return function, {"velocities": velocities}, kind, names, []
    if function == "correct_energy_drift":
        args = {"velocities": velocities, "target_mean_square": 2.0}
        if choice < 2:
            args["velocities"], kind, names = course_array(rng, "velocities", True)
            if names == ["velocities", "rows"]:  # (one array only: two rows are fine)
                args["velocities"], kind, names = np.zeros((3, 2)), "value", ["velocities"]  # at rest
        else:
            args["target_mean_square"] = rng.choice(BAD_NONNEGATIVE + [None, "2"])
            kind = "type" if args["target_mean_square"] is None or isinstance(args["target_mean_square"], str) else "value"
            names = ["target_mean_square"]
        return function, args, kind, names, ["velocities"]
    # visualize_table, propagate, movie: radii, coordinates, velocities (and collisions, svg_file)
    args = {"table_radius": R, "circle_radius": A, "coordinates": coordinates}
    if function != "visualize_table":
        args["velocities"] = velocities
    if function == "movie":
        args["collisions"] = 3
    if function != "propagate":
        args["svg_file"] = svg
    in_place = function != "visualize_table"
    if choice == 0:
        field = rng.choice(["table_radius", "circle_radius"])
        args[field] = rng.choice(radius_bad)
        kind, names = radius_kind(args[field]), [field, f"{field}:"]
    elif choice == 1:
        args["coordinates"], kind, names = course_array(rng, "coordinates", in_place)
        if names == ["coordinates", "rows"]:
            names = ["coordinates", "velocities", "n ="]
    elif choice == 2 and function != "visualize_table":
        args["velocities"], kind, names = course_array(rng, "velocities", True)
        if names == ["velocities", "rows"]:
            names = ["coordinates", "velocities"]
    elif function == "movie" and rng.random() < 0.5:
        args["collisions"] = rng.choice([-1, -2**31] + BEYOND_INT + NOT_INTS)
        in_range = isinstance(args["collisions"], int) and -2**31 <= args["collisions"] < 2**31
        kind, names = ("value", ["collisions"]) if in_range else ("type", ["collisions:"])
    else:  # circles overlapping, outside the table, or all at rest (a picture may show anything)
        problem = rng.randrange(3) if function != "visualize_table" else 3
        if problem == 0:
            args["coordinates"] = np.array([[0.0, 0.0], [1.5, 0.0], [-3.0, 4.0]])
        elif problem == 1:
            args["coordinates"] = np.array([[0.0, 0.0], [3.0, 0.0], [9.5, 0.0]])
        elif function != "visualize_table":
            args["velocities"] = np.zeros((3, 2))
        else:
            args["svg_file"] = rng.choice([None, 5])
            return function, args, "type", ["svg_file:"], []
        kind, names = "value", ["coordinates", "velocities"]
    return function, args, kind, names, (["coordinates", "velocities"] if in_place else [])


@pytest.mark.skipif(billiard.course_implementation != "solutions",
                    reason="the course functions here are the student's (the stubs raise NotImplementedError)")
def test_bad_calls_to_the_course_functions_raise_naming_the_argument_and_change_nothing(tmp_path, capsys):
    rng = random.Random(SEED + 1)
    counts = Counter()
    calls = 3000
    for _ in range(calls):
        function, args, kind, names, in_place = bad_course_call(rng, tmp_path)
        where = f"{function}(**{args!r})"
        saved = {key: args[key].copy() for key in in_place if isinstance(args.get(key), np.ndarray)}
        error = TypeError if kind == "type" else ValueError
        try:
            getattr(billiard, function)(**args)
        except (ValueError, TypeError) as refusal:
            raised = refusal
        else:
            pytest.fail(f"{where}: accepted, expected {error.__name__}")
        message = str(raised)
        assert type(raised) is error, f"{where}: {type(raised).__name__} instead of {error.__name__}: {message}"
        assert any(name in message for name in names), f"{where}: the message names none of {names}: {message}"
        for key, copy in saved.items():
            assert bits(args[key]) == bits(copy), f"{where}: the refused call changed {key}"
        assert not (tmp_path / "fuzz.svg").exists(), f"{where}: a refused call wrote the file"
        counts[type(raised).__name__] += 1
    with capsys.disabled():
        print(f"python course fuzz (seed {SEED + 1}): {calls} calls, {counts['ValueError']} ValueError, "
              f"{counts['TypeError']} TypeError; every refusal left the arrays unchanged")
    assert counts["ValueError"] + counts["TypeError"] == calls
    assert counts["ValueError"] > calls // 2 and counts["TypeError"] > calls // 20


@pytest.mark.skipif(billiard.course_implementation != "solutions",
                    reason="the course functions here are the student's (the stubs raise NotImplementedError)")
def test_extreme_but_valid_course_calls_return_finite_results(tmp_path):
    # The documented limits (1e50, 1e-50) and empty tables: accepted, quick and finite.
    for table_radius, circle_radius, n in [(1e50, 1e49, 5), (1e-40, 1e-41, 5), (10.0, 1.0, 0), (1e50, 1e44, 3)]:
        coordinates = billiard.init_billiard(table_radius, circle_radius, n, 1)
        assert coordinates.shape == (n, 2) and np.isfinite(coordinates).all()
        assert (np.hypot(coordinates[:, 0], coordinates[:, 1]) <= table_radius - circle_radius * (1 - 1e-9)).all()
    for scale in (1e49, 1e-50, 1.0):
        coordinates, velocities = CIRCLES.copy(), SPEEDS * scale
        collision = billiard.propagate(R, A, coordinates, velocities)
        assert math.isfinite(collision.time) and np.isfinite(coordinates).all() and np.isfinite(velocities).all()
        mean_square = billiard.kinetic_energy(velocities)
        assert math.isfinite(mean_square) and mean_square > 0
        billiard.correct_energy_drift(velocities, 4 * mean_square)  # doubles every speed
        assert billiard.kinetic_energy(velocities) == pytest.approx(4 * mean_square, rel=1e-12)
        billiard.propagate(R, A, coordinates, velocities)
        assert np.isfinite(coordinates).all() and np.isfinite(velocities).all()
    billiard.movie(R, A, CIRCLES.copy(), SPEEDS * 1e49, 20, tmp_path / "fast.svg")
    assert (tmp_path / "fast.svg").stat().st_size > 0
