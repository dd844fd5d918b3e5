#!/usr/bin/python3
"""How long add_random_discs takes to place N discs (default 10,000 of radius 1) in a periodic box,
a square box and the circular table at several area fractions, the median of a few seeds each:

    /usr/bin/python3 lib/bench/placement.py [--n 10000] [--fractions 0.3,0.5,0.7,0.8,0.9]
                                            [--containers periodic,box,table] [--seeds 3]

A fraction a container cannot take (the walls of a box or a table cost a few rows of the densest
packing's 0.907) is printed as refused.

It imports the `billiard` package /usr/bin/python3 finds (after ./build.sh python), or the one
in the folder given by --python (a build's python/ folder). Every placement is checked valid.
"""
import argparse
import math
import statistics
import sys
import time


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--n", type=int, default=10000)
    parser.add_argument("--fractions", default="0.3,0.5,0.7,0.8,0.9")
    parser.add_argument("--containers", default="periodic,box,table")
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--python", help="a build's python/ folder to import billiard from")
    arguments = parser.parse_args()
    if arguments.python:
        sys.path.insert(0, arguments.python)
    import billiard

    shapes = {"periodic": lambda area: billiard.periodic_box(math.sqrt(area), math.sqrt(area)),
              "box": lambda area: billiard.box((0, 0), (math.sqrt(area), math.sqrt(area))),
              "table": lambda area: billiard.circular_table(math.sqrt(area / math.pi))}
    print(f"add_random_discs: {arguments.n} discs of radius 1, median of {arguments.seeds} seeds")
    for name in arguments.containers.split(","):
        for fraction in [float(f) for f in arguments.fractions.split(",")]:
            area = arguments.n * math.pi / fraction
            seconds = []
            for seed in range(arguments.seeds):
                sim = billiard.Simulation(shapes[name](area))
                started = time.perf_counter()
                try:
                    sim.add_random_discs(arguments.n, 1.0, seed=seed)
                except ValueError as refused:
                    seconds.append(None)
                    print(f"{name} at area fraction {fraction}, seed {seed}: refused ({refused})")
                    break
                seconds.append(time.perf_counter() - started)
                problem = sim.validate()
                if problem is not None:
                    sys.exit(f"placement in the {name} at area fraction {fraction}, seed {seed} is not valid: {problem}")
            if None not in seconds:
                print(f"{name:<8} area fraction {fraction}: {statistics.median(seconds):.3f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
