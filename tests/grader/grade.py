#!/usr/bin/python3
"""Grades the course's tasks of a submission (tests/grader/course.txt: the six tasks and the
extension stages that are not switched off) and writes what the grading platforms read.

    /usr/bin/python3 tests/grader/grade.py [--submission DIR] [--results DIR] [options]

For each task it compiles the submitted file on its own, once, in the task's cell (a file that
does not compile, or defines or calls what a task file may not, scores 0 for its task, with the
reason as feedback), links the task's worker with it (and, where the reference solutions exist,
with the reference code of the tasks it uses, course.txt's "uses", so that a mistake in one task
cannot cost points in another, and the other tasks' stand-ins, so that no other task's reference
code answers for it), then
runs every graded test in a judge process and a worker process of its own, with time and
resource limits. The judge (the task's graded suite) holds no submitted code: it calls the
student's functions in the worker and judges their answers, so an early exit, a crash, a hang or
anything the code forges costs its own test's points and nothing more.

The rooms of the grader: building.py (the grader's build, compiling, what a task file may define,
linking the workers), cell.py (the cells every process of a grading starts in: user ids, seccomp,
Landlock, limits), judging.py (a test's judge and worker, time limits while they run),
time_limits.py (the limits), reports.py (the table, results.json, junit.xml, report.html),
course.py (the course's tasks, from course.txt), progress.py (where a student stands, what next)
and this command line.

The time limits follow the machine where the reference solutions exist (time_limits.py: ten
times what the reference needs here, measured once per build folder and task); otherwise they are fixed
(--timeout, --task-budget). Either way each task has a budget for compiling its file, linking its
worker and running its tests, so a submission, however it misbehaves, is graded within the
grader's own build plus the sum of the budgets, and only the misbehaving task loses points.

Prints a table (task, points / maximum, and each failing test's message and hint), and writes
results.json (Gradescope's format), junit.xml and report.html into --results. A failing visible
test of a task where a state evolves draws its failing case (tests/support/failure_pictures.hpp):
the picture goes to --results/pictures/, its message names it, report.html shows it under the
message and results.json embeds it. Exit status 0 when grading completed (whatever the score), 2
for bad arguments.
"""

import argparse
import contextlib
import json
import os
import sys
import time
from pathlib import Path

import cell
import time_limits
from building import REPO, Build, BuildLock, TaskFileCompiler, build_suites, stage_submission
from judging import ResultCache, place_pictures, run_tests
from course import TASK_FILE, TASKS
from reports import (gradescope_results, googletest_log, junit_xml, print_table, submission_report, task_records,
                     write_atomically)
from time_limits import Deadline, TaskClock, fixed_limits, measured_limits


def fail(message):
    print(f"grade: {message}", file=sys.stderr)
    sys.exit(2)


