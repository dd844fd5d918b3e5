#!/usr/bin/python3
"""Tests of the grading platforms' packages and the student release (package.py), run by CTest.
They build the packages, unpack them where the platforms would (a fake /autograder folder, a
fake Autolab job folder, a checkout of the student release) and run them there as the
platforms do, from a clean state, checking the scores they report.

    /usr/bin/python3 tests/grader/tests/test_packages.py TESTS_BUILD_FOLDER [unittest arguments]

TESTS_BUILD_FOLDER is the build's tests/ folder: it holds the graded suites test_<task> (for
each task's maximum points), and the tests work in its package-tests/ subfolder.
"""

import contextlib
import csv
import glob
import io
import json
import os
import re
import shlex
import shutil
import stat
import subprocess
import sys
import tarfile
import tempfile
import time
import unittest
import xml.etree.ElementTree as ET
import zipfile
from pathlib import Path
from unittest import mock

import yaml  # Debian's python3-yaml

HERE = Path(__file__).resolve().parent
GRADER = HERE.parent  # the grader, whose tests these are
REPO = HERE.parents[2]
sys.path.insert(0, str(GRADER))
import package  # noqa: E402  (the script under test, for its lists of tasks and exclusions)
import similarity  # noqa: E402  (whether this system can run the copy finder)
import release_check  # noqa: E402  (how the release's README is read: its commands and paths)
import course  # noqa: E402  (the course's tasks)
import time_limits  # noqa: E402

TASKS = package.TASKS
TASK_FILE = course.TASK_FILE  # <task>.cpp, or <task>.c for a C task
TESTS = None  # the build's tests/ folder, from the command line
WORK = None   # TESTS / "package-tests"


def environment(**extra):
    """The environment for the commands under test, without settings of the caller's that would
    change what they do."""
    env = {key: value for key, value in os.environ.items()
           if key not in {"BILLIARD_PRESET", "AUTOGRADER_ROOT", "MAKEFLAGS", "MAKELEVEL", "MFLAGS"}}
    # Each package is built from scratch in a tree of its own below WORK, of the same sources: with
    # the paths below WORK given to the compiler relative to the build folder (and that folder
    # left out of the hash), ccache finds one tree's compiles in another's.
    env.update(CCACHE_BASEDIR=str(WORK), CCACHE_NOHASHDIR="1")
    env.update(extra)
    return env


def run(command, cwd=None, timeout=1800, env=None, shell=False):
    """Runs a command; returns (exit status, combined output)."""
    done = subprocess.run(command, cwd=cwd, env=env or environment(), stdout=subprocess.PIPE,
                          stderr=subprocess.STDOUT, text=True, errors="replace", timeout=timeout, shell=shell)
    return done.returncode, done.stdout


def package_command(*arguments):
    status, output = run(["/usr/bin/python3", str(GRADER / "package.py"), *arguments])
    if status != 0:
        raise AssertionError(f"package.py {' '.join(arguments)} failed with status {status}:\n{output}")
    return output


def fresh(folder):
    shutil.rmtree(folder, ignore_errors=True)
    folder.mkdir(parents=True)
    return folder


def core_busy_seconds(core):
    """Seconds processor `core` has spent on anything since boot (/proc/stat; the time a
    hypervisor gave to other machines included)."""
    with open("/proc/stat") as stat_file:
        for line in stat_file:
            if line.startswith(f"cpu{core} "):
                user, nice, system, _idle, _iowait, irq, softirq, steal = map(int, line.split()[1:9])
                return (user + nice + system + irq + softirq + steal) / os.sysconf("SC_CLK_TCK")
    raise AssertionError(f"/proc/stat has no line for processor {core}")


class OnCoreZero:
    """Times a command pinned to processor 0 (taskset -c 0): its wall time, and that wall time
    less what processor 0 spent on other programs meanwhile (the tests CTest runs beside it),
    which is what the grader's clock counts: a test's duration without its waits for a
    processor."""

    def __enter__(self):
        import resource
        self._children = lambda: sum(resource.getrusage(resource.RUSAGE_CHILDREN)[:2])
        self._started, self._busy, self._own = time.monotonic(), core_busy_seconds(0), self._children()
        return self

    def __exit__(self, *exception):
        self.elapsed = time.monotonic() - self._started
        self.cpu = self._children() - self._own  # the command's, its processes' included
        others = (core_busy_seconds(0) - self._busy) - self.cpu
        self.others = max(0.0, others)
        self.own = self.elapsed - self.others
        return False

    def __str__(self):
        return (f"{self.own:.0f} s ({self.elapsed:.0f} s of wall time, {self.others:.0f} s of it processor 0 ran "
                f"others; {self.cpu:.0f} s of processor time its own)")


_points = {}


def maxima(hidden=True):
    """{task: maximum points} from the built graded suites; without the instructor-only hidden
    tests (what the student release can earn) when `hidden` is false."""
    if hidden not in _points:
        _points[hidden] = package.task_points(TESTS, hidden=hidden)
    return _points[hidden]


def scores_of(report):
    """{task: points} from a Gradescope results.json."""
    scores = {task: 0 for task in TASKS}
    for test in report["tests"]:
        scores[test["name"].split(":")[0]] += test["score"]
    return scores


def broken_propagate():
    """The reference propagate.cpp with a compile error that names `nxt`."""
    text = (REPO / "solutions" / "propagate.cpp").read_text()
    assert "return next;" in text
    return text.replace("return next;", "return nxt;")


def student_release():
    """The student release used by the StudentRelease and Classroom tests (exported if missing)."""
    folder = WORK / "student-release"
    if not (folder / "build.sh").is_file():
        shutil.rmtree(folder, ignore_errors=True)
        package_command("student-release", str(folder))
    return folder


class StudentRelease(unittest.TestCase):
    def test_export_builds_and_grades_the_stubs_as_zero(self):
        folder = WORK / "student-release"
        shutil.rmtree(folder, ignore_errors=True)
        package_command("student-release", str(folder))

        # Nothing that gives answers away, no instructors' tools; the workflow is there.
        for gone in ["solutions", "tests/mutants", "tests/grader/tests", "tests/graded/hidden", "tests/grader/package.py",
                     ".ci", "tests/grader/grade_class.py", "tests/grader/similarity.py"]:
            self.assertFalse((folder / gone).exists(), f"{gone} must not be in the student release")
        for kept in ["build.sh", "tasks/propagate.cpp", "tests/grader/grade.py", "tests/graded/test_movie.cpp",
                     package.WORKFLOW, ".devcontainer/devcontainer.json"]:
            self.assertTrue((folder / kept).is_file(), f"{kept} must be in the student release")
        self.assertTrue(os.access(folder / "build.sh", os.X_OK))
        # build.sh without the class grader's set-up (its copy finder's npm package stays out).
        shipped = (folder / "build.sh").read_text()
        self.assertEqual(shipped, package.INSTRUCTORS_LINES.sub("", (REPO / "build.sh").read_text()))
        self.assertNotIn("copy finder", shipped)
        for path in ["tests/graded/hidden/test_secret.cpp", "tests/mutants/propagate/off_by_one.cpp",
                     "solutions/movie.cpp", "tests/grader/tests/hostile/propagate.cpp"]:
            self.assertTrue(package.excluded(path, package.ALWAYS_EXCLUDED + package.STUDENT_EXCLUDED), path)
        readme = (folder / "README.md").read_text()
        self.assertEqual(readme, package.students_text((REPO / package.STUDENTS_GUIDE).read_text()))
        for gone in ["tasks/README.md", "lib/README.md"]:
            self.assertFalse((folder / gone).exists(), f"{gone} must not be in the student release")
        for word in ["solutions", "instructors", "mutants", "package.py", "hostile"]:
            self.assertNotIn(word, readme, "the student README must not keep the instructors' parts")
        for heading in ["## Quick start", "## The six tasks", "## Your grade", "## The `billiard` command"]:
            self.assertIn(heading, readme)
        self.assertEqual((folder / "tasks" / "propagate.cpp").read_bytes(), (REPO / "tasks" / "propagate.cpp").read_bytes())

        # A git repository with one commit holding every file.
        status, log = run(["git", "-C", str(folder), "log", "--oneline"])
        self.assertEqual((status, len(log.splitlines())), (0, 1), log)
        status, dirty = run(["git", "-C", str(folder), "status", "--porcelain"])
        self.assertEqual((status, dirty), (0, ""))

        # The student's first test run, the README's command on the stubs: it builds and runs
        # their tasks' suites and the commands' tests only, prints a short output, fails graded
        # tests only, and ends with the block that points to task 1. Its time is printed for
        # the README's figure (here ccache may have compiled some files before), not checked.
        started = time.monotonic()
        status, output = run(["./build.sh", "test"], cwd=folder)
        seconds = time.monotonic() - started
        lines = output.rstrip("\n").splitlines()
        print(f"student release: first ./build.sh test: {seconds:.0f} s, {len(lines)} lines", flush=True)
        self.assertNotEqual(status, 0, "the stubs cannot pass")
        self.assertLessEqual(len(lines), 150, output)
        self.assertEqual(lines[-2:], ["Next: write task 1 (init_billiard) in tasks/init_billiard.cpp",
                                      "  then run: ./build.sh test -L init_billiard"])
        self.assertNotIn("Traceback", output, "a task that is not written yet gives one line, not a traceback")
        results = ET.parse(folder / "build" / "tasks" / "Testing" / "results.xml").getroot()
        ran = [(case.get("name"), case.get("status")) for case in results.iter("testcase")]
        self.assertEqual(sorted({name.split(".")[0] for name, _ in ran}),
                         sorted(set(TASKS) | {"cli", "particles_command"}), "the student's tests only")
        failing = [name for name, status in ran if status not in ("run", "notrun")]
        self.assertEqual([name for name in failing if name.split(".")[0] not in TASKS], [], "graded tests only fail")
        self.assertFalse((folder / "build" / "tasks" / "python").exists() and
                         any((folder / "build" / "tasks" / "python").rglob("*.so")), "no Python module built")

        # The command builds from the student's tasks/ and names the task to work on.
        status, output = run(["./build.sh", "run"], cwd=folder)
        self.assertEqual(status, 1, output)
        self.assertIn("not implemented yet", output)
        self.assertTrue((folder / "build" / "tasks" / "billiard").is_file())
        self.assertFalse((folder / "build" / "release").exists())

        # The tests build and run (the tasks preset is the default): one suite here, and every
        # suite in the grader's build below.
        status, output = run(["cmake", "--build", "--preset", "tasks", "--target", "test_visualize_table"], cwd=folder)
        self.assertEqual(status, 0, output)
        status, output = run(["ctest", "--preset", "tasks", "-L", "visualize_table"], cwd=folder)
        self.assertNotEqual(status, 0, "the stubs cannot pass")
        self.assertIn("not implemented yet", output)
        self.assertIn("tests failed out of", output)

        # Local grading: the student's own code for every task; the stubs score 0 everywhere.
        status, output = run(["./build.sh", "grade", "--brief"], cwd=folder)
        self.assertEqual(status, 0, output)
        self.assertIn("your code for every task", output)
        report = json.loads((folder / "build" / "grade" / "results" / "results.json").read_text())
        self.assertEqual(scores_of(report), {task: 0 for task in TASKS})
        self.assertEqual({task: sum(t["max_score"] for t in report["tests"] if t["name"].startswith(task + ":"))
                          for task in TASKS}, maxima(hidden=False))
        self.assertFalse([t for t in report["tests"] if t["visibility"] == "hidden"], "no instructor-only test")
        self.assertNotEqual(maxima(hidden=False), maxima(), "the instructors' suites have hidden tests")


