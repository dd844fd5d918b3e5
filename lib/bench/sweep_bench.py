#!/usr/bin/python3
"""How much billiard.sweep gains from worker processes: notebook 04's equation-of-state sweep
(section 1: 12 area fractions x 4 seeds, 1,000 discs in a periodic box, 20,000 collisions of
equilibration and 40,000 measured per run) timed in this process (workers=0), on local Dask worker
processes, and, for scale, in a plain multiprocessing pool of as many processes (what the machine
itself gives without Dask), in turns (serial, Dask, pool, serial, ...) so that all see the same
machine.

    /usr/bin/python3 lib/bench/sweep_bench.py [--workers 2] [--repeats 3] [--seeds 4]

Prints each round's seconds and ratios to serial, the median ratio Dask / serial (the figure to
compare with 1 / workers; the workers are started once, before the timings), the same with the
workers' start counted in each sweep (what a single sweep with client=None costs) and the pool's
median ratio. It checks that all three give the same numbers. The module billiard must be
importable (./build.sh python).
"""

import argparse
import multiprocessing
import statistics
import sys
import time

N, RADIUS, ETAS = 1000, 1.0, [round(0.05 * k, 2) for k in range(1, 13)]
EQUILIBRATION, MEASURED = 20 * N, 40_000


def measure_periodic(eta, seed):
    """Notebook 04's periodic-box run, reduced to its compressibility factor Z."""
    import numpy as np  # imported where used, so that --help works without them

    import billiard

    side = np.sqrt(N * np.pi * RADIUS**2 / eta)
    sim = billiard.Simulation(billiard.periodic_box(side, side))
    sim.add_random_discs(N, RADIUS, seed=seed)
    sim.advance(events=EQUILIBRATION)
    virial, start = sim.totals["virial"], sim.time
    sim.advance(events=MEASURED)
    kT = sim.kinetic_energy() / N
    return 1 + (sim.totals["virial"] - virial) / (2 * (sim.time - start)) / (N * kT)


def measure_task(task):
    """measure_periodic for the pool, which passes one argument."""
    return measure_periodic(*task)


class OneLineParser(argparse.ArgumentParser):
    def error(self, message):
        print(f"sweep_bench: {message}; see --help", file=sys.stderr)
        sys.exit(2)


def positive(text):
    try:
        value = int(text)
    except ValueError:
        value = 0
    if value < 1:
        raise argparse.ArgumentTypeError(f"expected a whole number >= 1, got {text!r}")
    return value


def main():
    parser = OneLineParser(prog="sweep_bench", description=__doc__.split("\n\n")[0])
    parser.add_argument("--workers", type=positive, default=2, help="local worker processes (default 2)")
    parser.add_argument("--repeats", type=positive, default=3, help="rounds of timings (default 3)")
    parser.add_argument("--seeds", type=positive, default=4, help="seeds per area fraction (default 4)")
    options = parser.parse_args()

    import billiard  # after the options, so that --help works without the module

    grid = {"eta": ETAS}
    runs = len(ETAS) * options.seeds
    print(f"sweep_bench: notebook 04's EOS sweep, {len(ETAS)} area fractions x {options.seeds} seeds = {runs} runs "
          f"of {N} discs, {EQUILIBRATION + MEASURED} collisions each")
    clock = time.perf_counter()
    client = billiard.local_client(options.workers)
    start_seconds = time.perf_counter() - clock
    print(f"{options.workers} Dask worker processes started in {start_seconds:.2f} s")
    pool = multiprocessing.get_context("spawn").Pool(options.workers)
    tasks = [(eta, seed) for eta in ETAS for seed in range(options.seeds)]
    print(f"{'round':>5s} {'serial (s)':>11s} {'Dask (s)':>9s} {'ratio':>6s} {'pool (s)':>9s} {'ratio':>6s}")
    ratios, ratios_with_start, pool_ratios, same = [], [], [], True
    try:
        pool.map(measure_task, tasks[:options.workers], chunksize=1)  # the pool's processes imported billiard
        for round_ in range(1, options.repeats + 1):
            clock = time.perf_counter()
            serial = billiard.sweep(measure_periodic, grid, seeds=options.seeds, workers=0, quiet=True, as_frame=False)
            serial_seconds = time.perf_counter() - clock
            clock = time.perf_counter()
            parallel = billiard.sweep(measure_periodic, grid, seeds=options.seeds, client=client, quiet=True,
                                      as_frame=False)
            parallel_seconds = time.perf_counter() - clock
            clock = time.perf_counter()
            pooled = pool.map(measure_task, tasks, chunksize=1)
            pool_seconds = time.perf_counter() - clock
            results = [r["result"] for r in serial]
            same = same and results == [r["result"] for r in parallel] and results == pooled
            same = same and all(r["error"] is None for r in serial + parallel)
            ratios.append(parallel_seconds / serial_seconds)
            ratios_with_start.append((parallel_seconds + start_seconds) / serial_seconds)
            pool_ratios.append(pool_seconds / serial_seconds)
            print(f"{round_:5d} {serial_seconds:11.2f} {parallel_seconds:9.2f} {ratios[-1]:6.2f} "
                  f"{pool_seconds:9.2f} {pool_ratios[-1]:6.2f}")
    finally:
        pool.terminate()
        client.close()
    print(f"median ratio Dask / serial: {statistics.median(ratios):.2f} with {options.workers} workers "
          f"(ideal {1 / options.workers:.2f})")
    print(f"counting the workers' start in each Dask sweep: {statistics.median(ratios_with_start):.2f}")
    print(f"for scale, a plain process pool of {options.workers}: {statistics.median(pool_ratios):.2f}")
    print(f"same numbers serial, on Dask and in the pool: {'yes' if same else 'NO'}")
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(main())
