"""The time-stepped integrator through the Python module: billiard.stepping (lib/python/
stepping_bindings.cpp, billiard/stepping.py). The physics is tested by the C++ suite in
tests/stepping/; here what the binding adds: level sets written as numpy functions (called once
per step for all particles), states as dicts, replays as generators, errors as ValueError."""

import numpy as np
import pytest

import billiard

pytestmark = pytest.mark.skipif(not hasattr(billiard, "Stepper"),
                                reason="this build has no billiard.Stepper (the stepping library is not built)")

from billiard.stepping import Stepper, box, circle, ellipse, level_set  # noqa: E402

STATE_KEYS = {"time", "steps", "position", "velocity", "part", "reflections", "energy"}


def numpy_circle(centre, radius, calls=None):
    """The built-in circle's formulas in numpy; `calls` (a list) records the number of points of each call."""
    centre = np.asarray(centre, dtype=float)

    def omega(points):
        if calls is not None:
            calls.append(len(points))
        d = points - centre
        return radius - np.sqrt(d[:, 0] * d[:, 0] + d[:, 1] * d[:, 1])

    def grad(points):
        d = points - centre
        r = np.sqrt(d[:, 0] * d[:, 0] + d[:, 1] * d[:, 1])
        return -d / r[:, None]

    return level_set(omega, grad)


def random_particles(n, seed=3, spread=0.6):
    rng = np.random.default_rng(seed)
    x = rng.uniform(-spread, spread, size=(n, 2))
    angle = rng.uniform(0, 2 * np.pi, size=n)
    return x, np.column_stack([np.cos(angle), np.sin(angle)])


def test_numpy_level_set_follows_the_built_in_circle_to_rounding():
    x, v = random_particles(12)
    calls = []
    built_in = Stepper(circle((0.0, 0.0), 1.0), x, v, dt=2e-3, gravity=(0.0, -1.0))
    python = Stepper(numpy_circle((0.0, 0.0), 1.0, calls), x, v, dt=2e-3, gravity=(0.0, -1.0))
    calls.clear()
    built_in.step(2000)
    python.step(2000)
    assert built_in.total_reflections > 20
    a, b = built_in.current_state, python.current_state
    np.testing.assert_allclose(b["position"], a["position"], rtol=0, atol=1e-12)
    np.testing.assert_allclose(b["velocity"], a["velocity"], rtol=0, atol=1e-12)
    np.testing.assert_array_equal(b["reflections"], a["reflections"])
    # Vectorised: omega is called with all 12 particles once per step (the end points), plus
    # smaller batches for the particles that cross; never one call per particle and step.
    assert calls.count(12) == 2000
    assert len(calls) < 2000 + 4 * built_in.total_reflections


def test_state_dicts_have_the_simulation_key_names_and_the_energy():
    x, v = random_particles(5)
    stepper = billiard.Stepper([circle((0, 0), 1.0), box((-0.5, -2.0), (0.5, 0.0))], x, v, dt=1e-2, gravity=(0, -1))
    initial = stepper.initial_state
    assert set(initial) == STATE_KEYS
    assert initial["time"] == 0.0 and initial["steps"] == 0
    assert initial["position"].shape == (5, 2) and initial["velocity"].shape == (5, 2)
    np.testing.assert_array_equal(initial["part"], np.zeros(5))
    stepper.advance_to(3.0)
    now = stepper.current_state
    assert now["steps"] == 300 and now["time"] == pytest.approx(3.0)
    assert stepper.time == now["time"] and stepper.steps == 300 and len(stepper) == 5
    expected_energy = 0.5 * (now["velocity"] ** 2).sum(axis=1) + now["position"][:, 1]  # g = (0, -1)
    np.testing.assert_allclose(now["energy"], expected_energy, rtol=0, atol=1e-14)
    assert stepper.energy() == pytest.approx(now["energy"].sum(), abs=1e-13)
    assert stepper.initial_energy() == pytest.approx(initial["energy"].sum(), abs=1e-13)
    assert now["reflections"].sum() == stepper.total_reflections
    # The initial state is kept.
    np.testing.assert_array_equal(stepper.initial_state["position"], x)


