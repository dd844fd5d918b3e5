"""Figures and animations of billiard states with matplotlib (Debian's python3-matplotlib).

Four plain functions, each drawing into an ``Axes`` the caller owns (except ``animate``, which
writes a file):

- ``draw_table(ax, positions, radii, ...)``: the discs as circles, the circular table, a
  rectangular box, straight walls or circular arcs, and optionally the velocities as arrows
  (``simulation_walls(sim)`` gives the walls of a ``billiard.Simulation`` or a ``billiard.Container``
  in that form).
- ``animate(states, path, ...)``: a replay of many states as a GIF (Pillow) or an MP4 (ffmpeg).
- ``plot_energy(ax, events, mean_square, ...)``: the mean squared velocity <v^2> over the
  events, or its relative drift |<v^2>/<v^2>_0 - 1| on a log scale.
- ``speed_histogram(ax, speeds, kT=None, mass=1.0, ...)``: the distribution of speeds with
  the 2D Maxwell-Boltzmann density ``maxwell_boltzmann_2d`` drawn over it.

Units are the simulation's: lengths in the unit of the table radius, speeds in length per
time, kT in mass times speed squared. ``import billiard`` does not import this module (nor
matplotlib); ``import billiard.plotting`` does.

Example::

    import matplotlib.pyplot as plt
    import billiard, billiard.plotting as bp
    coordinates = billiard.init_billiard(10.0, 1.0, 10, 1)
    fig, ax = plt.subplots()
    bp.draw_table(ax, coordinates, 1.0, table_radius=10.0)
"""

from pathlib import Path

import numpy as np

import matplotlib
import matplotlib.colors
from matplotlib.collections import LineCollection
from matplotlib.patches import Arc, Circle, Rectangle

__all__ = ["draw_table", "animate", "plot_energy", "speed_histogram", "maxwell_boltzmann_2d", "simulation_walls"]


# --------------------------------------------------------------------------------------------
# States
# --------------------------------------------------------------------------------------------

def _state_arrays(positions, radii=None, velocities=None):
    """Positions (n, 2), radii (n,) and velocities ((n, 2) or None) from arrays or a state dict.

    A state dict has the keys 'position' (n, 2) and 'radius' (n,) or a number, and optionally
    'velocity' (n, 2); the plural spellings ('positions', 'radii', 'velocities') are accepted
    too. Arguments given explicitly win over the dict's entries.
    """
    if isinstance(positions, dict):
        state = positions
        positions = _first_key(state, "position", "positions")
        if radii is None:
            radii = _first_key(state, "radius", "radii", required=False)
        if velocities is None:
            velocities = _first_key(state, "velocity", "velocities", required=False)
    positions = np.asarray(positions, dtype=float)
    if positions.ndim != 2 or positions.shape[1] != 2:
        raise ValueError(f"positions must have shape (n, 2), got {positions.shape}")
    n = len(positions)
    if radii is None:
        raise ValueError("radii are needed: pass radii= (a number or one per disc) or a state with 'radius'")
    radii = np.broadcast_to(np.asarray(radii, dtype=float), (n,))
    if velocities is not None:
        velocities = np.asarray(velocities, dtype=float)
        if velocities.shape != positions.shape:
            raise ValueError(f"velocities must have the shape of positions {positions.shape}, got {velocities.shape}")
    return positions, radii, velocities


def _first_key(state, *keys, required=True):
    for key in keys:
        if key in state:
            return state[key]
    if required:
        raise ValueError(f"the state has none of the keys {keys}")
    return None


