"""billiard.plotting: what each function draws or writes, checked on the artists and files it
makes (not on pixels). Runs with MPLBACKEND=Agg; needs no course function (the states here are
made by hand), so it passes in the student build too."""

import shutil
import subprocess
import sys

import numpy as np
import pytest

matplotlib = pytest.importorskip("matplotlib")
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.patches import Circle, Rectangle  # noqa: E402

import billiard.plotting as bp  # noqa: E402

R, A = 10.0, 1.0
# Four equal discs on a square, well inside the table of radius 10.
POSITIONS = np.array([[-4.0, -4.0], [4.0, -4.0], [4.0, 4.0], [-4.0, 4.0]])
VELOCITIES = np.array([[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -1.0]])
# The trapezoidal rule: numpy 2's name (its old one, trapz, is deprecated there), else numpy 1's.
integrate = getattr(np, "trapezoid", None) or np.trapz


@pytest.fixture
def ax():
    figure, axes = plt.subplots()
    yield axes
    plt.close(figure)


def discs_of(ax):
    return [p for p in ax.patches if isinstance(p, Circle) and p.get_fill()]


def test_importing_billiard_does_not_import_matplotlib():
    code = "import sys, billiard; assert 'matplotlib' not in sys.modules, 'billiard imported matplotlib'"
    subprocess.run([sys.executable, "-c", code], check=True)


def test_draw_table_makes_one_patch_per_disc_plus_the_table(ax):
    discs = bp.draw_table(ax, POSITIONS, A, table_radius=R)
    assert len(discs) == len(POSITIONS)
    assert len(ax.patches) == len(POSITIONS) + 1
    table = [p for p in ax.patches if isinstance(p, Circle) and not p.get_fill()]
    assert len(table) == 1 and table[0].get_radius() == R and tuple(table[0].center) == (0.0, 0.0)
    for disc, centre in zip(discs, POSITIONS):
        assert tuple(disc.center) == tuple(centre) and disc.get_radius() == A
    assert ax.get_aspect() == 1.0  # "equal": circles look round
    x0, x1 = ax.get_xlim()
    assert x0 <= -R and x1 >= R, "the whole table is visible"


def test_draw_table_accepts_a_state_dict_radii_per_disc_box_walls_velocities_and_colours(ax):
    state = {"position": POSITIONS + 5.0, "radius": np.array([0.5, 1.0, 1.5, 2.0]), "velocity": VELOCITIES}
    discs = bp.draw_table(ax, state, box=(20.0, 20.0), walls=[[(0, 0), (20, 0)], [(0, 0), (0, 20)]],
                          colors=[1.0, 2.0, 3.0, 4.0])
    assert [d.get_radius() for d in discs] == [0.5, 1.0, 1.5, 2.0]
    boxes = [p for p in ax.patches if isinstance(p, Rectangle)]
    assert len(boxes) == 1 and boxes[0].get_width() == 20.0
    assert len(ax.collections) == 2  # the walls and the velocity arrows
    colours = {tuple(np.round(d.get_facecolor(), 6)) for d in discs}
    assert len(colours) == 4, "numbers as colours: one colour per value"


def test_draw_table_rejects_bad_shapes(ax):
    with pytest.raises(ValueError, match=r"\(n, 2\)"):
        bp.draw_table(ax, np.zeros(4), A)
    with pytest.raises(ValueError, match="radii"):
        bp.draw_table(ax, POSITIONS)
    with pytest.raises(ValueError, match="velocities"):
        bp.draw_table(ax, POSITIONS, A, velocities=np.zeros((3, 2)))


def frames(count):
    # the four discs turning around the centre
    return [POSITIONS @ np.array([[np.cos(t), np.sin(t)], [-np.sin(t), np.cos(t)]])
            for t in np.linspace(0, 1, count)]


def test_animate_writes_a_gif_with_one_frame_per_state(tmp_path):
    from PIL import Image

    path = bp.animate(frames(7), tmp_path / "replay.gif", fps=10, radii=A, table_radius=R, size=2.0,
                      title="frame {frame}")
    assert path == tmp_path / "replay.gif"
    with Image.open(path) as gif:
        assert gif.format == "GIF"
        assert gif.n_frames == 7
        assert gif.size == (200, 200)


def test_animate_takes_state_dicts(tmp_path):
    from PIL import Image

    states = [{"position": p, "radius": A} for p in frames(3)]
    path = bp.animate(states, tmp_path / "dicts.GIF", table_radius=R, size=1.0)
    with Image.open(path) as gif:
        assert gif.n_frames == 3


