#!/usr/bin/python3
"""Compares two builds of billiard_bench in one interleaved run and prints their ratio per row.

This machine's speed drifts by up to 30% from minute to minute, so two runs made one after the
other compare the minutes as much as the builds. Here the two builds take turns, round by round,
in alternating order (before, after; after, before; ...), with the same arguments; each row's
rate is the median over the rounds, and the ratio after / before is printed per row and as a
median over the rows.

    /usr/bin/python3 lib/bench/interleave.py BEFORE AFTER [--rounds 4] -- [billiard_bench options]

BEFORE and AFTER are billiard_bench programs, for example a copy of build/release/lib/bench/
billiard_bench made before a change and the one built after it. Only the engine's rows count
(the course's rows time students' code, which a change to the engine does not touch).
"""
import argparse
import pathlib
import statistics
import subprocess
import sys


def engine_rows(output):
    """{(container, N, eta, g): collisions per second} from billiard_bench's table."""
    rows = {}
    for line in output.splitlines():
        fields = line.split()
        if len(fields) < 6 or fields[0] != "engine" or fields[1] == "container":
            continue
        rows[tuple(fields[1:5])] = float(fields[5])
    return rows


def run(program, arguments):
    done = subprocess.run([program, *arguments], capture_output=True, text=True)
    rows = engine_rows(done.stdout)
    if not rows:
        sys.exit(f"interleave.py: {program} printed no engine rows (exit status {done.returncode}): "
                 f"{(done.stderr or done.stdout).strip()[:300]}")
    return rows


def compare(before, after, rounds, arguments, report=print):
    """Runs both programs `rounds` times in alternating order; returns {row: (before, after)} medians."""
    rates = {"before": [], "after": []}
    programs = {"before": before, "after": after}
    for k in range(rounds):
        for which in (("before", "after") if k % 2 == 0 else ("after", "before")):
            rates[which].append(run(programs[which], arguments))
        report(f"round {k + 1} of {rounds} done")
    common = set.intersection(*(set(r) for r in rates["before"] + rates["after"]))
    return {row: (statistics.median(r[row] for r in rates["before"]), statistics.median(r[row] for r in rates["after"]))
            for row in common}


def table(medians, rounds):
    def order(row):
        return (int(row[1]), row[0], row[2], row[3])
    lines = [f"{'container':10} {'N':>8} {'eta':>6} {'g':>2} {'before/s':>11} {'after/s':>11} {'after/before':>12}"]
    ratios = []
    for row in sorted(medians, key=order):
        b, a = medians[row]
        ratios.append(a / b)
        lines.append(f"{row[0]:10} {row[1]:>8} {row[2]:>6} {row[3]:>2} {b:>11.0f} {a:>11.0f} {a / b:>12.3f}")
    lines.append(f"after / before: median {statistics.median(ratios):.3f} over {len(ratios)} rows "
                 f"(range {min(ratios):.3f} to {max(ratios):.3f}); each rate the median of {rounds} runs")
    return "\n".join(lines)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0],
                                     usage="interleave.py BEFORE AFTER [--rounds N] -- [billiard_bench options]")
    parser.add_argument("before", type=pathlib.Path, help="billiard_bench of the build before the change")
    parser.add_argument("after", type=pathlib.Path, help="billiard_bench of the build after it")
    parser.add_argument("--rounds", type=int, default=4, help="runs of each program, taking turns (default 4)")
    argv = sys.argv[1:] if argv is None else list(argv)
    bench_arguments = argv[argv.index("--") + 1:] if "--" in argv else []
    options = parser.parse_args(argv[:argv.index("--")] if "--" in argv else argv)
    for program in (options.before, options.after):
        if not program.is_file():
            parser.error(f"{program} is not a file; give two billiard_bench programs")
    if options.rounds < 1:
        parser.error(f"--rounds must be at least 1, got {options.rounds}")
    medians = compare(str(options.before), str(options.after), options.rounds, bench_arguments,
                      report=lambda text: print(text, file=sys.stderr))
    print(table(medians, options.rounds))


if __name__ == "__main__":
    main()
