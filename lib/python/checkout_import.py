"""Makes Debian's /usr/bin/python3 import `billiard` from the checkout it runs in.

`./build.sh python` (and `./build.sh test`) install this file into the user's site-packages as
_billiard_checkout.py, beside a billiard.pth that imports it when Python starts and a
billiard-builds.txt that lists the builds registered, one per checkout, the latest last
(register_checkout.py writes all three). When `import billiard` finds nothing on sys.path
(PYTHONPATH comes first and always wins), the finder below walks up from the current folder to
the first billiard checkout (a folder holding lib/python/billiard/) and imports the package built
there: the build registered for that checkout, else the one of $BILLIARD_PRESET, else the one built
last. Outside every checkout it imports the build registered last. A checkout without a build says
so on standard error, once, naming the build imported instead and the command that builds its own.
Standard library only: it runs at every start of Python.
"""

import importlib.machinery
import os
import sys
from pathlib import Path

BUILDS = Path(__file__).with_name("billiard-builds.txt")


def registered_builds():
    """The registered builds' python folders, the latest last."""
    try:
        return [Path(line) for line in BUILDS.read_text().splitlines() if line.strip()]
    except OSError:
        return []


def checkout_of(folder):
    """The billiard checkout that holds `folder`, or None."""
    for candidate in [folder, *folder.parents]:
        if (candidate / "lib" / "python" / "billiard" / "__init__.py").is_file():
            return candidate
    return None


def is_build(folder):
    return (folder / "billiard" / "__init__.py").is_file()


def build_of(checkout, registered):
    """The python folder of `checkout`'s build to import, or None if it has none."""
    own = [folder for folder in registered if folder.is_relative_to(checkout) and is_build(folder)]
    if own:
        return own[-1]
    preset = os.environ.get("BILLIARD_PRESET")
    if preset and is_build(checkout / "build" / preset / "python"):
        return checkout / "build" / preset / "python"

    def built(folder):
        return max((path.stat().st_mtime for path in (folder / "billiard").glob("_billiard*.so")), default=0.0)
    builds = [folder for folder in (checkout / "build").glob("*/python") if is_build(folder)]
    return max(builds, key=built, default=None)


class CheckoutFinder:
    """A finder, last in sys.meta_path, for `billiard` alone (its modules follow its __path__)."""
    warned = set()

    @classmethod
    def find_spec(cls, name, path=None, target=None):
        if name != "billiard":
            return None
        registered = registered_builds()
        try:
            checkout = checkout_of(Path.cwd())
        except OSError:
            checkout = None
        folder = build_of(checkout, registered) if checkout else None
        if folder is None:
            fallback = next((build for build in reversed(registered) if is_build(build)), None)
            if checkout is not None and checkout not in cls.warned:
                cls.warned.add(checkout)
                instead = f"importing {fallback} instead" if fallback else "nothing to import"
                print(f"billiard: {checkout} has no build of the Python module ({instead}); build it there with "
                      "./build.sh python", file=sys.stderr)
            folder = fallback
        if folder is None:
            return None
        return importlib.machinery.PathFinder.find_spec(name, [str(folder)])


def install():
    if not any(getattr(finder, "__name__", "") == "CheckoutFinder" for finder in sys.meta_path):
        sys.meta_path.append(CheckoutFinder)


install()
