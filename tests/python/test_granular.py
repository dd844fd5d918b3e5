"""Granular gases through the Python module: the granular model's calls (set_contact_duration,
set_elastic_impact_speed, their properties), the stop reason, and the issue that made them: an
inelastic bed under gravity that used to stall and corrupt its state now runs to its end. The
physics is tested by the C++ suite tests/engine/test_granular.cpp."""

import math

import pytest

import billiard

pytestmark = pytest.mark.skipif(not hasattr(billiard, "Simulation"),
                                reason="this build has no billiard.Simulation (the engine library is not built)")


def falling_bed(restitution, table=False):
    """200 discs of radius 1 under gravity (0, -1), in the box (0,0)-(40,40) or a table of radius 22."""
    sim = billiard.Simulation()
    if table:
        sim.set_circular_table(22)
    else:
        sim.add_box((0, 0), (40, 40))
    sim.set_gravity((0, -1))
    sim.add_random_discs(200, 1.0, seed=7)
    sim.set_restitution(restitution)
    return sim


@pytest.mark.parametrize("table", [False, True])
@pytest.mark.parametrize("restitution", [0.5, 0.8])
def test_inelastic_bed_runs_to_the_end_never_gaining_energy(restitution, table):
    sim = falling_bed(restitution, table)
    energy = sim.kinetic_energy() + sim.potential_energy()
    while sim.time < 50 - 1e-9:
        result = sim.advance(time=5)
        assert not result["stuck"], result["stuck_reason"]
        assert result["stuck_reason"] == ""
        now = sim.kinetic_energy() + sim.potential_energy()
        assert now <= energy + 1e-12 * abs(energy), f"the energy rose at time {sim.time}"
        energy = now
    assert sim.time == pytest.approx(50)
    assert sim.validate() == ""


def test_model_values_are_chosen_at_the_first_advance_and_can_be_set():
    sim = falling_bed(0.8)
    assert sim.contact_duration == 0 and sim.elastic_impact_speed == 0  # not chosen yet
    sim.advance(events=10)
    # Under gravity |g| = 1, mean radius 1: at least 0.01 sqrt(a / g); sqrt(2 g 0.05 a).
    assert sim.contact_duration >= 0.01
    assert sim.elastic_impact_speed == pytest.approx(math.sqrt(2 * 0.05))
    sim.set_contact_duration(0.5)
    sim.set_elastic_impact_speed(0)
    assert sim.contact_duration == 0.5 and sim.elastic_impact_speed == 0
    sim.set_elastic_impact_speed(None)  # automatic again
    assert sim.elastic_impact_speed == pytest.approx(math.sqrt(2 * 0.05))


@pytest.mark.parametrize("call,argument", [("set_contact_duration", "duration"),
                                           ("set_elastic_impact_speed", "speed")])
@pytest.mark.parametrize("bad", [-1.0, math.nan, math.inf])
def test_bad_model_values_are_refused_naming_the_argument(call, argument, bad):
    sim = falling_bed(0.8)
    with pytest.raises(ValueError, match=argument):
        getattr(sim, call)(bad)
    sim.advance(events=100)
    assert sim.validate() == ""


def test_a_stuck_run_says_why_and_stays_valid():
    sim = falling_bed(0.8)
    sim.set_contact_duration(0)
    sim.set_elastic_impact_speed(0)
    result = sim.advance(time=50)
    assert result["stuck"]
    assert "stuck at time" in result["stuck_reason"]
    assert sim.validate() == ""
    sim.advance(time=50)
    assert sim.validate() == ""
