#!/usr/bin/python3
"""Benchmark of the grader: the CPU time of grading the reference solutions (every task of
course.txt, the grader's build done) with a previous version of the grader and with this one,
side by side in one run.

    /usr/bin/python3 tests/grader/grade_bench.py --previous REV [--rounds N] [--one-core]

REV is a git revision of this repository (its grader is taken from `git archive REV`). Each
version grades as the platforms do (its package.py's PLATFORM_GRADE_OPTIONS; as root also
--protect-reference, as on Gradescope), in a build folder of its own that a first, untimed
grading builds. Then the rounds alternate, previous then this one, so that a machine whose speed
drifts from minute to minute drifts for both alike. Every round grades the reference solutions
with a comment of its own added to each file (new at every run of the benchmark), so that neither
version takes a compiled file from an earlier round. The CPU time is that of the grader and every process it waited for (compilers,
linker, tests). Prints each round, the median ratio this / previous, and the machine; exit
status 1 if a version does not give the reference solutions full points.
"""

import argparse
import json
import os
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
REPO = HERE.parents[1]
sys.path.insert(0, str(HERE))
from course import TASK_FILE, TASKS  # noqa: E402
from time_limits import machine  # noqa: E402


def fail(message):
    print(f"grade_bench: {message}", file=sys.stderr)
    sys.exit(2)


def tree_of(revision, folder):
    """The repository's files at `revision`, unpacked into `folder` (kept between runs)."""
    marker = folder / ".revision"
    commit = subprocess.run(["git", "-C", str(REPO), "rev-parse", "--verify", f"{revision}^{{commit}}"],
                            stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    if commit.returncode != 0:
        fail(f"--previous {revision} is not a revision of this repository; give a commit, e.g. --previous HEAD~3")
    commit = commit.stdout.strip()
    if marker.is_file() and marker.read_text() == commit:
        return folder
    shutil.rmtree(folder, ignore_errors=True)
    folder.mkdir(parents=True)
    archive = subprocess.Popen(["git", "-C", str(REPO), "archive", commit], stdout=subprocess.PIPE)
    subprocess.run(["tar", "-x", "-C", str(folder)], stdin=archive.stdout, check=True)
    if archive.wait() != 0:
        fail(f"git archive {revision} failed")
    marker.write_text(commit)
    return folder


def platform_options(tree):
    """The version's own grading options for the platforms."""
    done = subprocess.run(["/usr/bin/python3", "-c", "import json, package; print(json.dumps(package.PLATFORM_GRADE_OPTIONS))"],
                          cwd=tree / "tests" / "grader", stdout=subprocess.PIPE, text=True, check=True)
    options = json.loads(done.stdout)
    return options + (["--protect-reference"] if os.geteuid() == 0 else [])


def reference_copy(tree, folder, mark):
    """The reference solutions of `tree` in `folder`, each file ending with a comment `mark`."""
    shutil.rmtree(folder, ignore_errors=True)
    folder.mkdir(parents=True)
    for task in TASKS:
        source = tree / "solutions" / TASK_FILE[task]
        comment = f"\n/* {mark} */\n" if source.suffix == ".c" else f"\n// {mark}\n"
        (folder / source.name).write_text(source.read_text() + comment)
    return folder


def grade(tree, submission, work, options, one_core):
    """Grades `submission` with the grader of `tree`; returns (CPU seconds, wall seconds, score,
    maximum)."""
    results = work / "results"
    command = ["/usr/bin/python3", str(tree / "tests" / "grader" / "grade.py"), "--submission", str(submission),
               "--build", str(work / "build"), "--results", str(results), "--brief", *options]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    started = time.monotonic()
    done = subprocess.run((["taskset", "-c", "0"] if one_core else []) + command, stdout=subprocess.PIPE,
                          stderr=subprocess.STDOUT, text=True)
    wall = time.monotonic() - started
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if done.returncode != 0:
        fail(f"grading with {tree} failed:\n{done.stdout[-3000:]}")
    report = json.loads((results / "results.json").read_text())
    maximum = sum(test["max_score"] for test in report["tests"])
    cpu = after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime
    return cpu, wall, report["score"], maximum


def main(argv=None):
    parser = argparse.ArgumentParser(prog="grade_bench", description=__doc__.split("\n\n")[0])
    parser.add_argument("--previous", required=True, help="git revision whose grader to compare with")
    parser.add_argument("--rounds", type=int, default=5, help="timed gradings per version (default 5)")
    parser.add_argument("--one-core", action="store_true", help="grade on one core (taskset -c 0)")
    parser.add_argument("--work", type=Path, default=REPO / "build" / "grade-bench",
                        help="folder for the previous tree and both build folders (default build/grade-bench)")
    arguments = parser.parse_args(argv)
    if arguments.rounds < 1:
        fail("--rounds must be at least 1")
    if not (REPO / "solutions").is_dir():
        fail("the benchmark grades the reference solutions, which this copy has not (solutions/)")
    work = arguments.work.absolute()
    versions = {"previous": tree_of(arguments.previous, work / "previous-tree"), "this": REPO}
    options = {name: platform_options(tree) for name, tree in versions.items()}
    print(f"grade_bench: {machine()}; {'one core' if arguments.one_core else 'every core'}; "
          f"{'as root, with --protect-reference' if os.geteuid() == 0 else 'as a user'}", flush=True)
    for name, tree in versions.items():
        print(f"  {name}: {' '.join(options[name])}", flush=True)
        # The untimed first grading: the grader's build, and what else a version does once.
        grade(tree, reference_copy(tree, work / name / "submission", "warm-up"), work / name, options[name],
              arguments.one_core)
    rows = []
    run_mark = os.urandom(8).hex()
    print(f"\n{'round':>5}  {'previous CPU s':>14}  {'this CPU s':>10}  {'ratio':>6}  (wall s: previous, this)")
    for round_number in range(1, arguments.rounds + 1):
        row = {}
        for name, tree in versions.items():
            # A mark of its own each round and run: a grader that remembers compiled files by their
            # text compiles them all the same.
            submission = reference_copy(tree, work / name / "submission", f"round {round_number} of run {run_mark}")
            cpu, wall, score, maximum = grade(tree, submission, work / name, options[name], arguments.one_core)
            if score != maximum:
                print(f"grade_bench: the {name} grader gave the reference solutions {score} of {maximum} points")
                return 1
            row[name] = (cpu, wall)
        rows.append(row)
        print(f"{round_number:>5}  {row['previous'][0]:>14.1f}  {row['this'][0]:>10.1f}  "
              f"{row['this'][0] / row['previous'][0]:>6.2f}  ({row['previous'][1]:.1f}, {row['this'][1]:.1f})",
              flush=True)
    ratios = [row["this"][0] / row["previous"][0] for row in rows]
    print(f"\nmedian CPU time: previous {statistics.median(r['previous'][0] for r in rows):.1f} s, this "
          f"{statistics.median(r['this'][0] for r in rows):.1f} s; median ratio this / previous "
          f"{statistics.median(ratios):.2f} (rounds {min(ratios):.2f} to {max(ratios):.2f})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
