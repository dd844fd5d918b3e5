"""billiard: event-driven simulation of hard discs.

The course functions (the student's tasks/ or the reference solutions/, whichever the build
chose; see ``billiard.course_implementation``) work on numpy arrays of shape (n, 2):

    >>> import billiard
    >>> rng = billiard.Rng(1)
    >>> coordinates = billiard.init_billiard(10.0, 1.0, 10, rng)
    >>> velocities = billiard.init_velocities(coordinates, rng)
    >>> billiard.propagate(10.0, 1.0, coordinates, velocities)   # in place, like C++
    Collision(time=..., circle=..., other=...)

Drawing and animation: ``billiard.plotting`` (matplotlib). Errors in arguments arrive as
ValueError with the library's message; a task not written yet raises NotImplementedError.
"""

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

__all__ = [
    "WALL", "Collision", "Rng", "correct_energy_drift", "course_implementation", "init_billiard",
    "init_velocities", "kinetic_energy", "movie", "propagate", "visualize_table",
]