def _disc_colors(colors, n):
    """One RGBA colour per disc: None (one default colour), a colour, a list of colours, or an
    array of n numbers mapped through the 'viridis' colour map (e.g. speeds)."""
    if colors is None:
        return [matplotlib.colors.to_rgba("C0")] * n
    if isinstance(colors, str):
        return [matplotlib.colors.to_rgba(colors)] * n
    values = np.asarray(colors)
    if values.ndim == 1 and values.dtype.kind in "fiu" and len(values) == n:  # numbers: a colour map
        span = np.ptp(values) if n else 0.0
        scaled = (values - values.min()) / span if span > 0 else np.full(n, 0.5)
        return [tuple(c) for c in matplotlib.colormaps["viridis"](scaled)]
    if matplotlib.colors.is_color_like(colors):  # one RGB(A) tuple for every disc
        return [matplotlib.colors.to_rgba(colors)] * n
    colors = list(colors)
    if len(colors) != n:
        raise ValueError(f"colors: {len(colors)} colours for {n} discs")
    return [matplotlib.colors.to_rgba(c) for c in colors]


def _box_corners(box):
    """(xmin, ymin, xmax, ymax) of a box given as (width, height) from the origin or as
    (xmin, ymin, xmax, ymax)."""
    box = tuple(float(x) for x in np.ravel(box))
    if len(box) == 2:
        return 0.0, 0.0, box[0], box[1]
    if len(box) == 4:
        return box
    raise ValueError(f"box must be (width, height) or (xmin, ymin, xmax, ymax), got {box}")


def _arc_rows(arcs):
    """Arcs as an (m, 5) array of rows (cx, cy, radius, start_angle, end_angle)."""
    rows = np.asarray(arcs, dtype=float).reshape(-1, 5)
    if np.any(rows[:, 2] <= 0) or np.any(rows[:, 4] <= rows[:, 3]):
        raise ValueError("arcs must be rows (cx, cy, radius, start_angle, end_angle) with radius > 0 and "
                         "end_angle > start_angle (radians, counter-clockwise)")
    return rows


def _arc_points(arcs):
    """Points along every arc (64 per arc), for the axis limits."""
    rows = _arc_rows(arcs)
    t = np.linspace(0.0, 1.0, 64)
    angles = rows[:, 3:4] + (rows[:, 4:5] - rows[:, 3:4]) * t
    x = rows[:, 0:1] + rows[:, 2:3] * np.cos(angles)
    y = rows[:, 1:2] + rows[:, 2:3] * np.sin(angles)
    return np.stack([x.ravel(), y.ravel()], axis=1)


def simulation_walls(sim):
    """The walls of a billiard.Simulation (or of a billiard.Container) as keyword arguments of
    draw_table and animate: ``walls`` (its segments), ``arcs`` (its arcs) and ``table_radius``
    (when it has a table). Point walls (end points, corners) are not drawn. Usage:
    ``draw_table(ax, sim.current_state, **simulation_walls(sim))``."""
    container = getattr(sim, "container", sim)
    segments, arcs = [], []
    for wall in container.walls:
        if wall["kind"] == "segment":
            segments.append([wall["a"], wall["b"]])
        elif wall["kind"] == "arc":
            start = wall["start_angle"]
            arcs.append([wall["a"][0], wall["a"][1], wall["radius"], start, start + wall["sweep"]])
    out = {"walls": segments, "arcs": arcs}
    if container.table_radius > 0:
        out["table_radius"] = container.table_radius
    return out


def _limits(positions_list, radii, table_radius, box, walls, arcs=None):
    """Axis limits (xmin, xmax, ymin, ymax) showing the table, box, walls, arcs and every disc."""
    lows, highs = [], []
    if table_radius is not None:
        lows.append([-table_radius, -table_radius])
        highs.append([table_radius, table_radius])
    if box is not None:
        x0, y0, x1, y1 = _box_corners(box)
        lows.append([x0, y0])
        highs.append([x1, y1])
    if walls is not None and len(walls):
        points = np.asarray(walls, dtype=float).reshape(-1, 2)
        lows.append(points.min(axis=0))
        highs.append(points.max(axis=0))
    if arcs is not None and len(arcs):
        points = _arc_points(arcs)
        lows.append(points.min(axis=0))
        highs.append(points.max(axis=0))
    for positions in positions_list:
        if len(positions):
            lows.append((positions - radii[:, None]).min(axis=0))
            highs.append((positions + radii[:, None]).max(axis=0))
    if not lows:
        return -1.0, 1.0, -1.0, 1.0
    low, high = np.min(lows, axis=0), np.max(highs, axis=0)
    margin = 0.03 * max(high - low) or 1.0
    return low[0] - margin, high[0] + margin, low[1] - margin, high[1] + margin