class StagesOff(unittest.TestCase):
    def test_a_stage_switched_off_stays_out_of_the_release(self):
        """course.txt decides: the files of a stage it switches off are not shipped to students."""
        folder = Path(tempfile.mkdtemp(prefix="release-stages-off-"))
        try:
            with mock.patch.object(package.course, "OFF", ["walls"]), contextlib.redirect_stdout(io.StringIO()):
                package.main(["student-release", str(folder / "release"), "--no-git"])
            release = folder / "release"
            self.assertFalse((release / "tasks" / "walls.cpp").exists())
            self.assertFalse((release / "tests" / "graded" / "test_walls.cpp").exists())
            for stage in [stage for stage in ("gravity", "sectors") if stage in TASKS]:
                self.assertTrue((release / "tasks" / f"{stage}.cpp").is_file(), stage)
            self.assertEqual((release / "tests" / "grader" / "course.txt").read_text(),
                             (REPO / "tests" / "grader" / "course.txt").read_text())
        finally:
            shutil.rmtree(folder)


def c_track_alone():
    """A copy of the project whose course.txt keeps only the C track: every C++ task off, particles
    required (what an instructor teaching the box assignment sets)."""
    copy = fresh(WORK / "c-track-alone" / "project")
    for relative in package.project_files():
        (copy / relative).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(REPO / relative, copy / relative)
    course = copy / "tests" / "grader" / "course.txt"
    course.write_text(re.sub(r"^(\d+) (\w+) \w+( uses \S+)?$",
                             lambda line: f"{line[1]} {line[2]} {'required' if line[2] == 'particles' else 'off'}"
                                          f"{line[3] or ''}",
                             course.read_text(), flags=re.MULTILINE))
    return copy


class CTrackAlone(unittest.TestCase):
    def test_grader_release_and_classroom_grade_only_particles(self):
        """The C track alone: the grader gives the reference full marks and the stub 0 for particles
        alone (as the required total), the student release carries the C task and none of the C++
        ones and grades its stub as 0, its `./build.sh run` runs the C program, and the Classroom
        workflow has the one step."""
        project = c_track_alone()
        work = project.parent

        def grade(repository, submission, name):
            status, output = run(["/usr/bin/python3", str(repository / "tests" / "grader" / "grade.py"),
                                  "--submission", str(submission), "--build", str(work / name / "build"),
                                  "--results", str(work / name / "results"), "--brief"])
            self.assertEqual(status, 0, output)
            report = json.loads((work / name / "results" / "results.json").read_text())
            self.assertEqual({test["name"].split(":")[0] for test in report["tests"]}, {"particles"}, output)
            return report, output

        report, output = grade(project, project / "solutions", "solutions")
        maximum = sum(test["max_score"] for test in report["tests"])
        self.assertEqual(report["score"], maximum)
        self.assertRegex(output, rf"total +{maximum} / {maximum}\n", "particles counts in the total")
        report, output = grade(project, project / "tasks", "stubs")
        self.assertEqual(report["score"], 0)
        self.assertIn("not implemented yet: write it in tasks/particles.c", output)

        status, output = run(["/usr/bin/python3", str(project / "tests" / "grader" / "package.py"), "classroom",
                              "--tests", str(work / "solutions" / "build" / "tests")], cwd=project)
        workflow = yaml.safe_load((project / package.WORKFLOW).read_text()) if status == 0 else None
        if status != 0:  # the graded suite itself is built on demand
            run(["cmake", "--build", str(work / "solutions" / "build"), "--target", "test_particles"])
            status, output = run(["/usr/bin/python3", str(project / "tests" / "grader" / "package.py"), "classroom",
                                  "--tests", str(work / "solutions" / "build" / "tests")], cwd=project)
            self.assertEqual(status, 0, output)
            workflow = yaml.safe_load((project / package.WORKFLOW).read_text())
        steps = [step["name"] for step in workflow["jobs"]["run-autograding-tests"]["steps"]]
        self.assertEqual(steps, ["Checkout code", "Task 10 particles", "Autograding Reporter"])

        release = work / "release"
        shutil.rmtree(release, ignore_errors=True)
        status, output = run(["/usr/bin/python3", str(project / "tests" / "grader" / "package.py"), "student-release",
                              str(release), "--no-git"])
        self.assertEqual(status, 0, output)
        self.assertTrue((release / "tasks" / "particles.c").is_file())
        self.assertTrue((release / "tests" / "graded" / "test_particles.cpp").is_file())
        self.assertTrue((release / "tests" / "particles" / "examples" / "three.expected").is_file())
        for gone in ["tasks/propagate.cpp", "tests/graded/test_propagate.cpp", "solutions",
                     "tests/graded/hidden", "tests/mutants"]:
            self.assertFalse((release / gone).exists(), gone)
        report, output = grade(release, release / "tasks", "release")
        self.assertEqual(report["score"], 0)
        self.assertIn("not implemented yet", output)

        # The student's first command: with no `billiard` in this course, it builds the C program
        # and runs it on the README's example (the stub says what to write).
        status, output = run(["./build.sh", "run"], cwd=release)
        self.assertEqual(status, 1, output)
        self.assertIn("task 10 (particles) is not implemented yet: write it in tasks/particles.c", output)
        shutil.copyfile(REPO / "solutions" / "particles.c", release / "tasks" / "particles.c")
        status, output = run(["./build.sh", "run"], cwd=release)
        self.assertEqual(status, 0, output)
        expected = (release / "tests" / "particles" / "examples" / "three.expected").read_text()
        self.assertTrue(output.endswith(expected), f"expected the lines of three.expected at the end:\n{output}")


class StudentLoop(unittest.TestCase):
    """The release as a student uses it: the first test run on the stubs, the edit-and-test loop of
    one task, the run once every task is written, and every command and path its README names."""

    def test_first_run_next_step_loop_and_every_command(self):
        folder = student_release()
        # build.sh registers the release's Python module for the user (a .pth file): a user
        # folder of its own, so that this build's registration stays as it is.
        env = environment(PYTHONUSERBASE=str(fresh(WORK / "student-loop-python")))
        try:
            # Edit one task, test it: only that suite is rebuilt (no other suite, no link-time
            # optimisation). The time is printed for the README's figure, not checked here.
            suites = folder / "build" / "tasks" / "tests"
            before = {name: (suites / name).stat().st_mtime_ns for name in ("test_kinetic_energy", "test_propagate")}
            (folder / "tasks" / "kinetic_energy.cpp").touch()
            started = time.monotonic()
            status, output = run(["./build.sh", "test", "-L", "kinetic_energy"], cwd=folder, env=env)
            seconds = time.monotonic() - started
            print(f"student loop: touch tasks/kinetic_energy.cpp, ./build.sh test -L kinetic_energy: {seconds:.1f} s",
                  flush=True)
            self.assertNotEqual((suites / "test_kinetic_energy").stat().st_mtime_ns, before["test_kinetic_energy"])
            self.assertEqual((suites / "test_propagate").stat().st_mtime_ns, before["test_propagate"])
            self.assertNotIn("lto-wrapper", output)
            self.assertIn("6 kinetic_energy   not written yet", output)

            # Task 1 written: its run passes, and the block names no task whose state it did not see.
            shutil.copyfile(REPO / "solutions" / TASK_FILE["init_billiard"], folder / "tasks" / TASK_FILE["init_billiard"])
            status, output = run(["./build.sh", "test", "-L", "init_billiard"], cwd=folder, env=env)
            self.assertEqual(status, 0, output[-3000:])
            self.assertEqual(output.rstrip("\n").splitlines()[-1],
                             "Every task that ran passes. Next: ./build.sh test, to see where every task stands")

            # Task 1's refusal without the words its task file asks for ("cannot fit"): its own suite
            # passes, the command's test of the refusal fails, and the block counts it under task 1.
            written = (REPO / "solutions" / TASK_FILE["init_billiard"]).read_text()
            self.assertIn("cannot fit", written)
            (folder / "tasks" / TASK_FILE["init_billiard"]).write_text(written.replace("cannot fit", "do not go"))
            status, output = run(["./build.sh", "test", "-L", "init_billiard|cli"], cwd=folder, env=env)
            self.assertNotEqual(status, 0, output[-3000:])
            block = output[output.rindex("Where the tasks stand:"):]
            self.assertRegex(block, r"1 init_billiard +2 of \d+ tests fail", block)  # both refusals of too many circles
            self.assertIn("starting with its first failing test, cli.Cli.TooManyCirclesForTheTableIsRefused", block)
            self.assertIn("then run: ./build.sh test -R 'cli.Cli.TooManyCirclesForTheTableIsRefused'", block)
            shutil.copyfile(REPO / "solutions" / TASK_FILE["init_billiard"], folder / "tasks" / TASK_FILE["init_billiard"])

            # Every task written (the reference code): the tests that use the tasks pass, and the
            # block says so. (The first run above already ran the tests that do not use them.)
            for task in TASKS:
                shutil.copyfile(REPO / "solutions" / TASK_FILE[task], folder / "tasks" / TASK_FILE[task])
            status, output = run(["./build.sh", "test", "-L", "graded|cli|python"], cwd=folder, env=env)
            self.assertEqual(status, 0, output[-5000:])
            self.assertTrue(output.rstrip().endswith("Next: nothing; every test passed. Well done."), output[-2000:])
            # The notebooks run the module the release built from the student's tasks: the tour and
            # the one on the student's own stages here (every notebook runs in the project's tests).
            status, output = run(["ctest", "--preset", "tasks", "-R", r"^notebooks\.(01_tour|07_your_stages)$"],
                                 cwd=folder, env=env)
            self.assertEqual(status, 0, output[-5000:])
            self.assertIn("100% tests passed, 0 tests failed out of 2", output)

            # Every command and path the release names works or exists there.
            status, output = run(["/usr/bin/python3", str(HERE / "release_check.py"), str(folder)], env=env)
            print(output.splitlines()[-1] if output else "", flush=True)
            self.assertEqual(status, 0, output[-8000:])
        finally:
            for task in TASKS:
                shutil.copyfile(REPO / "tasks" / TASK_FILE[task], folder / "tasks" / TASK_FILE[task])


