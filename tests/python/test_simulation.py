"""The event-driven engine through the Python module: billiard.Simulation (lib/python/
simulation_bindings.cpp). The physics is tested by the C++ engine suites; here what the binding
adds or could break: arguments in, dicts of numpy arrays out, counts, errors as ValueError,
the replays as generators, and a few physical facts seen from Python (times, conservation).
The container and settings values that make a simulation: test_describe.py."""

import math

import numpy as np
import pytest

import billiard

pytestmark = pytest.mark.skipif(not hasattr(billiard, "Simulation"),
                                reason="this build has no billiard.Simulation (the engine library is not built)")

STATE_KEYS = {"time", "position", "velocity", "spin", "mass", "radius", "inertia"}
LOG_KEYS = {"time", "kind", "disc", "other", "wall", "position", "velocity", "spin", "other_position",
            "other_velocity", "other_spin"}
COUNT_KEYS = ("disc_collisions", "wall_collisions", "cell_crossings")


def table_with_discs(n=30, radius=0.5, table=10.0, seed=1, log=False):
    sim = billiard.Simulation(billiard.circular_table(table))
    sim.add_random_discs(n, radius, kT=1.0, seed=seed)
    if log:
        sim.set_log_events(True)
    return sim


def assert_same_state(a, b, tolerance=1e-9):
    assert a["time"] == pytest.approx(b["time"], abs=tolerance)
    for key in ("position", "velocity", "spin"):
        np.testing.assert_allclose(a[key], b[key], rtol=0, atol=tolerance, err_msg=key)


# ---- a case with a known answer ------------------------------------------------------------

def test_disc_from_the_centre_hits_the_wall_of_radius_10_at_time_9():
    sim = billiard.Simulation(billiard.circular_table(10.0))
    index = sim.add_disc((0.0, 0.0), (1.0, 0.0), radius=1.0)
    assert index == 0 and len(sim) == 1 and sim.container.table_radius == 10.0
    result = sim.advance(events=1)
    assert sim.time == pytest.approx(9.0, abs=1e-12)
    assert result["collisions"] == 1 and result["wall_collisions"] == 1 and result["disc_collisions"] == 0
    assert result["elapsed"] == pytest.approx(9.0, abs=1e-12) and result["stuck"] is False
    state = sim.current_state
    np.testing.assert_allclose(state["position"], [[9.0, 0.0]], atol=1e-12)
    np.testing.assert_allclose(state["velocity"], [[-1.0, 0.0]], atol=1e-12)  # reflected
    # the next hit is on the opposite side, 18 time units later
    sim.advance(events=1)
    assert sim.time == pytest.approx(27.0, abs=1e-9)


def test_advance_by_time_stops_exactly_at_the_duration():
    sim = billiard.Simulation(billiard.circular_table(10.0))
    sim.add_disc((0.0, 0.0), (1.0, 0.0), radius=1.0)
    result = sim.advance(time=5.0)
    assert sim.time == 5.0 and result["collisions"] == 0 and result["elapsed"] == 5.0
    np.testing.assert_allclose(sim.current_state["position"], [[5.0, 0.0]], atol=1e-12)
    result = sim.advance(events=10, time=10.0)  # the wall at t = 9 comes first, then 10 time units end it
    assert result["collisions"] == 1 and sim.time == pytest.approx(15.0, abs=1e-12)


# ---- states, log and walls as numpy ------------------------------------------------------------

