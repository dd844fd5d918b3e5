"""The grader's time limits: how long a task's file may take to compile and its tests to run.

Where the reference solutions exist (the instructors' repository and the platforms' packages),
the limits follow the machine that grades: the grader first measures what the reference
solutions need there (once per build folder and task, for the tasks it grades, in its
reference-times.json; the platforms' set-up scripts do it when they grade the reference
solutions), then gives

  - each test MARGIN times the CPU time the reference takes for it, at least MIN_TEST_SECONDS;
  - each task MARGIN times the reference's time for the whole task (compiling its file, linking
    its worker, running its tests), at least MIN_TASK_SECONDS: the task's budget.

So correct code several times slower than the reference passes on a fast machine and on a slow
one, and an endless loop still costs only its own task. Without the reference solutions (the
student release, GitHub Classroom), the limits are fixed: --timeout per test, --task-budget
per task.

A test's limit is CPU time (its judge's and its worker's), which a busy machine does not eat
into; a test that sleeps or waits is stopped after WALL_SLACK times its limit of time spent
neither computing nor waiting for a processor (judging.py). A task's budget is wall time: its
compilation, its link and its tests' durations added up (also when two run at once; a test's
duration without the time it waited for a processor). A test
starts only with time left, and the task's remaining tests fail without running once the
budget is used up, so a submission, however it misbehaves, is graded within the sum of its
tasks' budgets (plus the grader's own build).

Those budgets leave out time spent waiting for a processor, so that a busy machine costs no
student points; a platform's own cutoff does not. A grading with a Deadline (grade.py
--deadline) therefore also stops there in wall time: no test starts after it, a test still
running is stopped, and the results are written in time, each such test saying why.
"""

import hashlib
import json
import math
import os
import platform
import time
from dataclasses import dataclass, field
from pathlib import Path

from course import TASK_FILE, TASK_FUNCTIONS

MARGIN = 10             # limits are this many times what the reference needs on the machine
MIN_TEST_SECONDS = 2.0  # CPU seconds any test may take: starting a process on a busy machine
MIN_TASK_SECONDS = 20.0  # seconds any task may take in all, a compilation of its file included
WALL_SLACK = 2          # a test is stopped after this many times its CPU limit of waiting (not for a processor)
# A test is started only with at least this much of its task's budget left (or its whole time
# limit, if that is shorter): a shorter run would stop almost any test.
MINIMUM_START_SECONDS = 1.0
REFERENCE_TIMES = "reference-times.json"  # in the grader's build folder
# A machine this much slower than the one where the reference's times were measured (the
# platforms measure them where the grader is set up, which need not be where it grades) scales
# the limits by how much slower it is.
SLOWER_MACHINE = 1.2


@dataclass
class TaskLimits:
    """The time limits of one task."""
    task: str
    budget: float            # wall seconds for the task in all
    compile: float           # wall seconds for compiling its file (within the budget)
    test_default: float      # CPU seconds for a test not in `tests`
    tests: dict = field(default_factory=dict)      # test name -> CPU seconds
    reference: dict = field(default_factory=dict)  # test name -> the reference's CPU seconds here
    reference_task: float = 0.0  # the reference's seconds for the whole task here (0: not measured)

    def test(self, name):
        return self.tests.get(name, self.test_default)

    @property
    def measured(self):
        return self.reference_task > 0


def fixed_limits(task, timeout, budget, compile_timeout):
    """Limits given as options, for a grader without the reference solutions."""
    return TaskLimits(task, budget=budget, compile=min(compile_timeout, budget), test_default=timeout)


def task_seconds(times):
    """The reference's wall seconds for a task: compiling, linking and its tests one after another."""
    return times["compile"] + times["link"] + sum(test["wall"] for test in times["tests"].values())


def measured_limits(task, times, slower=1.0):
    """Limits from the reference's times of one task (see the module's text), measured on a
    machine `slower` times faster than this one."""
    reference = {name: test["cpu"] * slower for name, test in times["tests"].items()}
    whole = task_seconds(times) * slower
    budget = max(MIN_TASK_SECONDS, MARGIN * whole)
    return TaskLimits(task, budget=budget, compile=min(budget, max(MIN_TASK_SECONDS, MARGIN * times["compile"])),
                      test_default=MIN_TEST_SECONDS,
                      tests={name: max(MIN_TEST_SECONDS, MARGIN * seconds) for name, seconds in reference.items()},
                      reference=reference, reference_task=whole)