class ProjectCI(unittest.TestCase):
    def test_ci_runs_the_readme_test_command_and_stays_out_of_the_release(self):
        """GitHub's CI runs .ci/run, .ci/run runs the README's test command, and neither ships."""
        workflow = yaml.safe_load((REPO / ".github/workflows/ci.yml").read_text())
        steps = [step for job in workflow["jobs"].values() for step in job["steps"]]
        self.assertIn(".ci/run", [step.get("run") for step in steps])
        # On the Debian systems that the README supports (both proven on fresh roots).
        self.assertEqual(workflow["jobs"]["test"]["strategy"]["matrix"]["system"], ["debian:bookworm", "debian:trixie"])
        self.assertIn("Debian 12 (bookworm)", (REPO / "README.md").read_text())
        self.assertIn("Debian 13 (trixie)", (REPO / "README.md").read_text())
        commands = [line for line in (REPO / ".ci/run").read_text().splitlines() if line and not line.startswith(("#", "set ", "cd ", "trap "))]
        self.assertEqual(commands, ["./build.sh test", "ctest --preset stress", "ctest --preset platforms"])
        self.assertIn("./build.sh test", (REPO / "README.md").read_text())
        for path in [".ci/run", ".github/workflows/ci.yml"]:
            self.assertTrue(package.excluded(path, package.STUDENT_EXCLUDED), f"{path} would ship to students")


class Bounds(unittest.TestCase):
    def test_readme_states_the_limits_the_grader_and_packages_use(self):
        """The instructors' guide's time limits and bounds are the ones grade.py and package.py compute."""
        limits = time_limits
        readme = " ".join((REPO / "tests" / "grader" / "README.md").read_text().split())
        self.assertEqual(limits.MARGIN, 10, "the instructors' guide says 'ten times'")
        statements = [
            f"each test ten times the CPU time the reference takes for it (at least {limits.MIN_TEST_SECONDS:g} s)",
            f"(compiling its file, linking its worker, running its tests; at least {limits.MIN_TASK_SECONDS:g} s)",
            "stopped after twice its limit of time spent",
            f"`--total {package.PLATFORM_TOTAL}`",
            f"budgets adding up to at most {package.PLATFORM_TOTAL} s",
            f"a submission takes at most {package.PLATFORM_TOTAL + package.GRADESCOPE_BUILD_ALLOWANCE} s, the "
            f"tasks' budgets and {package.GRADESCOPE_BUILD_ALLOWANCE} s allowed for checking the prebuilt grader",
            f"the driver stops the grader after {package.GRADESCOPE_CUTOFF} s",
            f"most {package.PLATFORM_TOTAL + package.AUTOLAB_BUILD_ALLOWANCE} s on one core "
            f"({package.AUTOLAB_BUILD_ALLOWANCE} s allowed for the build and the measuring, {package.PLATFORM_TOTAL} s "
            "for the tasks' budgets; the driver stops",
            f"the grader after {package.AUTOLAB_CUTOFF} s",
            f"timeout to {package.AUTOLAB_TIMEOUT} s",
            f"A job then only grades: at most {package.AUTOLAB_PREBUILT_TOTAL + package.AUTOLAB_PREBUILT_ALLOWANCE} s "
            f"(the tasks' budgets, at most {package.AUTOLAB_PREBUILT_TOTAL} s together, and "
            f"{package.AUTOLAB_PREBUILT_ALLOWANCE} s for the rest; the driver stops the grader after "
            f"{package.AUTOLAB_PREBUILT_CUTOFF} s), within Autolab's default autograding timeout of "
            f"{package.AUTOLAB_DEFAULT_TIMEOUT} s",
        ]
        # The measured budgets are the floor but for one task; their sum is that arithmetic's.
        measured = re.search(r"Budgets there are the (\d+) s floor for every task but `(\w+)` \((\d+) s\): "
                             r"(\d+) s for the (\d+) tasks of `course.txt`", readme)
        self.assertIsNotNone(measured, "the guide no longer states the measured budgets")
        floor, task, budget, total, count = measured.groups()
        self.assertEqual(float(floor), limits.MIN_TASK_SECONDS)
        self.assertIn(task, TASKS)
        self.assertEqual(int(count), len(TASKS))
        self.assertEqual(int(total), (len(TASKS) - 1) * int(floor) + int(budget))
        self.assertEqual(limits.WALL_SLACK, 2, "the instructors' guide says 'twice'")
        missing = [statement for statement in statements if statement not in readme]
        self.assertEqual(missing, [], "tests/grader/README.md does not say these (or says other numbers)")
        # The bounds fit the platforms' limits, with the drivers' cut-offs in between.
        self.assertLess(package.PLATFORM_TOTAL + package.GRADESCOPE_BUILD_ALLOWANCE, package.GRADESCOPE_CUTOFF)
        self.assertLess(package.GRADESCOPE_CUTOFF, 600)  # Gradescope's default timeout: 10 minutes
        self.assertLess(package.PLATFORM_TOTAL + package.AUTOLAB_BUILD_ALLOWANCE, package.AUTOLAB_CUTOFF)
        self.assertLess(package.AUTOLAB_CUTOFF, package.AUTOLAB_TIMEOUT)
        self.assertLess(package.AUTOLAB_PREBUILT_TOTAL + package.AUTOLAB_PREBUILT_ALLOWANCE,
                        package.AUTOLAB_PREBUILT_CUTOFF)
        self.assertLess(package.AUTOLAB_PREBUILT_CUTOFF, package.AUTOLAB_DEFAULT_TIMEOUT)