@pytest.mark.parametrize("which", ["initial_state", "current_state"])
def test_state_dicts_have_the_documented_keys_shapes_and_dtypes(which):
    n = 25
    sim = billiard.Simulation(billiard.circular_table(10.0))
    sim.add_disc((0.0, 0.0), (0.5, -0.25), radius=0.75, mass=2.0, spin=0.5)
    sim.add_random_discs(n - 1, 0.5, kT=1.0, seed=3)
    sim.advance(events=100)
    state = getattr(sim, which)
    assert set(state) == STATE_KEYS
    assert isinstance(state["time"], float)
    for key, shape in [("position", (n, 2)), ("velocity", (n, 2)), ("spin", (n,)), ("mass", (n,)),
                       ("radius", (n,)), ("inertia", (n,))]:
        assert isinstance(state[key], np.ndarray), key
        assert state[key].shape == shape and state[key].dtype == np.float64, (key, state[key].shape, state[key].dtype)
    assert state["radius"][0] == 0.75 and state["mass"][0] == 2.0
    assert state["inertia"][0] == pytest.approx(2.0 * 0.75**2 / 2)  # uniform disc: m a^2 / 2
    np.testing.assert_allclose(state["radius"][1:], 0.5)
    if which == "initial_state":
        assert state["time"] == 0.0
        np.testing.assert_array_equal(state["position"][0], [0.0, 0.0])
        np.testing.assert_array_equal(state["velocity"][0], [0.5, -0.25])
        assert state["spin"][0] == 0.5
    else:
        assert state["time"] == sim.time > 0


def test_event_log_is_a_dict_of_arrays_one_row_per_collision():
    sim = table_with_discs(20, log=True)
    result = sim.advance(events=300)
    log = sim.event_log
    assert set(log) == LOG_KEYS
    k = result["collisions"]
    assert k == 300
    for key, value in log.items():
        assert isinstance(value, np.ndarray), key
        assert len(value) == k, key
    for key in ("position", "velocity", "other_position", "other_velocity"):
        assert log[key].shape == (k, 2)
    assert np.all(np.diff(log["time"]) >= 0)
    walls = log["kind"] == billiard.DISC_WALL
    assert billiard.DISC_DISC == 0 and billiard.DISC_WALL == 1
    assert set(np.unique(log["kind"])) <= {0, 1}
    assert walls.sum() == result["wall_collisions"] and (~walls).sum() == result["disc_collisions"]
    assert np.all(log["other"][walls] == -1) and np.all(log["wall"][walls] >= 0)
    assert np.all(log["other"][~walls] >= 0) and np.all(log["other"][~walls] != log["disc"][~walls])
    sim.clear_event_log()
    assert len(sim.event_log["time"]) == 0


def test_walls_list_a_box_as_segments_and_corner_points():
    container = billiard.box((0.0, 0.0), (4.0, 3.0))
    index = container.add_segment((2.0, 0.0), (2.0, 1.0))
    sim = billiard.Simulation(container)
    walls = sim.container.walls
    assert walls == container.walls
    assert all(set(w) == {"kind", "a", "b", "radius", "start_angle", "sweep"} for w in walls)
    segments = [w for w in walls if w["kind"] == "segment"]
    assert len(segments) == 5
    assert walls[index]["kind"] == "segment"
    assert walls[index]["a"] == (2.0, 0.0) and walls[index]["b"] == (2.0, 1.0)
    assert sim.gravity == (0.0, 0.0) and sim.container.period == (0.0, 0.0) and sim.container.table_radius == 0.0
    periodic = billiard.Simulation(billiard.periodic_box(5.0, 7.0))
    assert periodic.container.period == (5.0, 7.0) and periodic.container.walls == []


# ---- errors ---------------------------------------------------------------------------------

def test_a_negative_radius_is_a_value_error_naming_it():
    sim = billiard.Simulation(billiard.circular_table(10.0))
    with pytest.raises(ValueError, match="radius") as error:
        sim.add_disc((0.0, 0.0), radius=-1.0)
    assert "-1" in str(error.value)
    with pytest.raises(ValueError, match="radius"):
        sim.add_discs(np.zeros((1, 2)), np.zeros((1, 2)), -0.5)
    assert len(sim) == 0  # refused calls change nothing


