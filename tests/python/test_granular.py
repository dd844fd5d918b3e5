"""Granular gases through the Python module: the granular model's calls (set_contact_duration,
set_elastic_impact_speed, set_sleep_speed, their properties), sleeping discs in the event log,
the stop reason, and an inelastic bed under gravity running to its end and falling asleep. The
physics is tested by the C++ suite tests/engine/test_granular.cpp."""

import math

import pytest

import billiard

pytestmark = pytest.mark.skipif(not hasattr(billiard, "Simulation"),
                                reason="this build has no billiard.Simulation (the engine library is not built)")


def falling_bed(restitution, table=False):
    """200 discs of radius 1 under gravity (0, -1), in the box (0,0)-(40,40) or a table of radius 22."""
    container = billiard.circular_table(22) if table else billiard.box((0, 0), (40, 40))
    sim = billiard.Simulation(container, billiard.Settings(gravity=(0, -1)))
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
    assert sim.validate() is None


def test_model_values_are_chosen_at_the_first_advance_and_can_be_set():
    sim = falling_bed(0.8)
    assert sim.contact_duration == 0 and sim.elastic_impact_speed == 0  # not chosen yet
    sim.advance(events=10)
    # Under gravity |g| = 1, mean radius 1: at least 0.01 sqrt(a / g); discs sleep below
    # sqrt(2 g 0.05 a), and then slow impacts are not made elastic.
    assert sim.contact_duration >= 0.01
    assert sim.sleep_speed == pytest.approx(math.sqrt(2 * 0.05))
    assert sim.elastic_impact_speed == 0
    sim.set_contact_duration(0.5)
    sim.set_elastic_impact_speed(0.2)
    assert sim.contact_duration == 0.5 and sim.elastic_impact_speed == 0.2
    sim.set_sleep_speed(0)  # no sleeping: the slow-impact rule takes over again
    sim.set_elastic_impact_speed(None)  # automatic again
    assert sim.sleep_speed == 0
    assert sim.elastic_impact_speed == pytest.approx(math.sqrt(2 * 0.05))


@pytest.mark.parametrize("call,argument", [("set_contact_duration", "duration"),
                                           ("set_elastic_impact_speed", "speed"),
                                           ("set_sleep_speed", "speed")])
@pytest.mark.parametrize("bad", [-1.0, math.nan, math.inf])
def test_bad_model_values_are_refused_naming_the_argument(call, argument, bad):
    sim = falling_bed(0.8)
    with pytest.raises(ValueError, match=argument):
        getattr(sim, call)(bad)
    sim.advance(events=100)
    assert sim.validate() is None


def test_a_stuck_run_says_why_and_stays_valid():
    sim = falling_bed(0.8)
    sim.set_contact_duration(0)
    sim.set_elastic_impact_speed(0)
    sim.set_sleep_speed(0)
    result = sim.advance(time=50)
    assert result["stuck"]
    assert "stuck at time" in result["stuck_reason"]
    assert sim.validate() is None
    sim.advance(time=50)
    assert sim.validate() is None


def test_a_bed_in_a_box_exactly_20_discs_wide_falls_asleep():
    # The box 40 wide holds exactly 20 discs per row: without sleeping, the bottom row's sideways
    # rattling grows for ever (over 2,000 collisions per disc per unit time by t = 200). With it,
    # every disc is asleep by t = 100 and the bed costs no events.
    sim = falling_bed(0.5)
    sim.advance(time=100)
    assert sim.sleeping_discs == list(range(200))
    assert (sim.current_state["velocity"] == 0).all()
    result = sim.advance(time=10)
    assert result["collisions"] == 0 and sim.time == pytest.approx(110)
    assert sim.validate() is None


def test_sleeping_is_in_the_event_log_and_the_replay_keeps_sleepers_still():
    sim = falling_bed(0.5, table=True)
    sim.set_log_events(True)
    sim.advance(time=100)
    assert len(sim.sleeping_discs) == 200
    log = sim.event_log
    assert billiard.SLEEP in set(log["kind"].tolist())
    assert set(log["other"][log["kind"] == billiard.SLEEP].tolist()) == {-1}  # no other disc
    # The replay's state at the end is the run's: sleeping discs stay where they fell asleep.
    *_, last = sim.replay_by_time(50)
    assert last["time"] == pytest.approx(100)
    assert last["position"] == pytest.approx(sim.current_state["position"], abs=1e-12)
    sim.set_sleep_speed(0)  # wakes them all
    assert sim.sleeping_discs == []
    assert billiard.WAKE in set(sim.event_log["kind"].tolist())
    assert sim.validate() is None
