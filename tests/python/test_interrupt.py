"""Ctrl-C during Simulation.advance: the engine holds Python's lock while it runs, so the binding
lets Python's signal handlers run every so many events. SIGINT then stops a long run within a
fraction of a second at an event boundary, raising KeyboardInterrupt, with the state valid and
advance able to go on; a handler that does not raise lets the run go on to its end.

Signals go to a child process (a fresh Python running CHILD), so that the test's own process
is never interrupted.
"""
import json
import math
import os
import signal
import subprocess
import sys
import time

import pytest

import billiard

# Builds a big gas, then runs two advances, each announced by a line on stdout once it is about
# to start: one that a SIGUSR1 handler (which does not raise) must not stop, and one that would
# run for days unless SIGINT stops it. Prints a JSON report at the end.
CHILD = r"""
import json, signal, sys, time
import billiard

# (Python keeps SIGINT ignored when its parent ignored it, as a shell does for background jobs.)
signal.signal(signal.SIGINT, signal.default_int_handler)
handled = []
signal.signal(signal.SIGUSR1, lambda number, frame: handled.append(time.monotonic()))

sim = billiard.Simulation(billiard.periodic_box(1000.0, 1000.0))
sim.add_random_discs(50_000, 1.0, seed=1)
sim.advance(events=1000)
report = {}

def collisions():
    totals = sim.totals
    return totals["disc_collisions"] + totals["wall_collisions"]

print("advancing through SIGUSR1", flush=True)
report["full_run"] = sim.advance(events=5_000_000)["collisions"]
report["full_run_returned_at"] = time.monotonic()
report["usr1_handled_at"] = handled

before = collisions()
print("advancing until SIGINT", flush=True)
try:
    sim.advance(events=2**62)
    report["interrupted"] = False
except KeyboardInterrupt:
    report["interrupted"] = True
    report["caught_at"] = time.monotonic()
report["collisions_before_interrupt"] = collisions() - before
report["problem"] = sim.validate()
report["next_run"] = sim.advance(events=1000)["collisions"]
report["problem_after_next_run"] = sim.validate()
print(json.dumps(report), flush=True)
"""


def expect_line(child, line):
    got = child.stdout.readline()
    if got != line + "\n":
        child.kill()
        _, err = child.communicate()
        pytest.fail(f"the child printed {got!r}, not {line!r}; its stderr:\n{err}")


def send_while_advancing(child, number):
    """Sends signal `number` once the child has surely entered advance; returns when it was sent."""
    time.sleep(0.3)
    assert child.poll() is None, "the child ended before the signal"
    sent_at = time.monotonic()
    child.send_signal(number)
    return sent_at


def test_ctrl_c_stops_a_long_advance_at_an_event_boundary():
    child = subprocess.Popen([sys.executable, "-c", CHILD], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                             text=True, env=os.environ.copy())
    try:
        expect_line(child, "advancing through SIGUSR1")
        usr1_sent_at = send_while_advancing(child, signal.SIGUSR1)
        expect_line(child, "advancing until SIGINT")
        sigint_sent_at = send_while_advancing(child, signal.SIGINT)
        try:
            out, err = child.communicate(timeout=20)
        except subprocess.TimeoutExpired:
            child.kill()
            child.communicate()
            pytest.fail("advance was still running 20 s after SIGINT")
    finally:
        if child.poll() is None:
            child.kill()
            child.communicate()
    assert child.returncode == 0, err
    report = json.loads(out)
    # SIGUSR1's handler ran during the run (not after it), which went on to its end.
    assert len(report["usr1_handled_at"]) == 1
    assert usr1_sent_at <= report["usr1_handled_at"][0] < report["full_run_returned_at"]
    assert report["usr1_handled_at"][0] - usr1_sent_at < 1.0
    assert report["full_run"] == 5_000_000
    # SIGINT stopped the long run within a second, in the middle, as KeyboardInterrupt.
    assert report["interrupted"], "advance ran to its end"
    assert report["caught_at"] - sigint_sent_at < 1.0
    assert report["collisions_before_interrupt"] > 0
    # The state is valid, and the run goes on.
    assert report["problem"] is None
    assert report["next_run"] == 1000
    assert report["problem_after_next_run"] is None


def test_advance_refuses_a_time_that_is_not_a_number():
    sim = billiard.Simulation(billiard.periodic_box(20.0, 20.0))
    sim.add_random_discs(10, 1.0, seed=1)
    with pytest.raises(ValueError, match=r"^advance: time must be a number >= 0, got nan \(not a number\)$"):
        sim.advance(time=math.nan)
    with pytest.raises(ValueError, match=r"^advance: time must be a number >= 0, got -1\.0$"):
        sim.advance(time=-1.0)
    assert sim.time == 0.0
    assert sim.advance(time=1.0)["elapsed"] == 1.0