def parse_arguments(argv):
    parser = argparse.ArgumentParser(prog="grade", description=__doc__.split("\n\n")[0])
    parser.add_argument("--submission", type=Path, default=REPO / "tasks",
                        help="folder with the task files <task>.cpp, or <task>.c for a C task (default: tasks/)")
    parser.add_argument("--results", type=Path,
                        help="folder for results.json and junit.xml (default: build/grade/results; with --class, "
                             "the class's results: build/grade/class)")
    parser.add_argument("--class", dest="class_folder", type=Path, metavar="DIR",
                        help="grade a whole class: DIR (or a .zip or .tar of it) is a folder with an entry per "
                             "student, a Gradescope export, an Autolab download or a folder of GitHub Classroom "
                             "repositories; each student is graded as the platforms grade, on Dask workers, and "
                             "only what changed since the last run (the instructors' guide: \"Grading a class\")")
    parser.add_argument("--workers", type=int,
                        help="with --class, local worker processes (default: the cores this process may use)")
    parser.add_argument("--client", metavar="ADDRESS",
                        help="with --class, grade on the Dask cluster whose scheduler is at ADDRESS "
                             "(tcp://host:8786); its workers need a copy of this repository")
    parser.add_argument("--worker-repo", type=Path, metavar="PATH",
                        help="with --client, where the workers' copy of this repository is (default: this one's path)")
    parser.add_argument("--build", type=Path, default=REPO / "build" / "grade" / "build",
                        help="build folder (default: build/grade/build)")
    parser.add_argument("--work", type=Path,
                        help="folder for this grading's own copy of the submitted files (default: the build "
                             "folder's parent); gradings that share a build folder each need their own")
    parser.add_argument("--prebuilt", action="store_true",
                        help="the build folder is shared with other gradings (the class grader's workers on one "
                             "machine) and was built by --prepare: grade from it without building, unless it is "
                             "not ready")
    parser.add_argument("--dependencies", choices=["reference", "submission"],
                        help="code for the other tasks of each suite: the reference solutions (default where "
                             "solutions/ exists) or the submission's own files")
    parser.add_argument("--task", action="append", choices=TASKS, help="grade only this task (repeatable)")
    parser.add_argument("--limits", choices=["reference", "fixed"],
                        help="time limits: 'reference' (the default where solutions/ exists) gives each test and "
                             f"each task {time_limits.MARGIN} times what the reference solutions need on this machine, "
                             "measured once per build folder; 'fixed' takes --timeout, --task-budget and "
                             "--compile-timeout")
    parser.add_argument("--timeout", type=float, default=60.0,
                        help="with fixed limits, seconds of computing per test (default 60)")
    parser.add_argument("--task-budget", type=float, default=120.0,
                        help="with fixed limits, seconds each task may take in all: compiling its file, linking its "
                             "suite and running its tests (their durations added up, also when two run at once); "
                             "tests left when it is used up fail without running. Grading takes at most the "
                             "grader's own build plus one budget per task (default 120)")
    parser.add_argument("--compile-timeout", type=float, default=60.0,
                        help="with fixed limits, seconds per submitted file, within its task's budget (default 60)")
    parser.add_argument("--total", type=float,
                        help="seconds the graded tasks' budgets may add up to at most (a platform's time limit for a "
                             "submission, less its other work): larger budgets are scaled down to fit")
    parser.add_argument("--deadline", type=float, metavar="SECONDS",
                        help="seconds of wall time after it starts by which the grading ends, however busy the "
                             "machine (a platform's cutoff, less the time to write the results): no test starts "
                             "later, one still running is stopped, and the results are written")
    parser.add_argument("--build-timeout", type=float, default=1800.0,
                        help="seconds for the grader's own build, which does not depend on the submission "
                             "(default 1800)")
    parser.add_argument("--jobs", type=int,
                        help="tests run at once (default: the cores this process may use)")
    parser.add_argument("--protect-reference", action="store_true",
                        help="(as root, the default there) make this repository and the grader's build unreadable "
                             "to every other user while grading: the cells run as user ids of their own, so no "
                             "submission can read the reference code, the hidden tests or the repository's history")
    parser.add_argument("--brief", action="store_true", help="list failing tests without their messages")
    parser.add_argument("--audience", choices=["student", "grader"],
                        help="who reads the report's end: the student who wrote the files (what to do next, "
                             "as ./build.sh test says it) or whoever grades them (a summary per task); default: "
                             "student for the repository's own tasks/, grader for any other folder")
    parser.add_argument("--require-full", action="store_true",
                        help="exit with status 1 unless every graded task has full points (for CI graders such "
                             "as GitHub Classroom's command grader)")
    parser.add_argument("--records", type=Path,
                        help="also write every task's full results (hidden tests included) to this JSON file, "
                             "for the class report; not for students")
    parser.add_argument("--prepare", action="store_true",
                        help="only build the grader and measure the reference's times in --build (in the --task "
                             "tasks, else in every task), grading nothing (the class grader's first step on each "
                             "machine)")
    parser.add_argument("--cache", type=Path,
                        help="folder to remember results by test and executable checksum, so that unchanged "
                             "suites are not run again (for grading many variants; not for untrusted setups)")
    arguments = parser.parse_args(argv)
    if arguments.class_folder is not None:
        if not (REPO / "solutions" / "CMakeLists.txt").is_file():
            fail("--class grades with the reference solutions for the other tasks, which this copy does not have: "
                 "grade a class in the instructors' repository")
        if not arguments.class_folder.exists():
            fail(f"--class {arguments.class_folder} does not exist; give the folder (or archive) of the class")
        if arguments.workers is None:
            arguments.workers = len(os.sched_getaffinity(0))
        if arguments.workers < 1:
            fail("--workers must be at least 1")
        return arguments
    if arguments.results is None:
        arguments.results = REPO / "build" / "grade" / "results"
    for folder in ["submission", "results", "build", "work"]:  # the build's own records hold absolute paths
        if getattr(arguments, folder) is not None:
            setattr(arguments, folder, getattr(arguments, folder).absolute())
    if not arguments.submission.is_dir():
        fail(f"--submission {arguments.submission} is not a folder; give the folder that holds the task files")
    if arguments.dependencies is None:
        arguments.dependencies = "reference" if (REPO / "solutions" / "CMakeLists.txt").is_file() else "submission"
    if arguments.dependencies == "reference" and not (REPO / "solutions" / "CMakeLists.txt").is_file():
        fail("--dependencies reference needs the reference solutions in solutions/, which this copy does not have")
    if arguments.limits is None:
        arguments.limits = "reference" if arguments.dependencies == "reference" else "fixed"
    if arguments.limits == "reference" and arguments.dependencies != "reference":
        fail("--limits reference measures the reference solutions, which --dependencies submission leaves out")
    if arguments.jobs is None:
        arguments.jobs = len(os.sched_getaffinity(0))
    if min(arguments.timeout, arguments.task_budget, arguments.compile_timeout, arguments.build_timeout,
           1 if arguments.total is None else arguments.total, 1 if arguments.deadline is None else arguments.deadline) \
            <= 0 or arguments.jobs < 1:
        fail("--timeout, --task-budget, --compile-timeout, --total, --deadline and --build-timeout must be positive, "
             "and --jobs at least 1")
    if arguments.protect_reference and os.geteuid() != 0:
        fail("--protect-reference needs root (the cells then run as user ids of their own): run as root, or leave it "
             "out")
    arguments.protect_reference = os.geteuid() == 0
    return arguments