# --------------------------------------------------------------------------------------------
# Tables
# --------------------------------------------------------------------------------------------

def draw_table(ax, positions, radii=None, table_radius=None, box=None, walls=None, velocities=None,
               colors=None, arrow_scale=1.0, arcs=None):
    """Draws one state of the billiard into ``ax``: every disc as a circle patch.

    ax: a matplotlib Axes; its aspect is set equal (circles look round) and its limits fit the
        table, the box, the walls and the discs.
    positions: (n, 2) array of disc centres, or a state dict with keys 'position' (n, 2),
        'radius' (n,) or a number, optionally 'velocity' (n, 2) (plurals accepted).
    radii: a number (equal discs, as in the course) or one radius per disc.
    table_radius: radius R of the circular table centred at 0, drawn as a black circle.
    box: a rectangular (e.g. periodic) box, (width, height) from the origin or
        (xmin, ymin, xmax, ymax), drawn dashed.
    walls: straight walls as segments [[(x0, y0), (x1, y1)], ...], drawn as thick lines.
    arcs: circular arc walls as rows (cx, cy, radius, start_angle, end_angle), angles in radians
        counter-clockwise, drawn as thick lines (matplotlib.patches.Arc).
    velocities: (n, 2) array; when given, each disc gets an arrow v * arrow_scale (in time
        units: where the centre would be after arrow_scale time units).
    colors: None, one matplotlib colour, one colour per disc, or n numbers (mapped with the
        viridis colour map; handy for speeds).

    Returns the list of the n disc patches (matplotlib.patches.Circle, in the order of
    positions), so that a caller can move them (``patch.center = ...``). The table circle is
    one more patch in ``ax.patches``, the box another.
    """
    positions, radii, velocities = _state_arrays(positions, radii, velocities)
    n = len(positions)
    ax.set_aspect("equal")
    if table_radius is not None:
        ax.add_patch(Circle((0.0, 0.0), table_radius, fill=False, edgecolor="black", linewidth=1.5, zorder=1))
    if box is not None:
        x0, y0, x1, y1 = _box_corners(box)
        ax.add_patch(Rectangle((x0, y0), x1 - x0, y1 - y0, fill=False, edgecolor="black", linestyle="--",
                               linewidth=1.0, zorder=1))
    if walls is not None and len(walls):
        segments = np.asarray(walls, dtype=float).reshape(-1, 2, 2)
        ax.add_collection(LineCollection(segments, colors="black", linewidths=2.5, zorder=1))
    if arcs is not None and len(arcs):
        for cx, cy, radius, start, end in _arc_rows(arcs):
            ax.add_patch(Arc((cx, cy), 2 * radius, 2 * radius, theta1=np.degrees(start), theta2=np.degrees(end),
                             edgecolor="black", linewidth=2.5, zorder=1))
    discs = []
    for centre, radius, color in zip(positions, radii, _disc_colors(colors, n)):
        disc = Circle(tuple(centre), radius, facecolor=color, edgecolor="black", linewidth=0.5, alpha=0.85,
                      zorder=2)
        # add_artist, not add_patch: add_patch recomputes the data limits for every disc (seconds
        # for a thousand discs); the limits are set once below.
        disc.set_clip_path(ax.patch)
        ax.add_artist(disc)
        discs.append(disc)
    if velocities is not None and n:
        ax.quiver(positions[:, 0], positions[:, 1], velocities[:, 0] * arrow_scale, velocities[:, 1] * arrow_scale,
                  angles="xy", scale_units="xy", scale=1.0, width=0.004, color="crimson", zorder=3)
    x0, x1, y0, y1 = _limits([positions], radii, table_radius, box, walls, arcs)
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    return discs


# --------------------------------------------------------------------------------------------
# Animations
# --------------------------------------------------------------------------------------------

