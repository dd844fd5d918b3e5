"""Trajectories in GSD, the file format HOOMD-blue writes and OVITO reads (Debian's python3-gsd).

Write frames of a ``billiard.Simulation`` as it runs, then read them back as numpy arrays::

    billiard.write_trajectory(sim, "gas.gsd", every_time=0.5, frames=100)   # or times=[...], every_events=k
    run = billiard.read_trajectory("gas.gsd")
    displacement = run["unwrapped"] - run["unwrapped"][0]                   # (frames, n, 2)
    msd = (displacement ** 2).sum(axis=2).mean(axis=1)

or frame by frame, in a loop of your own::

    with billiard.TrajectoryWriter("gas.gsd", sim) as writer:
        for _ in range(100):
            writer.write()
            sim.advance(events=1000)

Each frame is a HOOMD frame of dimension 2 (schema ``hoomd`` 1.x):

- ``configuration/box``: [Lx, Ly, 0, 0, 0, 0]. For a periodic box, its period; for any other
  container, a box that encloses it (the box around the centres' reach, ``Container.bounds``,
  widened by the largest radius on every side), which is not periodic: its images stay 0.
- ``configuration/step``: the collisions (disc-disc and disc-wall) since time 0.
- ``particles/position``: (x, y, 0) relative to the box's centre, as HOOMD boxes are centred on the
  origin: a periodic box's [0, Lx) x [0, Ly) becomes [-Lx/2, Lx/2) x [-Ly/2, Ly/2).
- ``particles/image``: (ix, iy, 0), the periodic image counts (``Simulation.images``), so that
  position + image * (Lx, Ly) is the unwrapped position, as in HOOMD.
- ``particles/velocity`` (vx, vy, 0); ``particles/diameter`` 2 radius; ``particles/mass``;
  ``particles/moment_inertia`` (0, 0, I); ``particles/angmom`` (0, 0, 0, 2 I spin), HOOMD's
  angular momentum quaternion P = 2 q (0, L) for the orientation q = (1, 0, 0, 0) (the engine
  keeps the spin, not the angle turned, so every frame has that orientation);
  ``particles/types`` ["disc"], every ``typeid`` 0.
- ``log/billiard/time``: the simulation's time (float64). ``log/billiard/box`` and
  ``log/billiard/box_centre``: the box's sides and its centre in the simulation's coordinates
  (float64), and ``log/billiard/periodic``: 1 for a periodic box.

HOOMD's schema stores positions, velocities and the box in single precision (float32). The image
counts keep the unwrapped positions within that rounding of a coordinate in the box (about
1e-7 of the box) however far the discs go; ``read_trajectory`` multiplies the images by the exact
sides from ``log/billiard/box``, since a side such as 0.1 is not a float32 number.

A trajectory is written to a hidden file next to ``path`` and renamed to ``path`` when the writer
closes: a file at ``path`` is always a complete trajectory, and a failed or interrupted write
removes its hidden file, leaving whatever was at ``path`` before.
"""

import numbers
import os
import pathlib
import secrets

import numpy as np

from . import _billiard

__all__ = ["TrajectoryWriter", "write_trajectory", "read_trajectory"]

_INT32 = np.iinfo(np.int32)


def _gsd_hoomd():
    """gsd.hoomd, imported when first needed: the rest of the package works without python3-gsd."""
    try:
        import gsd
        import gsd.hoomd
    except ImportError as error:
        raise ImportError(
            "billiard trajectories need the gsd module: install Debian's python3-gsd (apt-get install python3-gsd)"
        ) from error
    return gsd, gsd.hoomd


def _open_mode(gsd, mode):
    """gsd 3 names the modes 'r' and 'x'; gsd 2 (Debian 12 has 2.7) 'rb' and 'xb'. The version is
    gsd.version.version from gsd 3 on (gsd 3.4, Debian 13's, has no gsd.__version__), and
    gsd.version.__version__ in gsd 2."""
    import gsd.version
    found = getattr(gsd.version, "version", None) or getattr(gsd.version, "__version__")
    return mode if int(str(found).split(".")[0]) >= 3 else mode + "b"


def _new_frame(hoomd):
    """An empty frame: gsd.hoomd.Frame from gsd 2.8 on, Snapshot before."""
    return hoomd.Frame() if hasattr(hoomd, "Frame") else hoomd.Snapshot()


def _check_path(path, name):
    if not isinstance(path, (str, os.PathLike)):
        raise TypeError(f"{name} must be a file name (str or os.PathLike), got {path!r}")
    path = pathlib.Path(path)
    if path.name == "" or path.is_dir():
        raise ValueError(f"{name} must name a file, got {str(path)!r}")
    return path


