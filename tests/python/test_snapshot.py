"""Saving and restarting: a simulation saved part-way (Simulation.save) and loaded in a fresh
Python process (Simulation.load) continues exactly as the original does, bit for bit (the same
event log, the same state, the same bytes when saved again), for a table, a periodic box under
gravity, a granular bed with sleeping discs and rough discs of unequal sizes. Damaged and foreign
files are refused with a ValueError saying what is wrong; simulations, containers and settings
pickle (so that Dask can move them), and a sweep takes containers as a grid parameter."""

import copy
import os
import pickle
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import billiard

# The steps both copies take after the save: a number of events, then a duration.
STEPS = [{"events": 1500}, {"time": 2.0}]


def table():
    sim = billiard.Simulation(billiard.circular_table(20.0))
    sim.add_random_discs(80, 1.0, seed=3)
    return sim, 3000


def periodic_box_with_gravity():
    sim = billiard.Simulation(billiard.periodic_box(30.0, 24.0), billiard.Settings(gravity=(0.2, -0.3)))
    sim.add_random_discs(60, 1.0, seed=5)
    return sim, 4000


def granular_bed():
    sim = billiard.Simulation(billiard.box((0, 0), (40, 40)), billiard.Settings(gravity=(0, -1), restitution=0.5))
    sim.add_random_discs(120, 1.0, kT=2.0, seed=11)
    return sim, 0


def rough_discs():
    container = billiard.sinai_billiard((0, 0), (40, 30), 4.0)
    container.add_segment((2, 2), (8, 3))
    sim = billiard.Simulation(container, billiard.Settings(restitution=(1.0, 1.0)))  # perfectly rough
    rng = np.random.default_rng(17)
    for x in (4.0, 10.0, 16.0, 24.0, 30.0, 36.0):
        for y in (6.0, 12.0, 20.0, 26.0):
            radius, mass = rng.uniform(0.4, 1.2), rng.uniform(0.5, 2.0)
            sim.add_disc((x, y), tuple(rng.normal(size=2)), radius=radius, mass=mass,
                         inertia=0.3 * mass * radius**2 if x < 20 else None, spin=rng.uniform(-1, 1))
    return sim, 3000


SCENARIOS = [table, periodic_box_with_gravity, granular_bed, rough_discs]


def started(scenario):
    """The scenario's simulation, run part-way with its event log on."""
    sim, events = scenario()
    sim.set_log_events()
    if scenario is granular_bed:
        # Its first discs fall asleep near t = 3.2 (the whole bed only from t = 27).
        while not sim.sleeping_discs and sim.time < 20:
            sim.advance(time=0.1)
        assert 0 < len(sim.sleeping_discs) < len(sim)
    else:
        sim.advance(events=events)
    return sim


def outcome(sim):
    """Everything compared, as arrays: the event log, the state, the image counts, the totals and
    the simulation saved again."""
    arrays = {"log_" + name: np.asarray(value) for name, value in sim.event_log.items()}
    arrays.update({"state_" + name: np.asarray(value) for name, value in sim.current_state.items()})
    arrays["images"] = np.asarray(sim.images)
    arrays["sleeping"] = np.asarray(sim.sleeping_discs, dtype=np.int64)
    arrays["totals"] = np.array([float(value) for value in sim.totals.values()])
    arrays["saved"] = np.frombuffer(sim.to_bytes(), dtype=np.uint8)
    return arrays


def assert_bitwise_equal(first, second):
    assert sorted(first) == sorted(second)
    for name in first:
        a, b = np.asarray(first[name]), np.asarray(second[name])
        assert a.dtype == b.dtype and a.shape == b.shape, name
        assert a.tobytes() == b.tobytes(), f"{name} differs"


CONTINUE_ELSEWHERE = textwrap.dedent("""
    import sys
    import numpy as np
    import billiard
    sys.path.insert(0, sys.argv[3])
    from test_snapshot import STEPS, outcome
    sim = billiard.Simulation.load(sys.argv[1])
    for step in STEPS:
        sim.advance(**step)
    np.savez(sys.argv[2], **outcome(sim))
""")


@pytest.mark.parametrize("scenario", SCENARIOS, ids=lambda s: s.__name__)
def test_loaded_in_a_fresh_process_continues_bit_for_bit(scenario, tmp_path):
    sim = started(scenario)
    saved = tmp_path / "run.billiard"
    sim.save(saved)
    result = tmp_path / "elsewhere.npz"
    subprocess.run([sys.executable, "-c", CONTINUE_ELSEWHERE, str(saved), str(result), os.path.dirname(__file__)],
                   check=True, env=dict(os.environ))
    for step in STEPS:
        sim.advance(**step)
    here = outcome(sim)
    assert len(here["log_time"]) > STEPS[0]["events"]
    with np.load(result) as elsewhere:
        assert_bitwise_equal(here, dict(elsewhere))