def animate(states, path, fps=20, radii=None, table_radius=None, box=None, walls=None, colors=None,
            size=4.0, dpi=100, title=None, arcs=None):
    """Writes a replay of ``states`` (one frame each) to ``path``, a GIF or an MP4 file.

    states: a sequence of (n, 2) position arrays, or of state dicts (see draw_table); the
        number of discs must not change. Every state is one frame.
    path: output file; the suffix chooses the format: '.gif' (matplotlib's PillowWriter,
        Pillow from Debian's python3-pil) or '.mp4' (FFMpegWriter, H.264, needs the ffmpeg
        command from Debian's ffmpeg package). Other suffixes raise ValueError.
    fps: frames per second of the file.
    radii, table_radius, box, walls, arcs, colors: as in draw_table (radii may come from the states).
    size, dpi: the frame is size x size inches at dpi dots per inch (400 x 400 pixels by
        default; MP4 frames need an even number of pixels, which these give).
    title: text above the frames; '{frame}' in it is replaced by the frame number.

    The axis limits are fixed for the whole film (they fit every frame). Returns the Path
    written. Uses no pyplot, so nothing is left open or shown in a notebook.
    """
    from matplotlib import animation
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    path = Path(path)
    suffix = path.suffix.lower()
    if suffix == ".gif":
        writer = animation.PillowWriter(fps=fps)
    elif suffix == ".mp4":
        if not animation.FFMpegWriter.isAvailable():
            raise RuntimeError("writing MP4 needs the ffmpeg command (Debian package ffmpeg); write a .gif instead")
        writer = animation.FFMpegWriter(fps=fps, codec="h264", extra_args=["-pix_fmt", "yuv420p"])
    else:
        raise ValueError(f"animate writes .gif (Pillow) or .mp4 (ffmpeg) files, got '{path.name}'")

    states = list(states)
    if not states:
        raise ValueError("animate needs at least one state")
    frames = [_state_arrays(state, radii)[:2] for state in states]
    n = len(frames[0][0])
    if any(len(p) != n for p, _ in frames):
        raise ValueError("every state must have the same number of discs")
    radii_first = frames[0][1]

    figure = Figure(figsize=(size, size), dpi=dpi)
    FigureCanvasAgg(figure)
    ax = figure.add_axes([0.02, 0.02, 0.96, 0.9 if title else 0.96])
    ax.set_axis_off()
    discs = draw_table(ax, frames[0][0], radii_first, table_radius=table_radius, box=box, walls=walls,
                       colors=colors, arcs=arcs)
    x0, x1, y0, y1 = _limits([p for p, _ in frames], radii_first, table_radius, box, walls, arcs)
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    heading = ax.set_title("") if title else None

    path.parent.mkdir(parents=True, exist_ok=True)
    with writer.saving(figure, str(path), dpi):
        for k, (positions, _) in enumerate(frames):
            for disc, centre in zip(discs, positions):
                disc.center = tuple(centre)
            if heading is not None:
                heading.set_text(title.replace("{frame}", str(k)))
            writer.grab_frame()
    return path


# --------------------------------------------------------------------------------------------
# Energy and speeds
# --------------------------------------------------------------------------------------------

