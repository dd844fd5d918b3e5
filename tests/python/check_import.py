"""Checks what the README promises after its set-up (./build.sh test or ./build.sh python):
Debian's /usr/bin/python3 imports `billiard` from the repository root and from notebooks/,
without PYTHONPATH, and gets the package built here (registered by lib/python/register_checkout.py;
test_checkouts.py checks several checkouts on one machine).

    /usr/bin/python3 tests/python/check_import.py BUILD_PYTHON_FOLDER
"""
import os
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]


def main():
    expected = Path(sys.argv[1]).resolve() / "billiard"
    environment = {key: value for key, value in os.environ.items() if key != "PYTHONPATH"}
    problems = []
    for folder in [REPO, REPO / "notebooks"]:
        done = subprocess.run(["/usr/bin/python3", "-c", "import billiard; print(billiard.__file__)"], cwd=folder,
                              env=environment, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        if done.returncode != 0:
            problems.append(f"from {folder}: import billiard failed:\n{done.stdout.strip()}")
        elif Path(done.stdout.strip()).resolve().parent != expected:
            problems.append(f"from {folder}: imported {done.stdout.strip()}, not the package in {expected}")
    if problems:
        print("\n".join(problems))
        print("Run ./build.sh python (or ./build.sh test): it registers this build's package for /usr/bin/python3.")
        sys.exit(1)
    print(f"import billiard works from {REPO} and {REPO / 'notebooks'}: {expected}")


if __name__ == "__main__":
    main()
