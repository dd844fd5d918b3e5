#!/usr/bin/python3
"""Registers a build of the Python module `billiard` for Debian's /usr/bin/python3.

    /usr/bin/python3 lib/python/register_checkout.py BUILD_PYTHON_FOLDER

Writes into the user's site-packages the finder that imports `billiard` from the checkout Python
runs in (checkout_import.py, as _billiard_checkout.py), the billiard.pth that installs it, and
adds the build to billiard-builds.txt (one build per checkout, this one last: the one imported
outside every checkout). ./build.sh python and ./build.sh test run it.
"""

import shutil
import site
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent


def main():
    if len(sys.argv) != 2:
        print(__doc__.strip(), file=sys.stderr)
        return 2
    build = Path(sys.argv[1]).resolve()
    if not (build / "billiard" / "__init__.py").is_file():
        print(f"register_checkout: {build} holds no built package billiard; build it with ./build.sh python",
              file=sys.stderr)
        return 2
    sys.path.insert(0, str(HERE))
    import checkout_import
    checkout = checkout_import.checkout_of(build)
    user_site = Path(site.getusersitepackages())
    user_site.mkdir(parents=True, exist_ok=True)
    shutil.copyfile(HERE / "checkout_import.py", user_site / "_billiard_checkout.py")
    listed = user_site / checkout_import.BUILDS.name
    builds = [line for line in (listed.read_text().splitlines() if listed.is_file() else [])
              if line.strip() and (checkout is None or not Path(line).is_relative_to(checkout))]
    listed.write_text("\n".join([*builds, str(build)]) + "\n")
    (user_site / "billiard.pth").write_text("import _billiard_checkout\n")
    print(f"/usr/bin/python3 imports billiard from the checkout it runs in; here from {build} "
          f"(registered in {listed})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