class Guides(unittest.TestCase):
    def test_counts_in_the_guides_follow_the_repository(self):
        """Figures the guides give that follow from the repository: the mutants per kind of task, the
        thresholds of the copies."""
        readme = " ".join((REPO / ".github" / "CONTRIBUTING.md").read_text().split())
        mutants = sorted((REPO / "tests" / "mutants").glob("*/*.mutant"))
        kinds = {"six": 0, "stages": 0, "c": 0}
        for mutant in mutants:
            task = mutant.parent.name
            kinds["c" if task in course.PROGRAM_TASKS else "six" if
                  course.TASK_NUMBER[task] <= 6 else "stages"] += 1
        self.assertIn(f"{len(mutants)} buggy solutions it must catch ({kinds['six']} of the six tasks, "
                      f"{kinds['stages']} of the stages, {kinds['c']} of the C track)", readme)
        # The class grader's thresholds for near-copies, as similarity.py sets them.
        guide = " ".join((GRADER / "README.md").read_text().split())
        self.assertIn(f"found in more than {similarity.SHARED_BY} of a task's different files, or "
                      f"{100 * similarity.SHARED_BY_SHARE:.0f} % of them in a large class", guide)
        self.assertIn(f"over {similarity.COMPARED_FILE_CAP >> 10} KiB", guide)
        self.assertIn(f"least {similarity.SHARE_FLAGGED} % of one file's own code is found in the other, and "
                      f"{similarity.FINGERPRINTS_FLAGGED} of Dolos's fingerprints in all", guide)
        self.assertIn(f"Node.js {similarity.OLDEST_NODE}", guide)

    def test_layout_table_names_every_folder_and_header(self):
        """The README sends readers to the contributors' layout table for the whole layout: every
        folder of the repository (to three levels, or its parent: a mutant's task folder is under
        `tests/mutants/`) and every shared header of lib/include/billiard/ is named there."""
        table = "\n".join(line for line in (REPO / ".github" / "CONTRIBUTING.md").read_text().splitlines()
                          if line.startswith("| `"))
        tracked = subprocess.run(["git", "ls-files"], cwd=REPO, stdout=subprocess.PIPE, text=True).stdout.split()
        if not tracked:
            self.skipTest("not a git checkout")
        folders = {str(Path(path).parent) for path in tracked if 1 <= len(Path(path).parent.parts) <= 3}
        missing = [folder for folder in sorted(folders - {"lib", "tests"})
                   if f"`{folder}/" not in table and f"`{Path(folder).parent}/`" not in table]
        missing += [header.name for header in (REPO / "lib" / "include" / "billiard").glob("*.hpp")
                    if f"`{header.name}`" not in table]
        self.assertEqual(missing, [], "not in the layout table of .github/CONTRIBUTING.md")

    def test_front_page_picture_is_the_commands_movie(self):
        """The README's picture is the movie `billiard 10 1 10` draws with the reference solutions
        (numbers compared to 6 significant digits: another compiler may round the last ones)."""
        output = fresh(WORK / "front-page-movie")
        status, printed = run([str(TESTS.parent / "billiard"), "10", "1", "10", "--output", str(output)])
        self.assertEqual(status, 0, printed)

        def rounded(svg):
            return re.sub(r"-?\d+\.\d+(?:e-?\d+)?", lambda number: f"{float(number.group()):.6g}", svg)
        committed = REPO / "lib" / "app" / "movie-10-1-10.svg"
        self.assertEqual(rounded(committed.read_text()), rounded((output / "movie.svg").read_text()),
                         f"regenerate it: build/release/billiard 10 1 10 --output DIR, then copy DIR/movie.svg "
                         f"to {committed.relative_to(REPO)}")
        self.assertIn(committed.relative_to(REPO).as_posix(), (REPO / "README.md").read_text())

    GUIDES = ["README.md", "tasks/README.md", "tests/grader/README.md", "lib/README.md", ".github/CONTRIBUTING.md"]

    def test_every_path_and_command_in_the_guides_is_there(self):
        """Every repository path the guides show exists, and every command they show names a
        command, preset, label, option or script that exists (checked without running it: the
        student release's check runs the students' commands)."""
        build = TESTS.parent
        presets = json.loads((REPO / "CMakePresets.json").read_text())
        preset_names = {kind: {preset["name"] for preset in presets[kind]}
                        for kind in ("configurePresets", "buildPresets", "testPresets")}
        labels = set(run(["ctest", "--test-dir", str(build), "--print-labels"])[1].split())
        build_help = run(["./build.sh", "--help"], cwd=REPO)[1]
        helps = {"grade": run(["/usr/bin/python3", "tests/grader/grade.py", "--help"], cwd=REPO)[1],
                 "bench": run([str(build / "lib" / "bench" / "billiard_bench"), "--help"])[1],
                 "billiard": run([str(build / "billiard"), "--help"])[1]}
        problems = []
        for guide in self.GUIDES:
            text = (REPO / guide).read_text()
            paths = set(release_check.readme_paths(text)) | set(release_check.CITED_PATH.findall(text))
            for path in sorted(paths):
                path = path.rstrip("/")
                if path.startswith(("build/", "~", "..", "$")) or any(mark in path for mark in ("://", "=", "@")):
                    continue  # what a command writes, a user's folder, a URL, a setting or a GitHub action
                if not glob.glob(str(REPO / re.sub(r"<[^>]*>", "*", path))):
                    problems.append(f"{guide}: {path} does not exist")
            for command in release_check.readme_commands(text):
                words = [release_check.fill(word) for word in shlex.split(command, comments=True)]
                problems += [f"{guide}: `{command}`: {problem}"
                             for problem in self.command_problems(words, preset_names, labels, build_help, helps)]
        self.assertEqual(problems, [], "\n".join(problems))

    @staticmethod
    def command_problems(words, presets, labels, build_help, helps):
        """What is wrong with one command a guide shows ([] when nothing)."""
        def options_missing(help_text, options):
            return [f"no option {option}" for option in options
                    if option.startswith("--") and option.split("=")[0] not in help_text]
        head, rest = words[0], words[1:]
        named_labels = [rest[k + 1] for k, word in enumerate(rest[:-1]) if word in ("-L", "-LE")]
        unknown_labels = [f"no label {label}" for label in named_labels
                          if label.isidentifier() and not label.isupper() and label not in labels]
        if head == "./build.sh":
            sub = rest[0] if rest else ""
            if sub and not sub.startswith("-") and f"./build.sh {sub}" not in build_help:
                return [f"./build.sh has no command {sub}"]
            if sub in ("grade", "bench") and not release_check.is_usage(words):
                return options_missing(helps[sub], rest[1:])
            return unknown_labels
        if head in ("ctest", "cmake"):
            kind = "testPresets" if head == "ctest" else \
                "buildPresets" if "--build" in rest else "configurePresets"
            named = [rest[k + 1] for k, word in enumerate(rest[:-1]) if word == "--preset"]
            return [f"no {kind} preset {name}" for name in named if name not in presets[kind]] + unknown_labels
        if head == "/usr/bin/python3" and rest and not rest[0].startswith("-"):
            if not (REPO / rest[0]).is_file():
                return [f"no script {rest[0]}"]
            status, output = run(["/usr/bin/python3", rest[0], "--help"], cwd=REPO)
            return [] if status == 0 else [f"{rest[0]} --help fails: {output[-300:]}"]
        if head == "billiard" and not release_check.is_usage(words):
            return options_missing(helps["billiard"], rest)
        return []

    def test_students_guide_is_for_students_only(self):
        """The release's README (tasks/README.md without its instructors' parts) speaks to students:
        at most 250 lines, and none of the library's API, the stepper or the clusters."""
        guide = package.students_text((REPO / package.STUDENTS_GUIDE).read_text())
        self.assertLessEqual(len(guide.splitlines()), 250)
        for word in ["billiard.sweep", "Simulation", "stepper", "Dask", "cluster", "solutions/", "mutants",
                     "original Python script", "lib/README.md"]:
            self.assertNotIn(word, guide, f"the students' guide names {word}")
        for command in ["./build.sh run", "./build.sh test", "./build.sh test -L engine", ".devcontainer/"]:
            self.assertIn(command, guide.replace("`", ""), f"the students' guide does not name {command}")


class DevContainer(unittest.TestCase):
    # The properties of devcontainer.json in the Dev Container specification's reference
    # (containers.dev, "Dev Container metadata reference"): general, image and lifecycle ones.
    SPEC_PROPERTIES = {
        "name", "forwardPorts", "portsAttributes", "otherPortsAttributes", "containerEnv", "remoteEnv",
        "remoteUser", "containerUser", "updateRemoteUserUID", "userEnvProbe", "overrideCommand",
        "shutdownAction", "init", "privileged", "capAdd", "securityOpt", "mounts", "features",
        "overrideFeatureInstallOrder", "customizations", "image", "build", "appPort", "workspaceMount",
        "workspaceFolder", "runArgs", "initializeCommand", "onCreateCommand", "updateContentCommand",
        "postCreateCommand", "postStartCommand", "postAttachCommand", "waitFor", "hostRequirements"}

    def test_a_debian_container_whose_setup_is_build_sh(self):
        """The dev container is Debian (bookworm), holds only the specification's properties, sets
        up with the README's own set-up, and ships to students."""
        config = json.loads((REPO / ".devcontainer" / "devcontainer.json").read_text())
        self.assertEqual(set(config) - self.SPEC_PROPERTIES, set())
        self.assertRegex(config["image"], r"(debian|bookworm)")
        self.assertEqual(config["postCreateCommand"], "./build.sh setup")
        self.assertIn("setup", subprocess.run(["./build.sh", "--help"], cwd=REPO, stdout=subprocess.PIPE,
                                              text=True).stdout)
        self.assertFalse(package.excluded(".devcontainer/devcontainer.json", package.STUDENT_EXCLUDED))


class SetUp(unittest.TestCase):
    """build.sh's set-up on a system without some packages, with apt, dpkg and CMake stood in for
    (tools that say what they were asked on a system where nothing is installed yet)."""

    def set_up(self, absent, *command):
        """(exit status, output, the packages apt-get was asked to install) of ./build.sh COMMAND
        where apt has no package in `absent` and every other one."""
        tools = fresh(WORK / f"setup-tools-{self._testMethodName}")
        log = tools / "apt-get.log"
        for name, script in {
                "dpkg-query": "exit 1",  # nothing installed
                # (a long version table after the candidate, as apt's: a reader that stops early
                # leaves apt-cache writing into a closed pipe)
                "apt-cache": 'for p in $FAKE_ABSENT; do [ "$2" = "$p" ] && exit 0; done\n'
                             'printf "%s:\\n  Candidate: 1.0\\n" "$2"; seq 1 20000 | sed "s/^/     1.0 500 /"',
                "apt-get": 'echo "$@" >> "$FAKE_LOG"',
                "sudo": 'exec "$@"',
                "cmake": "exit 3",  # the set-up is done: stop before building
                "node": "exit 1", "npm": "exit 1"}.items():
            (tools / name).write_text(f"#!/bin/sh\n{script}\n")
            (tools / name).chmod(0o755)
        status, output = run([str(REPO / "build.sh"), *command], cwd=REPO,
                             env=environment(PATH=f"{tools}:{os.environ['PATH']}", FAKE_ABSENT=" ".join(absent),
                                             FAKE_LOG=str(log)))
        installs = [line.split()[4:] for line in (log.read_text().splitlines() if log.is_file() else [])
                    if line.startswith("install")]
        return status, output, [name for line in installs for name in line]

    def test_a_package_only_a_feature_needs_costs_that_feature(self):
        status, output, installed = self.set_up(["python3-gsd", "ffmpeg"], "test", "-L", "python")
        self.assertEqual(status, 3, output)  # on to configuring: the stand-in CMake stops it there
        lines = [line for line in output.splitlines() if "has no package" in line]
        self.assertEqual(len(lines), 2, output)
        self.assertRegex(lines[0] + lines[1], r"python3-gsd: GSD trajectories .* will be missing; setting up the rest")
        self.assertRegex(lines[0] + lines[1], r"ffmpeg: MP4 animations will be missing")
        self.assertIn("python3-numpy", installed)
        self.assertNotIn("python3-gsd", installed)
        self.assertNotIn("ffmpeg", installed)

    def test_a_package_the_build_needs_stops_it_at_once(self):
        status, output, installed = self.set_up(["libseccomp-dev"], "setup")
        self.assertEqual(status, 2, output)
        lines = [line for line in output.splitlines() if line.strip() and "apt-get" not in line]
        self.assertEqual(len(lines), 1, output)
        self.assertRegex(lines[0], r"^build.sh: .* has no package libseccomp-dev, which the build needs; ")
        self.assertEqual(installed, [])


