"""The library installed as a library: the C++ engine through `cmake --install` and
`find_package(billiard)` from a project outside the repository (the guide's example, as
printed), and the Python package through `pip install .` into a virtual environment, imported
from another folder. Neither needs a package index."""
import os
import pathlib
import re
import shutil
import subprocess
import sys

import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]
README = REPO / "lib" / "README.md"
BUILD = os.environ.get("BILLIARD_BUILD", "")  # this build folder, whose library is installed
sys.path.insert(0, str(REPO / "lib" / "python"))
from wheel_backend import project_version  # noqa: E402  (the version in CMakeLists.txt, read one way)


def run(command, **options):
    done = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=900, **options)
    assert done.returncode == 0, f"{' '.join(map(str, command))} failed:\n{done.stdout[-4000:]}"
    return done.stdout


FRAGMENTS_HEAD = """#include "billiard/engine/simulation.hpp"
#include "billiard/stepping/stepper.hpp"

#include <chrono>
#include <thread>

"""


@pytest.mark.skipif(not BUILD, reason="BILLIARD_BUILD names no build folder (CTest sets it)")
def test_find_package_builds_the_guides_example_outside_the_repository(tmp_path):
    run(["cmake", "--install", BUILD, "--prefix", str(tmp_path / "prefix")])
    blocks = re.findall(r"```cpp\n(.*?)```", README.read_text(), flags=re.S)
    program = next(block for block in blocks if "int main()" in block)
    fragments = [block for block in blocks if block is not program]
    assert len(fragments) >= 2, "the guide's C++ fragments (stopping a run, the stepper) are gone"
    project = re.search(r"```cmake\n(.*?)```", README.read_text(), flags=re.S)[1]
    assert "find_package(billiard" in project
    source = tmp_path / "my_discs"
    source.mkdir()
    (source / "main.cpp").write_text(program)
    # The guide's fragments compile against the installed headers too, each as the body of a
    # function given what they use (built, not run: they wait for seconds).
    (source / "fragments.cpp").write_text(FRAGMENTS_HEAD + "".join(
        f"void fragment_{k}(billiard::Simulation& sim, const billiard::Coordinates& positions,\n"
        f"                  const billiard::Velocities& velocities) {{\n{block}}}\n"
        for k, block in enumerate(fragments)) + "int main() {}\n")
    (source / "CMakeLists.txt").write_text(
        project + "add_executable(fragments fragments.cpp)\n"
        "target_link_libraries(fragments PRIVATE billiard::billiard billiard::stepping)\n")
    run(["cmake", "-S", str(source), "-B", str(source / "build"), "-G", "Ninja",
         f"-DCMAKE_PREFIX_PATH={tmp_path / 'prefix'}"])
    run(["cmake", "--build", str(source / "build")])
    output = run([str(source / "build" / "my_discs")])
    found = re.search(r"time (\S+), (\d+) disc collisions", output)
    assert found and float(found[1]) > 0 and int(found[2]) > 0, output
    # What was installed is the library's API: its headers, not the course's or the engine's internals.
    headers = {path.name for path in (tmp_path / "prefix" / "include").rglob("*.hpp")}
    assert "simulation.hpp" in headers and "course.hpp" not in headers, headers
    internals = {path.name for path in (REPO / "lib" / "src" / "engine").glob("*.hpp")}
    assert {"engine.hpp", "time_of_impact.hpp", "collide.hpp", "container_geometry.hpp"} <= internals
    assert not headers & internals, f"internal headers installed: {sorted(headers & internals)}"


def test_pip_install_into_a_virtual_environment_imports_from_anywhere(tmp_path):
    venv = tmp_path / "venv"
    run([sys.executable, "-m", "venv", "--system-site-packages", str(venv)])  # numpy: Debian's
    run([str(venv / "bin" / "pip"), "install", "--no-index", "--no-cache-dir", str(REPO)])
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    output = run([str(venv / "bin" / "python"), "-c", """
import billiard
print(billiard.__version__, billiard.__file__)
sim = billiard.Simulation(billiard.periodic_box(20, 20))
sim.add_random_discs(50, 0.5, seed=1)
print(sim.advance(events=2000)["collisions"], sim.validate())
"""], cwd=elsewhere, env={key: value for key, value in os.environ.items() if key != "PYTHONPATH"})
    first, second = output.strip().splitlines()[-2:]
    assert first.split()[0] == project_version()
    assert pathlib.Path(first.split()[1]).is_relative_to(venv), first  # the installed copy, not this build's
    assert second == "2000 None"