def test_pickled_simulation_continues_bit_for_bit():
    sim = started(rough_discs)
    copies = (lambda: pickle.loads(pickle.dumps(sim)), lambda: copy.deepcopy(sim),
              lambda: billiard.Simulation.from_bytes(sim.to_bytes()))
    for make_copy in copies:
        other = make_copy()
        assert other.validate() is None
        for s in (sim, other):
            s.advance(events=500)
        assert_bitwise_equal(outcome(sim), outcome(other))


def test_containers_and_settings_pickle():
    container = billiard.stadium((0, 0), 5.0, 8.0)
    container.add_segment((-3, -1), (3, 1))
    container.add_obstacle((6, 1), 1.0)
    for c in (container, billiard.periodic_box(7, 9), billiard.circular_table(3.0)):
        back = pickle.loads(pickle.dumps(c))
        assert back.walls == c.walls and back.period == c.period and back.periodic == c.periodic
        assert back.table_radius == c.table_radius and back.bounds == c.bounds
    settings = billiard.Settings(gravity=(0, -2), restitution=(0.8, 0.1), sleep_speed=0.0, cell_size=3.0, prefetch="on")
    assert pickle.loads(pickle.dumps(settings)) == settings


# ---- Refused files ----

@pytest.fixture
def saved_file(tmp_path):
    sim = started(table)
    path = tmp_path / "run.billiard"
    sim.save(path)
    return path


def refusal(path):
    with pytest.raises(ValueError) as error:
        billiard.Simulation.load(path)
    return str(error.value)


def test_truncated_file_is_refused(saved_file):
    data = saved_file.read_bytes()
    for length in (0, 12, len(data) // 2, len(data) - 1):
        saved_file.write_bytes(data[:length])
        message = refusal(saved_file)
        expected = "is empty" if length == 0 else "is truncated"
        assert message.startswith(str(saved_file) + " " + expected), message


def test_damaged_file_is_refused(saved_file):
    data = bytearray(saved_file.read_bytes())
    data[len(data) // 2] ^= 0x04
    saved_file.write_bytes(bytes(data))
    assert refusal(saved_file) == f"{saved_file} is damaged (checksum mismatch)"


def test_file_of_another_version_is_refused(saved_file):
    data = bytearray(saved_file.read_bytes())
    at = len(b"billiard-simulation\0") + 4  # after the byte-order mark
    this_version = int.from_bytes(data[at:at + 4], sys.byteorder)
    data[at:at + 4] = (this_version + 5).to_bytes(4, sys.byteorder)
    saved_file.write_bytes(bytes(data))
    message = refusal(saved_file)
    assert f"was written by format version {this_version + 5} of billiard simulation files" in message, message
    assert f"reads version {this_version} only" in message and billiard.__version__ in message, message


def test_foreign_files_are_refused(tmp_path):
    text = tmp_path / "positions.csv"
    text.write_text("x,y\n1,2\n")
    assert refusal(text) == f'{text} is not a billiard simulation file (it does not start with "billiard-simulation")'
    container = tmp_path / "table.bin"
    container.write_bytes(pickle.loads(pickle.dumps(billiard.circular_table(4.0))).__getstate__())
    assert "is a billiard container file, not a billiard simulation file" in refusal(container)
    with pytest.raises(FileNotFoundError):
        billiard.Simulation.load(tmp_path / "missing.billiard")
    pickled = bytearray(pickle.dumps(started(table)))
    pickled[len(pickled) // 2] ^= 0x04  # (inside the saved bytes the pickle carries)
    with pytest.raises(ValueError, match=r"the pickled simulation is damaged \(checksum mismatch\)"):
        pickle.loads(bytes(pickled))


# ---- A sweep over containers ----

def run_in(container, settings, seed):
    sim = billiard.Simulation(container, settings)
    sim.add_random_discs(12, 0.5, seed=seed)
    sim.advance(events=300)
    return {"virial": sim.totals["virial"], "time": sim.time, "walls": len(sim.container.walls)}


def test_sweep_takes_containers_as_a_parameter():
    grid = {"container": [billiard.box((0, 0), (10, 10)), billiard.circular_table(6.0), billiard.periodic_box(9, 9)],
            "settings": [billiard.Settings(), billiard.Settings(gravity=(0, -1), restitution=0.9)]}
    serial = billiard.sweep(run_in, grid, seeds=2, workers=0, quiet=True, as_frame=False)
    parallel = billiard.sweep(run_in, grid, seeds=2, workers=2, quiet=True, as_frame=False)
    assert len(parallel) == 12
    for a, b in zip(serial, parallel):
        assert a["error"] is None and b["error"] is None, (a["error"], b["error"])
        assert (a["virial"], a["time"], a["walls"]) == (b["virial"], b["time"], b["walls"])  # exact
    assert [r["walls"] for r in parallel[::4]] == [len(c.walls) for c in grid["container"]]
