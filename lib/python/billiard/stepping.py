"""billiard.stepping: time-stepped point particles in level-set domains, the method the
event-driven Simulation is contrasted with (lib/PHYSICS.md, "Time stepping in level-set domains").

    >>> import numpy as np
    >>> from billiard.stepping import Stepper, circle, level_set
    >>> stepper = Stepper(circle((0, 0), 1.0), [[0.2, 0.0]], [[1.0, 0.5]], dt=1e-3, gravity=(0, -1))
    >>> stepper.advance_to(10.0)
    >>> drift = stepper.energy() - stepper.initial_energy()    # about 7e-4: the time-stepping error

A domain is a level set or a list of them (their union): ``circle``, ``ellipse``, ``box``, or
``level_set(omega, grad)`` with two vectorised numpy functions of points (n, 2).
"""

import math
import numbers

from . import _billiard

if hasattr(_billiard, "stepping"):
    from ._billiard.stepping import LevelSet, Stepper, box, circle, ellipse, level_set  # noqa: F401

    def _check_until(name, until):
        if until is not None and not (isinstance(until, numbers.Real) and math.isfinite(until)):
            raise ValueError(f"{name}: until must be a finite number, got {until!r}")

    def _replay_by_time(self, dt, until=None):
        """Yields the state (a dict like current_state) at times 0, dt, 2 dt, ... up to `until`
        (default: the current time), re-running the steps from the initial state: each is the state
        after the last step at or before that time (its "time" says which)."""
        if not isinstance(dt, numbers.Real) or not dt > 0 or not math.isfinite(dt):
            raise ValueError(f"replay_by_time: dt must be a positive number, got {dt!r}")
        _check_until("replay_by_time", until)
        end = self.time if until is None else until
        frames = int(end / dt * (1 + 1e-12)) + 1 if end >= 0 else 0
        replay = self.restarted()
        for k in range(frames):
            replay.advance_to(k * dt)
            yield replay.current_state

    def _replay_by_steps(self, every=1, until=None):
        """Yields the state after 0, every, 2 every, ... steps, up to step `until` (default: the
        steps taken so far), re-running the steps from the initial state."""
        if not isinstance(every, numbers.Integral) or every < 1:
            raise ValueError(f"replay_by_steps: every must be an integer >= 1, got {every!r}")
        if until is not None and (not isinstance(until, numbers.Integral) or until < 0):
            raise ValueError(f"replay_by_steps: until must be an integer >= 0, got {until!r}")
        end = self.steps if until is None else until
        replay = self.restarted()
        yield replay.current_state
        for _ in range(end // every):
            replay.step(every)
            yield replay.current_state

    def _replay_at(self, times):
        """Yields the state at each of the given times (increasing, >= 0), re-running the steps
        from the initial state: each is the state after the last step at or before that time."""
        times = list(times)
        if not all(isinstance(t, numbers.Real) and math.isfinite(t) and t >= 0 for t in times):
            raise ValueError(f"replay_at: times must be finite numbers >= 0, got {times!r:.80}")
        if any(b < a for a, b in zip(times, times[1:])):
            raise ValueError("replay_at: times must be in increasing order")
        replay = self.restarted()
        for t in times:
            replay.advance_to(t)
            yield replay.current_state

    Stepper.replay_by_time = _replay_by_time
    Stepper.replay_by_steps = _replay_by_steps
    Stepper.replay_at = _replay_at

__all__ = ["LevelSet", "Stepper", "box", "circle", "ellipse", "level_set"]