def fit_total(limits, total):
    """Scales the budgets down so that they add up to at most `total` seconds (a platform's time
    limit for a submission); returns the factor (1 when they fit)."""
    planned = sum(item.budget for item in limits.values())
    if planned <= total:
        return 1.0
    factor = total / planned
    for item in limits.values():
        item.budget *= factor
        item.compile = min(item.compile, item.budget)
    return factor


def machine_speed():
    """CPU seconds for a fixed piece of work, the fastest of three tries: compared with the same
    measure where the reference's times were taken, it tells how much slower this machine is."""
    fastest = math.inf
    for _ in range(3):
        started = time.process_time()
        total = 0
        for number in range(1_000_000):
            total += number * number % 7
        fastest = min(fastest, time.process_time() - started)
    return fastest


def slower_than_measured(times, speed):
    """How many times slower this machine (whose machine_speed() is `speed`) is than the one where
    a task's saved reference times were measured, if more than SLOWER_MACHINE; else 1."""
    ratio = speed / times["speed"] if times.get("speed") else 1.0
    return ratio if ratio > SLOWER_MACHINE else 1.0


def machine():
    """This machine, as the reference's times were measured on it: processor and usable cores."""
    model = platform.processor() or platform.machine()
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                model = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    cores = len(os.sched_getaffinity(0))
    return f"{model}, {cores} core{'' if cores == 1 else 's'} usable"


RECORD_FORMAT = 3  # of reference-times.json: a record of another format is measured again


def fingerprint(paths, words):
    """What the reference's times depend on besides the machine: the suites (their catalogs), the
    reference solutions and the compile command (and the record's format)."""
    digest = hashlib.sha256(json.dumps([RECORD_FORMAT, words]).encode())
    for path in sorted(paths):
        digest.update(str(path.name).encode() + b"\0" + hashlib.sha256(Path(path).read_bytes()).digest())
    return digest.hexdigest()


def load_reference_times(build_folder, expected_fingerprint):
    """{task: times} of the tasks measured in this build folder (see save_reference_times); empty
    when none is, or the record is out of date."""
    try:
        saved = json.loads((Path(build_folder) / REFERENCE_TIMES).read_text())
    except (OSError, ValueError):
        return {}
    return saved["tasks"] if saved.get("fingerprint") == expected_fingerprint else {}


def saved_limits(build_folder):
    """{task: TaskLimits} from the reference's times saved in a build folder (whatever they were
    measured for), or None."""
    try:
        saved = json.loads((Path(build_folder) / REFERENCE_TIMES).read_text())
    except (OSError, ValueError):
        return None
    return {task: measured_limits(task, times) for task, times in saved["tasks"].items()}


def save_reference_times(build_folder, print_, tasks):
    """Adds tasks' reference times to the record of a build folder (replacing it if its
    fingerprint differs): {"fingerprint", "machine", "tasks": {task: {"speed" (machine_speed()
    when they were measured), "compile", "link", "tests": {name: {"cpu", "wall"}}}}}. The caller
    holds reference_times_lock()."""
    path = Path(build_folder) / REFERENCE_TIMES
    speed = machine_speed()
    record = {"fingerprint": print_, "machine": machine(),
              "tasks": load_reference_times(build_folder, print_) | {task: times | {"speed": speed}
                                                                    for task, times in tasks.items()}}
    partial = path.with_name(path.name + ".partial")
    partial.write_text(json.dumps(record, indent=1) + "\n")
    os.replace(partial, path)


def reference_times_lock(build_folder):
    """An open file holding the lock under which a grading measures the reference's times in a
    build folder, so that gradings sharing it measure each task once."""
    import fcntl
    lock = open(Path(build_folder) / (REFERENCE_TIMES + ".lock"), "w")
    fcntl.flock(lock, fcntl.LOCK_EX)
    return lock


class Deadline:
    """The wall-clock time by which a grading ends, a busy machine's waiting included (a
    platform's cutoff less the time to write the results), or none."""

    def __init__(self, seconds=None, started=None):
        self.seconds = seconds
        self.at = None if seconds is None else (time.monotonic() if started is None else started) + seconds

    def left(self):
        return math.inf if self.at is None else self.at - time.monotonic()


NO_DEADLINE = Deadline()


