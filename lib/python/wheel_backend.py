"""The build backend of `pip install .` (pyproject.toml names it): builds the Python module with
this project's CMake, for the Python that runs pip, and packs lib/python/billiard/ with the
compiled module into a wheel, which pip then installs (a virtual environment, the user's site).

It needs nothing from a package index (pip's isolated build gets no requirements), only what
`./build.sh python` installs from Debian: cmake, ninja, a C++ compiler, Eigen, pybind11-dev and
the Python headers. The package needs numpy at run time; in a virtual environment made with
`--system-site-packages`, Debian's. Only wheels are built (no source archives).
"""

import base64
import hashlib
import os
import re
import shutil
import subprocess
import sys
import sysconfig
import zipfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]  # the repository (lib/python/ is two folders down)
NAME = "billiard"


def project_version():
    """The version in the top-level CMakeLists.txt's project(), the one place it is written."""
    found = re.search(r"^project\(billiard VERSION ([0-9.]+)", (ROOT / "CMakeLists.txt").read_text(), re.M)
    if not found:
        raise RuntimeError("CMakeLists.txt's project() has no VERSION")
    return found[1]


def wheel_tag():
    """The tag of a wheel with a compiled module for this interpreter, such as cp311-cp311-linux_x86_64."""
    python = f"cp{sys.version_info.major}{sys.version_info.minor}"
    platform = sysconfig.get_platform().replace("-", "_").replace(".", "_")
    return f"{python}-{python}-{platform}"


def metadata():
    return (f"Metadata-Version: 2.1\nName: {NAME}\nVersion: {project_version()}\n"
            "Summary: Event-driven simulation of hard discs: engine, time stepper and ensembles\n"
            "Requires-Python: >=3.9\nRequires-Dist: numpy\n")


def build_package():
    """Builds the module with CMake for this Python; returns the folder of the built package."""
    build = ROOT / "build" / f"pip-{sys.implementation.cache_tag}"
    configure = ["cmake", "-S", str(ROOT), "-B", str(build), "-DCMAKE_BUILD_TYPE=Release",
                 "-DBILLIARD_BUILD_TESTS=OFF", "-DBILLIARD_PYTHON=ON", f"-DPython_EXECUTABLE={sys.executable}"]
    if shutil.which("ninja") and not (build / "CMakeCache.txt").exists():
        configure += ["-G", "Ninja"]
    for command in [configure, ["cmake", "--build", str(build), "--target", "billiard_python",
                                "--parallel", str(os.cpu_count() or 1)]]:
        done = subprocess.run(command, stdout=sys.stderr, stderr=sys.stderr)  # pip shows it with -v
        if done.returncode != 0:
            raise RuntimeError(f"{' '.join(command)} failed (status {done.returncode}); run `pip install -v .` to see "
                               "why, and ./build.sh python to install what the build needs")
    return build / "python" / NAME


def record_line(name, data):
    digest = base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode()
    return f"{name},sha256={digest},{len(data)}"


def build_wheel(wheel_directory, config_settings=None, metadata_directory=None):
    package = build_package()
    version = project_version()
    info = f"{NAME}-{version}.dist-info"
    wheel_name = f"{NAME}-{version}-{wheel_tag()}.whl"
    files = {f"{NAME}/{path.relative_to(package).as_posix()}": path.read_bytes()
             for path in sorted(package.rglob("*")) if path.is_file() and "__pycache__" not in path.parts}
    files[f"{info}/METADATA"] = metadata().encode()
    files[f"{info}/WHEEL"] = (f"Wheel-Version: 1.0\nGenerator: {NAME} wheel_backend\nRoot-Is-Purelib: false\n"
                              f"Tag: {wheel_tag()}\n").encode()
    record = [record_line(name, data) for name, data in files.items()] + [f"{info}/RECORD,,"]
    files[f"{info}/RECORD"] = ("\n".join(record) + "\n").encode()
    partial = Path(wheel_directory) / (wheel_name + ".partial")
    with zipfile.ZipFile(partial, "w", compression=zipfile.ZIP_DEFLATED) as wheel:
        for name, data in files.items():
            wheel.writestr(name, data)
    os.replace(partial, Path(wheel_directory) / wheel_name)
    return wheel_name


def get_requires_for_build_wheel(config_settings=None):
    return []
