"""Two ways of losing energy, for the energy-drift notebook (numpy only, no compiled code).

Exact event-driven dynamics of hard discs conserves the kinetic energy: every collision is
elastic and nothing happens between collisions. A computer still loses it slowly through
rounding, and a time-stepped integrator loses it much faster. This module holds the two
demonstration integrators, for N equal discs of radius ``radius`` on the circular table of
radius ``table_radius`` centred at 0 (the course's setting):

- ``event_driven_float32``: the algorithm of the course's ``propagate`` (find the earliest
  collision, fly everyone there, collide), with every quantity in single precision
  (np.float32, unit roundoff 6e-8 instead of 1.1e-16). Its <v^2> random-walks away from the
  start by about 1e-7 per collision.
- ``time_stepped``: a fixed time step dt; positions += v dt; a disc found beyond the wall
  and moving outwards is reflected; two discs found overlapping and approaching exchange
  the normal components of their velocities. All contacts of one step are resolved at once
  from the velocities at the start of the step, since a time-stepped code does not know
  their order; a disc meeting two partners (or a partner and the wall) in the same step then
  receives two impulses computed for velocities it no longer has, and the energy changes.

Both can apply the correction of course task 6 (rescale all velocities by one factor so that
<v^2> returns to its target) every ``correct_every`` collisions or steps, and both return a
``History``: the number of collisions, the time and <v^2> after each event or step.

Units are the course's: lengths in the unit of R and a, speeds in length per time unit, <v^2>
in speed units squared. All <v^2> values in a History are computed in double
precision from the state, so they measure the state's energy, not the rounding of the mean.
"""

from typing import NamedTuple

import numpy as np

__all__ = ["History", "mean_square", "rescale", "event_driven_float32", "time_stepped"]


class History(NamedTuple):
    """What an integrator returns: one entry per record (the start, then each event or step).

    events: cumulative number of collisions (disc-disc and disc-wall) at each record.
    time: simulated time at each record.
    mean_square: <v^2> = (1/N) sum |v_i|^2 at each record, computed in double precision.
    positions, velocities: the final state (n, 2), in the integrator's precision.
    """

    events: np.ndarray
    time: np.ndarray
    mean_square: np.ndarray
    positions: np.ndarray
    velocities: np.ndarray


def mean_square(velocities):
    """<v^2> = (1/N) sum |v_i|^2 of an (N, 2) array, computed in double precision (0 for N = 0)."""
    velocities = np.asarray(velocities, dtype=np.float64)
    return float(np.sum(velocities * velocities) / len(velocities)) if len(velocities) else 0.0


def rescale(velocities, target_mean_square):
    """The correction of task 6 in numpy, in place and in the array's own precision.

    Multiplies every velocity by sqrt(target / <v^2>), so that <v^2> becomes the target and
    every direction is kept. For a float32 array every step (the sum, the square root, the
    products) is done in float32, so the result is the target only to single precision
    (relative error of a few 1e-7). Zero velocities are left alone.
    """
    dtype = velocities.dtype.type
    now = np.sum(velocities * velocities, dtype=dtype) / dtype(len(velocities))
    if now > 0:
        velocities *= np.sqrt(dtype(target_mean_square) / now)


def _checked_state(table_radius, radius, positions, velocities, dtype):
    positions = np.array(positions, dtype=dtype, copy=True)
    velocities = np.array(velocities, dtype=dtype, copy=True)
    if positions.ndim != 2 or positions.shape[1] != 2 or velocities.shape != positions.shape:
        raise ValueError(f"positions and velocities must be (n, 2) arrays of one shape, got {positions.shape} "
                         f"and {velocities.shape}")
    if not (table_radius > 0 and radius > 0 and radius < table_radius):
        raise ValueError(f"need 0 < radius < table_radius, got radius={radius}, table_radius={table_radius}")
    return positions, velocities


def _history(events, time, values, positions, velocities):
    return History(np.asarray(events, dtype=np.int64), np.asarray(time, dtype=np.float64),
                   np.asarray(values, dtype=np.float64), positions, velocities)