def _check_simulation(simulation, name):
    simulation_class = getattr(_billiard, "Simulation", None)
    if simulation_class is None or not isinstance(simulation, simulation_class):
        raise TypeError(f"{name} must be a billiard.Simulation, got {type(simulation).__name__}")


class TrajectoryWriter:
    """Writes frames of a billiard.Simulation to a GSD file (see the module's help for the fields).

    ``TrajectoryWriter(path, simulation)`` opens the file (a hidden name next to `path` until
    closed); ``write()`` appends a frame of the simulation as it is now; ``close()`` finishes the
    file and renames it to `path` (replacing a file there). Used as a context manager it closes
    at the end of the block, or, if the block raises, discards the frames (``discard()``) and
    leaves `path` as it was. The parent folder of `path` must exist.
    """

    def __init__(self, path, simulation):
        self.path = _check_path(path, "path")
        _check_simulation(simulation, "simulation")
        if not self.path.parent.is_dir():
            raise ValueError(f"path: the folder {str(self.path.parent)!r} does not exist")
        self.simulation = simulation
        self.frames = 0
        gsd, hoomd = _gsd_hoomd()
        self._hoomd = hoomd
        self._partial = self.path.with_name(f".{self.path.name}.{os.getpid()}-{secrets.token_hex(4)}.partial")
        self._file = hoomd.open(str(self._partial), _open_mode(gsd, "x"))
        self._n = None  # discs in every frame, from the first
        self.periodic = bool(simulation.container.periodic)
        self.box = self.box_centre = None  # (chosen at the first frame, when the discs are known)

    def _choose_box(self, radii):
        container = self.simulation.container
        if self.periodic:
            self.box = np.array(container.period, dtype=np.float64)
            self.box_centre = self.box / 2
        else:
            # A box enclosing the discs: the centres' reach widened by the largest radius.
            lower, upper = (np.array(corner, dtype=np.float64) for corner in container.bounds)
            margin = float(radii.max()) if len(radii) else 0.0
            self.box = (upper - lower) + 2 * margin
            self.box_centre = (lower + upper) / 2

    def __enter__(self):
        return self

    def __exit__(self, kind, error, trace):
        if kind is None:
            self.close()
        else:
            self.discard()
        return False

    @property
    def closed(self):
        return self._file is None

    def write(self):
        """Appends a frame of the simulation now; returns the number of frames written."""
        if self.closed:
            raise ValueError(f"write: the writer of {str(self.path)!r} is closed")
        sim = self.simulation
        state = sim.current_state
        images = np.asarray(sim.images, dtype=np.int64).copy()
        n = len(state["radius"])
        if self._n is None:
            self._n = n
            self._choose_box(state["radius"])
        elif n != self._n:
            raise ValueError(f"simulation: it has {n} discs now, the trajectory's frames {self._n}")
        position = np.zeros((n, 3), dtype=np.float32)
        for axis in range(2):
            position[:, axis], images[:, axis] = self._centred(state["position"][:, axis], images[:, axis], axis)
        if n and (images.min() < _INT32.min or images.max() > _INT32.max):
            raise OverflowError("write: an image count is beyond the 32 bits GSD stores "
                                "(a disc crossed the box over 2**31 times)")
        velocity = np.zeros((n, 3))
        velocity[:, :2] = state["velocity"]
        inertia = state["inertia"]
        moment_inertia = np.zeros((n, 3))
        moment_inertia[:, 2] = inertia
        angmom = np.zeros((n, 4))
        angmom[:, 3] = 2 * inertia * state["spin"]
        image = np.zeros((n, 3), dtype=np.int32)
        image[:, :2] = images

        frame = _new_frame(self._hoomd)
        frame.configuration.step = int(sim.totals["disc_collisions"] + sim.totals["wall_collisions"])
        frame.configuration.dimensions = 2
        frame.configuration.box = [self.box[0], self.box[1], 0, 0, 0, 0]
        particles = frame.particles
        particles.N = n
        particles.types = ["disc"]
        particles.typeid = np.zeros(n, dtype=np.uint32)
        particles.position = position
        particles.image = image
        particles.velocity = velocity
        particles.diameter = 2 * state["radius"]
        particles.mass = state["mass"]
        particles.moment_inertia = moment_inertia
        particles.angmom = angmom
        frame.log["billiard/time"] = np.array([state["time"]], dtype=np.float64)
        frame.log["billiard/box"] = self.box.copy()
        frame.log["billiard/box_centre"] = self.box_centre.copy()
        frame.log["billiard/periodic"] = np.array([int(self.periodic)], dtype=np.uint8)
        self._file.append(frame)
        self.frames += 1
        return self.frames

    def _centred(self, wrapped, image, axis):
        """Coordinates along `axis` relative to the box's centre in single precision, and the image
        counts. In a periodic box a coordinate that rounds onto the upper face moves a period down
        (and its image one up), so that every stored position lies in [-L/2, L/2) of the stored box."""
        shifted = wrapped - self.box_centre[axis]
        stored = shifted.astype(np.float32)
        if not self.periodic:
            return stored, image
        side = self.box[axis]
        half = float(np.float32(side)) / 2
        high, low = stored >= half, stored < -half
        stored[high] = (shifted[high] - side).astype(np.float32)
        stored[low] = (shifted[low] + side).astype(np.float32)
        return stored, image + high - low

    def close(self):
        """Finishes the file and renames it to `path`; returns `path`. Closing twice does nothing."""
        if self.closed:
            return self.path
        try:
            self._file.close()
            self._file = None
            os.replace(self._partial, self.path)
        except BaseException:
            self.discard()
            raise
        return self.path

    def discard(self):
        """Drops the frames written: removes the hidden file; `path` stays as it was."""
        if self._file is not None:
            try:
                self._file.close()
            finally:
                self._file = None
        try:
            os.remove(self._partial)
        except FileNotFoundError:
            pass

    def __del__(self):
        # A writer dropped without close() never leaves its hidden file behind.
        if getattr(self, "_file", None) is not None:
            try:
                self.discard()
            except Exception:  # (at interpreter exit the modules it needs may be gone)
                pass

    def __repr__(self):
        state = "closed" if self.closed else "open"
        return f"TrajectoryWriter({str(self.path)!r}, {self.frames} frames, {state})"