def test_union_part_switches_without_reflection_at_the_inner_arcs():
    stepper = Stepper([circle((-1, 0), 1.5), circle((1, 0), 1.5)], [[-1.0, 0.0]], [[1.0, 0.0]], dt=0.01)
    stepper.advance_to(1.6)
    state = stepper.current_state
    assert state["part"][0] == 1 and state["reflections"][0] == 0
    assert state["position"][0, 0] == pytest.approx(0.6, abs=1e-12)
    stepper.advance_to(3.6)
    state = stepper.current_state
    assert state["reflections"][0] == 1 and state["part"][0] == 1
    assert state["position"][0, 0] == pytest.approx(2.4, abs=1e-12)


def test_replays_repeat_the_run_exactly():
    x, v = random_particles(4)
    stepper = Stepper([ellipse((0, 0), (1.5, 1.0)), numpy_circle((1.2, 0.0), 0.5)], x, v, dt=5e-3, gravity=(0.2, -1.0))
    stepper.step(1000)
    by_steps = list(stepper.replay_by_steps(250))
    assert [s["steps"] for s in by_steps] == [0, 250, 500, 750, 1000]
    for key in ("position", "velocity", "part", "reflections"):
        np.testing.assert_array_equal(by_steps[-1][key], stepper.current_state[key])
        np.testing.assert_array_equal(by_steps[0][key], stepper.initial_state[key])
    by_time = list(stepper.replay_by_time(0.5))
    assert [s["steps"] for s in by_time] == [0, 100, 200, 300, 400, 500, 600, 700, 800, 900, 1000]
    np.testing.assert_array_equal(by_time[5]["position"], by_steps[2]["position"])
    # A frame time between steps gives the last step before it.
    assert [s["steps"] for s in stepper.replay_by_time(0.0123, until=0.03)] == [0, 2, 4]
    assert [s["steps"] for s in stepper.replay_at([0.5, 0.5, 2.0, 4.999])] == [100, 100, 400, 999]
    np.testing.assert_array_equal(next(stepper.replay_at([2.5]))["velocity"], by_steps[2]["velocity"])
    # The replay does not move the stepper.
    assert stepper.steps == 1000


def test_euler_drifts_and_leapfrog_does_not_in_free_flight():
    domain = box((-100, -100), (100, 100))
    euler = Stepper(domain, [[0.0, 0.0]], [[1.0, 1.0]], dt=1e-2, gravity=(0, -2), integrator="euler")
    leapfrog = Stepper(domain, [[0.0, 0.0]], [[1.0, 1.0]], dt=1e-2, gravity=(0, -2))
    assert euler.integrator == "euler" and leapfrog.integrator == "leapfrog"
    euler.step(400)
    leapfrog.step(400)
    assert euler.energy() - euler.initial_energy() == pytest.approx(400 * 4 * 1e-4 / 2, abs=1e-12)
    assert abs(leapfrog.energy() - leapfrog.initial_energy()) < 1e-11


def test_level_set_objects_evaluate_omega_and_grad():
    c = circle((1.0, 0.0), 2.0)
    np.testing.assert_allclose(c.omega([[1.0, 0.0], [4.0, 0.0]]), [2.0, -1.0])
    np.testing.assert_allclose(c.grad([[3.0, 0.0]]), [[-1.0, 0.0]])
    b = box((0, 0), (2, 1))
    np.testing.assert_allclose(b.omega([[1.0, 0.2]]), [0.2])
    np.testing.assert_allclose(b.grad([[1.0, 0.2]]), [[0.0, 1.0]])
    assert "circle" in repr(c)


def good_args():
    return dict(domain=circle((0, 0), 1.0), positions=[[0.0, 0.0]], velocities=[[1.0, 0.0]], dt=0.1)


