#!/usr/bin/python3
"""The course's tasks, and where a student stands in them after a run of the tests.

    /usr/bin/python3 tests/grader/progress.py [--counts] JUNIT_XML

reads the JUnit file of a CTest run (ctest --output-junit, as ./build.sh test writes it) and
prints one short block: each task whose tests ran and how it stands, then what to do next (the
first task that is not written or not passing, and the command that runs its tests; once the
tasks that ran pass, the next task). --counts starts the block with how many tests passed,
failed and were skipped, for a run whose own output was not shown. The grader
(grade.py) ends its report with the same "Next:" lines. Exit status 0, or 2 for a missing or
unreadable file.

The tasks come from course.txt next to this file (the six tasks and the extension stages, and
which of them count); every script of the grader takes them from here.
"""

import re
import sys
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path

COURSE_FILE = Path(__file__).resolve().parent / "course.txt"
TASKS_FOLDER = Path(__file__).resolve().parents[2] / "tasks"
STATUSES = ("required", "optional", "off")
# Tasks 1-6 are the course's core: the `billiard` command, the Python module and the extension
# stages are built on them, so they stay required, unless the course is the C track alone (every
# task in C++ off, the program tasks such as particles on).
CORE_TASKS = 6


def is_program_task(name):
    """A task written in C as a whole program (tasks/<name>.c), graded by running it."""
    return (TASKS_FOLDER / f"{name}.c").is_file()


def read_course(path=COURSE_FILE):
    """[(number, name, status)] from course.txt, in course order; ValueError names a bad line."""
    course = []
    for line_number, line in enumerate(path.read_text().splitlines(), start=1):
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        words = line.split()
        if len(words) != 3 or not words[0].isdigit() or words[2] not in STATUSES:
            raise ValueError(f"{path.name} line {line_number}: '{line}' is not 'NUMBER NAME required|optional|off'")
        number, name, status = int(words[0]), words[1], words[2]
        if number != len(course) + 1:
            raise ValueError(f"{path.name} line {line_number}: task {number} should be task {len(course) + 1}")
        course.append((number, name, status, line_number))
    c_track_alone = all(status == "off" for _, name, status, _ in course if not is_program_task(name))
    for number, name, status, line_number in course:
        if number <= CORE_TASKS and status != "required" and not c_track_alone:
            raise ValueError(f"{path.name} line {line_number}: task {number} ({name}) is one of the six core tasks "
                             "and must stay required (unless every C++ task is off: the C track alone)")
    return [(number, name, status) for number, name, status, _ in course]


COURSE = read_course()
TASKS = [name for _, name, status in COURSE if status != "off"]           # built and graded
# Each task's file: <task>.cpp (functions linked with its graded suite), or <task>.c for a
# program task (a whole C program with main(), graded by running it; see tests/CMakeLists.txt).
PROGRAM_TASKS = [name for _, name, _ in COURSE if is_program_task(name)]
TASK_FILE = {name: f"{name}.c" if name in PROGRAM_TASKS else f"{name}.cpp" for _, name, _ in COURSE}
OPTIONAL = [name for _, name, status in COURSE if status == "optional"]   # extra credit
# The extension stages, built on the core in C++ (not the program tasks such as particles).
STAGES = [name for number, name, status in COURSE
          if number > CORE_TASKS and status != "off" and name not in PROGRAM_TASKS]
OFF = [name for _, name, status in COURSE if status == "off"]
TASK_NUMBER = {name: number for number, name, _ in COURSE}
# What a student writes in each task's file, for hints.
TASK_FUNCTIONS = {task: task for task in TASKS} | {
    "kinetic_energy": "kinetic_energy or correct_energy_drift",
    "gravity": "propagate_gravity or mean_energy",
    "walls": "propagate_walls",
    "sectors": "propagate_sectors",
} | {task: "main (the whole program)" for task in PROGRAM_TASKS}
# The course's error for a task that is not written yet (lib/src/course/not_implemented.cpp).
NOT_WRITTEN = re.compile(r"task (\d+) \(\w+\) is not implemented yet")
# The lines of a graded test's message for students (tests/support/student_messages.hpp), with
# the picture of its failing case where it draws one.
STUDENT_MESSAGE = re.compile(r"(Expected|Your code|Hint|Picture): ")


