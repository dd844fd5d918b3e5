#!/usr/bin/python3
"""Benchmark of class grading: a class of 21 students (test_class.py's) graded on local Dask
workers against the same students graded one after another, side by side in one run.

    /usr/bin/python3 tests/grader/grade_class_bench.py [--workers 2] [--rounds 2] [--all-tasks] [--same-files]

Each round grades the class both ways from nothing: new results folders and no grader built
(the workers' shared build folder, build/grade/workers/<machine>/build, and the serial run's
are removed first; the compiler cache stays), alternating which goes first. It prints each way's
wall time split into the grader's build and the grading, the CPU time it used (how many
processors it kept busy), and their ratio; then the time of a run again of the finished class,
which grades nobody. The last line also gives the ratio that one by one's work would reach if it
kept every processor busy the whole time: the least the class can reach unless each student costs
it less work than one by one. By default every student's files differ from everyone else's (the
class's files, each with a comment of its own), so that no file is graded once for several
students; --same-files keeps the class as it is (the stubs and the reference handed in by many).
The class is graded in test_class.py's tasks; --all-tasks grades every task of course.txt
(slower).
"""

import argparse
import os
import re
import resource
import shutil
import socket
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
import test_class  # noqa: E402
from course import TASK_FILE, TASKS  # noqa: E402


def processor_seconds():
    """CPU seconds of this process's children that have ended, with theirs (the gradings')."""
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def timed(command):
    """(seconds, output, CPU seconds) of a command that must succeed."""
    started, computed = time.monotonic(), processor_seconds()
    done = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if done.returncode != 0:
        sys.exit(f"grade_class_bench: {' '.join(command[:4])} ... failed:\n{done.stdout[-3000:]}")
    return time.monotonic() - started, done.stdout, processor_seconds() - computed


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--rounds", type=int, default=2)
    parser.add_argument("--all-tasks", action="store_true")
    parser.add_argument("--same-files", action="store_true",
                        help="grade the class as it is: files several students hand in alike are graded once")
    arguments = parser.parse_args()
    tasks = TASKS if arguments.all_tasks else test_class.GRADED
    work = Path(tempfile.mkdtemp(prefix="billiard-class-bench-"))
    students = test_class.the_class()
    if not arguments.same_files:
        students = {student: {TASK_FILE[task]: files.get(TASK_FILE[task], (REPO / "solutions" / TASK_FILE[task]).read_bytes())
                              + f"\n/* {student} */\n".encode() for task in TASKS}
                    for student, files in students.items()}
    test_class.write_layout("folders", students, work / "class")
    task_options = [word for task in tasks for word in ("--task", task)]
    workers = REPO / "build" / "grade" / "workers"
    host = re.sub(r"[^A-Za-z0-9._-]", "_", socket.gethostname())

    def in_class(results):
        """(wall seconds, the grader's build in them, CPU seconds)."""
        seconds, output, computed = timed(["/usr/bin/python3", str(HERE / "grade.py"), "--class", str(work / "class"),
                                 "--results", str(results), "--workers", str(arguments.workers), *task_options])
        built = re.search(r"the grader is ready on .* workers \((\d+) s\)", output)
        return seconds, float(built[1]) if built else 0.0, computed

    def one_by_one():
        """(wall seconds, the grader's build in them, CPU seconds)."""
        started, built, computed = time.monotonic(), 0.0, processor_seconds()
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
            built += grade_class.own_build_seconds(timed(command)[1])
        return time.monotonic() - started, built, processor_seconds() - computed

    print(f"class of {len(students)} students, tasks {', '.join(tasks)}, "
          f"{'some files alike' if arguments.same_files else 'every file different'}; {arguments.workers} workers; "
          "each way from no grader built", flush=True)
    ratios, bounds = [], []
    processors = len(os.sched_getaffinity(0))
    for round_number in range(arguments.rounds):
        results = work / f"results-{round_number}"
        order = ["class", "serial"] if round_number % 2 == 0 else ["serial", "class"]
        seconds = {}
        for way in order:
            shutil.rmtree(workers / host / "build" if way == "class" else work / "serial-build", ignore_errors=True)
            seconds[way] = in_class(results) if way == "class" else one_by_one()
        ratios.append(seconds["class"][0] / seconds["serial"][0])
        # One by one's work done on every processor the whole time: the least the class could take.
        bounds.append(seconds["serial"][2] / processors / seconds["serial"][0])
        print(f"round {round_number + 1}: " + ", ".join(
            f"{label} {total:.1f} s (build {built:.0f} s, grading {total - built:.1f} s; {computed:.0f} CPU s, "
            f"{computed / total:.2f} processors busy)"
            for label, (total, built, computed) in [(f"class on {arguments.workers} workers", seconds["class"]),
                                                    ("one by one", seconds["serial"])])
              + f"; ratio {ratios[-1]:.2f}", flush=True)
        again = in_class(results)[0]
        print(f"round {round_number + 1}: the finished class again: {again:.1f} s (grades nobody)", flush=True)
    print(f"median ratio class / one by one: {statistics.median(ratios):.2f} ({len(ratios)} rounds); one by one's "
          f"work on all {processors} processors the whole time would take {statistics.median(bounds):.2f} of its time")
    shutil.rmtree(work, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
