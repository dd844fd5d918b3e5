"""billiard.drift, the integrators of the energy notebook: that they are what the notebook says
(the event-driven algorithm in float32, a time-stepped code whose simultaneous contacts change
the energy), and the drift bounds the notebook relies on. Tests marked solutions_only compare
with the course's propagate and need the reference solutions (as in test_course.py)."""

import numpy as np
import pytest

import billiard
from billiard import drift

solutions_only = pytest.mark.skipif(billiard.course_implementation != "solutions",
                                    reason="the course functions here are the student's")

R, A = 10.0, 1.0


def lattice_start(n=20, seed=4):
    """n discs of radius 1 on a square lattice of spacing 3 inside the table of radius 10, with
    Gaussian velocities: a valid start made without the course functions."""
    grid = np.array([(x, y) for x in np.arange(-7.5, 7.6, 3.0) for y in np.arange(-7.5, 7.6, 3.0)
                     if np.hypot(x, y) <= R - A - 0.1])
    assert len(grid) >= n
    velocities = np.random.default_rng(seed).normal(size=(n, 2))
    return grid[:n].copy(), velocities


def course_start(n=20, seed=2):
    """The energy notebook's table: 20 discs of radius 1 on the table of radius 10, seed 2."""
    rng = billiard.Rng(seed)
    positions = billiard.init_billiard(R, A, n, rng)
    return positions, billiard.init_velocities(positions, rng)


def relative_drift(history, target=None):
    target = history.mean_square[0] if target is None else target
    return np.abs(history.mean_square / target - 1)


def assert_valid(positions, radius=A, table_radius=R, slack=1e-4):
    """Inside the table and not overlapping, to `slack` (float32 positions round)."""
    positions = positions.astype(np.float64)
    assert np.all(np.hypot(positions[:, 0], positions[:, 1]) <= table_radius - radius + slack)
    gaps = np.hypot(*(positions[:, None, :] - positions[None, :, :]).transpose(2, 0, 1))
    gaps = gaps[np.triu_indices(len(positions), k=1)]
    assert gaps.min() >= 2 * radius - slack


# --- event-driven in single precision ----------------------------------------------------------

def test_float32_run_is_single_precision_valid_and_drifts_more_than_1e_7():
    positions, velocities = lattice_start()
    history = drift.event_driven_float32(R, A, positions, velocities, 1500)
    assert history.positions.dtype == np.float32 and history.velocities.dtype == np.float32
    assert len(history.mean_square) == 1501 and history.events[-1] == 1500
    assert np.all(np.diff(history.time) >= 0) and history.time[-1] > 0
    assert_valid(history.positions)
    # single precision: the energy wanders far beyond double rounding, but stays near 1e-5
    assert relative_drift(history).max() > 1e-7
    assert relative_drift(history).max() < 1e-3
    # the caller's arrays are untouched
    np.testing.assert_array_equal(positions, lattice_start()[0])


def test_float32_run_with_the_correction_stays_at_the_target_to_single_precision():
    positions, velocities = lattice_start()
    target = drift.mean_square(velocities)
    history = drift.event_driven_float32(R, A, positions, velocities, 1500, correct_every=1, target=target)
    assert relative_drift(history, target).max() < 1e-6


@solutions_only
def test_float32_run_follows_propagate_until_rounding_takes_over():
    positions, velocities = course_start()
    history = drift.event_driven_float32(R, A, positions, velocities, 15)
    elapsed = [0.0]
    for _ in range(15):
        elapsed.append(elapsed[-1] + billiard.propagate(R, A, positions, velocities).time)
    # same collisions at the same times, to single precision
    np.testing.assert_allclose(history.time, elapsed, rtol=1e-4)
    np.testing.assert_allclose(history.positions, positions, atol=1e-3)


@solutions_only
def test_double_event_driven_code_drifts_less_than_1e_12_over_the_same_events():
    positions, velocities = course_start()
    start = billiard.kinetic_energy(velocities)
    worst = 0.0
    for _ in range(1500):
        billiard.propagate(R, A, positions, velocities)
        worst = max(worst, abs(billiard.kinetic_energy(velocities) / start - 1))
    assert worst < 1e-12


# --- time-stepped ------------------------------------------------------------------------------

def test_one_collision_per_step_conserves_energy_exactly():
    # head-on along x: the discs swap velocities, energy kept to rounding
    positions = np.array([[-1.05, 0.0], [1.05, 0.0]])
    velocities = np.array([[1.0, 0.0], [-1.0, 0.0]])
    history = drift.time_stepped(R, A, positions, velocities, dt=0.01, steps=20)
    np.testing.assert_allclose(history.velocities, [[-1.0, 0.0], [1.0, 0.0]], atol=1e-15)
    assert history.events[-1] == 1
    assert relative_drift(history).max() < 1e-15