def grade(arguments):
    started = time.monotonic()
    tasks = arguments.task or TASKS
    grading = arguments.work or arguments.build.parent
    for folder in {grading, arguments.build.parent}:
        folder.mkdir(parents=True, exist_ok=True)

    # Only the task files are taken from the submission, into a folder of the grader's own.
    if not arguments.prepare:
        staged, problems = stage_submission(arguments.submission, grading)
    build = Build(arguments.build, arguments.dependencies, arguments.build_timeout)
    lock = BuildLock(arguments.build)
    if arguments.prebuilt:
        lock.to_grade()
    building = not (arguments.prebuilt and build.is_ready())
    if building:
        lock.to_build()
        build.mark_ready(False)
        print(f"grade: building the grader's own code and the graded suites in {arguments.build} (a minute or two "
              "the first time, seconds after), with "
              f"{'the reference code for the other tasks' if arguments.dependencies == 'reference' else 'your code for every task'}",
              flush=True)
        build.configure()
        build.prebuild()
    else:
        print(f"grade: grading with the grader built in {arguments.build}", flush=True)
    with contextlib.closing(lock), protected(arguments.protect_reference, build), cell.Cells(build.launcher, TASKS) as cells:
        print(f"grade: each grading in its cells: {cells.protections.describe()}", flush=True)
        compiler = TaskFileCompiler(build, cells)
        limits, factor, slower = task_limits(arguments, build, compiler, cells, grading, tasks)
        if building:  # built and measured: other gradings may use the folder now, and so do we
            build.mark_ready(True)
            lock.to_grade()
        own_build = time.monotonic() - started  # the grader's own work, whatever the submission
        if arguments.prepare:
            print(f"grade: the grader is ready in {arguments.build} ({own_build:.0f} s)", flush=True)
            return []
        deadline = Deadline(arguments.deadline, started)
        clocks = {task: TaskClock(limits[task], deadline) for task in limits}
        results = build_suites(build, compiler, staged, problems, tasks, clocks)
        cache = ResultCache(arguments.cache, limits) if arguments.cache else None
        run_tests(results, build, cells, clocks, arguments.jobs, cache)
        place_pictures(results, cells.root, arguments.results)

    elapsed = time.monotonic() - started
    write_atomically(arguments.results / "results.json",
                     json.dumps(gradescope_results(results, elapsed, arguments.results), indent=2) + "\n")
    write_atomically(arguments.results / "junit.xml", junit_xml(results))
    write_atomically(arguments.results / "googletest.log", googletest_log(results))
    write_atomically(arguments.results / "report.html",
                     submission_report(results, arguments.results, arguments.submission.resolve().name))
    if arguments.records:
        write_atomically(arguments.records.absolute(), json.dumps(task_records(results)) + "\n")
    audience = arguments.audience or ("student" if arguments.submission.resolve() == (REPO / "tasks").resolve()
                                      else "grader")
    print_table(results, verbose=not arguments.brief, own_tasks=audience == "student")
    print(f"\nresults: {arguments.results / 'report.html'} (open it in a browser: each failing test with the picture "
          f"of its case), {arguments.results / 'results.json'} (Gradescope), {arguments.results / 'junit.xml'} (JUnit) "
          f"and {arguments.results / 'googletest.log'} (GoogleTest's own lines of each failure)")
    print(f"grade: {elapsed:.0f} s in all, of which {own_build:.0f} s for the grader's own build; "
          + limits_summary(limits, tasks, factor, slower))
    return results


