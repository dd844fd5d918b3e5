"""Describe, then run, from Python: the shape functions and billiard.Container, billiard.Settings,
and billiard.Simulation(container, settings) (lib/python/simulation_bindings.cpp). The geometry
and the checks are the C++ library's (tests/engine); here what the binding adds or could break:
the arguments, the values read back, the errors as ValueError naming the argument or the field,
and the copies (a simulation keeps its own container and settings)."""

import copy
import math
import pathlib
import pickle
import re

import numpy as np
import pytest

import billiard

pytestmark = pytest.mark.skipif(not hasattr(billiard, "Simulation"),
                                reason="this build has no billiard.Simulation (the engine library is not built)")

FIELDS = ["gravity", "restitution", "exchange_velocities", "contact_duration", "elastic_impact_speed", "sleep_speed",
          "cell_size", "prefetch"]


def kinds(container):
    """The number of walls of each kind."""
    counts = {}
    for wall in container.walls:
        counts[wall["kind"]] = counts.get(wall["kind"], 0) + 1
    return counts


# ---- The shapes -------------------------------------------------------------------------------

def test_each_shape_function_makes_its_container():
    table = billiard.circular_table(10.0)
    assert isinstance(table, billiard.Container)
    assert kinds(table) == {"circle": 1} and table.table_radius == 10.0
    assert not table.periodic and table.period == (0.0, 0.0)
    assert table.walls[0]["a"] == (0.0, 0.0) and table.walls[0]["radius"] == 10.0

    periodic = billiard.periodic_box(5.0, 7.0)
    assert periodic.periodic and periodic.period == (5.0, 7.0) and periodic.walls == []
    assert periodic.table_radius == 0.0

    box = billiard.box((0, 0), (4, 3))
    assert kinds(box) == {"segment": 4, "point": 4} and box.table_radius == 0.0 and not box.periodic
    corners = {w["a"] for w in box.walls if w["kind"] == "point"}
    assert corners == {(0.0, 0.0), (4.0, 0.0), (4.0, 3.0), (0.0, 3.0)}

    triangle = billiard.polygon(np.array([[0.0, 0.0], [3.0, 0.0], [0.0, 4.0]]))
    assert kinds(triangle) == {"segment": 3, "point": 3}
    assert kinds(billiard.polygon([[0, 0], [1, 0], [1, 1], [0, 1]])) == {"segment": 4, "point": 4}  # lists too

    stadium = billiard.stadium((0.0, 0.0), 5.0, 4.0)
    assert kinds(stadium) == {"arc": 2, "segment": 2, "point": 4}
    assert sorted(w["radius"] for w in stadium.walls if w["kind"] == "arc") == [5.0, 5.0]

    sinai = billiard.sinai_billiard((0, 0), (10, 10), 2.0)
    assert kinds(sinai) == {"segment": 4, "point": 4, "arc": 1}
    obstacle = next(w for w in sinai.walls if w["kind"] == "arc")
    assert obstacle["a"] == (5.0, 5.0) and obstacle["radius"] == 2.0 and obstacle["sweep"] == pytest.approx(2 * math.pi)

    mushroom = billiard.mushroom((0, 0), 5.0, 2.0, 4.0)
    assert kinds(mushroom) == {"segment": 5, "arc": 1, "point": 6}

    union = billiard.union_of_circles([[0, 0], [4, 0]], [3.0, 2.5])
    assert kinds(union) == {"arc": 2, "point": 2}  # two arcs meeting at two points


def test_a_container_has_no_public_constructor():
    with pytest.raises(TypeError, match="circular_table.*union_of_circles"):
        billiard.Container()


def test_the_repr_says_what_the_container_is():
    assert repr(billiard.periodic_box(20.0, 15.0)) == "Container(periodic box 20.0 x 15.0, no walls)"
    assert repr(billiard.circular_table(10.0)) == "Container(circular table of radius 10.0; 1 wall: 1 circle)"
    sinai = billiard.sinai_billiard((0, 0), (10, 10), 2.0)
    assert repr(sinai) == "Container(1 closed outline, 1 obstacle; 9 walls: 4 segments, 1 arc, 4 points)"


# ---- Adding to a container ----------------------------------------------------------------------

