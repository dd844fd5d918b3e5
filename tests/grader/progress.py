#!/usr/bin/python3
"""Where a student stands in the course's tasks after a run of the tests.

    /usr/bin/python3 tests/grader/progress.py [--counts] JUNIT_XML

reads the JUnit file of a CTest run (ctest --output-junit, as ./build.sh test writes it) and
prints one short block: each task whose tests ran and how it stands (a failing test of the command
that names the task it checks counts as that task's), then what to do next (the first task that
is not written or not passing, and the command that runs its tests; once the tasks that ran pass,
a task that tests skipped for is not written, or else a run of every test: it names no task whose
state the run does not show). --counts starts the block with how many tests passed,
failed and were skipped, for a run whose own output was not shown. The grader
(grade.py) ends its report with the same "Next:" lines. Exit status 0, or 2 for a missing or
unreadable file.

The tasks come from the course's catalogue (course.py, which reads course.txt).
"""

import re
import sys
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path

from course import (NOT_WRITTEN, PROGRAM_TASKS, TASK_FILE, TASK_NUMBER, TASKS, is_optional, task_name,
                    task_with_number)

# The lines of a graded test's message for students (tests/support/student_messages.hpp), with
# the picture of its failing case where it draws one.
STUDENT_MESSAGE = re.compile(r"(Expected|Your code|Hint|Picture): ")
# The line by which a test outside a task's suite (the command's, say) names the task a failure of
# it is about, so that the task is not said to pass (tests/cli/test_cli.cpp writes it).
CHECKS_TASK = re.compile(r"This test checks task (\d+) \((\w+)\)")


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


def next_step(progress, other_failing=(), waiting_for=()):
    """The "Next:" lines: the first task (in course order) that is not done, and how to go on.
    progress: TaskProgress of the tasks that ran; other_failing: names of failing tests that are
    not a task's; waiting_for: the tasks that skipped tests said are not written yet. It names
    only tasks whose state this run shows."""
    for item in sorted(progress, key=lambda p: TASK_NUMBER[p.task]):
        if item.passes:
            continue
        task = item.task
        if item.problem:
            first = (f"Next: {task_name(task)} was not tested: fix what the message above says in "
                     f"tasks/{TASK_FILE[task]}")
        elif item.missing:
            task = item.missing
            first = write_line(task)
        else:
            first = f"Next: {task_name(task)}, starting with its first failing test, {item.failing[0]}:"
            details = [f"  {shortened(line)}" for line in item.first_message] or \
                [f"  (its message: ./build.sh test -R '{item.failing[0]}')"]
            again = run_command(task) if task_of(item.failing[0]) == task else f"./build.sh test -R '{item.failing[0]}'"
            return [first, *details, f"  Fix tasks/{TASK_FILE[task]}, then run: {again}"]
        return [first, f"  then run: {run_command(task)}"]
    if other_failing:
        return [f"Next: every task that ran passes, but {len(other_failing)} other test(s) fail; start with "
                f"{other_failing[0]}, whose message this shows:",
                f"  ./build.sh test -R '{other_failing[0]}'"]
    if len(progress) == len(TASKS):
        return ["Next: nothing; every test passed. Well done."]
    if waiting_for:  # what ran passes, and some of its tests wait for a task that is not written
        task = min(waiting_for, key=TASK_NUMBER.get)
        return [write_line(task), f"  then run: {run_command(task)}"]
    # Only some tasks ran (./build.sh test -L <task>), or none (-L cli): the others' state is unknown.
    return [f"Every {'task' if progress else 'test'} that ran passes. Next: ./build.sh test, to see where every "
            "task stands"]


def write_line(task):
    line = f"Next: write {task_name(task)} in tasks/{TASK_FILE[task]}"
    if is_optional(task):
        line += " (optional: extra credit)" if task in PROGRAM_TASKS else " (an optional extension stage: extra credit)"
    return line


def shortened(line, limit=160):
    """A message's line cut to `limit` characters; a hint and a picture's path are never cut (a
    hint's end is often the part that says what to do)."""
    return line if len(line) <= limit or line.startswith(("Hint: ", "Picture: ")) else line[:limit - 3] + "..."


def task_of(test_name):
    """The task whose graded suite a CTest test belongs to ("propagate.Propagate.X"), or None."""
    prefix = test_name.split(".", 1)[0]
    return prefix if prefix in TASK_NUMBER else None


def from_ctest_junit(path):
    """(progress per task, names of other failing tests, the tasks other skipped tests wait for).
    A failing test outside the tasks' suites that names its task (CHECKS_TASK) counts as the
    task's."""
    progress, other_failing, waiting_for = {}, [], set()
    for case in ET.parse(path).getroot().iter("testcase"):
        name = case.get("name", "")
        status = case.get("status", "")
        output = "".join(case.findtext(tag) or "" for tag in ("system-out", "system-err"))
        skipped = status in ("notrun", "disabled") and case.find("skipped") is not None
        checked = CHECKS_TASK.search(output) if status != "run" and not skipped else None
        task = task_of(name) or (checked and task_with_number(int(checked[1])))
        if task:
            progress.setdefault(task, TaskProgress(task)).record(name, status == "run", output)
        elif skipped:
            waiting_for |= {task_with_number(int(number)) for number in NOT_WRITTEN.findall(output)} - {None}
        elif status != "run":
            other_failing.append(name)
    return list(progress.values()), other_failing, waiting_for


def report(progress, other_failing, waiting_for):
    """The block ./build.sh test ends with: one line per task that ran, then at most 4 lines."""
    lines = []
    if progress:
        width = max(len(task) for task in TASKS)
        number_width = max(len(str(TASK_NUMBER[task])) for task in TASKS)
        lines.append("Where the tasks stand:")
        for item in sorted(progress, key=lambda p: TASK_NUMBER[p.task]):
            optional = " (optional)" if is_optional(item.task) else ""
            lines.append(f"  {TASK_NUMBER[item.task]:>{number_width}} {item.task:<{width}}  {item.state()}{optional}")
    return lines + next_step(progress, other_failing, waiting_for)


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