class protected:
    """As root (--protect-reference): while grading, this repository (the reference solutions,
    the instructor-only tests, the mutants, every build folder in it and the repository's history)
    and the grader's build folder are readable by root alone, not by any cell's or judge's user id;
    their permissions are restored afterwards. Everything a cell needs is copied out first (the
    headers, the compiled objects, the programs: cell.Cells).

    Several gradings may run at once (the class grader's workers): the shared folders' original
    modes and the gradings protecting them are kept in one file under a lock, so the folders
    stay protected until the last grading ends and then get their original modes back, also
    after a grading that was killed (its process is gone)."""

    STATE = REPO / "build" / "grade" / "protected.json"

    def __init__(self, protect, build):
        self.shared = [REPO] if protect else []
        self.own = build.folder if protect and build.folder.is_dir() and not build.folder.is_relative_to(REPO) else None
        self.own_mode = None

    def update(self, change):
        """Runs change(state) on the shared state under the lock, then saves it."""
        import fcntl
        self.STATE.parent.mkdir(parents=True, exist_ok=True)
        with open(self.STATE.with_suffix(".lock"), "w") as lock:
            fcntl.flock(lock, fcntl.LOCK_EX)
            try:
                state = json.loads(self.STATE.read_text())
            except (OSError, ValueError):
                state = {"modes": {}, "gradings": []}
            state["gradings"] = [pid for pid in state["gradings"] if pid != os.getpid() and pid_alive(pid)]
            change(state)
            if state["gradings"]:
                write_atomically(self.STATE, json.dumps(state))
            else:
                self.STATE.unlink(missing_ok=True)

    def __enter__(self):
        if self.own:
            self.own_mode = self.own.stat().st_mode
            os.chmod(self.own, 0o700)
        if not self.shared:
            return self

        def enter(state):
            if not state["gradings"]:  # the first grading: it saves the original modes
                for path, mode in state["modes"].items():  # left by a grading that was killed
                    if Path(path).is_dir():
                        os.chmod(path, mode)
                state["modes"] = {str(path): path.stat().st_mode for path in self.shared}
            for path in self.shared:
                os.chmod(path, 0o700)
            state["gradings"].append(os.getpid())
        self.update(enter)
        return self

    def __exit__(self, *_):
        if self.own:
            os.chmod(self.own, self.own_mode)
        if not self.shared:
            return

        def leave(state):
            if not state["gradings"]:  # the last grading: the original modes come back
                for path, mode in state["modes"].items():
                    if Path(path).is_dir():
                        os.chmod(path, mode)
        self.update(leave)


