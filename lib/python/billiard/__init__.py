"""billiard: event-driven simulation of hard discs.

The course functions (the student's tasks/ or the reference solutions/, whichever the build
chose; see ``billiard.course_implementation``) work on numpy arrays of shape (n, 2):

    >>> import billiard
    >>> rng = billiard.Rng(1)
    >>> coordinates = billiard.init_billiard(10.0, 1.0, 10, rng)
    >>> velocities = billiard.init_velocities(coordinates, rng)
    >>> billiard.propagate(10.0, 1.0, coordinates, velocities)   # in place, like C++
    Collision(time=..., circle=..., other=...)

The extension stages (tasks 7-9) this build has are in ``billiard.stages`` (its ``available``
lists them): ``propagate_gravity``, ``mean_energy``, ``propagate_walls``, ``propagate_sectors``.

The event-driven engine: describe a system, then run it. A container (made by
``billiard.circular_table``, ``periodic_box``, ``box``, ``polygon``, ``stadium``,
``sinai_billiard``, ``mushroom`` or ``union_of_circles``, then given walls and obstacles) and
optional ``billiard.Settings`` make a ``billiard.Simulation``:

    >>> sim = billiard.Simulation(billiard.box((0, 0), (10, 10)), billiard.Settings(gravity=(0, -1)))
    >>> sim.add_random_discs(20, 0.3, seed=1)
    0
    >>> sim.advance(events=1000)["collisions"]
    1000

Time stepping of point particles in level-set domains, for comparison with the exact engine:
``billiard.stepping`` (``billiard.Stepper`` is its integrator).

Ensembles: ``billiard.sweep(run, grid, seeds=...)`` runs a function of parameters and a seed
over a parameter grid and seeds in parallel worker processes (Dask; a local cluster by default,
or a Dask cluster's address) and returns one record per run.

Trajectories: ``billiard.write_trajectory(sim, path, ...)`` (or ``billiard.TrajectoryWriter``) writes
frames to a GSD file, the format HOOMD-blue writes and OVITO reads, with the periodic image counts;
``billiard.read_trajectory(path)`` reads them back as arrays, unwrapped positions included.

Drawing and animation: ``billiard.plotting`` (matplotlib). Errors in arguments arrive as
ValueError with the library's message, naming the argument; an argument of the wrong Python type
(a string for a number, a list where a numpy array is required, an int beyond the C++ parameter's
range such as n >= 2**31) is a TypeError from pybind11 listing the signature. Adding discs after
the first advance() is a RuntimeError. A task not written yet raises NotImplementedError.
"""

import math
import numbers

from ._billiard import (  # noqa: F401  (re-exported)
    WALL,
    Collision,
    Rng,
    correct_energy_drift,
    course_implementation,
    init_billiard,
    init_velocities,
    kinetic_energy,
    movie,
    propagate,
    visualize_table,
)
from . import _billiard
__version__ = _billiard.__version__  # the project's version (CMakeLists.txt)
from ._billiard import stages  # noqa: F401  (the extension stages this build has: stages.available)
from ._sweep import local_client, sweep  # noqa: F401  (re-exported; import Dask only when called)
from .trajectory import TrajectoryWriter, read_trajectory, write_trajectory  # noqa: F401  (gsd imported when used)

if hasattr(_billiard, "Simulation"):
    from ._billiard import (  # noqa: F401  (re-exported)
        DISC_DISC,
        DISC_WALL,
        SLEEP,
        WAKE,
        Container,
        Settings,
        Simulation,
        box,
        circular_table,
        mushroom,
        periodic_box,
        polygon,
        sinai_billiard,
        stadium,
        union_of_circles,
    )

    def _replay_by_event(self):
        """Yields the state (a dict like current_state) just after each logged event, in order.
        The event log must have been enabled before the first advance()."""
        replay = _billiard._Replay(self)
        while not replay.finished:
            yield replay.after_next_event(self)

    def _replay_by_time(self, dt, until=None):
        """Yields the state at times t0, t0 + dt, t0 + 2 dt, ... up to `until` (default: the current
        time), t0 being the initial time: frames at a fixed rate for animations."""
        if not isinstance(dt, numbers.Real) or not (until is None or isinstance(until, numbers.Real)):
            raise TypeError(f"replay_by_time: dt and until must be numbers, got dt={dt!r}, until={until!r}")
        if not dt > 0:
            raise ValueError(f"replay_by_time: dt must be positive, got {dt}")
        if until is not None and not math.isfinite(until):
            raise ValueError(f"replay_by_time: until must be finite, got {until}")
        replay = _billiard._Replay(self)
        start = self.initial_state["time"]
        end = self.time if until is None else until
        # Frames k = 0 .. floor((end - start) / dt), counted with a relative tolerance of 1e-12 so
        # that an end which is a whole number of steps is not lost to rounding.
        frames = int((end - start) / dt * (1 + 1e-12)) + 1 if end >= start else 0
        for k in range(frames):
            yield replay.at(self, start + k * dt)

    Simulation.replay_by_event = _replay_by_event
    Simulation.replay_by_time = _replay_by_time

from . import stepping  # noqa: E402  (after _billiard: it extends the compiled Stepper)

if hasattr(_billiard, "stepping"):
    from .stepping import Stepper  # noqa: F401

__all__ = [
    "DISC_DISC", "DISC_WALL", "SLEEP", "WAKE", "Simulation", "Container", "Settings", "box", "circular_table",
    "mushroom", "periodic_box", "polygon", "sinai_billiard", "stadium", "union_of_circles", "WALL",
    "Collision", "Rng", "correct_energy_drift", "course_implementation", "init_billiard", "init_velocities",
    "kinetic_energy", "local_client", "movie", "propagate", "stages", "stepping", "Stepper", "sweep",
    "visualize_table", "TrajectoryWriter", "read_trajectory", "write_trajectory",
]
