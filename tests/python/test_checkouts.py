"""`import billiard` in Debian's /usr/bin/python3 without PYTHONPATH imports the checkout it runs
in (lib/python/checkout_import.py, registered by lib/python/register_checkout.py): two checkouts
on one machine never import each other's build. Each case runs a new python3 with its own HOME
(so its own user site-packages) and without PYTHONPATH."""

import os
import shutil
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
BUILD = Path(os.environ["PYTHONPATH"].split(os.pathsep)[0]).resolve()  # this checkout's build, set by CTest


def imported(home, folder, **variables):
    """(billiard.__file__ as a new python3 in `folder` imports it, standard error)."""
    environment = {key: value for key, value in os.environ.items() if key not in ("PYTHONPATH", "BILLIARD_PRESET")}
    environment.update(HOME=str(home), **variables)
    done = subprocess.run(["/usr/bin/python3", "-c", "import billiard; print(billiard.__file__)"], cwd=folder,
                          env=environment, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    return Path(done.stdout.strip()).resolve(), done.stderr


@pytest.fixture
def machine(tmp_path):
    """A home whose site-packages has this checkout registered, and two more checkouts: `other`,
    built (a package of its own), and `unbuilt`."""
    home = tmp_path / "home"
    home.mkdir()
    for name in ["other", "unbuilt"]:
        (tmp_path / name / "lib" / "python" / "billiard").mkdir(parents=True)
        (tmp_path / name / "lib" / "python" / "billiard" / "__init__.py").write_text("")
        (tmp_path / name / "notebooks").mkdir()
    package = tmp_path / "other" / "build" / "release" / "python" / "billiard"
    package.mkdir(parents=True)
    (package / "__init__.py").write_text("WHO = 'other'\n")
    done = subprocess.run(["/usr/bin/python3", str(REPO / "lib" / "python" / "register_checkout.py"), str(BUILD)],
                          env=dict(os.environ, HOME=str(home)), capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stderr
    return home, tmp_path


def test_each_checkout_imports_its_own_build(machine):
    home, places = machine
    assert imported(home, REPO)[0] == BUILD / "billiard" / "__init__.py"
    assert imported(home, REPO / "notebooks")[0] == BUILD / "billiard" / "__init__.py"
    other = places / "other" / "build" / "release" / "python" / "billiard" / "__init__.py"
    assert imported(home, places / "other" / "notebooks")[0] == other


def test_outside_every_checkout_the_build_registered_last(machine):
    home, places = machine
    assert imported(home, places)[0] == BUILD / "billiard" / "__init__.py"
    # Registering the other checkout makes it the default outside, and changes nothing inside.
    done = subprocess.run(["/usr/bin/python3", str(REPO / "lib" / "python" / "register_checkout.py"),
                           str(places / "other" / "build" / "release" / "python")],
                          env=dict(os.environ, HOME=str(home)), capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stderr
    assert imported(home, places)[0].parent.parent == places / "other" / "build" / "release" / "python"
    assert imported(home, REPO)[0] == BUILD / "billiard" / "__init__.py"


def test_a_checkout_without_a_build_says_so_and_what_it_imports(machine):
    home, places = machine
    file, errors = imported(home, places / "unbuilt" / "notebooks")
    assert file == BUILD / "billiard" / "__init__.py"
    assert f"billiard: {places / 'unbuilt'} has no build of the Python module (importing {BUILD} instead)" in errors
    assert "./build.sh python" in errors


def test_pythonpath_still_comes_first(machine):
    home, places = machine
    other = places / "other" / "build" / "release" / "python"
    assert imported(home, REPO, PYTHONPATH=str(other))[0] == other / "billiard" / "__init__.py"