class Contributing(unittest.TestCase):
    """The contributors' guide's steps, followed in a copy of the project."""

    STUB = """// Task 11: mean_speed -- the mean speed of the circles.
#include "billiard/course.hpp"
#include "billiard/not_implemented.hpp"

namespace billiard {

double mean_speed(const Velocities& velocities) {
  throw NotImplemented(11, "mean_speed", "tasks/mean_speed.cpp");
  (void)velocities;
}

}  // namespace billiard
"""
    SOLUTION = """#include "billiard/course.hpp"

namespace billiard {

double mean_speed(const Velocities& velocities) {
  if (velocities.rows() == 0) return 0;
  return velocities.rowwise().norm().mean();
}

}  // namespace billiard
"""
    SUITE = """#include "support/graded.hpp"
#include "support/student_messages.hpp"

namespace {

GRADED_TEST(MeanSpeed, TwoCircles, 2, visible) {
  billiard::Velocities v(2, 2);
  v << 3, 4, 0, 1;
  EXPECT_DOUBLE_EQ(billiard::mean_speed(v), 3.0)
      << billiard::testing::explain("(5 + 1) / 2 = 3", billiard::testing::text(billiard::mean_speed(v)),
                                    "average |v| over the circles");
}

GRADED_TEST(MeanSpeed, NoCircles, 1, after_due_date) {
  EXPECT_EQ(billiard::mean_speed(billiard::Velocities(0, 2)), 0.0);
}

}  // namespace
"""

    def test_adding_a_task_as_the_guide_says_gets_it_graded(self):
        """Follows "Add a task" of .github/CONTRIBUTING.md in a copy: the task's declaration, its
        stub and reference, its line in course.txt, its suite and the Classroom workflow; then
        the grader grades it (the reference: full points; the stub: none) and the workflow has
        its step. (Mutants and the command's and Python module's use of it are left out.)"""
        guide = " ".join((REPO / ".github" / "CONTRIBUTING.md").read_text().split())
        for step in ["lib/include/billiard/course.hpp", "tasks/<task>.cpp", "solutions/<task>.cpp",
                     "tests/grader/not_implemented.cpp", "tests/grader/judge/calls.hpp", "tests/grader/course.txt",
                     "tests/graded/test_<task>.cpp",
                     "/usr/bin/python3 tests/grader/package.py classroom"]:
            self.assertIn(step, guide)
        copy = fresh(WORK / "contributing")
        for path in package.project_files():
            (copy / path).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(REPO / path, copy / path)
        header = copy / "lib" / "include" / "billiard" / "course.hpp"
        text = header.read_text()
        at = text.rindex("}  // namespace billiard")
        header.write_text(text[:at] + "// Task 11. The mean speed of the circles (0 for none).\n"
                          "double mean_speed(const Velocities& velocities);\n\n" + text[at:])
        (copy / "tasks" / "mean_speed.cpp").write_text(self.STUB)
        (copy / "solutions" / "mean_speed.cpp").write_text(self.SOLUTION)
        (copy / "tests" / "graded" / "test_mean_speed.cpp").write_text(self.SUITE)
        stand_ins = copy / "tests" / "grader" / "not_implemented.cpp"
        text = stand_ins.read_text()
        at = text.rindex("}  // namespace billiard")
        stand_ins.write_text(text[:at] + "#ifdef BILLIARD_STUB_MEAN_SPEED\ndouble mean_speed(const Velocities&) "
                             "{ throw NotImplemented(11, \"mean_speed\", \"mean_speed.cpp\"); }\n#endif\n\n" + text[at:])
        calls = copy / "tests" / "grader" / "judge" / "calls.hpp"
        lines = calls.read_text().splitlines(keepends=True)
        at = next(k for k, line in enumerate(lines) if line.startswith("#define BILLIARD_COURSE_CALLS(CALL)")) + 1
        calls.write_text("".join(lines[:at]) + "  CALL(double, mean_speed, (const Velocities& velocities), (velocities)) \\\n"
                         + "".join(lines[at:]))
        with open(copy / "tests" / "grader" / "course.txt", "a") as course:
            course.write("11 mean_speed optional\n")
        status, output = run(["/usr/bin/python3", "tests/grader/package.py", "classroom"], cwd=copy, timeout=3600)
        self.assertEqual(status, 0, output[-3000:])
        self.assertIn("mean_speed", (copy / package.WORKFLOW).read_text())
        for submission, points in [("solutions", 3), ("tasks", 0)]:
            status, output = run(["/usr/bin/python3", "tests/grader/grade.py", "--submission", submission,
                                  "--task", "mean_speed", "--results", f"build/grade/{submission}"],
                                 cwd=copy, timeout=3600)
            self.assertEqual(status, 0, output[-3000:])
            report = json.loads((copy / "build" / "grade" / submission / "results.json").read_text())
            self.assertEqual(sum(test["score"] for test in report["tests"] if test["name"].startswith("mean_speed:")),
                             points, output[-3000:])
            self.assertEqual(sum(test["max_score"] for test in report["tests"]
                                 if test["name"].startswith("mean_speed:")), 3)


class PointsToEnter(unittest.TestCase):
    def test_each_package_prints_the_points_to_set_on_its_platform(self):
        """gradescope and autolab print the assignment's total, the required tasks' points with
        their hidden tests, and the optional tasks' points as extra credit; classroom prints the
        total of its steps (GitHub Classroom adds them all), without hidden tests."""
        folder = fresh(WORK / "points-to-enter")
        required = [task for task in TASKS if not course.is_optional(task)]
        optional = [task for task in TASKS if course.is_optional(task)]

        def total(points, tasks):
            return sum(points[task] for task in tasks)
        for platform, command in [("Gradescope", ["gradescope", str(folder / "autograder.zip")]),
                                  ("Autolab", ["autolab", str(folder / "autolab")])]:
            listing = " ".join(package_command(*command, "--tests", str(TESTS)).split())
            self.assertIn(f"{platform}: set the assignment's total to {total(maxima(), required)} points", listing)
            if optional:
                self.assertIn(f"the optional tasks' {total(maxima(), optional)} points", listing)
                self.assertIn("come on top as extra credit", listing)
        steps = package.points_to_enter(maxima(hidden=False), "GitHub Classroom", total_counts_optional=True)
        self.assertIn(f"the steps add up to {total(maxima(hidden=False), TASKS)} points: "
                      f"{total(maxima(hidden=False), required)} for the required tasks", steps)


class Classroom(unittest.TestCase):
    def test_committed_workflow_is_the_generated_one(self):
        status, output = run(["/usr/bin/python3", str(GRADER / "package.py"), "classroom", "--tests", str(TESTS), "--check"])
        self.assertEqual(status, 0, output)

    def workflow_steps(self, folder):
        workflow = yaml.safe_load((folder / package.WORKFLOW).read_text())
        steps = workflow["jobs"]["run-autograding-tests"]["steps"]
        graders = [step for step in steps if step.get("uses") == "classroom-resources/autograding-command-grader@v1"]
        reporter = steps[-1]
        self.assertEqual(reporter["uses"], "classroom-resources/autograding-grading-reporter@v1")
        self.assertEqual(reporter["with"]["runners"].split(","), [step["id"] for step in graders])
        self.assertEqual(reporter["env"], {f"{step['id'].upper()}_RESULTS": f"${{{{steps.{step['id']}.outputs.result}}}}"
                                           for step in graders})
        self.assertEqual(len(graders), len(TASKS))
        for task, step in zip(TASKS, graders):
            self.assertIn(f"--task {task} ", step["with"]["command"] + " ")
            self.assertIn("--require-full", step["with"]["command"])
            self.assertEqual(step["with"]["max-score"], maxima(hidden=False)[task])
        self.assertEqual(len({step["with"]["test-name"] for step in graders}), len(TASKS))
        return graders

    def run_steps(self, folder, graders):
        """Runs every step as the command grader does: its setup command, then its command."""
        statuses = []
        for step in graders:
            inputs = step["with"]
            timeout = float(inputs.get("timeout", 10)) * 60
            status, output = run(inputs["setup-command"], cwd=folder, timeout=timeout, shell=True)
            self.assertEqual(status, 0, output)
            status, output = run(inputs["command"], cwd=folder, timeout=timeout, shell=True)
            self.assertIn(status, {0, 1}, output)  # graded (not a crash of the grader)
            report = json.loads((folder / "build" / "grade" / "results" / "results.json").read_text())
            task = inputs["command"].split("--task ")[1].split()[0]
            self.assertEqual(scores_of(report)[task] == maxima(hidden=False)[task], status == 0, output)
            statuses.append(status)
            print(f"{inputs['test-name']}: exit status {status}", flush=True)
        return statuses

    def test_steps_fail_on_the_stubs_and_pass_on_the_solutions(self):
        # The student's checkout: the stubs, with the solutions of two tasks that need no other
        # task (each step recompiles every file, so one round of steps proves both outcomes).
        folder = student_release()
        graders = self.workflow_steps(folder)
        solved = {"visualize_table", "kinetic_energy"}
        try:
            for task in TASKS:
                source = REPO / ("solutions" if task in solved else "tasks") / TASK_FILE[task]
                shutil.copyfile(source, folder / "tasks" / TASK_FILE[task])
            self.assertEqual(self.run_steps(folder, graders), [0 if task in solved else 1 for task in TASKS])
        finally:
            for task in TASKS:
                shutil.copyfile(REPO / "tasks" / TASK_FILE[task], folder / "tasks" / TASK_FILE[task])


def unzip(archive_path, folder):
    """Unpacks a zip as unzip does, with the permissions it records."""
    with zipfile.ZipFile(archive_path) as archive:
        for info in archive.infolist():
            target = folder / info.filename
            target.parent.mkdir(parents=True, exist_ok=True)
            target.write_bytes(archive.read(info))
            mode = info.external_attr >> 16
            if mode:
                os.chmod(target, stat.S_IMODE(mode))


