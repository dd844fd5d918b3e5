#!/usr/bin/python3
"""Benchmark of class grading: a class of 21 students (test_class.py's) graded on local Dask
workers against the same students graded one after another, side by side in one run.

    /usr/bin/python3 tests/grader/grade_class_bench.py [--workers 2] [--rounds 2] [--all-tasks]

Each round grades the class both ways from scratch (new results folders; the grader's build
folders, one per worker and one for the serial run, built before the first round), alternating
which goes first, and prints their wall times and ratio; then the time of a run again of the
finished class, which grades nobody. By default the class is graded in test_class.py's three
tasks; --all-tasks grades every task of course.txt (slower), and --distinct makes every file of
every student different, so that no file is graded once for several students.
"""

import argparse
import os
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
sys.path.insert(0, str(HERE / "tests"))  # the class of its tests
import grade_class  # noqa: E402
import package  # noqa: E402
import test_class  # noqa: E402
from course import TASK_FILE, TASKS  # noqa: E402


def timed(command):
    started = time.monotonic()
    done = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if done.returncode != 0:
        sys.exit(f"grade_class_bench: {' '.join(command[:4])} ... failed:\n{done.stdout[-3000:]}")
    return time.monotonic() - started


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--rounds", type=int, default=2)
    parser.add_argument("--all-tasks", action="store_true")
    parser.add_argument("--distinct", action="store_true",
                        help="every student hands in every task's file, each different from everyone else's (the "
                             "reference solutions with a comment of their own), so nothing is graded once for many")
    arguments = parser.parse_args()
    tasks = TASKS if arguments.all_tasks else test_class.GRADED
    work = Path(tempfile.mkdtemp(prefix="billiard-class-bench-"))
    students = test_class.the_class(mutants_per_task=None)
    if arguments.distinct:
        students = {student: {TASK_FILE[task]: files.get(TASK_FILE[task], (REPO / "solutions" / TASK_FILE[task]).read_bytes())
                              + f"\n/* {student} */\n".encode() for task in TASKS}
                    for student, files in students.items()}
    test_class.write_layout("folders", students, work / "class")
    task_options = [word for task in tasks for word in ("--task", task)]

    def in_class(results):
        return timed(["/usr/bin/python3", str(HERE / "grade.py"), "--class", str(work / "class"), "--results",
                      str(results), "--workers", str(arguments.workers), *task_options])

    def one_by_one():
        for student, files in sorted(students.items()):
            submission = work / "serial" / "submission"
            shutil.rmtree(submission, ignore_errors=True)
            submission.mkdir(parents=True)
            for task in TASKS:
                (submission / TASK_FILE[task]).write_bytes(files.get(TASK_FILE[task])
                                                           or (REPO / "tasks" / TASK_FILE[task]).read_bytes())
            command = ["/usr/bin/python3", str(HERE / "grade.py"), "--submission", str(submission), "--results",
                       str(work / "serial" / "results"), "--build", str(work / "serial-build"),
                       *grade_class.grading_options(tasks)]
            if os.geteuid() == 0:
                command.append("--protect-reference")
            timed(command)

    print(f"class of {len(students)} students, tasks {', '.join(tasks)}; {arguments.workers} workers; "
          "building the graders first", flush=True)
    in_class(work / "warm")
    started = time.monotonic()
    one_by_one()
    print(f"warm-up done (serial {time.monotonic() - started:.0f} s)", flush=True)
    ratios = []
    for round_number in range(arguments.rounds):
        results = work / f"results-{round_number}"
        order = ["class", "serial"] if round_number % 2 == 0 else ["serial", "class"]
        seconds = {}
        for way in order:
            if way == "class":
                seconds[way] = in_class(results)
            else:
                started = time.monotonic()
                one_by_one()
                seconds[way] = time.monotonic() - started
        ratios.append(seconds["class"] / seconds["serial"])
        print(f"round {round_number + 1}: class on {arguments.workers} workers {seconds['class']:.1f} s, "
              f"one by one {seconds['serial']:.1f} s, ratio {ratios[-1]:.2f}", flush=True)
        again = in_class(results)
        print(f"round {round_number + 1}: the finished class again: {again:.1f} s (grades nobody)", flush=True)
    print(f"median ratio class / one by one: {statistics.median(ratios):.2f} ({len(ratios)} rounds)")
    shutil.rmtree(work, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