class TaskClock:
    """The time one task may take: compiling its file, linking its worker and running its tests.

    Tests of a task may run at the same time; each reserves its wall-time limit from the budget
    before it starts and gives back what it did not use, so that the durations of a task's tests
    add up to no more than what its compilation left of the budget. Since the grader always has a
    test running while tests remain, grading takes no longer than the sum of the budgets (plus
    the grader's own build), on any number of cores."""

    def __init__(self, limits, deadline=NO_DEADLINE):
        import threading
        self.limits = limits
        self.deadline = deadline
        self.out_of_time = False  # a test was not run because the grading's deadline had come
        self.left = limits.budget
        self.spent_building = 0.0
        self.running = 0
        self.unfinished = 0  # tests stopped at their time limit
        self.condition = threading.Condition()

    @property
    def task(self):
        return self.limits.task

    def build_limit(self):
        """Seconds for compiling the task's file or linking its worker: its compile limit, within
        what is left of the budget and before the deadline (at least enough to start)."""
        return max(min(self.limits.compile, self.left, self.deadline.left()), MINIMUM_START_SECONDS)

    def spend(self, seconds, building=False):
        with self.condition:
            self.left -= seconds
            if building:
                self.spent_building += seconds

    def reserve(self, name):
        """(CPU seconds, wall seconds, why) for the next test, reserved: why is "each test" or
        "budget" (cut short by what is left of the budget); None when the budget is used up or
        the grading's deadline has come. Waits while the rest of the budget is reserved by tests
        of this task that are running."""
        wanted = self.limits.test(name)
        with self.condition:
            while True:
                if self.deadline.left() < MINIMUM_START_SECONDS:
                    self.out_of_time = True
                    return None
                wall = min(WALL_SLACK * wanted, self.left)
                if wall >= min(WALL_SLACK * wanted, MINIMUM_START_SECONDS):
                    self.left -= wall
                    self.running += 1
                    cpu = min(wanted, wall)
                    return cpu, wall, ("budget" if cpu < wanted else "each test")
                if not self.running:
                    return None
                self.condition.wait()

    def release(self, reserved, seconds, unfinished):
        with self.condition:
            self.left += reserved - seconds
            self.running -= 1
            self.unfinished += unfinished
            self.condition.notify_all()


def unfinished_message(clock, name, cpu_limit, why):
    """What a student reads about a test stopped at its time limit."""
    limits = clock.limits
    task = limits.task
    if why == "deadline":
        return (f"The test did not finish before the time this grading has on the grading machine "
                f"({clock.deadline.seconds:.0f} s) ran out, and was stopped: {BUSY_MACHINE}")
    if why == "budget":
        because = (f"what was left of the {limits.budget:.0f} s that compiling {TASK_FILE[task]} and running all of "
                   f"{task}'s tests may take")
        if limits.measured:
            because += f", {MARGIN} times what the reference solution needs for them on this machine"
    elif name in limits.reference:
        because = (f"{MARGIN} times the {limits.reference[name]:.2g} s the reference solution needs for this test on "
                   "this machine" if MARGIN * limits.reference[name] >= MIN_TEST_SECONDS else
                   f"every test may take {MIN_TEST_SECONDS:g} s; the reference solution needs "
                   f"{limits.reference[name]:.2g} s for this one on this machine")
    else:
        because = "the limit for each test"
    return (f"The test did not finish within {cpu_limit:.3g} seconds of computing ({because}) and was stopped. "
            f"Is there an endless loop in {TASK_FUNCTIONS[task]}, or a loop whose end depends on a condition that "
            "never holds?")


BUSY_MACHINE = ("the grading machine was busy with other work and could not give this test its time. Submit again "
                "to have it graded.")


def not_run_message(clock):
    task = clock.task
    if clock.out_of_time:
        return (f"This test was not run: the time this grading has on the grading machine "
                f"({clock.deadline.seconds:.0f} s) had run out: {BUSY_MACHINE}")
    return (f"This test was not run: compiling {TASK_FILE[task]} and running {task}'s tests may take "
            f"{clock.limits.budget:.0f} s in all here, and {used_up(clock)}. A correct solution needs far less"
            + (f" (the reference solution: {clock.limits.reference_task:.1f} s)" if clock.limits.measured else "")
            + f". Is there an endless loop in {TASK_FUNCTIONS[task]}? Once its tests finish, this one runs too.")


def used_up(clock):
    """What used up a task's budget, for students."""
    count = clock.unfinished
    return (f"that time was used up: compiling took {clock.spent_building:.0f} s and "
            f"{count} test{'' if count == 1 else 's'} did not finish (see {'its' if count == 1 else 'their'} "
            "messages)")