def event_driven_float32(table_radius, radius, positions, velocities, events, correct_every=None,
                         correct=rescale, target=None):
    """Runs ``events`` collisions of the exact event-driven algorithm in single precision.

    The algorithm is that of the course's propagate: compute for every disc its time to the
    wall and for every pair its time to contact, advance all discs by the smallest time in
    straight lines, and apply the elastic collision rule to the colliding disc(s):
    disc-wall v' = v - 2 (v.n) n with n = r/|r|; disc-disc: exchange of the velocity
    components along the line of centres n. Every array and scalar is np.float32.

    table_radius, radius: R and a (the discs are equal, mass 1).
    positions, velocities: (n, 2) arrays of the start (not modified; copied to float32).
    events: number of collisions to run.
    correct_every: when set, apply ``correct(velocities, target)`` after every
        correct_every collisions (the correction of task 6; default: ``rescale``, in float32).
    target: the <v^2> the correction restores; default: that of the start.

    Returns a History with events + 1 records. Time of impact formulas: the stable roots of
    lib/PHYSICS.md (wall: |r + v t| = R - a; pair: |dr + dv t| = 2a).
    """
    f32 = np.float32
    r, v = _checked_state(table_radius, radius, positions, velocities, f32)
    n = len(r)
    if target is None:
        target = mean_square(v)
    reach = f32(table_radius - radius)  # a centre touches the wall at |r| = R - a
    contact2 = f32(2 * radius) ** 2  # squared centre distance of touching discs
    first, second = np.triu_indices(n, k=1)
    history_events, history_time, history_ms = [0], [0.0], [mean_square(v)]
    time = 0.0
    with np.errstate(divide="ignore", invalid="ignore"):
        for event in range(1, events + 1):
            # Wall: A t^2 + 2 B t + C = 0, A = v.v, B = r.v, C = r.r - (R-a)^2 <= 0.
            a_ = np.einsum("ij,ij->i", v, v)
            b_ = np.einsum("ij,ij->i", r, v)
            c_ = np.einsum("ij,ij->i", r, r) - reach * reach
            root = np.sqrt(np.maximum(b_ * b_ - a_ * c_, f32(0)))
            t_wall = np.where(b_ <= 0, (root - b_) / a_, -c_ / (b_ + root))
            t_wall = np.where(a_ > 0, np.maximum(t_wall, f32(0)), np.inf).astype(f32)
            # Pairs: approaching (b < 0) and real root: t = c / (-b + sqrt(b^2 - dv.dv c)).
            dr = r[first] - r[second]
            dv = v[first] - v[second]
            b = np.einsum("ij,ij->i", dr, dv)
            c = np.einsum("ij,ij->i", dr, dr) - contact2
            disc = b * b - np.einsum("ij,ij->i", dv, dv) * c
            t_pair = np.where((b < 0) & (disc >= 0), np.maximum(c / (np.sqrt(disc) - b), f32(0)), np.inf).astype(f32)

            k_wall = int(np.argmin(t_wall))
            k_pair = int(np.argmin(t_pair)) if len(t_pair) else -1
            hits_wall = k_pair < 0 or t_wall[k_wall] <= t_pair[k_pair]
            t = t_wall[k_wall] if hits_wall else t_pair[k_pair]
            if not np.isfinite(t):
                raise ValueError("no collision ahead: every disc is at rest")
            r += v * t
            time += float(t)
            if hits_wall:
                normal = r[k_wall] / np.sqrt(np.dot(r[k_wall], r[k_wall]))
                v[k_wall] -= f32(2) * np.dot(v[k_wall], normal) * normal
            else:
                i, j = first[k_pair], second[k_pair]
                normal = r[j] - r[i]
                normal /= np.sqrt(np.dot(normal, normal))
                exchange = np.dot(v[i] - v[j], normal) * normal
                v[i] -= exchange
                v[j] += exchange
            if correct_every and event % correct_every == 0:
                correct(v, target)
            history_events.append(event)
            history_time.append(time)
            history_ms.append(mean_square(v))
    return _history(history_events, history_time, history_ms, r, v)


def time_stepped(table_radius, radius, positions, velocities, dt, steps, correct_every=None, correct=rescale,
                 target=None, dtype=np.float64):
    """Runs ``steps`` fixed time steps of a simple hard-disc integrator (default in double).

    Each step: every centre moves by v dt; a disc found beyond the wall (|r| > R - a) and
    moving outwards is reflected, v' = v - 2 (v.n) n; then every pair found overlapping
    (|r_i - r_j| < 2a) and approaching exchanges the normal components of the velocities,
    all pairs at once from the velocities before the exchange (their order is unknown to a
    time-stepped code). Single collisions conserve energy exactly; a disc in two contacts
    in one step does not, so <v^2> wanders by a finite amount at each such step, and more
    so the larger dt.

    table_radius, radius: R and a (equal discs, mass 1).
    positions, velocities: (n, 2) arrays of the start (not modified; copied to dtype).
    dt: the time step (e.g. 0.05 a / sqrt(<v^2>): a disc moves 5% of its radius per step).
    steps: number of steps.
    correct_every: when set, apply ``correct(velocities, target)`` after every correct_every
        steps, e.g. ``billiard.correct_energy_drift`` (float64 arrays) or ``rescale``.
    target: the <v^2> the correction restores; default: that of the start.

    Returns a History with steps + 1 records (events counts the collisions resolved so far).
    """
    r, v = _checked_state(table_radius, radius, positions, velocities, dtype)
    n = len(r)
    if target is None:
        target = mean_square(v)
    dt = dtype(dt)
    reach = dtype(table_radius - radius)
    contact2 = dtype(2 * radius) ** 2
    first, second = np.triu_indices(n, k=1)
    collisions = 0
    history_events, history_time, history_ms = [0], [0.0], [mean_square(v)]
    for step in range(1, steps + 1):
        r += v * dt
        # The wall: found outside and still moving out (a disc already turned back is left alone).
        distance = np.sqrt(np.einsum("ij,ij->i", r, r))
        normal_speed = np.einsum("ij,ij->i", r, v) / np.maximum(distance, dtype(1e-300))
        outside = (distance > reach) & (normal_speed > 0)
        if outside.any():
            normals = r[outside] / distance[outside, None]
            v[outside] -= 2 * normal_speed[outside, None] * normals
            collisions += int(outside.sum())
        # Pairs: overlapping and approaching, all resolved from the same velocities.
        dr = r[second] - r[first]
        d2 = np.einsum("ij,ij->i", dr, dr)
        close = d2 < contact2
        if close.any():
            i, j, dr_close = first[close], second[close], dr[close]
            normals = dr_close / np.sqrt(d2[close])[:, None]  # unit vector from i to j
            approach = np.einsum("ij,ij->i", v[i] - v[j], normals)  # > 0: closing in
            hit = approach > 0
            if hit.any():
                exchange = approach[hit, None] * normals[hit]
                np.add.at(v, i[hit], -exchange)
                np.add.at(v, j[hit], exchange)
                collisions += int(hit.sum())
        if correct_every and step % correct_every == 0:
            correct(v, target)
        history_events.append(collisions)
        history_time.append(step * float(dt))
        history_ms.append(mean_square(v))
    return _history(history_events, history_time, history_ms, r, v)