@pytest.mark.skipif(shutil.which("ffmpeg") is None, reason="writing MP4 needs ffmpeg (Debian package ffmpeg)")
def test_animate_writes_an_mp4(tmp_path):
    path = bp.animate(frames(10), tmp_path / "replay.mp4", fps=10, radii=A, table_radius=R, size=2.0)
    data = path.read_bytes()
    assert len(data) > 1000
    assert data[4:8] == b"ftyp", "an MP4 file starts with its ftyp box"
    probe = shutil.which("ffprobe")
    if probe:
        frames_counted = subprocess.run(
            [probe, "-v", "error", "-count_frames", "-select_streams", "v:0", "-show_entries",
             "stream=nb_read_frames", "-of", "csv=p=0", str(path)], capture_output=True, text=True, check=True)
        assert int(frames_counted.stdout.strip()) == 10


def test_animate_refuses_other_formats_and_mismatched_states(tmp_path):
    with pytest.raises(ValueError, match=r"\.gif.*\.mp4"):
        bp.animate(frames(2), tmp_path / "replay.avi", radii=A)
    assert not (tmp_path / "replay.avi").exists()
    with pytest.raises(ValueError, match="same number"):
        bp.animate([POSITIONS, POSITIONS[:2]], tmp_path / "replay.gif", radii=A)
    with pytest.raises(ValueError, match="at least one"):
        bp.animate([], tmp_path / "replay.gif", radii=A)


def test_maxwell_boltzmann_density_integrates_to_one_with_the_right_mean_square():
    kT, mass = 0.7, 2.0
    v = np.linspace(0, 40, 400001)
    density = bp.maxwell_boltzmann_2d(v, kT, mass)
    assert integrate(density, v) == pytest.approx(1.0, abs=1e-7)
    # equipartition in 2D: <v^2> = 2 kT / m
    assert integrate(v**2 * density, v) == pytest.approx(2 * kT / mass, rel=1e-9)
    assert bp.maxwell_boltzmann_2d(-1.0, kT) == 0.0
    with pytest.raises(ValueError):
        bp.maxwell_boltzmann_2d(v, 0.0)


def test_speed_histogram_is_a_density_with_the_law_over_it(ax):
    rng = np.random.default_rng(5)
    velocities = rng.normal(0.0, np.sqrt(0.5), size=(20000, 2))  # kT/m = 0.5 per component
    density, edges = bp.speed_histogram(ax, velocities, bins=40)  # (n, 2) velocities accepted
    assert len(density) == 40 and len(edges) == 41
    assert np.sum(density * np.diff(edges)) == pytest.approx(1.0, rel=1e-12)
    law = ax.lines[0]
    x, y = law.get_data()
    assert integrate(y, x) == pytest.approx(1.0, abs=2e-3)  # the curve is the normalised law
    # kT from the speeds themselves is close to the 0.5 they were drawn with
    assert "0.5" in law.get_label()
    # each bin holds what the law puts there, within 5 standard deviations of its count
    width = np.diff(edges)
    expected = np.diff(1 - np.exp(-edges**2 / (2 * 0.5))) / width  # the law's CDF, kT/m = 0.5
    sigma = np.sqrt(expected / (len(velocities) * width))
    assert np.all(np.abs(density - expected) < 5 * sigma + 1e-12)


def test_plot_energy_draws_the_relative_drift_on_a_log_scale(ax):
    events = np.arange(5)
    mean_square = np.array([2.0, 2.0, 2.0 * (1 + 2.0**-50), 2.0 * (1 - 2.0**-30), 2.5])  # exact in binary
    line = bp.plot_energy(ax, events, mean_square, relative=True, label="run")
    assert ax.get_yscale() == "log"
    _, y = line.get_data()
    np.testing.assert_array_equal(y, [1e-17, 1e-17, 2.0**-50, 2.0**-30, 0.25])  # exact zeros at the floor
    assert line.get_label() == "run"
    with pytest.raises(ValueError, match="shape"):
        bp.plot_energy(ax, events[:3], mean_square)


def test_plot_energy_plain_draws_the_values_and_the_target(ax):
    line = bp.plot_energy(ax, [0, 1, 2], [1.0, 1.1, 0.9], target=1.0)
    assert ax.get_yscale() == "linear"
    np.testing.assert_array_equal(line.get_data()[1], [1.0, 1.1, 0.9])
    assert len(ax.lines) == 2  # the values and the target line


def test_help_explains_every_function():
    for name in ["draw_table", "animate", "plot_energy", "speed_histogram", "maxwell_boltzmann_2d"]:
        doc = getattr(bp, name).__doc__
        assert doc and len(doc) > 200, name
    assert "GIF" in bp.animate.__doc__ and "MP4" in bp.animate.__doc__
    assert "Maxwell-Boltzmann" in bp.__doc__