def test_add_calls_return_the_wall_index_and_extend_the_walls():
    container = billiard.box((-10, -10), (10, 10))
    first = len(container.walls)
    segment = container.add_segment((1.0, 1.0), (3.0, 1.0))
    assert segment == first and container.walls[segment]["kind"] == "segment"
    assert container.walls[segment]["a"] == (1.0, 1.0) and container.walls[segment]["b"] == (3.0, 1.0)
    arc = container.add_arc((0, 0), 5.0, 0.0, math.pi)
    assert arc == first + 3  # after the segment and its two end points
    assert container.walls[arc]["kind"] == "arc" and container.walls[arc]["sweep"] == pytest.approx(math.pi)
    before = len(container.walls)
    container.add_obstacle((-5.0, -5.0), 1.0)
    assert len(container.walls) == before + 1 and container.walls[-1]["radius"] == 1.0  # a whole circle: no end points
    before = len(container.walls)
    container.add_obstacle(billiard.polygon([[5, -5], [7, -5], [6, -3]]))
    assert len(container.walls) == before + 6  # three sides and three corners
    assert "2 obstacles" in repr(container)


def test_discs_stay_out_of_an_outlined_obstacle():
    container = billiard.box((-10, -10), (10, 10))
    container.add_obstacle(billiard.box((-3, -3), (3, 3)))
    sim = billiard.Simulation(container)
    with pytest.raises(ValueError):
        sim.add_disc((0.0, 0.0), radius=0.5)  # inside the obstacle
    sim.add_random_discs(40, 0.4, seed=2)
    sim.advance(events=5000)
    assert sim.validate() is None
    position = sim.current_state["position"]
    assert np.all(np.abs(position).max(axis=1) >= 3 + 0.4 - 1e-9)


@pytest.mark.parametrize("call, match", [
    (lambda c: c.add_segment((1, 1), (1, 1)), "add_segment: a and b must differ"),
    (lambda c: c.add_segment((math.nan, 1), (2, 2)), "add_segment: a "),
    (lambda c: c.add_segment((1, 1), (1, 2, 3)), "add_segment: b "),
    (lambda c: c.add_arc((0, 0), -1.0, 0.0, 1.0), "add_arc: radius"),
    (lambda c: c.add_arc((0, 0), 1.0, math.inf, 1.0), "add_arc: start_angle"),
    (lambda c: c.add_arc((0, 0), 1.0, 1.0, 0.5), "add_arc: end_angle - start_angle"),
    (lambda c: c.add_arc("centre", 1.0, 0.0, 1.0), "add_arc: centre"),
    (lambda c: c.add_obstacle((0, 0), 0.0), "add_obstacle: radius"),
    (lambda c: c.add_obstacle((0, 1e51), 1.0), "add_obstacle: centre"),
    (lambda c: c.add_obstacle(billiard.circular_table(1.0)), "add_obstacle: shape must be an outline"),
    (lambda c: c.add_obstacle(billiard.periodic_box(1.0, 1.0)), "add_obstacle: shape must be an outline"),
])
def test_refused_add_calls_name_the_argument_and_leave_the_container_unchanged(call, match):
    container = billiard.box((-10, -10), (10, 10))
    container.add_segment((1.0, 1.0), (3.0, 1.0))
    walls, text = container.walls, repr(container)
    with pytest.raises(ValueError, match=match):
        call(container)
    assert container.walls == walls and repr(container) == text


def test_an_obstacle_with_free_walls_is_refused():
    shape = billiard.box((0, 0), (1, 1))
    shape.add_segment((0.2, 0.5), (0.8, 0.5))
    container = billiard.box((-10, -10), (10, 10))
    with pytest.raises(ValueError, match="add_obstacle: shape has walls besides its outline"):
        container.add_obstacle(shape)
    assert kinds(container) == {"segment": 4, "point": 4}


def test_a_periodic_box_refuses_every_wall():
    periodic = billiard.periodic_box(10.0, 10.0)
    for call, name in [(lambda: periodic.add_segment((1, 1), (2, 2)), "add_segment"),
                       (lambda: periodic.add_arc((5, 5), 1.0, 0.0, 1.0), "add_arc"),
                       (lambda: periodic.add_obstacle((5, 5), 1.0), "add_obstacle"),
                       (lambda: periodic.add_obstacle(billiard.box((1, 1), (2, 2))), "add_obstacle")]:
        with pytest.raises(ValueError, match=f"{name}: walls inside a periodic box are not supported"):
            call()
    assert periodic.walls == [] and periodic.period == (10.0, 10.0)


