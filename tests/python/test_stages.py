"""The extension stages through the Python module (billiard.stages): the stages this build has,
in-place updates as in C++, and errors that leave the caller's arrays unchanged. The physics
itself is tested by the stages' graded C++ suites; here only what the binding adds."""

import sys
from pathlib import Path

import numpy as np
import pytest

import billiard

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "grader"))
import course  # noqa: E402  (the course's tasks)

R, A, N = 10.0, 1.0, 10
stages = billiard.stages


def built(stage):
    """Run the test only where the stage is built, and from the reference solutions."""
    return pytest.mark.skipif(stage not in stages.available or billiard.course_implementation != "solutions",
                              reason=f"the {stage} stage is not built from the reference solutions here")


def test_available_follows_the_course_file():
    assert stages.available == course.STAGES
    for stage, function in [("gravity", "propagate_gravity"), ("walls", "propagate_walls"),
                            ("sectors", "propagate_sectors")]:
        assert hasattr(stages, function) == (stage in stages.available)


def test_wall_id_numbers_walls_below_the_table():
    assert [stages.wall_id(k) for k in range(3)] == [-2, -3, -4]
    assert billiard.WALL == -1


def table(seed=1):
    rng = billiard.Rng(seed)
    coordinates = billiard.init_billiard(R, A, N, rng)
    return coordinates, billiard.init_velocities(coordinates, rng)


@built("gravity")
def test_gravity_updates_in_place_and_conserves_the_mean_energy():
    coordinates, velocities = table()
    g = (0.0, -1.0)
    before = stages.mean_energy(coordinates, velocities, g)
    start = coordinates.copy()
    for _ in range(200):
        collision = stages.propagate_gravity(R, A, coordinates, velocities, g)
        assert collision.time >= 0
    assert not np.array_equal(coordinates, start)
    assert abs(stages.mean_energy(coordinates, velocities, g) - before) <= 1e-10 * abs(before)


@built("gravity")
def test_bad_gravity_is_a_value_error_and_changes_nothing():
    coordinates, velocities = table()
    saved = coordinates.copy(), velocities.copy()
    for g in [(0.0, float("nan")), (1.0, 2.0, 3.0)]:
        with pytest.raises(ValueError, match="g"):
            stages.propagate_gravity(R, A, coordinates, velocities, g)
    assert np.array_equal(coordinates, saved[0]) and np.array_equal(velocities, saved[1])


@built("walls")
def test_walls_as_rows_and_the_wall_id_of_a_hit():
    coordinates = np.array([[0.0, 0.0]])
    velocities = np.array([[0.0, 1.0]])
    collision = stages.propagate_walls(R, A, coordinates, velocities, [[-5.0, 4.0, 5.0, 4.0]])
    assert collision.other == stages.wall_id(0)
    assert collision.time == pytest.approx(3.0, rel=1e-12)
    assert velocities[0].tolist() == pytest.approx([0.0, -1.0])
    collision = stages.propagate_walls(R, A, coordinates, velocities, np.empty((0, 4)))
    assert collision.other == billiard.WALL


@built("walls")
def test_walls_of_the_wrong_shape_are_a_value_error_and_change_nothing():
    coordinates, velocities = table()
    saved = coordinates.copy(), velocities.copy()
    with pytest.raises(ValueError, match="walls"):
        stages.propagate_walls(R, A, coordinates, velocities, [[0.0, 0.0, 1.0]])
    assert np.array_equal(coordinates, saved[0]) and np.array_equal(velocities, saved[1])


@built("sectors")
def test_sectors_count_pair_tests_and_refuse_small_cells():
    coordinates, velocities = table()
    calls = stages.pair_time_calls()
    collision = stages.propagate_sectors(R, A, coordinates, velocities, 2 * A)
    assert collision.time >= 0 and stages.pair_time_calls() > calls
    saved = coordinates.copy()
    with pytest.raises(ValueError, match="cell_size"):
        stages.propagate_sectors(R, A, coordinates, velocities, A)
    assert np.array_equal(coordinates, saved)
