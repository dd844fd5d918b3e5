"""The Python examples of lib/README.md run as printed, against this build's package.

Each ```python block runs in a fresh namespace that has `billiard` imported (the guide imports it
once, above its first example), after the blocks before it (a later block may use a function an
earlier one defined). A block that needs a Dask scheduler's address is only compiled. After its
block, each example's own result is checked, so that an example that runs but says something
else than the guide claims fails too.
"""
import os
import pathlib
import re
import subprocess
import sys

import numpy as np
import pytest

import billiard

README = pathlib.Path(__file__).resolve().parents[2] / "lib" / "README.md"


def python_blocks():
    return re.findall(r"```python\n(.*?)```", README.read_text(), flags=re.S)


def needs_a_scheduler(block):
    return "tcp://" in block


def test_the_guide_has_its_examples():
    blocks = python_blocks()
    assert len(blocks) >= 4, f"lib/README.md has {len(blocks)} Python examples"
    assert any("billiard.Simulation(" in block for block in blocks)


@pytest.fixture(scope="module")
def namespace():
    return {"billiard": billiard, "__name__": "readme_example"}


def run(block, namespace):
    exec(compile(block, str(README), "exec"), namespace)


def test_every_example_runs(namespace, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # (the trajectory example writes gas.gsd)
    for block in python_blocks():
        if needs_a_scheduler(block):
            compile(block, str(README), "exec")
            continue
        run(block, namespace)
    # The stepper's example leaves its own state, the engine's its own: check what each claims.
    assert isinstance(namespace["sim"], billiard.Simulation)
    assert namespace["frames"], "replay_by_time returned no frames"
    assert namespace["stepper"].current_state["time"] == pytest.approx(20.0)
    msd = namespace["msd"]  # the trajectory's mean squared displacement: 0, then growing
    assert len(msd) == 41 and msd[0] == 0 and msd[-1] > msd[1] > 0


def test_the_stadium_example_keeps_its_discs_inside():
    block = next(b for b in python_blocks() if "billiard.stadium(" in b)
    namespace = {"billiard": billiard, "__name__": "readme_example"}
    run(block.replace("1_000_000", "20_000"), namespace)
    sim = namespace["sim"]
    assert sim.validate() is None
    assert sim.container.walls, "the stadium has no walls"
    radius = sim.current_state["radius"][0]
    # Inside the stadium's box: |x| <= L/2 + R - a, |y| <= R - a (R = L = 10).
    position = sim.current_state["position"]
    assert np.all(np.abs(position[:, 0]) <= 15 - radius + 1e-9)
    assert np.all(np.abs(position[:, 1]) <= 10 - radius + 1e-9)


def test_the_sweep_example_measures_a_pressure_above_the_ideal_gas():
    block = next(b for b in python_blocks() if "def pressure(" in b)
    namespace = {"billiard": billiard, "__name__": "readme_example"}
    run(block, namespace)  # defines pressure; the sweep itself is under __main__
    z = namespace["pressure"](0.3, 200, 1)["Z"]
    # Henderson's equation of state at area fraction 0.3: Z = (1 + eta^2 / 8) / (1 - eta)^2 = 2.10.
    assert z == pytest.approx((1 + 0.3**2 / 8) / (1 - 0.3) ** 2, rel=0.1)


def test_the_sweep_example_runs_as_a_script(tmp_path):
    """The sweep example as the guide prints it, saved as a script and run by Python (its workers
    import the script), at a smaller scale: it prints a line per area fraction, without pandas."""
    block = next(b for b in python_blocks() if "def pressure(" in b)
    smaller = block.replace('"n": [1000]', '"n": [100]').replace("seeds=10", "seeds=2")
    assert smaller != block, "the example's scale is not where this test expects it"
    script = tmp_path / "pressure_sweep.py"
    script.write_text(smaller)
    done = subprocess.run([sys.executable, str(script)], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                          timeout=300, cwd=tmp_path, env=dict(os.environ))
    assert done.returncode == 0, done.stdout[-3000:]
    values = {float(eta): float(z) for eta, z in re.findall(r"^eta ([0-9.]+): Z = ([0-9.]+) \+- ", done.stdout, re.M)}
    assert sorted(values) == [0.1, 0.3, 0.5], done.stdout[-3000:]
    assert values[0.1] < values[0.3] < values[0.5]  # the pressure rises with the density


def test_the_quoted_refusal_of_another_format_version_names_this_one():
    data = billiard.Simulation(billiard.periodic_box(5.0, 5.0)).to_bytes()
    at = len(b"billiard-simulation\0") + 4  # after the byte-order mark
    this_version = int.from_bytes(data[at:at + 4], sys.byteorder)
    assert f"reads version {this_version} only" in README.read_text(), "the guide quotes another format version"