@pytest.mark.parametrize("call, match", [
    (lambda: billiard.circular_table(-1.0), "circular_table: radius"),
    (lambda: billiard.periodic_box(0.0, 1.0), "periodic_box: width"),
    (lambda: billiard.periodic_box(1.0, math.inf), "periodic_box: height"),
    (lambda: billiard.box((0, 0), (0, 1)), "box: upper .* must exceed lower"),
    (lambda: billiard.box((0, 0, 0), (1, 1)), "box: lower"),
    (lambda: billiard.polygon([[0, 0], [1, 0]]), "polygon: vertices needs at least 3 rows"),
    (lambda: billiard.polygon([[0, 0], [1, 0], [math.nan, 1]]), "polygon: vertex 2"),
    (lambda: billiard.polygon(np.zeros((3, 3))), "polygon: vertices"),
    (lambda: billiard.stadium((0, 0), 1.0, 0.0), "stadium: length"),
    (lambda: billiard.sinai_billiard((0, 0), (2, 2), 1.5), "sinai_billiard: obstacle_radius"),
    (lambda: billiard.mushroom((0, 0), 1.0, 3.0, 1.0), "mushroom: stem_width"),
    (lambda: billiard.union_of_circles([[0, 0], [1, 0]], [1.0]), "union_of_circles: radii"),
    (lambda: billiard.union_of_circles([[0, 0], [1, 0]], [True, False]), "union_of_circles: radii"),
    (lambda: billiard.union_of_circles([[0, 0]], "wide"), "union_of_circles: radii"),
])
def test_refused_shapes_name_the_function_and_the_argument(call, match):
    with pytest.raises(ValueError, match=match):
        call()


def test_a_container_is_a_value():
    container = billiard.box((0, 0), (10, 10))
    twin = copy.copy(container)
    deep = copy.deepcopy(container)
    container.add_segment((1, 1), (2, 2))
    assert len(twin.walls) == len(deep.walls) == 8 and len(container.walls) == 11


# ---- Settings ---------------------------------------------------------------------------------

def test_settings_have_the_documented_defaults():
    settings = billiard.Settings()
    assert settings.gravity == (0.0, 0.0)
    assert settings.restitution == (1.0, -1.0)
    assert settings.exchange_velocities is False
    assert settings.contact_duration is None and settings.elastic_impact_speed is None and settings.sleep_speed is None
    assert settings.cell_size == 0.0 and settings.prefetch == "auto"
    assert repr(settings) == ("Settings(gravity=(0.0, 0.0), restitution=(1.0, -1.0), exchange_velocities=False, "
                              "contact_duration=None, elastic_impact_speed=None, sleep_speed=None, cell_size=0.0, "
                              "prefetch='auto')")


def test_settings_take_keywords_only_and_read_back_what_was_given():
    with pytest.raises(TypeError):
        billiard.Settings((0.0, -1.0))
    with pytest.raises(TypeError):
        billiard.Settings(gravty=(0.0, -1.0))  # a misspelt field is not ignored
    settings = billiard.Settings(gravity=np.array([0.5, -1.0]), restitution=(0.9, 0.25), exchange_velocities=True,
                                 contact_duration=0.5, elastic_impact_speed=0.25, sleep_speed=0.0, cell_size=3.0,
                                 prefetch="off")
    assert settings.gravity == (0.5, -1.0) and settings.restitution == (0.9, 0.25)
    assert settings.exchange_velocities is True and settings.contact_duration == 0.5
    assert settings.elastic_impact_speed == 0.25 and settings.sleep_speed == 0.0
    assert settings.cell_size == 3.0 and settings.prefetch == "off"
    assert eval(repr(settings), {"Settings": billiard.Settings}) == settings


def test_settings_fields_are_writable_attributes():
    settings = billiard.Settings()
    settings.gravity = [0, -2]
    settings.restitution = 0.8
    settings.exchange_velocities = True
    settings.contact_duration = 1e-3
    settings.elastic_impact_speed = 0.0
    settings.sleep_speed = None
    settings.cell_size = 2.5
    settings.prefetch = "on"
    assert settings == billiard.Settings(gravity=(0, -2), restitution=(0.8, -1), exchange_velocities=True,
                                         contact_duration=1e-3, elastic_impact_speed=0.0, cell_size=2.5, prefetch="on")
    with pytest.raises(AttributeError):
        settings.gravty = (0, -1)  # a misspelt field is not a new attribute


@pytest.mark.parametrize("given, expected", [(0.5, (0.5, -1.0)), (1, (1.0, -1.0)), (np.float64(0.25), (0.25, -1.0)),
                                             ((0.9, 0.5), (0.9, 0.5)), ([0.9, -0.5], (0.9, -0.5)),
                                             (np.array([1.0, 1.0]), (1.0, 1.0))])
def test_restitution_is_a_number_or_a_pair_and_reads_back_as_a_pair(given, expected):
    assert billiard.Settings(restitution=given).restitution == expected
    settings = billiard.Settings()
    settings.restitution = given
    assert settings.restitution == expected