def endless_loops(task):
    """The stub of a task (tasks/<task>.cpp) with each `throw` replaced by an endless loop (for a C
    task, the stub's `exit(1)` after its "not implemented yet")."""
    stub = (REPO / "tasks" / TASK_FILE[task]).read_text()
    unwritten = r"exit\(1\);" if task in course.PROGRAM_TASKS else r"throw NotImplemented\([^;]*\);"
    looping, count = re.subn(unwritten, "for (volatile unsigned spin = 0;; spin = spin + 1) {}", stub)
    assert count >= 1, f"tasks/{TASK_FILE[task]} has no `throw NotImplemented(...)` to replace"
    return looping


# The functions a task file defines for the course (not inline ones, nor the library's own).
CONTRACT_FUNCTIONS = sorted({name for header in ["course.hpp", "extensions.hpp"]
                             for name in re.findall(r"^(?!inline|constexpr|#)[\w:<>]+[\s&*]+(\w+)\(",
                                                    (REPO / "lib" / "include" / "billiard" / header).read_text(),
                                                    re.MULTILINE)})
SLOWER_CXX = """#include <ctime>
namespace {
// Test code (test_packages.py): each call of a task function computes four times as long again
// after its own work, so that the file is a correct solution five times slower than the reference.
struct FiveTimesSlower {
  std::clock_t start = std::clock();
  ~FiveTimesSlower() {
    const std::clock_t until = std::clock() + 4 * (std::clock() - start);
    while (std::clock() < until) {
    }
  }
};
}  // namespace
"""
SLOWER_C = """#include <stdlib.h>
#include <time.h>
/* Test code (test_packages.py): the program computes four times as long again after its own work
 * (at exit), so that it is a correct solution five times slower than the reference. */
static clock_t slower_start;
static void slower_spin(void) {
  clock_t until = clock() + 4 * (clock() - slower_start);
  while (clock() < until) {
  }
}
#define main slower_main
"""


def slow_solution(task):
    """The reference solution of a task made five times slower: each call of the course's
    functions it defines (a C task: the whole program) takes five times its CPU time."""
    source = (REPO / "solutions" / TASK_FILE[task]).read_text()
    if task in course.PROGRAM_TASKS:
        return (SLOWER_C + source + "\n#undef main\nint main(int argc, char **argv) {\n  slower_start = clock();\n"
                "  atexit(slower_spin);\n  return slower_main(argc, argv);\n}\n")
    definition = re.compile(rf"^[\w:<>]+[\s&*]+({'|'.join(CONTRACT_FUNCTIONS)})\([^;{{}}]*\)\s*\{{", re.MULTILINE)
    slowed, count = definition.subn(lambda found: found.group(0) + " FiveTimesSlower slower;", source)
    assert count >= 1, f"solutions/{TASK_FILE[task]} defines none of {CONTRACT_FUNCTIONS}"
    return SLOWER_CXX + slowed


class FakeAutograder:
    """A fake /autograder folder under WORK/<folder>, set up and run as Gradescope does; each
    command goes through platform_command (the platform's own Python by default)."""
    folder = "gradescope"

    def platform_command(self, command):
        return command

    def run_autograder(self, root, submission_files, one_core=False):
        """Puts the files {relative path: text} into a fresh submission folder, runs run_autograder
        as Gradescope does (on one core: limited to CPU 0); returns (results.json, output)."""
        submission = fresh(root / "submission")
        for path, text in submission_files.items():
            (submission / path).parent.mkdir(parents=True, exist_ok=True)
            (submission / path).write_text(text)
        fresh(root / "results")
        status, output = run(self.platform_command((["taskset", "-c", "0"] if one_core else []) +
                                                   [str(root / "run_autograder")]),
                             cwd=root, env=environment(AUTOGRADER_ROOT=str(root)), timeout=1800)
        self.assertEqual(status, 0, output)
        return json.loads((root / "results" / "results.json").read_text()), output

    def autograder(self):
        """The fake /autograder folder, set up by test_autograder_zip_in_a_fake_autograder_folder
        (a CTest fixture) or here if it is missing."""
        root = WORK / self.folder / "autograder"
        if not (root / "run_autograder").is_file():
            self.set_up_autograder()
        return root

    def set_up_autograder(self):
        base = fresh(WORK / self.folder)
        zip_path = base / "autograder.zip"
        status, listing = run(self.platform_command(["/usr/bin/python3", str(GRADER / "package.py"), "gradescope",
                                                     str(zip_path), "--tests", str(TESTS)]))
        self.assertEqual(status, 0, listing)
        # The stated bound, the driver's cut-off and Gradescope's default limit of 10 minutes, in order.
        bound = package.PLATFORM_TOTAL + package.GRADESCOPE_BUILD_ALLOWANCE
        self.assertLess(bound, package.GRADESCOPE_CUTOFF)
        self.assertLess(package.GRADESCOPE_CUTOFF, 600)
        self.assertIn(f"at most {bound} s, however", listing)
        with zipfile.ZipFile(zip_path) as archive:
            self.assertIn(f"at most {package.PLATFORM_TOTAL} s", archive.read("setup.sh").decode())
        # Gradescope: unpack to /autograder/source, run setup.sh there once (as root), copy
        # run_autograder to /autograder.
        root = base / "autograder"
        unzip(zip_path, root / "source")
        status, output = run(self.platform_command([str(root / "source" / "setup.sh")]), cwd=root / "source",
                             timeout=1800)
        self.assertEqual(status, 0, output)
        shutil.copy2(root / "source" / "run_autograder", root / "run_autograder")
        return zip_path, root


class Gradescope(FakeAutograder, unittest.TestCase):
    def test_endless_loops_fit_the_time_limit_on_one_core(self):
        # Every task loops forever (the stubs with each `throw` replaced by an endless loop),
        # graded on one core: results.json comes well within Gradescope's default limit of 10
        # minutes. Then only propagate loops: the other tasks keep full points.
        root = self.autograder()
        # The bound setup.sh printed: the budgets measured there, and the check of the build.
        limits = time_limits.saved_limits(root / "source" / "build" / "grade" / "build")
        limit = sum(item.budget for item in limits.values()) + package.GRADESCOPE_BUILD_ALLOWANCE
        self.assertLess(limit, package.GRADESCOPE_CUTOFF)
        # Other tests may run on processor 0 meanwhile: the bound is for the grading's own time.
        with OnCoreZero() as timing:
            report, output = self.run_autograder(root, {f"tasks/{TASK_FILE[task]}": endless_loops(task)
                                                        for task in TASKS}, one_core=True)
        print(f"every task looping, on one core: {timing} (bound {limit:.0f} s)", flush=True)
        self.assertLess(timing.own, limit, output[-3000:])
        # Each task loops until its budget is used up, computing: so the grading's processor time
        # is most of the budgets' sum, or its processes' time was not counted (and the bound
        # above would hold for any grading).
        budgets = limit - package.GRADESCOPE_BUILD_ALLOWANCE
        self.assertGreater(timing.cpu, budgets / 2, f"{timing}: its processes' time is not counted")
        self.assertEqual(scores_of(report), {task: 0 for task in TASKS}, output[-3000:])
        for task in TASKS:
            outputs = [test["output"] for test in report["tests"] if test["name"].startswith(task + ":")]
            self.assertTrue(outputs and all("did not finish" in text or "not run" in text for text in outputs),
                            f"{task}: {outputs}")

        files = {f"tasks/{TASK_FILE[task]}": (REPO / "solutions" / TASK_FILE[task]).read_text() for task in TASKS}
        files["tasks/propagate.cpp"] = endless_loops("propagate")
        with OnCoreZero() as timing:
            report, output = self.run_autograder(root, files, one_core=True)
        print(f"propagate looping, on one core: {timing}", flush=True)
        self.assertLess(timing.own, limit, output[-3000:])
        scores = scores_of(report)
        self.assertEqual(scores["propagate"], 0, output[-3000:])
        for task in TASKS:
            if task != "propagate":
                self.assertEqual(scores[task], maxima()[task], f"{task}\n{output[-3000:]}")

    def test_the_hostile_suite_gains_nothing(self):
        # Gradescope grades as root: the attacks score 0, the tasks beside them keep full points,
        # and no output shows anything of the reference code or the hidden tests.
        import test_attacks
        root = self.autograder()
        files, attacked = test_attacks.platform_submission(root / "source", root / "source" / "build" / "grade" / "build")
        report, output = self.run_autograder(root, {f"tasks/{name}": text for name, text in files.items()})
        scores = scores_of(report)
        for task in TASKS:
            self.assertEqual(scores[task], 0 if task in attacked else maxima()[task], f"{task}\n{output[-3000:]}")
        texts = {"results.json": json.dumps(report), "output": output}
        for where, text in texts.items():
            for secret in test_attacks.secrets():
                self.assertNotIn(secret, text, f"{where} shows '{secret}'")
            if "Landlock ABI" in output:  # no stash at all (without Landlock, visible tests may share theirs)
                self.assertNotIn("LEAKED:", text)
        self.assertEqual(test_attacks.leftovers(), [])

    def test_correct_code_five_times_slower_keeps_full_points_on_one_core(self):
        # Every task's reference solution made five times slower, graded on one core while the
        # reference solutions are graded again and again on the other core: full points.
        root = self.autograder()
        files = {f"tasks/{TASK_FILE[task]}": slow_solution(task) for task in TASKS}
        other = subprocess.Popen(
            ["taskset", "-c", "1", "/bin/sh", "-c", "while true; do /usr/bin/python3 \"$0\" --submission \"$1\" "
             "--build \"$2\" --results \"$3\" --brief >/dev/null 2>&1; done", str(REPO / "tests" / "grader" / "grade.py"),
             str(REPO / "solutions"), str(WORK / "other-grading" / "build"), str(WORK / "other-grading" / "results")],
            start_new_session=True)
        try:
            started = time.monotonic()
            report, output = self.run_autograder(root, files, one_core=True)
            elapsed = time.monotonic() - started
        finally:
            os.killpg(other.pid, 9)
            other.wait()
        print(f"every task five times slower, on one core beside another grading: {elapsed:.0f} s", flush=True)
        self.assertEqual(scores_of(report), maxima(), output[-3000:])

    def test_autograder_zip_in_a_fake_autograder_folder(self):
        zip_path, root = self.set_up_autograder()
        with zipfile.ZipFile(zip_path) as archive:
            names = archive.namelist()
            modes = {info.filename: stat.S_IMODE(info.external_attr >> 16) for info in archive.infolist()}
        for name in ["setup.sh", "run_autograder"]:
            self.assertIn(name, names)
            self.assertEqual(modes[name], 0o755, name)
        self.assertIn("solutions/propagate.cpp", names)
        self.assertIn("tests/grader/grade.py", names)
        self.assertFalse([name for name in names if name.startswith(("build/", "tests/mutants/", ".git/"))])

        # The files in a folder, with a broken propagate, a stray copy of a task file nearer the
        # top, and other files that must be ignored.
        files = {f"billiard-main/tasks/{TASK_FILE[task]}": (REPO / "solutions" / TASK_FILE[task]).read_text() for task in TASKS}
        files["billiard-main/tasks/propagate.cpp"] = broken_propagate()
        # Including the reference solution does not work (the solutions are protected).
        files["billiard-main/tasks/init_velocities.cpp"] = f'#include "{root}/source/solutions/init_velocities.cpp"\n'
        files["init_billiard.cpp"] = "this is not C++ and must not be graded\n"
        files["billiard-main/CMakeLists.txt"] = "message(FATAL_ERROR \"not ours\")\n"
        files["billiard-main/tests/graded/test_propagate.cpp"] = "int main() { return 0; }\n"
        files["billiard-main/.git/propagate.cpp"] = "hidden folders (a cloned repository's .git) are skipped\n"
        report, output = self.run_autograder(root, files)
        scores = scores_of(report)
        self.assertEqual(scores["propagate"], 0, output)
        self.assertEqual(scores["init_velocities"], 0, output)
        for task in TASKS:
            if task not in {"propagate", "init_velocities"}:
                self.assertEqual(scores[task], maxima()[task], f"{task}\n{output}")
        self.assertEqual(report["score"], sum(scores.values()))
        compile_error = next(test for test in report["tests"] if test["name"].startswith("propagate:"))
        self.assertIn("nxt", compile_error["output"])
        self.assertEqual(compile_error["visibility"], "visible")
        self.assertIn("billiard-main/tasks/init_billiard.cpp", report["output"])
        self.assertNotIn(".git/", report["output"])

        # The grader crashes: a results.json with score 0 and the error, all the same. (The driver
        # imports grade.py too, so the script stays importable and fails when run.)
        grade_py = root / "source" / "tests" / "grader" / "grade.py"
        original = grade_py.read_text()
        self.assertIn("sys.exit(main())", original)
        grade_py.write_text(original.replace("sys.exit(main())", "raise RuntimeError('a broken grader')"))
        try:
            report, output = self.run_autograder(root, files)
        finally:
            grade_py.write_text(original)
        self.assertEqual(report["score"], 0)
        self.assertIn("course staff", report["output"])

        # Even the driver cannot start: run_autograder's own fallback.
        driver = root / "source" / "tests" / "grader" / "package.py"
        driver.rename(driver.with_suffix(".hidden"))
        try:
            report, output = self.run_autograder(root, files)
        finally:
            driver.with_suffix(".hidden").rename(driver)
        self.assertEqual(report["score"], 0)
        self.assertIn("course staff", report["output"])


