"""Trajectories in GSD (billiard/trajectory.py) and the periodic image counts behind them
(Simulation.images).

The main check: a periodic run written to GSD and read back with the gsd module itself has the
simulation's positions, velocities and image counts at its frames, and its unwrapped mean
squared displacement (HOOMD's position + image * box, as OVITO computes it) agrees with one
computed independently from the event log, by integrating each disc's free flight between its
logged events. Tolerances come from HOOMD's single-precision fields (float32, unit roundoff
2^-24 = 6e-8); each is stated where it is used.
"""

import math
import os

import gsd.hoomd as gsd_hoomd  # Debian's python3-gsd (./build.sh python installs it): required, not skipped
import numpy as np
import pytest

import billiard

pytestmark = pytest.mark.skipif(not hasattr(billiard, "Simulation"),
                                reason="this build has no billiard.Simulation (the engine library is not built)")

FLOAT32_ROUNDOFF = 2.0**-24


def gsd_read_mode():
    """The read mode of the gsd installed, as the module chooses it (gsd 2 and 3 name it apart)."""
    import gsd
    return billiard.trajectory._open_mode(gsd, "r")


def unwrapped_from_event_log(sim, frame_times):
    """Each disc's unwrapped position at each frame time (frames, n, 2), from the initial state and the
    event log only: free flight (r + v dt + g dt^2 / 2) from the disc's last logged event, where the
    unwrapped position is re-anchored on the logged (wrapped) one plus the whole periods that bring it
    nearest the flight's prediction."""
    period = np.array(sim.container.period)
    gravity = np.array(sim.gravity)
    start = sim.initial_state
    anchor = start["position"].copy()
    velocity = start["velocity"].copy()
    since = np.full(len(anchor), start["time"])
    log = sim.event_log
    k, events = 0, len(log["time"])
    frames = []
    for t in frame_times:
        while k < events and log["time"][k] <= t:
            when = log["time"][k]
            for disc, position, new_velocity in ((log["disc"][k], log["position"][k], log["velocity"][k]),
                                                 (log["other"][k], log["other_position"][k], log["other_velocity"][k])):
                if disc < 0:
                    continue
                dt = when - since[disc]
                predicted = anchor[disc] + velocity[disc] * dt + 0.5 * gravity * dt * dt
                anchored = position + period * np.round((predicted - position) / period)
                # The flight lands where the log says, up to rounding: the log is read correctly.
                assert np.all(np.abs(anchored - predicted) < 1e-9 * period), (k, disc, anchored, predicted)
                anchor[disc], velocity[disc], since[disc] = anchored, new_velocity, when
            k += 1
        dt = (t - since)[:, None]
        frames.append(anchor + velocity * dt + 0.5 * gravity * dt * dt)
    return np.array(frames)


def mean_squared_displacement(unwrapped):
    displacement = unwrapped - unwrapped[0]
    return (displacement**2).sum(axis=2).mean(axis=1)


def assert_msd_agrees(msd, reference, error):
    """An error of at most `error` along each axis of each displacement changes the mean squared
    displacement by at most 2 error sqrt(2 MSD) + 2 error^2; twice that is allowed."""
    bound = 2 * (2 * error * np.sqrt(2 * reference) + 2 * error**2)
    worst = np.argmax(np.abs(msd - reference) - bound)
    assert np.all(np.abs(msd - reference) <= bound), (
        f"frame {worst}: MSD {msd[worst]} against {reference[worst]} from the event log (allowed {bound[worst]:.3g})")


def periodic_gas(gravity=(0.0, 0.0), seed=3):
    sim = billiard.Simulation(billiard.periodic_box(12.0, 9.0), billiard.Settings(gravity=gravity))
    sim.add_random_discs(40, 0.35, kT=4.0, seed=seed)
    sim.set_log_events()
    return sim