def is_optional(task):
    return task in OPTIONAL


def task_name(task):
    return f"task {TASK_NUMBER[task]} ({task})"


def task_with_number(number):
    return next((name for name, n in TASK_NUMBER.items() if n == number and name in TASKS), None)


def run_command(task):
    return f"./build.sh test -L {task}"


@dataclass
class TaskProgress:
    """One task's tests in one run: how many, which failed, and why."""
    task: str
    tests: int = 0
    failing: list = field(default_factory=list)  # names of the failing tests, in the run's order
    waits_for: set = field(default_factory=set)   # tasks a failure said are not implemented yet
    other_failures: int = 0                       # failures for any other reason
    problem: str = ""                             # grader only: why the suite could not be built
    first_message: list = field(default_factory=list)  # Expected / Your code / Hint / Picture of the first failure

    def record(self, name, passed, output):
        self.tests += 1
        if passed:
            return
        self.failing.append(name)
        named = {task_with_number(int(number)) for number in NOT_WRITTEN.findall(output)} - {None}
        if named:
            self.waits_for |= named
            return
        self.other_failures += 1
        if self.other_failures == 1:
            self.first_message = [line.strip() for line in output.splitlines()
                                  if STUDENT_MESSAGE.match(line.strip())][:4]

    @property
    def passes(self):
        return not self.problem and not self.failing and self.tests > 0

    @property
    def missing(self):
        """The first task its failures wait for, when that is their only reason; else None."""
        if self.problem or not self.failing or self.other_failures:
            return None
        return min(self.waits_for, key=TASK_NUMBER.get)

    def state(self):
        if self.problem:
            return "was not tested (see above why)"
        if self.passes:
            return f"passes all {self.tests} tests" if self.tests > 1 else "passes its test"
        if self.missing == self.task:
            return "not written yet"
        if self.missing:
            return f"waits for {task_name(self.missing)}"
        return f"{len(self.failing)} of {self.tests} tests fail"


def next_step(progress, other_failing=(), waiting=0):
    """The "Next:" lines: the first task (in course order) that is not done, and how to go on.
    progress: TaskProgress of the tasks that ran; other_failing: names of failing tests that are
    not a task's; waiting: how many other tests were skipped because a task is not written."""
    for item in sorted(progress, key=lambda p: TASK_NUMBER[p.task]):
        if item.passes:
            continue
        task = item.task
        if item.problem:
            first = (f"Next: {task_name(task)} was not tested: fix what the message above says in "
                     f"tasks/{TASK_FILE[task]}")
        elif item.missing:
            task = item.missing
            first = f"Next: write {task_name(task)} in tasks/{TASK_FILE[task]}"
            if is_optional(task):
                first += " (optional: extra credit)" if task in PROGRAM_TASKS else \
                    " (an optional extension stage: extra credit)"
        else:
            first = f"Next: {task_name(task)}, starting with its first failing test, {item.failing[0]}:"
            details = [f"  {shortened(line)}" for line in item.first_message] or \
                [f"  (its message: ./build.sh test -R '{item.failing[0]}')"]
            return [first, *details, f"  Fix tasks/{TASK_FILE[task]}, then run: {run_command(task)}"]
        return [first, f"  then run: {run_command(task)}"]
    if other_failing:
        return [f"Next: every task that ran passes, but {len(other_failing)} other test(s) fail; start with "
                f"{other_failing[0]}, whose message this shows:",
                f"  ./build.sh test -R '{other_failing[0]}'"]
    if len(progress) == len(TASKS):
        return ["Next: nothing; every test passed. Well done."]
    # Only some tasks ran (./build.sh test -L <task>) and they pass: the next task after them.
    last_passing = max((TASK_NUMBER[item.task] for item in progress), default=0)
    later = [task for task in TASKS if TASK_NUMBER[task] > last_passing]
    if later:
        task = later[0]
        optional = " (optional: extra credit)" if is_optional(task) else ""
        return [f"Next: {task_name(task)} in tasks/{TASK_FILE[task]}{optional}",
                f"  then run: {run_command(task)}"]
    return ["Every task that ran passes. Next: ./build.sh test, to see every task pass together"]