def oldest_python():
    """The oldest Python the project supports (3.10, Ubuntu 22.04's, on Gradescope's default image):
    BILLIARD_OLDEST_PYTHON, or pyenv's 3.10; None if this machine has neither."""
    named = os.environ.get("BILLIARD_OLDEST_PYTHON")
    if named:
        return Path(named)
    if shutil.which("pyenv") is None:
        return None
    done = subprocess.run(["pyenv", "prefix", "3.10"], stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    found = sorted(Path(done.stdout.strip()).glob("bin/python3.10")) if done.returncode == 0 else []
    return found[0] if found else None


class OldestPython(FakeAutograder, unittest.TestCase):
    """What the platforms run, under Python 3.10 as /usr/bin/python3 (in a mount namespace of its
    own: every command, the packages' scripts included, runs it), with none of Debian's modules:
    Gradescope's set-up and a grading, a class graded and reported, every Python file compiled."""
    folder = "gradescope-oldest-python"

    @classmethod
    def setUpClass(cls):
        cls.python = oldest_python()
        if cls.python is None:
            raise unittest.SkipTest("OldestPython: skipped: this machine has no Python 3.10 (pyenv's, or "
                                    "BILLIARD_OLDEST_PYTHON): the grader is not tried under it here")
        if os.geteuid() != 0 or shutil.which("unshare") is None:
            raise unittest.SkipTest("OldestPython: skipped: it needs root and unshare to put Python 3.10 in place")

    def platform_command(self, command):
        """command with /usr/bin/python3 being Python 3.10, and nothing of Debian's on its path."""
        target = os.path.realpath("/usr/bin/python3")
        return ["unshare", "--mount", "--propagation", "private", "/bin/sh", "-c",
                f"mount --bind {shlex.quote(str(self.python))} {shlex.quote(target)} && "
                f"export PYTHONHOME={shlex.quote(str(self.python.parents[1]))} PYTHONNOUSERSITE=1 && exec \"$@\"",
                "oldest-python", *command]

    def test_it_is_the_oldest_python(self):
        status, output = run(self.platform_command(["/usr/bin/python3", "-c",
                                                    "import sys; print(sys.version_info[:2]); import yaml"]))
        self.assertIn("(3, 10)", output)
        self.assertIn("No module named 'yaml'", output)  # Debian's modules are not there

    def test_every_python_file_compiles(self):
        # Every Python file, and every notebook's code, compiles under 3.10 (syntax of 3.11 or
        # later would not).
        files = [REPO / name for name in subprocess.run(["git", "ls-files", "*.py", "*.ipynb"], cwd=REPO, check=True,
                                                         stdout=subprocess.PIPE, text=True).stdout.split()]
        check = ("import json, sys\n"
                 "for name in sys.argv[1:]:\n"
                 "    text = open(name).read()\n"
                 "    if name.endswith('.ipynb'):\n"
                 "        cells = [''.join(c['source']) for c in json.loads(text)['cells'] if c['cell_type'] == 'code']\n"
                 "        text = '\\n'.join(l for c in cells for l in c.splitlines() if not l.lstrip().startswith(('%', '!')))\n"
                 "    compile(text, name, 'exec')\n"
                 "print('compiled', len(sys.argv) - 1)\n")
        status, output = run(self.platform_command(["/usr/bin/python3", "-c", check, *map(str, files)]))
        self.assertEqual(status, 0, output[-3000:])
        self.assertIn(f"compiled {len(files)}", output)

    def test_gradescope_sets_up_and_grades_a_mutant_and_an_attack(self):
        # setup.sh builds the grader and grades the reference (full points, or it fails); then a
        # submission of the reference with a mutant of propagate and the hostile kinetic_energy.
        from test_grader import mutant_source
        root = self.autograder()
        files = {f"tasks/{TASK_FILE[task]}": (REPO / "solutions" / TASK_FILE[task]).read_text() for task in TASKS}
        files["tasks/propagate.cpp"] = mutant_source(REPO / "tests" / "mutants" / "propagate" /
                                                     "full_reversal_at_wall.mutant")
        files["tasks/kinetic_energy.cpp"] = (HERE / "hostile" / "kinetic_energy.cpp").read_text()
        report, output = self.run_autograder(root, files)
        scores = scores_of(report)
        self.assertLess(scores["propagate"], maxima()["propagate"], output[-3000:])
        self.assertEqual(scores["kinetic_energy"], 0, output[-3000:])
        for task in TASKS:
            if task not in {"propagate", "kinetic_energy"}:
                self.assertEqual(scores[task], maxima()[task], f"{task}\n{output[-3000:]}")
        self.assertEqual(report["score"], sum(scores.values()))

    def test_a_class_is_graded_and_reported(self):
        # grade.py --class under 3.10, where neither Dask nor matplotlib imports (the packages are
        # installed, by the test command, as ./build.sh grade --class installs them): graded
        # on this machine's processes, a gradebook, and a report that says its figures are missing;
        # the copy finder (Node.js) flags the disguised copy all the same.
        import random
        from disguises import hidden
        from test_grader import mutant_source
        graded = ["kinetic_energy", "propagate"]
        reference = {task: (REPO / "solutions" / TASK_FILE[task]).read_text() for task in graded}
        students = {"reference": reference,
                    "mutant": {**reference, "propagate": mutant_source(REPO / "tests" / "mutants" / "propagate" /
                                                                        "full_reversal_at_wall.mutant")},
                    "hostile": {**reference, "kinetic_energy": (HERE / "hostile" / "kinetic_energy.cpp").read_text()},
                    "copier": {**reference, "propagate": hidden(reference["propagate"], random.Random(5))}}
        class_folder, results = fresh(WORK / "oldest-python-class"), WORK / "oldest-python-results"
        shutil.rmtree(results, ignore_errors=True)
        for student, own in students.items():
            (class_folder / student).mkdir()
            for task, text in own.items():
                (class_folder / student / TASK_FILE[task]).write_text(text)
        status, output = run(self.platform_command(["/usr/bin/python3", str(GRADER / "grade.py"), "--class",
                                                    str(class_folder), "--results", str(results), "--workers", "2",
                                                    *[word for task in graded for word in ("--task", task)]]),
                             cwd=REPO, timeout=1800)
        self.assertEqual(status, 0, output[-5000:])
        self.assertIn("Dask is not installed", output)
        with open(results / "gradebook.csv") as file:
            rows = {row["student"]: row for row in csv.DictReader(file)}
        full = {task: maxima()[task] for task in graded}
        for student in ["reference", "copier"]:
            self.assertEqual({task: int(rows[student][task]) for task in graded}, full, student)
        self.assertLess(int(rows["mutant"]["propagate"]), full["propagate"])
        self.assertEqual(int(rows["mutant"]["kinetic_energy"]), full["kinetic_energy"])
        self.assertEqual(int(rows["hostile"]["kinetic_energy"]), 0)
        self.assertEqual(int(rows["hostile"]["propagate"]), full["propagate"])
        page = (results / "report.html").read_text()
        self.assertIn("No figures: matplotlib is not installed for /usr/bin/python3", page)
        with open(results / "similarity.csv") as file:
            flagged = {(row["task"], row["first"], row["second"]) for row in csv.DictReader(file)
                       if row["identical"] == "no"}
        if similarity.node_too_old():  # Ubuntu 22.04's Node.js: the report says so, in one line
            self.assertIn("Near-copies were not looked for", page)
        else:
            self.assertIn(("propagate", "copier", "reference"), flagged)  # (the mutant is a near-copy too)


class Autolab(unittest.TestCase):
    def run_job(self, job, package_folder, handin=None, tar_path=None):
        """An Autolab job: the Makefile, autograde.tar and the handin in an empty folder; `make`.
        Returns (scores from the last line, output)."""
        fresh(job)
        shutil.copyfile(package_folder / "autograde-Makefile", job / "Makefile")
        if tar_path:
            shutil.copyfile(tar_path, job / "autograde.tar")
        if handin:
            shutil.copyfile(handin, job / "handin.tar")
        status, output = run(["make"], cwd=job, timeout=1800)
        self.assertEqual(status, 0, output)
        last = output.rstrip("\n").splitlines()[-1]
        scores = json.loads(last)["scores"]
        self.assertEqual(set(scores), set(TASKS), last)
        return scores, output

    def test_autograde_package_in_a_fake_job_folder(self):
        base = fresh(WORK / "autolab")
        package_folder = base / "package"
        listing = package_command("autolab", str(package_folder), "--tests", str(TESTS))
        for task in TASKS:
            self.assertIn(f"{task}  {maxima()[task]}", listing)
        # The stated bound fits the timeout it asks for, with the driver's cut-off in between.
        bound = package.PLATFORM_TOTAL + package.AUTOLAB_BUILD_ALLOWANCE
        self.assertLess(bound, package.AUTOLAB_CUTOFF)
        self.assertLess(package.AUTOLAB_CUTOFF, package.AUTOLAB_TIMEOUT)
        self.assertIn(f"set the timeout to {package.AUTOLAB_TIMEOUT} s", listing)
        self.assertIn(f"at most {bound} s on one core", listing)
        makefile = " ".join(line.lstrip("# ") for line in (package_folder / "autograde-Makefile").read_text().splitlines())
        self.assertIn(f"at most {bound} s on one core", makefile)
        tar_path = package_folder / "autograde.tar"
        with tarfile.open(tar_path) as archive:
            names = archive.getnames()
        self.assertIn(f"{package.AUTOLAB_FOLDER}/tests/grader/package.py", names)
        self.assertIn(f"{package.AUTOLAB_FOLDER}/solutions/movie.cpp", names)
        self.assertFalse([name for name in names if "/build/" in name or "/tests/mutants/" in name])

        # The handin: a zip (under the handin name handin.tar) with one correct task, a broken
        # propagate and other files; the missing tasks score 0.
        handin = base / "handin.zip"
        with zipfile.ZipFile(handin, "w") as archive:
            archive.writestr("tasks/visualize_table.cpp", (REPO / "solutions" / "visualize_table.cpp").read_text())
            archive.writestr("tasks/propagate.cpp", broken_propagate())
            archive.writestr("tasks/notes.md", "not graded\n")
        scores, output = self.run_job(base / "job", package_folder, handin, tar_path)
        expected = {task: 0 for task in TASKS}
        expected["visualize_table"] = maxima()["visualize_table"]
        self.assertEqual(scores, expected, output)
        self.assertIn("nxt", output)  # the compiler's message is in the feedback

        # The build fails (a broken package): all zeros, as the last line.
        broken_tar = base / "broken.tar"
        with tarfile.open(tar_path) as source, tarfile.open(broken_tar, "w") as target:
            for member in source.getmembers():
                data = source.extractfile(member).read() if member.isfile() else None
                if member.name == f"{package.AUTOLAB_FOLDER}/CMakeLists.txt":
                    data = b"cmake_minimum_required(VERSION 3.22)\nproject(broken)\nmessage(FATAL_ERROR \"broken\")\n"
                    member.size = len(data)
                target.addfile(member, None if data is None else io.BytesIO(data))
        scores, output = self.run_job(base / "job-broken", package_folder, handin, broken_tar)
        self.assertEqual(scores, {task: 0 for task in TASKS}, output)
        self.assertIn("course staff", output)

        # No autograde.tar at all: the Makefile's own fallback.
        scores, output = self.run_job(base / "job-empty", package_folder, handin, None)
        self.assertEqual(scores, {task: 0 for task in TASKS}, output)

    def test_grader_in_the_autograding_image_fits_the_default_timeout(self):
        # autograding-image.sh sets up the grader where the image is built; a job, run as an
        # unprivileged user as Autolab runs it, then only grades, within the default timeout.
        base = fresh(WORK / "autolab-image")
        package_folder = base / "package"
        listing = package_command("autolab", str(package_folder), "--tests", str(TESTS))
        bound = package.AUTOLAB_PREBUILT_TOTAL + package.AUTOLAB_PREBUILT_ALLOWANCE
        self.assertLess(bound, package.AUTOLAB_PREBUILT_CUTOFF)
        self.assertLess(package.AUTOLAB_PREBUILT_CUTOFF, package.AUTOLAB_DEFAULT_TIMEOUT)
        self.assertIn(f"a job takes at most {bound} s", listing)
        image = Path(tempfile.mkdtemp(prefix="autolab-image-"))  # where the job's user can go
        try:
            folder = image / "opt" / package.AUTOLAB_FOLDER
            status, output = run(["sh", str(package_folder / "autograding-image.sh"), str(package_folder / "autograde.tar")],
                                 env=environment(BILLIARD_GRADER=str(folder)))
            self.assertEqual(status, 0, output[-3000:])
            handin = image / "handin.zip"
            with zipfile.ZipFile(handin, "w") as archive:
                archive.writestr("tasks/visualize_table.cpp", (REPO / "solutions" / "visualize_table.cpp").read_text())
                archive.writestr("tasks/propagate.cpp", broken_propagate())
            job = image / "job"
            job.mkdir()
            shutil.copyfile(package_folder / "autograde-Makefile", job / "Makefile")
            shutil.copyfile(package_folder / "autograde.tar", job / "autograde.tar")
            shutil.copyfile(handin, job / "handin.tar")
            user = {}
            if os.geteuid() == 0:
                for path in [image, *image.rglob("*")]:
                    if path.is_dir():
                        os.chmod(path, path.stat().st_mode | 0o755)
                os.chmod(job, 0o777)
                user = {"user": "nobody", "group": "nogroup", "extra_groups": []}
            started = time.monotonic()
            done = subprocess.run(["make", f"BILLIARD_GRADER={folder}"], cwd=job, stdout=subprocess.PIPE,
                                  stderr=subprocess.STDOUT, text=True, env=environment(), timeout=600, **user)
            elapsed = time.monotonic() - started
            print(f"a job with the image's grader: {elapsed:.0f} s (bound {bound} s)", flush=True)
            output = done.stdout
            self.assertEqual(done.returncode, 0, output)
            scores = json.loads(output.rstrip("\n").splitlines()[-1])["scores"]
            expected = {task: 0 for task in TASKS}
            expected["visualize_table"] = maxima()["visualize_table"]
            self.assertEqual(scores, expected, output[-3000:])
            self.assertIn("nxt", output)
            self.assertNotIn("measuring what the reference solutions need", output, "the image measured them")
            self.assertFalse((job / package.AUTOLAB_FOLDER).exists(), "the job used the image's grader")
            self.assertLess(elapsed, bound)

            # A hostile handin, graded as Autolab grades it, by an unprivileged user beside the
            # image's course (reference code included), which only Landlock keeps from its cells.
            import test_attacks
            files, attacked = test_attacks.platform_submission(folder, folder / "build" / "grade" / "build")
            with zipfile.ZipFile(handin, "w") as archive:
                for name, text in files.items():
                    archive.writestr(f"tasks/{name}", text)
            shutil.rmtree(job)
            job.mkdir()
            os.chmod(job, 0o777)
            for name in ["autograde-Makefile", "autograde.tar"]:
                shutil.copyfile(package_folder / name, job / ("Makefile" if name.endswith("Makefile") else name))
            shutil.copyfile(handin, job / "handin.tar")
            done = subprocess.run(["make", f"BILLIARD_GRADER={folder}"], cwd=job, stdout=subprocess.PIPE,
                                  stderr=subprocess.STDOUT, text=True, env=environment(), timeout=600, **user)
            output = done.stdout
            self.assertEqual(done.returncode, 0, output)
            scores = json.loads(output.rstrip("\n").splitlines()[-1])["scores"]
            landlock = "Landlock ABI" in output
            for task in TASKS:
                if task in attacked:
                    self.assertEqual(scores[task], 0, f"{task}\n{output[-3000:]}")
                elif landlock or not user:
                    self.assertEqual(scores[task], maxima()[task], f"{task}\n{output[-3000:]}")
            if landlock or not user:  # without Landlock, an unprivileged job's cells can read the image
                for secret in test_attacks.secrets():
                    self.assertNotIn(secret, output, f"the feedback shows '{secret}'")
            if landlock:
                self.assertNotIn("LEAKED:", output)
        finally:
            shutil.rmtree(image, ignore_errors=True)


if __name__ == "__main__":
    if len(sys.argv) < 2:
        print(__doc__)
        sys.exit(2)
    TESTS = Path(sys.argv.pop(1)).resolve()
    WORK = TESTS / "package-tests"
    unittest.main(verbosity=2)
