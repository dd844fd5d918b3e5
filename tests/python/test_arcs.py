"""Curved walls through the Python module: arcs, disc obstacles and the curved containers
(stadium, Sinai billiard, mushroom, union of circles). The physics is tested by the C++ engine
suite (tests/engine/test_arcs.cpp); here the arguments, the walls seen from Python, a known time
and the errors as ValueError."""

import math

import numpy as np
import pytest

import billiard

pytestmark = pytest.mark.skipif(not hasattr(billiard, "Simulation"),
                                reason="this build has no billiard.Simulation (the engine library is not built)")


def test_disc_through_the_gap_meets_the_inside_of_an_arc_at_time_12_5():
    # Upper half of the circle of radius 5; a disc of radius 0.5 from (0, -8) moving up passes the
    # open lower half and meets the arc from inside at y = 4.5.
    container = billiard.box((-10, -10), (10, 10))
    arc = container.add_arc((0, 0), 5.0, 0.0, math.pi)
    sim = billiard.Simulation(container)
    sim.add_disc((0.0, -8.0), (0.0, 1.0), radius=0.5)
    sim.set_log_events(True)
    sim.advance(events=1)
    log = sim.event_log
    assert log["wall"][0] == arc
    assert log["time"][0] == pytest.approx(12.5, abs=1e-12)
    np.testing.assert_allclose(log["velocity"][0], [0.0, -1.0], atol=1e-12)
    wall = sim.container.walls[arc]
    assert wall["kind"] == "arc" and wall["radius"] == 5.0
    assert wall["start_angle"] == 0.0 and wall["sweep"] == pytest.approx(math.pi)
    assert sum(1 for w in sim.container.walls if w["kind"] == "point") == 4 + 2  # box corners and arc ends


def test_stadium_keeps_the_discs_inside_and_the_energy():
    sim = billiard.Simulation(billiard.stadium((0.0, 0.0), 5.0, 4.0))
    sim.add_random_discs(30, 0.3, kT=1.0, seed=3)
    energy = sim.kinetic_energy()
    sim.advance(events=20000)
    assert sim.validate() is None
    assert sim.kinetic_energy() == pytest.approx(energy, rel=1e-12)
    p = sim.current_state["position"]
    nearest = np.stack([np.clip(p[:, 0], -2.0, 2.0), np.zeros(len(p))], axis=1)
    assert np.all(np.linalg.norm(p - nearest, axis=1) <= 5.0 - 0.3 + 1e-9)


@pytest.mark.parametrize("build", [
    lambda: billiard.sinai_billiard((0, 0), (10, 10), 2.0),
    lambda: billiard.mushroom((0, 0), 5.0, 2.0, 4.0),
    lambda: billiard.union_of_circles([[0, 0], [4, 0]], [3.0, 2.5]),
])
def test_curved_containers_take_random_discs_and_run(build):
    sim = billiard.Simulation(build())
    sim.add_random_discs(20, 0.25, kT=1.0, seed=5)
    sim.advance(events=5000)
    assert sim.validate() is None


def test_bad_arguments_raise_value_error_naming_the_argument():
    container = billiard.box((-10, -10), (10, 10))
    walls = container.walls
    with pytest.raises(ValueError, match="add_arc: radius"):
        container.add_arc((0, 0), -1.0, 0.0, 1.0)
    with pytest.raises(ValueError, match="end_angle - start_angle"):
        container.add_arc((0, 0), 1.0, 1.0, 0.5)
    with pytest.raises(ValueError, match="centre"):
        container.add_arc((0, 0, 0), 1.0, 0.0, 1.0)
    with pytest.raises(ValueError, match="stadium: length"):
        billiard.stadium((0, 0), 1.0, 0.0)
    with pytest.raises(ValueError, match="mushroom: stem_width"):
        billiard.mushroom((0, 0), 1.0, 3.0, 1.0)
    with pytest.raises(ValueError, match="sinai_billiard: obstacle_radius"):
        billiard.sinai_billiard((0, 0), (2, 2), 1.5)
    with pytest.raises(ValueError, match="union_of_circles: radii"):
        billiard.union_of_circles([[0, 0], [1, 0]], [1.0])
    with pytest.raises(ValueError, match="radii"):
        billiard.union_of_circles([[0, 0]], "wide")
    assert container.walls == walls


def test_stadium_drawn_with_its_arcs_and_straight_sides():
    matplotlib = pytest.importorskip("matplotlib")
    matplotlib.use("Agg")
    from matplotlib.figure import Figure
    from matplotlib.patches import Arc
    import billiard.plotting as bp

    sim = billiard.Simulation(billiard.stadium((0.0, 0.0), 5.0, 4.0))  # spans x in [-7, 7], y in [-5, 5]
    sim.add_random_discs(10, 0.3, seed=2)
    walls = bp.simulation_walls(sim)
    assert len(walls["walls"]) == 2 and len(walls["arcs"]) == 2 and "table_radius" not in walls
    ax = Figure().add_subplot()
    bp.draw_table(ax, sim.current_state, **walls)
    assert len([p for p in ax.patches if isinstance(p, Arc)]) == 2
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    assert -7.5 < x0 <= -7 and 7 <= x1 < 7.5 and -5.5 < y0 <= -5 and 5 <= y1 < 5.5
    with pytest.raises(ValueError, match="arcs"):
        bp.draw_table(Figure().add_subplot(), sim.current_state, arcs=[[0, 0, 1, 2, 1]])