def plot_energy(ax, events, mean_square, target=None, relative=False, floor=1e-17, label=None, **style):
    """Plots the mean squared velocity <v^2> over the events into ``ax``.

    events: x values, e.g. the event (collision) number of each record; same length as
        mean_square.
    mean_square: <v^2> = (1/N) sum |v_i|^2 after each event (twice the kinetic energy per disc
        for unit mass).
    target: the reference <v^2>; default: the first value, mean_square[0].
    relative: False plots <v^2> itself (with the target as a dotted line); True plots the
        relative drift |<v^2>/target - 1| on a logarithmic y axis.
    floor: on the log scale, a drift of exactly 0 (a run that is exact to the last bit) is
        drawn at this value instead of vanishing; 1e-17 is below the double rounding unit
        (1.1e-16), so such points sit visibly under every real drift.
    label, **style: passed to ax.plot (colour, line style, ...).

    Returns the Line2D drawn.
    """
    events = np.asarray(events)
    mean_square = np.asarray(mean_square, dtype=float)
    if events.shape != mean_square.shape:
        raise ValueError(f"events {events.shape} and mean_square {mean_square.shape} differ in shape")
    if target is None:
        target = float(mean_square[0])
    if relative:
        drift = np.abs(mean_square / target - 1.0)
        (line,) = ax.plot(events, np.maximum(drift, floor), label=label, **style)
        ax.set_yscale("log")
        ax.set_ylabel(r"relative drift $|\langle v^2\rangle / \langle v^2\rangle_0 - 1|$")
    else:
        (line,) = ax.plot(events, mean_square, label=label, **style)
        ax.axhline(target, color="gray", linestyle=":", linewidth=1)
        ax.set_ylabel(r"$\langle v^2\rangle$")
    ax.set_xlabel("event")
    return line


def maxwell_boltzmann_2d(v, kT, mass=1.0):
    """The 2D Maxwell-Boltzmann speed density P(v) = (m v / kT) exp(-m v^2 / (2 kT)), v >= 0.

    In two dimensions the velocity components are independent Gaussians of variance kT/m, so
    the speed has this (Rayleigh) density; it integrates to 1 over v in [0, inf), its mean
    square is 2 kT / m (hence kT = m <v^2> / 2 per disc) and its cumulative distribution is
    1 - exp(-m v^2 / (2 kT)). Zero for v < 0.
    """
    v = np.asarray(v, dtype=float)
    if kT <= 0 or mass <= 0:
        raise ValueError(f"kT and mass must be positive, got kT={kT}, mass={mass}")
    density = (mass * v / kT) * np.exp(-mass * v * v / (2.0 * kT))
    return np.where(v >= 0, density, 0.0)


def speed_histogram(ax, speeds, kT=None, mass=1.0, bins=30, label="simulation", color="C0", show_law=True):
    """Histogram of the speeds (as a density) with the 2D Maxwell-Boltzmann law over it.

    speeds: 1D array of speeds |v|, or an (n, 2) array of velocities (their lengths are taken).
        Pool several snapshots for smoother histograms.
    kT: temperature in energy units (mass times speed squared); default: from the speeds
        themselves, kT = m <v^2> / 2 (equipartition in 2D: kT/2 per degree of freedom).
    mass: the disc mass m (1 in the course).
    bins: number of bins (equal width from 0 to the largest speed, or 3.5 sqrt(kT/m) when
        larger, so that the law's tail shows) or explicit bin edges.
    show_law: draw the density maxwell_boltzmann_2d(v, kT, mass) as a line.

    Returns (density, edges): the histogram values (integrating to 1) and the bin edges.
    """
    speeds = np.asarray(speeds, dtype=float)
    if speeds.ndim == 2 and speeds.shape[1] == 2:
        speeds = np.hypot(speeds[:, 0], speeds[:, 1])
    speeds = speeds.ravel()
    if speeds.size == 0:
        raise ValueError("speed_histogram needs at least one speed")
    if kT is None:
        kT = mass * np.mean(speeds**2) / 2.0
    if np.ndim(bins) == 0:
        top = max(speeds.max(), 3.5 * np.sqrt(kT / mass)) if kT > 0 else speeds.max()
        bins = np.linspace(0.0, top if top > 0 else 1.0, int(bins) + 1)
    density, edges, _ = ax.hist(speeds, bins=bins, density=True, color=color, alpha=0.6, edgecolor="white",
                                label=label)
    if show_law and kT > 0:
        v = np.linspace(0.0, edges[-1], 400)
        ax.plot(v, maxwell_boltzmann_2d(v, kT, mass), color="black",
                label=fr"2D Maxwell-Boltzmann, $kT = {kT:.3g}$")
    ax.set_xlabel("speed $v$")
    ax.set_ylabel("probability density $P(v)$")
    return density, edges