def _number(value, name):
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise TypeError(f"{name} must be a number, got {value!r}")
    return float(value)


def _count(value, name, least):
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise TypeError(f"{name} must be a whole number, got {value!r}")
    if value < least:
        raise ValueError(f"{name} must be >= {least}, got {value}")
    return int(value)


def _advance(simulation, **limits):
    result = simulation.advance(**limits)
    if result["stuck"] or result.get("stopped", False):
        why = result["stuck_reason"] if result["stuck"] else "the run was asked to stop"
        raise RuntimeError(f"write_trajectory: the simulation stopped at time {simulation.time}: {why}")


def write_trajectory(simulation, path, *, times=None, every_time=None, every_events=None, frames=None):
    """Advances `simulation` and writes a frame to the GSD file `path` at each of the chosen moments;
    returns `path` (a pathlib.Path).

    Give one of:
      times=[t0, t1, ...]: frames at these times (increasing, none before simulation.time);
      every_time=dt, frames=m: m frames, at simulation.time, + dt, + 2 dt, ...;
      every_events=k, frames=m: m frames, the first now, then one after every k collisions (disc-disc
        and disc-wall; cell crossings do not count).
    The file is renamed to `path` only once every frame is written: if the run fails (it gets stuck,
    or is interrupted), `path` is left as it was and the error is raised. Bad arguments raise
    ValueError (or TypeError for a value of the wrong kind) naming the argument, before any frame.
    """
    _check_simulation(simulation, "simulation")
    path = _check_path(path, "path")
    chosen = [name for name, value in (("times", times), ("every_time", every_time), ("every_events", every_events))
              if value is not None]
    if len(chosen) != 1:
        raise ValueError("write_trajectory: give exactly one of times, every_time and every_events, "
                         f"got {chosen or 'none'}")
    start = simulation.time
    if times is not None:
        if frames is not None:
            raise ValueError("frames: not with times (the times give the frames)")
        try:
            moments = np.asarray(times, dtype=np.float64)
        except (TypeError, ValueError):
            raise TypeError(f"times must be a sequence of numbers, got {times!r}") from None
        if moments.ndim != 1 or len(moments) == 0:
            raise ValueError(f"times must be a non-empty sequence of numbers, got {times!r}")
        if not np.all(np.isfinite(moments)):
            raise ValueError(f"times must be finite, got {moments[~np.isfinite(moments)][0]}")
        if moments[0] < start:
            raise ValueError(f"times must not start before the simulation's time {start}, got {moments[0]}")
        if np.any(np.diff(moments) < 0):
            raise ValueError("times must not decrease")
        steps = [("time", t) for t in moments]
    else:
        if frames is None:
            raise ValueError(f"frames: give the number of frames with {chosen[0]}")
        frames = _count(frames, "frames", 1)
        if every_time is not None:
            dt = _number(every_time, "every_time")
            if not (dt > 0 and np.isfinite(dt)):
                raise ValueError(f"every_time must be positive and finite, got {every_time}")
            steps = [("time", start + k * dt) for k in range(frames)]
        else:
            k = _count(every_events, "every_events", 1)
            steps = [("events", 0)] + [("events", k)] * (frames - 1)

    with TrajectoryWriter(path, simulation) as writer:
        for kind, value in steps:
            if kind == "time":
                # Each frame's duration from the start, so that rounding does not add up.
                if value > simulation.time:
                    _advance(simulation, time=value - simulation.time)
            elif value > 0:
                _advance(simulation, events=value)
            writer.write()
    return path