def test_overlapping_discs_are_a_value_error_and_add_discs_is_all_or_nothing():
    sim = billiard.Simulation(billiard.circular_table(10.0))
    sim.add_disc((0.0, 0.0), radius=1.0)
    with pytest.raises(ValueError, match="overlap"):
        sim.add_disc((1.5, 0.0), radius=1.0)
    assert len(sim) == 1
    positions = np.array([[5.0, 0.0], [-5.0, 0.0], [-5.5, 0.0]])  # the last two overlap
    with pytest.raises(ValueError, match="overlap"):
        sim.add_discs(positions, np.zeros((3, 2)), 1.0)
    assert len(sim) == 1
    assert sim.add_discs(positions[:2], np.zeros((2, 2)), 1.0) == 1  # index of the first added
    assert len(sim) == 3


def test_other_bad_calls_raise():
    sim = billiard.Simulation(billiard.circular_table(5.0))
    with pytest.raises(ValueError):
        sim.add_disc((10.0, 0.0))  # outside the table
    with pytest.raises(ValueError, match="positions|velocities"):
        sim.add_discs(np.zeros((2, 3)), np.zeros((2, 3)), 1.0)  # not (n, 2)
    with pytest.raises(ValueError, match="fit"):
        sim.add_random_discs(1000, 1.0)  # cannot fit
    sim.add_disc((0.0, 0.0), (1.0, 0.0))
    with pytest.raises(ValueError):
        sim.advance()  # neither events nor time
    sim.advance(events=1)
    with pytest.raises((RuntimeError, ValueError), match="started"):
        sim.add_disc((0.0, 3.0))  # setup is frozen after the first advance
    assert len(sim) == 1


def test_prefetch_ahead_changes_no_event_and_refuses_an_unknown_mode():
    runs = {}
    for mode in ("on", "off"):
        sim = billiard.Simulation(billiard.periodic_box(60.0, 60.0), billiard.Settings(prefetch=mode))
        sim.add_random_discs(400, 1.0, seed=3)
        sim.set_log_events(True)
        sim.advance(events=500)
        runs[mode] = sim.event_log
    # A speed hint only: the same events (the two discs of a collision may be listed the other way
    # round, since its two queue entries are equal up to rounding), at the same times.
    on, off = runs["on"], runs["off"]
    np.testing.assert_allclose(on["time"], off["time"], rtol=0, atol=1e-9)
    np.testing.assert_array_equal(np.sort(np.stack([on["disc"], on["other"]]), axis=0),
                                  np.sort(np.stack([off["disc"], off["other"]]), axis=0))
    np.testing.assert_array_equal(on["wall"], off["wall"])
    with pytest.raises(ValueError, match="settings.prefetch.*'sometimes'"):
        billiard.Settings(prefetch="sometimes")
    settings = billiard.Settings()
    with pytest.raises(ValueError, match="settings.prefetch.*'sometimes'"):
        settings.prefetch = "sometimes"
    assert settings.prefetch == "auto"


# ---- replays ----------------------------------------------------------------------------------

def test_replay_by_event_yields_one_state_per_event_ending_at_the_current_state():
    sim = table_with_discs(15, log=True)
    sim.advance(events=200)  # stops exactly at the 200th event
    log_times = sim.event_log["time"]
    states = list(sim.replay_by_event())
    assert len(states) == len(log_times) == 200
    assert all(set(s) == STATE_KEYS for s in states)
    np.testing.assert_allclose([s["time"] for s in states], log_times, rtol=0, atol=0)
    assert sim.time == log_times[-1]
    assert_same_state(states[-1], sim.current_state)
    # each logged disc is where the log says, just after its event
    for k in (0, 57, 199):
        disc = sim.event_log["disc"][k]
        np.testing.assert_allclose(states[k]["position"][disc], sim.event_log["position"][k], atol=1e-9)
        np.testing.assert_allclose(states[k]["velocity"][disc], sim.event_log["velocity"][k], atol=1e-12)