@pytest.mark.parametrize("gravity", [(0.0, 0.0), (0.05, -0.3)], ids=["no gravity", "gravity"])
def test_periodic_run_in_gsd_matches_the_simulation_and_the_event_log(tmp_path, gravity):
    sim = periodic_gas(gravity)
    period = np.array(sim.container.period)
    path = tmp_path / "gas.gsd"
    dt, frame_count = 0.5, 61
    live = []  # the simulation's own view at each frame
    with billiard.TrajectoryWriter(path, sim) as writer:
        for k in range(frame_count):
            if k > 0:
                sim.advance(time=k * dt - sim.time)
            writer.write()
            live.append((sim.current_state, sim.images))
    assert path.is_file() and sorted(os.listdir(tmp_path)) == ["gas.gsd"]  # no hidden file left

    # ---- read back with the gsd module itself ----
    with gsd_hoomd.open(str(path), gsd_read_mode()) as trajectory:
        frames = list(trajectory)
    assert len(frames) == frame_count
    hoomd_unwrapped = []
    for frame, (state, images) in zip(frames, live):
        n = frame.particles.N
        assert n == 40 and frame.configuration.dimensions == 2
        np.testing.assert_array_equal(frame.configuration.box, np.float32([12, 9, 0, 0, 0, 0]))
        position, image = frame.particles.position, frame.particles.image
        assert position.dtype == np.float32 and image.dtype == np.int32
        np.testing.assert_array_equal(position[:, 2], 0)
        np.testing.assert_array_equal(image[:, 2], 0)
        # Centred on the origin: every stored coordinate in [-L/2, L/2).
        assert np.all(position[:, :2] >= -period / 2) and np.all(position[:, :2] < period / 2)
        # Positions: the simulation's minus the box's centre, to single precision (half a unit in
        # the last place of a coordinate below L/2: L/2 2^-24; twice that allowed).
        expected = state["position"] - period / 2
        wrapped_again = image[:, :2] != images  # (a coordinate that rounds onto the upper face moves
        expected[wrapped_again] -= np.broadcast_to(period, expected.shape)[wrapped_again]  # a period down)
        np.testing.assert_allclose(position[:, :2], expected, rtol=0, atol=FLOAT32_ROUNDOFF * period.max())
        # Image counts: the simulation's, exactly, except for such a coordinate (its count one up).
        np.testing.assert_array_equal(image[:, :2] - images, wrapped_again.astype(int))
        assert np.all(np.abs(state["position"][wrapped_again] - np.broadcast_to(period, expected.shape)[wrapped_again])
                      < 1e-6 * period.max())
        speed = np.abs(state["velocity"]).max()
        np.testing.assert_allclose(frame.particles.velocity[:, :2], state["velocity"], rtol=0,
                                   atol=FLOAT32_ROUNDOFF * speed)
        np.testing.assert_array_equal(frame.particles.velocity[:, 2], 0)
        np.testing.assert_allclose(frame.particles.diameter, 2 * state["radius"], rtol=FLOAT32_ROUNDOFF)
        np.testing.assert_allclose(frame.particles.mass, state["mass"], rtol=FLOAT32_ROUNDOFF)
        np.testing.assert_allclose(frame.particles.moment_inertia[:, 2], state["inertia"], rtol=FLOAT32_ROUNDOFF)
        np.testing.assert_allclose(frame.particles.angmom[:, 3], 2 * state["inertia"] * state["spin"], rtol=1e-6)
        assert frame.log["billiard/time"][0] == state["time"]
        # HOOMD's unwrapped position, from the standard fields only (as OVITO computes it).
        hoomd_unwrapped.append(position[:, :2].astype(np.float64) + image[:, :2] * frame.configuration.box[:2])
    hoomd_unwrapped = np.array(hoomd_unwrapped)

    # The run must wrap discs both ways along both axes (else a wrong sign or a lost axis could pass).
    all_images = np.array([images for _, images in live])
    for axis in range(2):
        assert all_images[:, :, axis].min() <= -1 and all_images[:, :, axis].max() >= 1, f"axis {axis}"

    # ---- against the event log ----
    times = np.array([state["time"] for state, _ in live])
    from_log = unwrapped_from_event_log(sim, times)
    # Each unwrapped position: the two frames' rounding of a coordinate (L/2 2^-24 each) and nothing
    # that grows with the distance travelled; the tolerance is 4 L 2^-24 (3e-6 here).
    tolerance = 4 * FLOAT32_ROUNDOFF * period.max()
    np.testing.assert_allclose(hoomd_unwrapped - hoomd_unwrapped[0], from_log - from_log[0], rtol=0, atol=tolerance)
    # The mean squared displacement, with that error per axis (assert_msd_agrees).
    msd_log = mean_squared_displacement(from_log)
    msd_gsd = mean_squared_displacement(hoomd_unwrapped)
    assert msd_log[-1] > period.max() ** 2  # discs travel a box on average: an image off by one would show
    assert_msd_agrees(msd_gsd, msd_log, tolerance)
    # The helper reads the same, with the box's exact sides.
    run = billiard.read_trajectory(path)
    np.testing.assert_array_equal(run["time"], times)
    assert_msd_agrees(mean_squared_displacement(run["unwrapped"]), msd_log, tolerance)
    np.testing.assert_allclose(run["position"], [state["position"] for state, _ in live], rtol=0,
                               atol=FLOAT32_ROUNDOFF * period.max() + 1e-12)  # (back in [0, L): no shift here)