@pytest.mark.parametrize("field, value, match", [
    ("gravity", (1.0, 2.0, 3.0), "settings.gravity must be a point"),
    ("gravity", None, "settings.gravity must be a point"),
    ("restitution", "elastic", "settings.restitution must be a number .* or a pair"),
    ("restitution", (0.9, 0.5, 0.1), "settings.restitution must be a number .* or a pair"),
    ("restitution", True, "settings.restitution must be a number .* or a pair"),
    ("prefetch", "sometimes", "settings.prefetch must be 'auto', 'on' or 'off', got 'sometimes'"),
    ("prefetch", None, "settings.prefetch must be 'auto', 'on' or 'off', got None"),
    ("prefetch", True, "settings.prefetch"),
])
def test_settings_that_cannot_be_read_are_refused_at_once_naming_the_field(field, value, match):
    with pytest.raises(ValueError, match=match):
        billiard.Settings(**{field: value})
    settings = billiard.Settings()
    with pytest.raises(ValueError, match=match):
        setattr(settings, field, value)
    assert settings == billiard.Settings()  # unchanged


@pytest.mark.parametrize("field, value", [("cell_size", "big"), ("cell_size", None), ("contact_duration", "soon"),
                                          ("sleep_speed", [0.1]), ("exchange_velocities", "yes")])
def test_settings_of_the_wrong_type_are_type_errors_naming_the_field(field, value):
    with pytest.raises(TypeError, match=f"{field}:"):
        billiard.Settings(**{field: value})
    settings = billiard.Settings()
    with pytest.raises(TypeError, match=f"{field}:"):
        setattr(settings, field, value)
    assert settings == billiard.Settings()


@pytest.mark.parametrize("field, value, match", [
    ("gravity", (0.0, math.nan), "settings.gravity must be finite"),
    ("gravity", (0.0, 1e51), "settings.gravity must be finite"),
    ("gravity", (1e-300, 0.0), "settings.gravity must be 0 or at least 1e-50"),
    ("restitution", 1.5, r"settings.restitution.normal must be in \[0, 1\], got 1.5"),
    ("restitution", (0.5, -2.0), r"settings.restitution.tangential must be in \[-1, 1\], got -2"),
    ("contact_duration", -1.0, "settings.contact_duration must be >= 0"),
    ("elastic_impact_speed", math.inf, "settings.elastic_impact_speed must be >= 0"),
    ("sleep_speed", math.nan, "settings.sleep_speed must be >= 0"),
    ("cell_size", -1.0, "settings.cell_size must be >= 0"),
])
def test_bad_values_are_refused_by_the_simulation_naming_the_field(field, value, match):
    settings = billiard.Settings(**{field: value})  # read, not judged: the simulation checks them
    with pytest.raises(ValueError, match=match):
        billiard.Simulation(billiard.box((0, 0), (10, 10)), settings)


def test_settings_copy_and_pickle():
    settings = billiard.Settings(gravity=(0, -1), restitution=(0.9, 0.5), sleep_speed=0.0, prefetch="on")
    assert copy.copy(settings) == settings and copy.deepcopy(settings) == settings
    assert pickle.loads(pickle.dumps(settings)) == settings
    other = copy.copy(settings)
    other.cell_size = 4.0
    assert other != settings and settings.cell_size == 0.0


# ---- The simulation ------------------------------------------------------------------------------

def test_a_simulation_needs_a_container():
    with pytest.raises(TypeError, match="Simulation needs a container"):
        billiard.Simulation()
    with pytest.raises(TypeError, match="container must be a billiard.Container"):
        billiard.Simulation(billiard.Settings())
    with pytest.raises(TypeError, match="settings a billiard.Settings or None"):
        billiard.Simulation(billiard.box((0, 0), (1, 1)), {"gravity": (0, -1)})
    for old in ("set_circular_table", "add_box", "set_gravity", "set_cell_size", "set_prefetch_ahead", "walls",
                "period", "table_radius"):
        assert not hasattr(billiard.Simulation, old), old


def test_the_simulation_keeps_a_copy_of_its_container():
    container = billiard.sinai_billiard((0, 0), (10, 10), 2.0)
    container.add_segment((1.0, 1.0), (3.0, 1.0))
    walls = container.walls
    sim = billiard.Simulation(container)
    assert sim.container.walls == walls
    assert repr(sim.container) == repr(container)
    assert sim.container.period == container.period and sim.container.table_radius == container.table_radius
    assert sim.container.periodic is False
    container.add_segment((1.0, 8.0), (3.0, 8.0))  # the simulation's container is its own
    assert sim.container.walls == walls
    view = sim.container
    view.add_segment((7.0, 1.0), (7.0, 3.0))  # and what it gives is a copy
    assert sim.container.walls == walls
    del sim
    assert len(view.walls) == len(walls) + 3  # usable after the simulation is gone
    periodic = billiard.Simulation(billiard.periodic_box(5.0, 7.0)).container
    assert periodic.periodic and periodic.period == (5.0, 7.0)