@pytest.mark.parametrize("duration, dt", [(10.0, 0.25), (10.0, 0.3), (7.5, 1.0)])
def test_replay_by_time_yields_floor_of_duration_over_dt_plus_one_states(duration, dt):
    sim = table_with_discs(15, log=True)
    sim.advance(time=duration)
    states = list(sim.replay_by_time(dt))
    assert len(states) == math.floor(duration / dt) + 1
    np.testing.assert_allclose([s["time"] for s in states], dt * np.arange(len(states)), rtol=0, atol=1e-12)
    assert_same_state(states[0], sim.initial_state)
    if duration / dt == int(duration / dt):
        assert_same_state(states[-1], sim.current_state)
    # `until` limits the replay
    assert len(list(sim.replay_by_time(dt, until=duration / 2))) == math.floor(duration / 2 / dt) + 1
    with pytest.raises(ValueError, match="dt"):
        next(sim.replay_by_time(0.0))


# ---- totals and conservation -------------------------------------------------------------------

def test_totals_count_what_advance_reported():
    sim = table_with_discs(40)
    summed = dict.fromkeys(COUNT_KEYS, 0)
    for step in [dict(events=1), dict(events=7), dict(time=1.5), dict(events=2000), dict(events=50, time=0.5)]:
        result = sim.advance(**step)
        assert result["collisions"] == result["disc_collisions"] + result["wall_collisions"]
        if "time" not in step:
            assert result["collisions"] == step["events"]
        for key in COUNT_KEYS:
            summed[key] += result[key]
        totals = sim.totals
        for key in COUNT_KEYS:
            assert totals[key] == summed[key], (step, key)
    assert set(sim.totals) == {"wall_momentum", "virial", *COUNT_KEYS}
    assert totals["wall_momentum"] > 0 and totals["virial"] > 0  # repulsive collisions: positive virial


def test_kinetic_energy_is_conserved_to_1e_12_over_1e5_collisions():
    sim = billiard.Simulation(billiard.periodic_box(40.0, 40.0))
    sim.add_random_discs(200, 1.0, kT=1.0, seed=4)
    before = sim.kinetic_energy()
    result = sim.advance(events=100_000)
    assert result["collisions"] == 100_000 and not result["stuck"]
    assert abs(sim.kinetic_energy() / before - 1) < 1e-12
    state = sim.current_state
    assert sim.kinetic_energy() == pytest.approx(0.5 * np.sum(state["mass"] * np.sum(state["velocity"] ** 2, axis=1))
                                                 + 0.5 * np.sum(state["inertia"] * state["spin"] ** 2), rel=1e-12)
    assert sim.validate() is None


def test_energy_with_gravity_is_kinetic_plus_potential():
    sim = billiard.Simulation(billiard.box((0.0, 0.0), (20.0, 20.0)), billiard.Settings(gravity=(0.0, -1.0)))
    sim.add_random_discs(30, 0.5, kT=1.0, seed=5)
    before = sim.kinetic_energy() + sim.potential_energy()
    state = sim.initial_state
    assert sim.potential_energy() == pytest.approx(np.sum(state["mass"] * state["position"][:, 1]), rel=1e-12)
    result = sim.advance(events=20_000)
    assert not result["stuck"]
    assert abs((sim.kinetic_energy() + sim.potential_energy()) / before - 1) < 1e-10
    assert sim.gravity == (0.0, -1.0)


# ---- random discs ---------------------------------------------------------------------------------