def test_lone_disc_unwraps_to_free_flight():
    # The sign convention seen from Python: right and down through a 10 x 8 box, many times.
    sim = billiard.Simulation(billiard.periodic_box(10.0, 8.0))
    start, velocity = np.array([3.0, 2.0]), np.array([7.3, -5.1])
    sim.add_disc(start, velocity, radius=0.5)
    assert sim.images.dtype == np.int64 and sim.images.shape == (1, 2)
    sim.advance(time=13.0)
    unwrapped = sim.current_state["position"] + sim.images * np.array(sim.container.period)
    np.testing.assert_allclose(unwrapped[0], start + 13.0 * velocity, rtol=1e-13)
    np.testing.assert_array_equal(sim.images[0], np.floor((start + 13.0 * velocity) / [10.0, 8.0]))


def test_write_trajectory_at_times_every_time_and_every_events(tmp_path):
    sim = periodic_gas(seed=5)
    times = [0.0, 0.25, 1.0, 1.0, 3.5]
    run = billiard.read_trajectory(billiard.write_trajectory(sim, tmp_path / "times.gsd", times=times))
    np.testing.assert_allclose(run["time"], times, rtol=1e-14, atol=0)
    assert run["position"].shape == (5, 40, 2) and run["periodic"] is True
    np.testing.assert_array_equal(run["box"], [[12.0, 9.0]] * 5)

    start = sim.time
    path = billiard.write_trajectory(sim, tmp_path / "every_time.gsd", every_time=0.5, frames=4)
    run = billiard.read_trajectory(path)
    np.testing.assert_allclose(run["time"], start + 0.5 * np.arange(4), rtol=1e-14)

    before = sim.totals["disc_collisions"]
    path = billiard.write_trajectory(sim, str(tmp_path / "every_events.gsd"), every_events=25, frames=5)
    run = billiard.read_trajectory(path)
    np.testing.assert_array_equal(run["step"], before + 25 * np.arange(5))
    state = sim.current_state
    np.testing.assert_allclose(run["velocity"][-1], state["velocity"], rtol=0,
                               atol=1e-6 * np.abs(state["velocity"]).max())
    np.testing.assert_allclose(run["radius"][-1], state["radius"], rtol=1e-7)
    np.testing.assert_allclose(run["spin"][-1], state["spin"], atol=1e-12)
    assert sorted(os.listdir(tmp_path)) == ["every_events.gsd", "every_time.gsd", "times.gsd"]


def test_a_closed_container_gets_a_box_around_it(tmp_path):
    sim = billiard.Simulation(billiard.box((2.0, 1.0), (8.0, 5.0)), billiard.Settings(restitution=(0.9, 0.5)))
    sim.add_random_discs(10, 0.3, seed=2)
    billiard.write_trajectory(sim, tmp_path / "box.gsd", every_events=50, frames=3)
    with gsd_hoomd.open(str(tmp_path / "box.gsd"), gsd_read_mode()) as trajectory:
        last = trajectory[-1]
    # The box: the container's (6 x 4) widened by a radius on each side, centred on the container.
    np.testing.assert_allclose(last.configuration.box, [6.6, 4.6, 0, 0, 0, 0], rtol=1e-7)
    np.testing.assert_array_equal(last.particles.image, 0)
    state = sim.current_state
    np.testing.assert_allclose(last.particles.position[:, :2], state["position"] - [5.0, 3.0], atol=1e-6)
    # Rough discs spin: the angular momentum quaternion carries 2 I w (orientation (1, 0, 0, 0)).
    assert np.any(state["spin"] != 0)
    np.testing.assert_allclose(last.particles.angmom[:, 3], 2 * state["inertia"] * state["spin"], rtol=1e-6, atol=1e-30)
    run = billiard.read_trajectory(tmp_path / "box.gsd")
    assert run["periodic"] is False
    np.testing.assert_allclose(run["spin"][-1], state["spin"], rtol=1e-6, atol=1e-30)
    np.testing.assert_allclose(run["unwrapped"][-1], state["position"], atol=1e-6)