def read_trajectory(path):
    """Reads a 2D GSD trajectory (written by write_trajectory or TrajectoryWriter, or by HOOMD) into
    a dict of numpy arrays, one row per frame (F frames, n discs, the same n in every frame):

      time (F,): the simulation's time (the HOOMD step where the file has no billiard/time);
      step (F,): the collisions so far (HOOMD's step);
      box (F, 2): the box's sides Lx, Ly; periodic: whether the box is periodic (bool);
      position (F, n, 2): the positions in the simulation's coordinates (the box's centre added back;
        as HOOMD stores them, relative to the centre, for a file from elsewhere), wrapped into the box;
      image (F, n, 2): the periodic image counts;
      unwrapped (F, n, 2): position + image * box, continuous in time: for displacements;
      velocity (F, n, 2); radius, mass, inertia, spin (F, n).

    Values are those of the file: single precision, as HOOMD's schema stores them, except time and
    the box (double precision where the file has billiard's own log entries).
    """
    path = _check_path(path, "path")
    if not path.is_file():
        raise FileNotFoundError(f"path: no file {str(path)!r}")
    gsd, hoomd = _gsd_hoomd()
    try:
        trajectory = hoomd.open(str(path), _open_mode(gsd, "r"))
    except (RuntimeError, OSError) as error:
        raise ValueError(f"path: {str(path)!r} is not a HOOMD GSD file ({error})") from None
    columns = {name: [] for name in ("time", "step", "box", "centre", "position", "image", "velocity", "radius",
                                     "mass", "inertia", "spin")}
    periodic = True
    with trajectory:
        for index, frame in enumerate(trajectory):
            if frame.configuration.dimensions != 2:
                raise ValueError(f"path: frame {index} of {str(path)!r} has {frame.configuration.dimensions} "
                                 "dimensions, not 2")
            particles = frame.particles
            if index > 0 and particles.N != len(columns["radius"][0]):
                raise ValueError(f"path: frame {index} of {str(path)!r} has {particles.N} particles, frame 0 "
                                 f"{len(columns['radius'][0])}")
            log = frame.log
            step = int(frame.configuration.step)
            box = np.array(log["billiard/box"], dtype=np.float64) if "billiard/box" in log else \
                np.array(frame.configuration.box[:2], dtype=np.float64)
            centre = np.array(log["billiard/box_centre"], dtype=np.float64) if "billiard/box_centre" in log else \
                np.zeros(2)
            if "billiard/periodic" in log:
                periodic = bool(log["billiard/periodic"][0])
            columns["time"].append(float(log["billiard/time"][0]) if "billiard/time" in log else float(step))
            columns["step"].append(step)
            columns["box"].append(box)
            columns["centre"].append(centre)
            columns["position"].append(np.asarray(particles.position, dtype=np.float64)[:, :2] + centre)
            columns["image"].append(np.asarray(particles.image, dtype=np.int64)[:, :2])
            columns["velocity"].append(np.asarray(particles.velocity, dtype=np.float64)[:, :2])
            columns["radius"].append(np.asarray(particles.diameter, dtype=np.float64) / 2)
            columns["mass"].append(np.asarray(particles.mass, dtype=np.float64))
            inertia = np.asarray(particles.moment_inertia, dtype=np.float64)[:, 2]
            columns["inertia"].append(inertia)
            angmom = np.asarray(particles.angmom, dtype=np.float64)[:, 3]
            columns["spin"].append(np.divide(angmom, 2 * inertia, out=np.zeros_like(angmom), where=inertia > 0))
    n = len(columns["radius"][0]) if columns["radius"] else 0
    shapes = {"time": (0,), "step": (0,), "box": (0, 2), "centre": (0, 2), "position": (0, n, 2), "image": (0, n, 2),
              "velocity": (0, n, 2), "radius": (0, n), "mass": (0, n), "inertia": (0, n), "spin": (0, n)}
    run = {name: np.array(values) if values else np.zeros(shapes[name]) for name, values in columns.items()}
    run["step"] = run["step"].astype(np.int64)
    run["image"] = run["image"].astype(np.int64)
    run["unwrapped"] = run["position"] + run["image"] * run["box"][:, None, :]
    run["periodic"] = periodic
    del run["centre"]
    return run
