#!/usr/bin/python3
"""How long add_random_discs takes to place N discs (default 10,000 of radius 1) in a periodic box,
a square box and the circular table at several area fractions, the median of a few seeds each:

    /usr/bin/python3 lib/bench/placement.py [--n 10000] [--fractions 0.3,0.5,0.7,0.8,0.9]
                                            [--containers periodic,box,table] [--seeds 3]
                                            [--python FOLDER ...]

It imports the `billiard` package /usr/bin/python3 finds (after ./build.sh python), or the one in
each folder given by --python (a build's python/ folder): with several, each in a process of its
own, their times side by side in a column per folder (an older build beside this one). Every
placement is checked valid. A fraction a container cannot take (the walls of a box or a table
cost a few rows of the densest packing's 0.907) is printed as refused.
"""
import argparse
import json
import math
import statistics
import subprocess
import sys
import time


def measure(arguments):
    """{(container, fraction): median seconds, or None when refused} with the billiard package
    this process imports."""
    import billiard
    shapes = {"periodic": lambda area: billiard.periodic_box(math.sqrt(area), math.sqrt(area)),
              "box": lambda area: billiard.box((0, 0), (math.sqrt(area), math.sqrt(area))),
              "table": lambda area: billiard.circular_table(math.sqrt(area / math.pi))}
    times = {}
    for name in arguments.containers.split(","):
        for fraction in [float(f) for f in arguments.fractions.split(",")]:
            area = arguments.n * math.pi / fraction
            seconds = []
            for seed in range(arguments.seeds):
                sim = billiard.Simulation(shapes[name](area))
                started = time.perf_counter()
                try:
                    sim.add_random_discs(arguments.n, 1.0, seed=seed)
                except ValueError:
                    seconds = None
                    break
                seconds.append(time.perf_counter() - started)
                problem = sim.validate()
                if problem is not None:
                    sys.exit(f"placement in the {name} at area fraction {fraction}, seed {seed} is not valid: {problem}")
            times[f"{name} {fraction}"] = None if seconds is None else statistics.median(seconds)
    return times


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--n", type=int, default=10000)
    parser.add_argument("--fractions", default="0.3,0.5,0.7,0.8,0.9")
    parser.add_argument("--containers", default="periodic,box,table")
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--python", action="append", default=[],
                        help="a build's python/ folder to import billiard from (repeatable: a column each)")
    parser.add_argument("--json", action="store_true", help=argparse.SUPPRESS)  # one column, for the parent
    arguments = parser.parse_args()
    if arguments.json or len(arguments.python) <= 1:
        sys.path[:0] = arguments.python
        times = measure(arguments)
        if arguments.json:
            print(json.dumps(times))
            return 0
        columns = {arguments.python[0] if arguments.python else "billiard": times}
    else:
        columns = {}
        for folder in arguments.python:
            command = [sys.executable, __file__, "--json", "--python", folder, "--n", str(arguments.n),
                       "--fractions", arguments.fractions, "--containers", arguments.containers,
                       "--seeds", str(arguments.seeds)]
            columns[folder] = json.loads(subprocess.run(command, check=True, stdout=subprocess.PIPE, text=True).stdout)
    print(f"add_random_discs: {arguments.n} discs of radius 1, median of {arguments.seeds} seeds, seconds")
    for number, folder in enumerate(columns, 1):
        print(f"  [{number}] {folder}")
    print(f"{'container':<10}{'fraction':>9}" + "".join(f"{f'[{number}]':>12}" for number in range(1, len(columns) + 1)))
    for key in next(iter(columns.values())):
        name, fraction = key.split()
        cells = [columns[folder].get(key) for folder in columns]
        print(f"{name:<10}{fraction:>9}" + "".join(f"{'refused' if s is None else f'{s:.3f}':>12}" for s in cells))
    return 0


if __name__ == "__main__":
    sys.exit(main())