def shortened(line, limit=160):
    """A message's line cut to `limit` characters; a picture's path is never cut."""
    return line if len(line) <= limit or line.startswith("Picture: ") else line[:limit - 3] + "..."


def task_of(test_name):
    """The task whose graded suite a CTest test belongs to ("propagate.Propagate.X"), or None."""
    prefix = test_name.split(".", 1)[0]
    return prefix if prefix in TASK_NUMBER else None


def from_ctest_junit(path):
    """(progress per task, names of other failing tests, count of other skipped tests)."""
    progress, other_failing, waiting = {}, [], 0
    for case in ET.parse(path).getroot().iter("testcase"):
        name = case.get("name", "")
        status = case.get("status", "")
        output = "".join(case.findtext(tag) or "" for tag in ("system-out", "system-err"))
        skipped = status in ("notrun", "disabled") and case.find("skipped") is not None
        task = task_of(name)
        if task:
            progress.setdefault(task, TaskProgress(task)).record(name, status == "run", output)
        elif skipped:
            waiting += 1
        elif status != "run":
            other_failing.append(name)
    return list(progress.values()), other_failing, waiting


def report(progress, other_failing, waiting):
    """The block ./build.sh test ends with: one line per task that ran, then at most 4 lines."""
    lines = []
    if progress:
        width = max(len(task) for task in TASKS)
        number_width = max(len(str(TASK_NUMBER[task])) for task in TASKS)
        lines.append("Where the tasks stand:")
        for item in sorted(progress, key=lambda p: TASK_NUMBER[p.task]):
            optional = " (optional)" if is_optional(item.task) else ""
            lines.append(f"  {TASK_NUMBER[item.task]:>{number_width}} {item.task:<{width}}  {item.state()}{optional}")
    return lines + next_step(progress, other_failing, waiting)


def counts(path):
    """One line: how many tests ran and how they ended (for a run whose own output was not shown)."""
    ended = {"passed": 0, "failed": 0, "skipped": 0}
    for case in ET.parse(path).getroot().iter("testcase"):
        status = case.get("status", "")
        if status == "run":
            ended["passed"] += 1
        elif status in ("notrun", "disabled") and case.find("skipped") is not None:
            ended["skipped"] += 1
        else:
            ended["failed"] += 1
    waiting = " (waiting for a task)" if ended["skipped"] else ""
    return (f"{sum(ended.values())} tests: {ended['passed']} passed, {ended['failed']} failed, "
            f"{ended['skipped']} skipped{waiting}")


def main(argv):
    with_counts = "--counts" in argv
    argv = [argument for argument in argv if argument != "--counts"]
    if len(argv) != 1:
        print("usage: progress.py [--counts] JUNIT_XML", file=sys.stderr)
        return 2
    try:
        ran = ET.parse(argv[0]).getroot().find(".//testcase") is not None
        found = from_ctest_junit(Path(argv[0]))
    except (OSError, ET.ParseError) as error:
        print(f"progress: cannot read the test results {argv[0]}: {error}", file=sys.stderr)
        return 2
    if ran:  # nothing to say when no test ran (ctest -N)
        print("\n" + "\n".join(([counts(argv[0])] if with_counts else []) + report(*found)))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
