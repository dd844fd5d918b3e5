#!/usr/bin/python3
"""How long add_random_discs takes to place N discs (default 10,000 of radius 1) in a periodic box
at several area fractions, the median of a few seeds each:

    /usr/bin/python3 lib/bench/placement.py [--n 10000] [--fractions 0.3,0.5,0.7,0.8,0.9] [--seeds 3]

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
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--python", help="a build's python/ folder to import billiard from")
    arguments = parser.parse_args()
    if arguments.python:
        sys.path.insert(0, arguments.python)
    import billiard

    print(f"add_random_discs: {arguments.n} discs of radius 1 in a periodic box, median of {arguments.seeds} seeds")
    for fraction in [float(f) for f in arguments.fractions.split(",")]:
        side = math.sqrt(arguments.n * math.pi / fraction)
        seconds = []
        for seed in range(arguments.seeds):
            sim = billiard.Simulation(billiard.periodic_box(side, side))
            started = time.perf_counter()
            sim.add_random_discs(arguments.n, 1.0, seed=seed)
            seconds.append(time.perf_counter() - started)
            problem = sim.validate()
            if problem is not None:
                sys.exit(f"placement at area fraction {fraction}, seed {seed} is not valid: {problem}")
        print(f"area fraction {fraction}: {statistics.median(seconds):.3f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