def test_the_simulation_uses_the_settings_and_keeps_a_copy():
    settings = billiard.Settings(gravity=(0.0, -1.0), restitution=(0.5, 0.25), exchange_velocities=True,
                                 contact_duration=0.5, elastic_impact_speed=0.25, sleep_speed=0.125)
    sim = billiard.Simulation(billiard.box((0, 0), (10, 10)), settings)
    settings.gravity = (0.0, -5.0)  # changes nothing in the simulation made before
    settings.restitution = 1.0
    assert sim.gravity == (0.0, -1.0) and sim.restitution == (0.5, 0.25) and sim.exchange_velocities is True
    sim.add_random_discs(10, 0.3, seed=1)
    sim.advance(events=10)
    assert sim.contact_duration == 0.5 and sim.elastic_impact_speed == 0.25 and sim.sleep_speed == 0.125
    sim.set_restitution(0.75)  # the setters still change them during a run
    assert sim.restitution == (0.75, -1.0)
    with pytest.raises(ValueError, match=r"set_restitution: restitution.normal must be in \[0, 1\]"):
        sim.set_restitution(2.0)
    default = billiard.Simulation(billiard.box((0, 0), (10, 10)), None)
    assert default.gravity == (0.0, 0.0) and default.restitution == (1.0, -1.0) and default.exchange_velocities is False


def test_settings_give_the_same_run_as_the_setters_before_any_disc():
    def run(with_settings):
        container = billiard.box((0, 0), (20, 20))
        if with_settings:
            sim = billiard.Simulation(container, billiard.Settings(restitution=(0.9, 0.5), contact_duration=1e-3))
        else:
            sim = billiard.Simulation(container)
            sim.set_restitution((0.9, 0.5))
            sim.set_contact_duration(1e-3)
        sim.add_random_discs(30, 0.5, seed=4)
        sim.set_log_events(True)
        sim.advance(events=2000)
        return sim.event_log

    by_settings, by_setters = run(True), run(False)
    for key in by_settings:
        np.testing.assert_array_equal(by_settings[key], by_setters[key], err_msg=key)


def test_simulation_walls_takes_a_simulation_or_a_container():
    pytest.importorskip("matplotlib")
    import billiard.plotting as bp

    container = billiard.stadium((0.0, 0.0), 5.0, 4.0)
    sim = billiard.Simulation(container)
    assert bp.simulation_walls(container) == bp.simulation_walls(sim)
    assert len(bp.simulation_walls(container)["arcs"]) == 2
    assert bp.simulation_walls(billiard.circular_table(3.0))["table_radius"] == 3.0


# ---- One rule for the names' form ------------------------------------------------------------------

# Getters of the C++ Simulation that compute rather than hold, methods in Python as well.
COMPUTED = {"kinetic_energy", "potential_energy", "memory_bytes", "to_bytes"}
# Getters that Python reaches another way.
ELSEWHERE = {"size": "len(sim)", "radii": "current_state['radius']", "masses": "current_state['mass']",
             "inertias": "current_state['inertia']", "cell_count": "the engine's tuning, C++ only",
             "last_problem": "validate() returns it"}


def test_what_a_simulation_holds_is_a_property_and_what_it_computes_a_method():
    header = pathlib.Path(__file__).resolve().parents[2] / "lib/include/billiard/engine/simulation.hpp"
    getters = re.findall(r"^\s+[\w:<>&,\s]+?\b(\w+)\(\) const;", header.read_text(), re.MULTILINE)
    assert {"time", "contact_duration", "sleeping_discs", "kinetic_energy"} <= set(getters), getters
    for name in getters:
        if name in ELSEWHERE:
            assert not hasattr(billiard.Simulation, name), f"{name} is bound: take it out of ELSEWHERE"
            continue
        attribute = getattr(billiard.Simulation, name, None)
        assert attribute is not None, f"Simulation::{name}() has no Python counterpart"
        if name in COMPUTED:
            assert not isinstance(attribute, property), f"{name} computes: a method, as in C++"
        else:
            assert isinstance(attribute, property), f"{name} is held by the simulation: a property in Python"