def test_a_disc_beyond_the_wall_is_reflected():
    positions = np.array([[8.95, 0.0]])
    velocities = np.array([[1.0, 0.5]])
    history = drift.time_stepped(R, A, positions, velocities, dt=0.1, steps=1)
    # found at r = (9.05, 0.05), beyond R - a = 9: v' = v - 2 (v.n) n with n = r / |r|
    normal = np.array([9.05, 0.05]) / np.hypot(9.05, 0.05)
    np.testing.assert_allclose(history.velocities[0], velocities[0] - 2 * (velocities[0] @ normal) * normal,
                               atol=1e-15)
    assert history.events[-1] == 1 and relative_drift(history).max() < 1e-15


def test_two_contacts_in_one_step_do_not_conserve_energy():
    # Three discs in a row, the outer two closing in on the middle one at once. In sequence this
    # is Newton's cradle and keeps the energy; resolved together from the old velocities, the
    # two impulses cancel on the middle disc and every disc stops: all the energy is gone.
    positions = np.array([[-1.99, 0.0], [0.0, 0.0], [1.99, 0.0]])
    velocities = np.array([[1.0, 0.0], [0.0, 0.0], [-1.0, 0.0]])
    history = drift.time_stepped(R, A, positions, velocities, dt=0.001, steps=1)
    assert history.events[-1] == 2
    np.testing.assert_allclose(history.velocities, 0.0, atol=1e-15)
    assert history.mean_square[-1] == 0.0


def test_time_stepped_drift_exceeds_1e_3_on_a_lattice_start():
    positions, velocities = lattice_start()
    dt = 0.05 * A / np.sqrt(drift.mean_square(velocities))
    history = drift.time_stepped(R, A, positions, velocities, dt, 6000)
    assert history.events[-1] > 500
    assert relative_drift(history).max() > 1e-3


@solutions_only
def test_time_stepped_drift_exceeds_1e_3_in_the_notebook_setting_and_the_correction_repairs_it():
    positions, velocities = course_start()
    target = billiard.kinetic_energy(velocities)
    dt = 0.05 * A / np.sqrt(target)
    duration = 0.0
    p, v = positions.copy(), velocities.copy()
    for _ in range(3000):
        duration += billiard.propagate(R, A, p, v).time
    steps = int(np.ceil(duration / dt))
    plain = drift.time_stepped(R, A, positions, velocities, dt, steps)
    assert relative_drift(plain, target).max() > 1e-3
    corrected = drift.time_stepped(R, A, positions, velocities, dt, steps, correct_every=1,
                                   correct=billiard.correct_energy_drift, target=target)
    assert relative_drift(corrected, target).max() < 1e-12


# --- helpers -----------------------------------------------------------------------------------

def test_rescale_restores_the_target_in_the_arrays_precision_and_keeps_directions():
    rng = np.random.default_rng(1)
    for dtype, tolerance in [(np.float64, 1e-14), (np.float32, 1e-6)]:
        velocities = rng.normal(size=(50, 2)).astype(dtype)
        directions = velocities / np.linalg.norm(velocities, axis=1)[:, None]
        drift.rescale(velocities, 3.0)
        assert velocities.dtype == dtype
        assert drift.mean_square(velocities) == pytest.approx(3.0, rel=tolerance)
        np.testing.assert_allclose(velocities / np.linalg.norm(velocities, axis=1)[:, None], directions,
                                   atol=10 * np.finfo(dtype).eps)
    at_rest = np.zeros((3, 2))
    drift.rescale(at_rest, 1.0)  # nothing to scale: left alone
    assert not at_rest.any()


def test_bad_arguments_raise_value_error():
    positions, velocities = lattice_start()
    with pytest.raises(ValueError, match="radius"):
        drift.event_driven_float32(R, R + 1, positions, velocities, 1)
    with pytest.raises(ValueError, match=r"\(n, 2\)"):
        drift.time_stepped(R, A, positions, velocities[:3], 0.1, 1)
    with pytest.raises(ValueError, match="at rest"):
        drift.event_driven_float32(R, A, positions, np.zeros_like(velocities), 1)


def test_help_explains_every_function():
    for name in ["event_driven_float32", "time_stepped", "rescale", "mean_square", "History"]:
        assert len(getattr(drift, name).__doc__ or "") > 80, name
    assert "float32" in drift.__doc__ and "time step" in drift.__doc__