def test_bad_arguments_are_refused_naming_them(tmp_path):
    sim = periodic_gas()
    path = tmp_path / "run.gsd"
    refusals = [
        (ValueError, "exactly one", dict()),
        (ValueError, "exactly one", dict(times=[1.0], every_events=3, frames=2)),
        (ValueError, "frames", dict(every_time=0.5)),
        (ValueError, "frames", dict(times=[1.0], frames=3)),
        (ValueError, "frames", dict(every_events=10, frames=0)),
        (TypeError, "frames", dict(every_events=10, frames=2.5)),
        (ValueError, "every_events", dict(every_events=0, frames=2)),
        (TypeError, "every_events", dict(every_events="10", frames=2)),
        (ValueError, "every_time", dict(every_time=-1.0, frames=2)),
        (ValueError, "every_time", dict(every_time=math.nan, frames=2)),
        (TypeError, "every_time", dict(every_time="1", frames=2)),
        (ValueError, "times", dict(times=[])),
        (ValueError, "times", dict(times=[1.0, 0.5])),
        (ValueError, "times", dict(times=[1.0, math.inf])),
        (TypeError, "times", dict(times=["soon"])),
    ]
    for error, name, arguments in refusals:
        with pytest.raises(error, match=name):
            billiard.write_trajectory(sim, path, **arguments)
    with pytest.raises(TypeError, match="simulation"):
        billiard.write_trajectory("not a simulation", path, every_events=1, frames=1)
    with pytest.raises(TypeError, match="path"):
        billiard.write_trajectory(sim, 42, every_events=1, frames=1)
    with pytest.raises(ValueError, match="path"):
        billiard.write_trajectory(sim, tmp_path / "no such folder" / "run.gsd", every_events=1, frames=1)
    with pytest.raises(ValueError, match="path"):
        billiard.write_trajectory(sim, tmp_path, every_events=1, frames=1)
    sim.advance(time=2.0)
    with pytest.raises(ValueError, match="times must not start before"):
        billiard.write_trajectory(sim, path, times=[1.0, 3.0])
    assert sim.time == 2.0 and os.listdir(tmp_path) == []  # nothing run, nothing written
    with pytest.raises(FileNotFoundError, match="path"):
        billiard.read_trajectory(tmp_path / "missing.gsd")
    (tmp_path / "text.gsd").write_text("not a trajectory\n")
    with pytest.raises(ValueError, match="path.*not a HOOMD GSD file"):
        billiard.read_trajectory(tmp_path / "text.gsd")


def test_a_failed_write_leaves_the_old_file(tmp_path):
    sim = periodic_gas()
    path = tmp_path / "run.gsd"
    path.write_text("the previous run\n")
    with pytest.raises(RuntimeError, match="planned failure"):
        with billiard.TrajectoryWriter(path, sim) as writer:
            writer.write()
            sim.advance(events=10)
            writer.write()
            assert [p for p in os.listdir(tmp_path) if p.endswith(".partial")]  # the frames go elsewhere
            raise RuntimeError("planned failure")
    assert path.read_text() == "the previous run\n" and os.listdir(tmp_path) == ["run.gsd"]

    # A run that stops (here: a subclass whose advance reports stuck) raises and writes nothing.
    class Stuck(billiard.Simulation):
        def advance(self, **limits):
            result = super().advance(**limits)
            result["stuck"], result["stuck_reason"] = True, "planned"
            return result

    stuck = Stuck(billiard.periodic_box(10.0, 10.0))
    stuck.add_random_discs(5, 0.3, seed=1)
    with pytest.raises(RuntimeError, match="planned"):
        billiard.write_trajectory(stuck, path, every_events=5, frames=3)
    assert path.read_text() == "the previous run\n" and os.listdir(tmp_path) == ["run.gsd"]

    # Writing after close, and a change in the number of discs between frames, are refused.
    fresh = billiard.Simulation(billiard.periodic_box(10.0, 10.0))
    fresh.add_disc((1.0, 1.0), (1.0, 0.0), radius=0.5)
    with billiard.TrajectoryWriter(tmp_path / "grow.gsd", fresh) as writer:
        writer.write()
        fresh.add_disc((5.0, 5.0), (0.0, 1.0), radius=0.5)
        with pytest.raises(ValueError, match="simulation: it has 2 discs"):
            writer.write()
    with pytest.raises(ValueError, match="closed"):
        writer.write()
    assert billiard.read_trajectory(tmp_path / "grow.gsd")["position"].shape == (1, 1, 2)