def pid_alive(pid):
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def task_limits(arguments, build, compiler, cells, grading, tasks):
    """{task: TaskLimits} (of the graded tasks; of every task with fixed limits), the factor by
    which --total scaled the graded tasks' budgets down (1 if not), and how many times slower this
    machine is than where the reference's times were measured (the most of any graded task's; 1 if
    not slower). Limits that follow the machine come from the reference's times in the build
    folder, measured first for the tasks that miss them."""
    slower = 1.0
    if arguments.limits == "fixed":  # every task's: with the submission's code for the other tasks, each is compiled
        limits = {task: fixed_limits(task, arguments.timeout, arguments.task_budget, arguments.compile_timeout)
                  for task in TASKS}
    else:
        saved = reference_times(build, compiler, cells, grading, arguments.jobs, tasks)
        speed = time_limits.machine_speed()
        slowness = {task: time_limits.slower_than_measured(saved[task], speed) for task in tasks}
        slower = max(slowness.values())
        limits = {task: measured_limits(task, saved[task], slowness[task]) for task in tasks}
    factor = time_limits.fit_total({task: limits[task] for task in tasks}, arguments.total) if arguments.total else 1.0
    return limits, factor, slower


def reference_times(build, compiler, cells, grading, jobs, tasks):
    """{task: what the reference solution needs} for `tasks` (see time_limits.save_reference_times),
    from the build folder, the tasks not measured there yet measured now by grading the reference
    in them (every test twice, keeping the longer time) and saved there."""
    catalogs = [build.judge(task) for task in TASKS]
    solutions = [REPO / "solutions" / TASK_FILE[task] for task in TASKS]
    expected = time_limits.fingerprint(catalogs + solutions, compiler.commands)
    saved = time_limits.load_reference_times(build.folder, expected)
    if all(task in saved for task in tasks):
        return saved
    with contextlib.closing(time_limits.reference_times_lock(build.folder)):
        saved = time_limits.load_reference_times(build.folder, expected)  # another grading's, meanwhile
        missing = [task for task in TASKS if task in tasks and task not in saved]
        if not missing:
            return saved
        print(f"grade: measuring what the reference solutions need on this machine in {', '.join(missing)} (once "
              "for this build folder)", flush=True)
        staged, problems = stage_submission(REPO / "solutions", grading, name="reference")
        os.chmod(staged, 0o700)  # the reference code, for the grader's eyes only
        generous = {task: fixed_limits(task, 60.0, 600.0, 120.0) for task in missing}
        clocks = {task: TaskClock(generous[task]) for task in missing}
        results = build_suites(build, compiler, staged, problems, missing, clocks, remembered=False, quiet=True)
        longest = {}
        for _ in range(2):
            for clock in clocks.values():
                clock.left = clock.limits.budget
            run_tests(results, build, cells, clocks, jobs, cache=None, quiet=True)
            for result in results:
                for test in result.tests:
                    cpu, wall = longest.get(test.name, (0.0, 0.0))
                    longest[test.name] = (max(cpu, test.cpu_seconds), max(wall, test.seconds))
        failing = [f"{result.task}: {result.problem or ', '.join(t.name for t in result.tests if not t.passed)}"
                   for result in results if result.problem or result.score < result.maximum]
        if failing:
            raise RuntimeError("the reference solutions do not pass every test here, so their times cannot set the "
                               "limits:\n" + "\n".join(failing))
        times = {result.task: {"compile": result.compile_seconds, "link": result.link_seconds,
                               "tests": {test.name: {"cpu": longest[test.name][0], "wall": longest[test.name][1]}
                                         for test in result.tests}}
                 for result in results}
        time_limits.save_reference_times(build.folder, expected, times)
        return time_limits.load_reference_times(build.folder, expected)


def limits_summary(limits, tasks, factor, slower):
    """One line on the time limits, for the end of the report."""
    budgets = sum(limits[task].budget for task in tasks)
    if not limits[tasks[0]].measured:
        return f"the tasks' time budgets add up to {budgets:.0f} s"
    reference = sum(limits[task].reference_task for task in tasks)
    scaled = f" (scaled down by {factor:.2f} to fit --total)" if factor < 1 else ""
    measured = (f" (this machine is {slower:.1f} times slower than where they were measured: their times scaled "
                "so)" if slower > 1 else "")
    return (f"time limits {time_limits.MARGIN} times what the reference solutions need on this machine{measured} "
            f"({reference:.1f} s for these tasks): budgets adding up to {budgets:.0f} s{scaled}")


def main(argv=None):
    arguments = parse_arguments(sys.argv[1:] if argv is None else argv)
    if arguments.class_folder is not None:
        import grade_class
        return grade_class.main(arguments)
    results = grade(arguments)
    if arguments.require_full and any(result.score < result.maximum for result in results):
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
