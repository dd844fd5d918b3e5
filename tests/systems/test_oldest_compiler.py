#!/usr/bin/python3
"""Every translation unit of a build compiled again by GCC 11 (Ubuntu 22.04's, the oldest compiler
the project supports), with the build's own flags, warnings included: none may fail or warn.
-fsyntax-only checks the language, the headers and every template instantiated, not the code
generation. Debian 12 has GCC 11 as the package g++-11; where it is missing, the test says so
and is skipped (exit status 77).

    /usr/bin/python3 tests/systems/test_oldest_compiler.py BUILD/compile_commands.json
"""

import concurrent.futures
import json
import os
import shlex
import shutil
import subprocess
import sys

OLDEST = "11"
SKIPPED = 77


def compile_again(entry, compilers):
    """(file, exit status, what the compiler printed) for one compile_commands.json entry."""
    arguments = entry["arguments"] if "arguments" in entry else shlex.split(entry["command"])
    arguments = [compilers[entry["file"].endswith(".c")], *arguments[1:]]
    if "-o" in arguments:
        at = arguments.index("-o")
        del arguments[at:at + 2]
    done = subprocess.run([*arguments, "-fsyntax-only"], cwd=entry["directory"], stdout=subprocess.PIPE,
                          stderr=subprocess.STDOUT, text=True, errors="replace")
    return entry["file"], done.returncode, done.stdout


def main():
    if len(sys.argv) != 2:
        print(__doc__)
        return 2
    compilers = {False: shutil.which(f"g++-{OLDEST}"), True: shutil.which(f"gcc-{OLDEST}")}
    if not all(compilers.values()):
        print(f"skipped: GCC {OLDEST} is not installed (Debian 12's g++-{OLDEST}; ./build.sh test installs it where "
              "the system has it): the build is not tried with the oldest compiler here")
        return SKIPPED
    with open(sys.argv[1]) as file:
        entries = json.load(file)
    with concurrent.futures.ThreadPoolExecutor(len(os.sched_getaffinity(0))) as pool:
        results = list(pool.map(lambda entry: compile_again(entry, compilers), entries))
    complaints = [(name, status, output) for name, status, output in results if status != 0 or output.strip()]
    for name, status, output in complaints:
        print(f"{name}: GCC {OLDEST} {'fails' if status else 'warns'}:\n{output[-3000:]}")
    version = subprocess.run([compilers[False], "-dumpfullversion"], stdout=subprocess.PIPE, text=True).stdout.strip()
    print(f"{len(entries)} translation units compiled by GCC {version}: {len(complaints)} fail or warn")
    return 1 if complaints else 0


if __name__ == "__main__":
    sys.exit(main())