@pytest.mark.parametrize("change, words", [
    (dict(dt=0.0), "dt = 0"),
    (dict(dt=-1.0), "dt = -1"),
    (dict(dt=float("nan")), "dt = nan"),
    (dict(positions=[[2.0, 0.0]]), "positions row 0"),
    (dict(positions=[[0.0, 0.0, 0.0]]), "positions"),
    (dict(velocities=[[1.0, 0.0], [0.0, 1.0]]), "velocities has 2"),
    (dict(velocities=[1.0, 0.0]), "velocities"),
    (dict(gravity=(0.0,)), "gravity"),
    (dict(domain="circle"), "domain"),
    (dict(domain=[]), "domain"),
    (dict(integrator="rk4"), "integrator"),
])
def test_bad_arguments_raise_value_error_naming_them(change, words):
    args = good_args()
    args.update(change)
    with pytest.raises(ValueError, match=words.replace("(", r"\(")):
        Stepper(**args)


@pytest.mark.parametrize("call, words", [
    (lambda: circle((0, 0), 0.0), "radius = 0"),
    (lambda: ellipse((0, 0), (1.0, -1.0)), "semi_axes.y = -1"),
    (lambda: box((0, 0), (0, 1)), "upper"),
    (lambda: level_set(1.0, lambda p: p), "omega must be a function"),
])
def test_bad_shapes_raise_value_error(call, words):
    with pytest.raises(ValueError, match=words):
        call()


def test_wrong_shapes_from_the_users_functions_raise_value_error_and_change_nothing():
    def omega_scalar(points):
        return 1.0 - np.sum(points ** 2)  # forgot axis=1: one number for all points

    with pytest.raises(ValueError, match=r"omega returned an array of shape \(\) for 2 points; it must return shape \(2,\)"):
        Stepper(level_set(omega_scalar, lambda p: -p), [[0.0, 0.0], [0.1, 0.0]], [[1.0, 0.0], [1.0, 0.0]], dt=0.1)

    state = {"bad": False}

    def omega(points):
        return 1.0 - np.sqrt((points ** 2).sum(axis=1))

    def grad(points):
        g = -points / np.sqrt((points ** 2).sum(axis=1))[:, None]
        return g[:, :1] if state["bad"] else g  # wrong shape (n, 1) once switched

    stepper = Stepper(level_set(omega, grad), [[0.5, 0.0]], [[1.0, 0.0]], dt=0.1)
    stepper.step(3)  # at 0.8, no crossing yet
    before = stepper.current_state
    state["bad"] = True
    with pytest.raises(ValueError, match=r"grad returned an array of shape \(1, 1\) for 1 points; it must return shape \(1, 2\)"):
        stepper.step(5)  # the crossing needs grad
    after = stepper.current_state
    assert after["steps"] == 3
    np.testing.assert_array_equal(after["position"], before["position"])
    np.testing.assert_array_equal(after["velocity"], before["velocity"])


def test_exceptions_from_the_users_functions_pass_through_unchanged():
    def omega(points):
        raise ZeroDivisionError("inside the user's omega")

    with pytest.raises(ZeroDivisionError, match="user's omega"):
        Stepper(level_set(omega, lambda p: p), [[0.0, 0.0]], [[1.0, 0.0]], dt=0.1)


def test_bad_step_counts_and_replay_arguments():
    stepper = Stepper(**good_args())
    with pytest.raises(ValueError, match="n = -1"):
        stepper.step(-1)
    stepper.step(2)
    with pytest.raises(ValueError, match="time = 0.1"):
        stepper.advance_to(0.1)
    with pytest.raises(ValueError, match="dt must be a positive number"):
        next(stepper.replay_by_time(0.0))
    with pytest.raises(ValueError, match="every must be an integer"):
        next(stepper.replay_by_steps(0))
    with pytest.raises(ValueError, match="until must be a finite number"):
        next(stepper.replay_by_time(0.1, until=float("inf")))
    with pytest.raises(ValueError, match="increasing order"):
        next(stepper.replay_at([0.2, 0.1]))
    with pytest.raises(ValueError, match="times must be finite numbers"):
        next(stepper.replay_at([float("nan")]))
    assert stepper.steps == 2


def test_nan_from_the_users_omega_raises_value_error():
    def omega(points):
        return np.full(len(points), np.nan)

    with pytest.raises(ValueError, match="omega = nan"):
        Stepper(level_set(omega, lambda p: -p), [[0.0, 0.0]], [[1.0, 0.0]], dt=0.1)