@pytest.mark.parametrize("container", ["periodic", "table", "box"])
def test_add_random_discs_places_the_requested_number_without_overlap(container):
    if container == "periodic":
        sim = billiard.Simulation(billiard.periodic_box(60.0, 40.0))
    elif container == "table":
        sim = billiard.Simulation(billiard.circular_table(25.0))
    else:
        sim = billiard.Simulation(billiard.box((-10.0, -10.0), (40.0, 30.0)))
    sim.add_disc((5.0, 5.0), radius=2.0)  # something there already
    first = sim.add_random_discs(500, 0.8, mass=2.0, kT=1.5, seed=9)
    assert first == 1 and len(sim) == 501
    assert sim.validate() is None
    state = sim.current_state
    n = len(sim)
    centres = state["position"][1:]
    gaps = np.hypot(*(centres[:, None, :] - centres[None, :, :]).transpose(2, 0, 1)) + np.eye(n - 1) * 1e9
    if container == "periodic":
        d = centres[:, None, :] - centres[None, :, :]
        d -= np.array([60.0, 40.0]) * np.round(d / np.array([60.0, 40.0]))
        gaps = np.hypot(d[..., 0], d[..., 1]) + np.eye(n - 1) * 1e9
    assert gaps.min() >= 1.6 - 1e-9
    np.testing.assert_allclose(state["mass"][1:], 2.0)
    np.testing.assert_allclose(state["radius"][1:], 0.8)
    kinetic = 0.5 * np.sum(state["mass"][1:] * np.sum(state["velocity"][1:] ** 2, axis=1))
    assert kinetic == pytest.approx(500 * 1.5, rel=1e-12)  # kT per disc in 2D
    momentum = np.sum(state["mass"][1:, None] * state["velocity"][1:], axis=0)
    if container == "periodic":
        assert np.abs(momentum).max() < 1e-12, momentum


def test_add_random_discs_depends_only_on_the_seed():
    def positions(seed):
        sim = billiard.Simulation(billiard.periodic_box(30.0, 30.0))
        sim.add_random_discs(100, 1.0, seed=seed)
        return sim.current_state["position"]

    np.testing.assert_array_equal(positions(3), positions(3))
    assert not np.array_equal(positions(3), positions(4))


@pytest.mark.parametrize("shape, fraction, aspect", [("periodic", 0.9, 1.0), ("periodic", 0.895, 0.6),
                                                     ("periodic", 0.89, 2.3), ("box", 0.88, 1.0), ("table", 0.88, 1.0)])
def test_discs_fit_up_to_nearly_the_densest_packing(shape, fraction, aspect):
    # The densest packing of equal discs, the triangular lattice, has area fraction 0.9069: a
    # lattice fitted to the periodic box places 10,000 discs at 0.9 in a square box, and nearly as
    # many in boxes of other shapes; walls cost a box or a table a few rows. Beyond the densest
    # packing the call is refused.
    n, radius = 10_000, 1.0

    def container(area):
        width = math.sqrt(area * aspect)
        if shape == "periodic":
            return billiard.periodic_box(width, area / width)
        if shape == "box":
            return billiard.box((0.0, 0.0), (width, area / width))
        return billiard.circular_table(math.sqrt(area / math.pi))

    area = n * math.pi * radius**2 / fraction
    sim = billiard.Simulation(container(area))
    sim.add_random_discs(n, radius, seed=5)
    assert len(sim) == n and sim.validate() is None
    sim.advance(events=20_000)
    assert sim.validate() is None
    too_dense = billiard.Simulation(container(n * math.pi * radius**2 / 0.91))
    with pytest.raises(ValueError, match="cannot fit|fit in the container"):
        too_dense.add_random_discs(n, radius, seed=5)
    assert len(too_dense) == 0


def test_dense_random_discs_in_a_periodic_box():
    # area fraction 0.6: beyond random sequential placement, still placed (documented: from lattice sites)
    n, radius = 400, 1.0
    side = math.sqrt(n * math.pi * radius**2 / 0.6)
    sim = billiard.Simulation(billiard.periodic_box(side, side))
    sim.add_random_discs(n, radius, seed=2)
    assert len(sim) == n and sim.validate() is None
    assert np.abs(sim.current_state["velocity"].sum(axis=0)).max() < 1e-12
    sim.advance(events=10_000)
    assert sim.validate() is None
