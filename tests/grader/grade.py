#!/usr/bin/python3
"""Grades the course's tasks of a submission (tests/grader/course.txt: the six tasks and the
extension stages that are not switched off) and writes what the grading platforms read.

    /usr/bin/python3 tests/grader/grade.py [--submission DIR] [--results DIR] [options]

For each task it compiles the submitted file on its own (a file that does not compile scores 0
for its task, with the compiler's message as feedback), links the task's graded suite with it
(and, where the reference solutions exist, with the reference code of the other tasks, so a
mistake in one task cannot cost points in another), then runs every graded test in its own
process with a time limit, an output cap, resource limits and, when run as root, as an
unprivileged user. A test earns its points only if the suite's own main() reports it passed
with a secret token given to that process alone: an early exit(0), a crash, a hang or forged
output earns nothing.

Each task has a time budget (--task-budget): compiling its file, linking its suite and running
its tests may take that long in all. Once one of its tests does not finish within --timeout, its
other tests get --short-timeout each, and when the budget is used up its remaining tests fail
without running. So a submission, however it misbehaves, is graded within the grader's own build
plus one budget per task, and only the misbehaving task loses points.

Prints a table (task, points / maximum, and each failing test's message and hint), and writes
results.json (Gradescope's format) and junit.xml into --results. Exit status 0 when grading
completed (whatever the score), 2 for bad arguments.
"""

import argparse
import concurrent.futures
import ctypes
import hashlib
import json
import os
import pwd
import re
import resource
import secrets
import shutil
import signal
import stat
import subprocess
import sys
import tempfile
import threading
import time
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path

from progress import OFF, PROGRAM_TASKS, TASK_FILE, TASKS, TASK_FUNCTIONS, TASK_NUMBER, TaskProgress, is_optional, next_step, task_name  # noqa: F401 (OFF: for package.py)

REPO = Path(__file__).resolve().parents[2]
HIDDEN_FEEDBACK = "This test is hidden: its details are not shown."
FEEDBACK_CAP = 8 * 1024  # characters of feedback kept per test
COMPILER_CAP = 6 * 1024  # characters of compiler output kept per task
SUBMITTED_FILE_CAP = 1_000_000  # bytes: a larger task file is not graded
# Why a task file cannot be graded, after its name.
LINK = "is a symbolic link, which the grader does not follow"
FOLDER = "is a folder, not a file"
SPECIAL = "is not an ordinary file"
TOO_LARGE = f"is larger than the {SUBMITTED_FILE_CAP:,} bytes the grader accepts (a task file has a few kilobytes)"
# Bytes of address space per compiler or linker process: for the grader's own build, and for
# a submitted file (the reference files need less than 300 MB).
BUILD_MEMORY = 4 << 30
SUBMISSION_BUILD_MEMORY = 2 << 30
# A test is started only with at least this much of its task's budget left (or its whole time
# limit, if that is shorter): a shorter run would stop almost any test.
MINIMUM_TEST_SECONDS = 1.0


@dataclass
class TestResult:
    task: str
    name: str  # "Suite.Name"
    points: int
    visibility: str
    passed: bool = False
    feedback: str = ""
    seconds: float = 0.0
    unfinished: bool = False  # stopped at its time limit
    not_run: bool = False     # its task's time budget was used up before it could start

    @property
    def score(self):
        return self.points if self.passed else 0


@dataclass
class TaskResult:
    task: str
    tests: list = field(default_factory=list)
    maximum: int = 0
    problem: str = ""  # why the task could not be tested (compile or link error), if so
    clock: object = None  # its TaskClock: its time budget, and what used it

    @property
    def score(self):
        return sum(test.score for test in self.tests)


def fail(message):
    print(f"grade: {message}", file=sys.stderr)
    sys.exit(2)


def cap(text, limit):
    if len(text) <= limit:
        return text
    return text[:limit] + f"\n... (output cut after {limit} characters)"


def build_limits(memory_bytes):
    """The function to run in a build step's process between fork and exec: its own process
    group (killed as a whole at its time limit, compilers included) and a memory limit, so that
    a submitted file that makes the compiler read /dev/zero or instantiate templates without end
    stops soon."""
    def prepare():
        os.setsid()
        for limit, value in [(resource.RLIMIT_AS, memory_bytes), (resource.RLIMIT_CORE, 0)]:
            resource.setrlimit(limit, (value, value))
    return prepare


def run_limited(command, timeout, preexec=build_limits(BUILD_MEMORY), cwd=None, output_cap=4 << 20):
    """Runs a build step with stdin from /dev/null (a file that includes /dev/stdin reads
    nothing), in its own process group that is killed at the time limit, keeping the first
    `output_cap` bytes of its output. Returns (ok, output, timed out)."""
    process = subprocess.Popen(command, cwd=cwd, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                               stderr=subprocess.STDOUT, preexec_fn=preexec)
    captured = []
    reader = threading.Thread(target=read_capped, args=(process.stdout, output_cap, captured), daemon=True)
    reader.start()
    timed_out = False
    try:
        process.wait(timeout=max(timeout, 0.1))
    except subprocess.TimeoutExpired:
        timed_out = True
    finally:
        kill_group(process)
    reader.join(timeout=5)
    output, dropped = captured[0] if captured else (b"", 0)
    text = output.decode(errors="replace")
    if dropped:
        text += f"\n... ({dropped} more bytes of output were dropped)"
    if timed_out:
        text += f"\n(stopped after {timeout:.0f} s)"
    return not timed_out and process.returncode == 0, text, timed_out


def kill_group(process):
    """Kills a process started in its own group, and whatever it started, and waits for it."""
    try:
        os.killpg(process.pid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError):
        pass
    process.wait()


# --- Building ----------------------------------------------------------------------------------

class Build:
    """The grader's CMake build of one submission (see tests/grader/CMakeLists.txt)."""

    def __init__(self, folder, submission, dependencies, compile_timeout, build_timeout):
        self.folder = folder
        self.submission = submission
        self.dependencies = dependencies
        self.compile_timeout = compile_timeout
        self.build_timeout = build_timeout

    def configure(self, stubbed):
        command = [
            "cmake", "-S", str(REPO), "-B", str(self.folder), "-G", "Ninja", "-DCMAKE_BUILD_TYPE=Release",
            "-DBILLIARD_COURSE=" + ("solutions" if self.dependencies == "reference" else "tasks"),
            "-DBILLIARD_CHECK_STUBS=OFF", "-DBILLIARD_PYTHON=OFF", "-DCMAKE_EXPORT_COMPILE_COMMANDS=ON",
            f"-DBILLIARD_SUBMISSION={self.submission}",
            f"-DBILLIARD_GRADE_DEPENDENCIES={self.dependencies}", "-DBILLIARD_STUBBED_TASKS=" + ";".join(stubbed),
        ]
        ok, output, _ = run_limited(command, timeout=self.build_timeout)
        if not ok:
            raise RuntimeError("configuring the grader's build failed:\n" + output)

    def build(self, targets, timeout, memory_bytes=BUILD_MEMORY):
        """Builds targets; returns (ok, output, timed out)."""
        return run_limited(["cmake", "--build", str(self.folder), "--target", *targets], timeout=timeout,
                           preexec=build_limits(memory_bytes))

    def prebuild(self, tasks):
        """Builds everything that does not depend on the submission (the library, the suites'
        test code, the reference code, the catalogs), so that the time of each task's budget
        goes to its own file and tests only."""
        targets = [f"catalog_{task}" for task in TASKS]
        if self.dependencies == "reference":
            targets += [f"billiard_solutions_{task}" for task in TASKS]
        targets += [f"submission_{task}" for task in tasks]  # stand-ins: the grader's own code
        ok, output, _ = self.build(targets, timeout=self.build_timeout)
        if not ok:
            raise RuntimeError("building the grader's own code failed:\n" + output[-20000:])

    def executable(self, name):
        return self.folder / "tests" / "grader" / name


def readable_copy(folder, work):
    """A header folder inside the repository, copied into `work` (the repository may sit where
    the test user cannot read, such as under /root); folders elsewhere are used as they are."""
    if not folder.is_relative_to(REPO):
        return folder
    include = work / "include"
    include.mkdir(exist_ok=True)
    os.chmod(include, 0o755)
    copy = include / str(len(list(include.iterdir())))
    shutil.copytree(folder, copy)
    for path in [copy, *copy.rglob("*")]:
        os.chmod(path, 0o755 if path.is_dir() else 0o644)
    return copy


def preprocess_as(sandbox, build, tasks, clocks):
    """Expands each submitted file's #include lines as the unprivileged user, in place, and
    compiles the result as that user too.

    With the reference solutions made unreadable to that user (--protect-reference), a file
    that tries `#include "../solutions/propagate.cpp"` (or any other file the user may not read)
    fails here, and the later compilation, as the grader, sees no #include left to follow. The
    compilation as the user catches what the assembler would read (`asm(".incbin ...")`): the
    grader's own compilation only sees files that passed it. Each file's time comes from its
    task's budget. Returns {task: message} for the files that fail.
    """
    commands = {Path(entry["file"]).name: entry for entry in
                json.loads((build.folder / "compile_commands.json").read_text())
                if Path(entry["file"]).parent == build.submission}
    problems = {}
    for task in tasks:
        source = build.submission / TASK_FILE[task]
        if not source.is_file():
            continue
        if source.name not in commands:  # never compile a file unchecked
            raise RuntimeError(f"the grader's build has no compile command for {source}")
        work = Path(tempfile.mkdtemp(prefix="preprocess-"))
        os.chmod(work, 0o755)
        sandbox.own(work)
        shutil.copyfile(source, work / source.name)
        sandbox.own(work / source.name)
        words = commands[source.name]["command"].split()
        flags = []  # the flags of the real compilation, with the headers where the user can read them
        skip = False
        for at, word in enumerate(words[1:], start=1):
            if skip:
                skip = False
            elif word in {"-o", "-c", "-MT", "-MF"}:
                skip = True  # the next word is the output, source or dependency file
            elif word == "-MD" or Path(word).name == source.name:
                pass
            elif word.startswith("-I"):
                flags.append("-I" + str(readable_copy(Path(word[2:]), work)))
            elif word == "-isystem":
                flags += [word, str(readable_copy(Path(words[at + 1]), work))]
                skip = True
            else:
                flags.append(word)
        expanded = "expanded" + source.suffix  # the suffix tells the compiler the language
        steps = [([words[0], *flags, "-E", source.name, "-o", expanded], expanded),
                 ([words[0], *flags, "-c", expanded, "-o", "expanded.o"], None)]
        try:
            for command, product in steps:
                limit = min(build.compile_timeout - clocks[task].spent_building, clocks[task].left)
                started = time.monotonic()
                ok, output, timed_out = run_limited(command, timeout=limit, cwd=work,
                                                    preexec=sandbox.preexec(limit, SUBMISSION_BUILD_MEMORY))
                clocks[task].spend(time.monotonic() - started, building=True)
                if timed_out:
                    problems[task] = (f"{TASK_FILE[task]} does not compile: the compiler did not finish within "
                                      f"{limit:.0f} s and was stopped. A correct file compiles in a few seconds: "
                                      "does it include a file that never ends, or make the compiler work without end?")
                    break
                if not ok:
                    messages = compiler_messages(output.replace(str(work) + "/", ""))
                    problems[task] = does_not_compile(task, source, messages)
                    break
                if product:
                    shutil.copyfile(work / product, source)
        finally:
            shutil.rmtree(work, ignore_errors=True)
    return problems


def compile_submission(build, tasks, clocks):
    """Compiles each submitted file alone, within its task's budget; returns {task: compiler
    message} for those that fail."""
    problems = {}
    for task in tasks:
        source = build.submission / TASK_FILE[task]
        if not source.is_file():
            problems[task] = f"{TASK_FILE[task]} was not submitted."
            continue
        limit = min(build.compile_timeout - clocks[task].spent_building, clocks[task].left)
        print(f"grade: {task_name(task)}: compiling {TASK_FILE[task]}", flush=True)
        started = time.monotonic()
        ok, output, timed_out = build.build([f"submission_{task}"], timeout=limit,
                                            memory_bytes=SUBMISSION_BUILD_MEMORY)
        clocks[task].spend(time.monotonic() - started, building=True)
        if timed_out:
            problems[task] = (f"{TASK_FILE[task]} does not compile: the compiler did not finish within {limit:.0f} s "
                              "and was stopped. A correct file compiles in a few seconds: does it include a file "
                              "that never ends, or make the compiler work without end?")
        elif not ok:
            problems[task] = does_not_compile(task, source, compiler_messages(output))
    return problems


def does_not_compile(task, source, messages):
    """The message for a file the compiler rejects, with a hint when it is not text at all."""
    binary = b"\0" in source.read_bytes()
    return (f"{TASK_FILE[task]} does not compile" + (": it holds binary data, not source code. Did you submit the right file? "
                                              "The compiler says" if binary else "") + ":\n"
            + cap(messages, COMPILER_CAP // 4 if binary else COMPILER_CAP))


def compiler_messages(output):
    """The compiler's own lines from a build log (without ninja's progress and commands)."""
    keep = []
    for line in output.splitlines():
        if re.match(r"\[\d+/\d+\] ", line) or line.startswith(("ninja:", "FAILED:", ": && ")):
            continue
        if line.startswith(("/usr/bin/c++", "/usr/bin/g++", "c++ ", "g++ ", "/usr/bin/cc ", "/usr/bin/gcc ", "cc ", "gcc ")):
            continue
        keep.append(line.replace(str(REPO) + "/", ""))
    return "\n".join(keep).strip()


# --- Running one test --------------------------------------------------------------------------

class Sandbox:
    """Limits for the processes of submitted code; as root, also an unprivileged user."""

    def __init__(self, user, memory_bytes, file_bytes):
        self.account = pwd.getpwnam(user) if user else None
        self.memory_bytes = memory_bytes
        self.file_bytes = file_bytes

    def preexec(self, seconds, memory_bytes=None):
        """The function to run in the child between fork and exec, for a run of `seconds`."""
        def prepare():
            os.setsid()  # its own process group, killed as a whole afterwards
            limits = [
                (resource.RLIMIT_CPU, int(seconds) + 5),
                (resource.RLIMIT_AS, memory_bytes or self.memory_bytes),
                (resource.RLIMIT_FSIZE, self.file_bytes),
                (resource.RLIMIT_CORE, 0),
            ]
            if self.account:
                limits.append((resource.RLIMIT_NPROC, 512))
            for limit, value in limits:
                resource.setrlimit(limit, (value, value))
            if self.account:
                os.setgroups([])
                os.setgid(self.account.pw_gid)
                os.setuid(self.account.pw_uid)
        return prepare

    def own(self, path):
        if self.account:
            os.chown(path, self.account.pw_uid, self.account.pw_gid)


class TaskClock:
    """The time one task may take: compiling its file, linking its suite and running its tests.

    Tests of a task may run at the same time; each reserves its time limit from the budget before
    it starts and gives back what it did not use, so that the durations of a task's tests add up
    to no more than what its compilation left of the budget. Since the grader always has a test
    running while tests remain, grading takes no longer than the sum of the budgets (plus the
    grader's own build), on any number of cores."""

    def __init__(self, task, budget, timeout, short_timeout):
        self.task = task
        self.budget = budget
        self.left = budget
        self.timeout = timeout
        self.short_timeout = short_timeout
        self.spent_building = 0.0
        self.running = 0
        self.unfinished = 0  # tests stopped at their time limit
        self.condition = threading.Condition()

    def spend(self, seconds, building=False):
        with self.condition:
            self.left -= seconds
            if building:
                self.spent_building += seconds

    def reserve(self):
        """The time limit for the next test, reserved, and why it is that long ("each test",
        "short" or "budget"); None when the budget is used up. Waits while the rest of the budget
        is reserved by tests of this task that are running."""
        with self.condition:
            while True:
                wanted = self.short_timeout if self.unfinished else self.timeout
                granted = min(wanted, self.left)
                if granted >= min(wanted, MINIMUM_TEST_SECONDS):
                    self.left -= granted
                    self.running += 1
                    return granted, ("budget" if granted < wanted else "short" if self.unfinished else "each test")
                if not self.running:
                    return None
                self.condition.wait()

    def release(self, granted, seconds, unfinished):
        with self.condition:
            self.left += granted - seconds
            self.running -= 1
            self.unfinished += unfinished
            self.condition.notify_all()


class Processes:
    """The test processes running, and the orphans they leave.

    A test may start a process that leaves its process group (setsid) and keep running after the
    test is over, taking the CPU from the tests after it. The grader is made a "child subreaper":
    such orphans become its children instead of init's, and are killed after each test."""

    def __init__(self):
        self.lock = threading.Lock()
        self.running = set()
        try:
            libc = ctypes.CDLL(None, use_errno=True)
            libc.prctl(36, 1, 0, 0, 0)  # PR_SET_CHILD_SUBREAPER (Linux)
        except (OSError, AttributeError):
            pass

    def start(self, *arguments, **options):
        with self.lock:  # so that stop_orphans never takes a test being started for an orphan
            process = subprocess.Popen(*arguments, **options)
            self.running.add(process.pid)
        return process

    def finished(self, process):
        with self.lock:
            self.running.discard(process.pid)

    def stop_orphans(self):
        """Kills the grader's children that are not running tests: tests' orphans."""
        me = os.getpid()
        with self.lock:
            for _ in range(100):  # a fork bomb's orphans may appear while others are killed
                orphans = []
                for entry in os.listdir("/proc"):
                    if not entry.isdigit() or int(entry) in self.running:
                        continue
                    try:
                        status = Path(f"/proc/{entry}/stat").read_text()
                    except OSError:
                        continue
                    if int(status[status.rindex(")") + 2:].split()[1]) == me:  # the parent's pid
                        orphans.append(int(entry))
                if not orphans:
                    return
                for pid in orphans:
                    try:
                        os.kill(pid, signal.SIGKILL)
                        os.waitpid(pid, 0)
                    except (ProcessLookupError, ChildProcessError, PermissionError):
                        pass


def read_capped(stream, limit, sink):
    """Keeps the first `limit` bytes of a stream and drains (discards) the rest."""
    kept = bytearray()
    dropped = 0
    while True:
        chunk = stream.read(65536)
        if not chunk:
            break
        room = limit - len(kept)
        kept += chunk[:max(room, 0)]
        dropped += max(len(chunk) - max(room, 0), 0)
    sink.append((bytes(kept), dropped))


SIGNAL_HINTS = {
    signal.SIGSEGV: "a segmentation fault: the code read or wrote memory that is not its own, for example "
                    "a row or column past the end of a matrix, or a reference to a destroyed object",
    signal.SIGABRT: "an abort: often a failed assertion, an uncaught exception outside the test, or Eigen "
                    "checking an index (in a debug build)",
    signal.SIGFPE: "an arithmetic error, such as an integer division by zero",
    signal.SIGKILL: "being killed, usually for using too much memory or CPU time",
    signal.SIGXCPU: "using more CPU time than allowed: an endless loop?",
    signal.SIGXFSZ: "writing a file larger than allowed",
}


def program_files(task, folder):
    """For a program task (a C program graded by running it), its suite's companions in `folder`,
    by the environment variable that tells the suite where they are: the submitted program and
    the project's own command that gives the expected output (tests/support/program_under_test.hpp)."""
    if task not in PROGRAM_TASKS:
        return {}
    return {"BILLIARD_PROGRAM_UNDER_TEST": folder / f"program_{task}",
            "BILLIARD_EXPECTED_PROGRAM": folder / f"expected_{task}"}


def run_test(test, executable, sandbox, scratch, processes, limit, why, clock):
    """Runs one graded test in its own process, stopped after `limit` seconds (why: see
    TaskClock.reserve), and fills in test.passed and test.feedback."""
    work = Path(tempfile.mkdtemp(prefix="test-", dir=scratch))
    sandbox.own(work)
    token = secrets.token_hex(16)
    result_file = work / "result.txt"
    environment = {
        "PATH": "/usr/bin:/bin", "HOME": str(work), "TMPDIR": str(work), "LANG": "C.UTF-8",
        "BILLIARD_GRADER_TOKEN": token,
    } | {name: str(path) for name, path in program_files(test.task, executable.parent).items()}
    if test.task in PROGRAM_TASKS:  # the suite's own limit on the program then stays out of the way
        environment["BILLIARD_TEST_TIME_LIMIT"] = f"{limit:g}"
    command = [str(executable), f"--gtest_filter={test.name}", f"--graded-result={result_file}",
               "--gtest_color=no", "--gtest_brief=0"]
    started = time.monotonic()
    process = processes.start(command, cwd=work, env=environment, stdin=subprocess.DEVNULL,
                              stdout=subprocess.PIPE, stderr=subprocess.STDOUT, preexec_fn=sandbox.preexec(limit))
    captured = []
    reader = threading.Thread(target=read_capped, args=(process.stdout, FEEDBACK_CAP * 4, captured), daemon=True)
    reader.start()
    timed_out = False
    try:
        process.wait(timeout=limit)
    except subprocess.TimeoutExpired:
        timed_out = True
    finally:
        kill_group(process)  # the test and anything it started
        processes.finished(process)
        processes.stop_orphans()  # and what left its group
    reader.join(timeout=5)
    test.seconds = time.monotonic() - started
    output, dropped = captured[0] if captured else (b"", 0)
    text = output.decode(errors="replace")

    try:
        reported = result_file.read_text(errors="replace").strip() if result_file.is_file() else ""
    except OSError:
        reported = ""
    test.passed = not timed_out and process.returncode == 0 and reported == f"{token} passed"
    # Stopped for its CPU time (several busy threads) is not finishing either.
    test.unfinished = timed_out or process.returncode == -signal.SIGXCPU

    messages = gtest_messages(text)
    if dropped:
        messages += f"\n... ({dropped} more bytes of output were dropped)"
    if test.unfinished:
        messages = unfinished_message(clock, limit, why) + "\n" + messages
    elif process.returncode < 0:
        number = -process.returncode
        name = signal.Signals(number).name if number in signal.Signals._value2member_map_ else f"signal {number}"
        messages = (f"The test program crashed with {name}, "
                    f"{SIGNAL_HINTS.get(number, 'an error the program could not recover from')}.\n" + messages)
    elif not test.passed and not reported and process.returncode == 0:
        messages = ("The test program ended before the test was over (did the code call exit()?), "
                    "so the test cannot count as passed.\n" + messages)
    test.feedback = cap(messages.strip(), FEEDBACK_CAP)
    shutil.rmtree(work, ignore_errors=True)


def unfinished_message(clock, limit, why):
    """What a student reads about a test stopped at its time limit."""
    because = {
        "budget": f"what was left of the {clock.budget:g} s that compiling {TASK_FILE[clock.task]} and running all of "
                  f"{clock.task}'s tests may take",
        "short": f"the limit for {clock.task}'s tests once one of them did not finish within {clock.timeout:g} s",
        "each test": "the limit for each test",
    }[why]
    return (f"The test did not finish within {limit:.3g} seconds ({because}) and was stopped; a correct solution "
            f"finishes each test in a few seconds. Is there an endless loop in {TASK_FUNCTIONS[clock.task]}, "
            "or a loop whose end depends on a condition that never holds?")


def not_run_message(clock):
    return (f"This test was not run: compiling {TASK_FILE[clock.task]} and running {clock.task}'s tests may take "
            f"{clock.budget:g} s in all, and {used_up(clock)}. A correct solution needs a few seconds for all of "
            f"them. Is there an endless loop in {TASK_FUNCTIONS[clock.task]}? Once its tests finish, this one runs "
            "too.")


def used_up(clock):
    """What used up a task's budget, for students."""
    return (f"that time was used up: compiling took {clock.spent_building:.0f} s and "
            f"{plural(clock.unfinished, 'test')} did not finish (see {'its' if clock.unfinished == 1 else 'their'} "
            "messages)")


def run_budgeted(test, executable, sandbox, scratch, processes, clock):
    """Runs one test within its task's budget, or marks it not run when the budget is used up."""
    reserved = clock.reserve()
    if reserved is None:
        test.not_run = True
        test.feedback = not_run_message(clock)
        return
    limit, why = reserved
    try:
        run_test(test, executable, sandbox, scratch, processes, limit, why, clock)
    finally:
        clock.release(limit, test.seconds, test.unfinished)


def gtest_messages(text):
    """GoogleTest's output without its banner lines: the failure messages and anything printed."""
    noise = ("[==========]", "[----------]", "[ RUN      ]", "[       OK ]", "Note: Google Test filter",
             "[  PASSED  ]", "[  FAILED  ]", "[  SKIPPED ]")
    text = re.sub(r'unknown file: Failure\nC\+\+ exception with description "(.*)" thrown in the test body\.',
                  r"The code threw an exception: \1", text)
    lines = [line for line in text.splitlines() if not line.startswith(noise)]
    while lines and not lines[-1].strip():
        lines.pop()
    return "\n".join(line.replace(str(REPO) + "/", "") for line in lines
                     if not line.strip().endswith("FAILED TEST") and not line.strip().endswith("FAILED TESTS"))


class ResultCache:
    """Results of tests by (executable checksum, test, time limit): the suites are deterministic,
    so an unchanged executable gives the same results. Used when grading many variants of one
    submission, such as the mutants."""

    def __init__(self, folder, timeout):
        self.folder = folder
        self.timeout = timeout
        self.checksums = {}
        folder.mkdir(parents=True, exist_ok=True)

    def key(self, test, executable):
        if executable not in self.checksums:
            # A program task's suite is the same for every submission: its program counts too.
            files = [executable, *program_files(test.task, executable.parent).values()]
            self.checksums[executable] = hashlib.sha256(b"".join(hashlib.sha256(path.read_bytes()).digest()
                                                                 for path in files)).hexdigest()
        name = f"{self.checksums[executable]}-{test.name}-{self.timeout:g}"
        return self.folder / (hashlib.sha256(name.encode()).hexdigest() + ".json")

    def recall(self, test, executable):
        entry = self.key(test, executable)
        if not entry.is_file():
            return False
        saved = json.loads(entry.read_text())
        test.passed, test.feedback, test.seconds = saved["passed"], saved["feedback"], saved["seconds"]
        return True

    def remember(self, test, executable):
        if test.unfinished or test.not_run:
            return  # depends on the time left, not only on the executable
        write_atomically(self.key(test, executable), json.dumps(
            {"passed": test.passed, "feedback": test.feedback, "seconds": test.seconds}))


# --- Reports -----------------------------------------------------------------------------------

def catalog(build, task):
    """The graded tests of a task's suite, with points and visibility (no submitted code runs)."""
    done = subprocess.run([str(build.executable(f"catalog_{task}")), "--list-graded"], stdout=subprocess.PIPE,
                          stderr=subprocess.PIPE, text=True, timeout=60)
    if done.returncode != 0:
        raise RuntimeError(f"listing the tests of {task} failed:\n{done.stderr}")
    return [json.loads(line) for line in done.stdout.splitlines() if line.strip()]


def print_table(results, verbose):
    width = max(len(task) for task in TASKS) + 2
    print(f"\n{'task':<{width + 4}}points")
    for result in results:
        optional = "  (optional)" if is_optional(result.task) else ""
        print(f"{TASK_NUMBER[result.task]:>2}  {result.task:<{width}}{result.score:>3} / {result.maximum}{optional}")
        if result.problem:
            print(indent(result.problem, 6))
            continue
        failed = [test for test in result.tests if not test.passed and not test.not_run]
        not_run = [test for test in result.tests if test.not_run]
        if task_progress(result).missing == result.task:
            print(f"      not implemented yet: write it in tasks/{TASK_FILE[result.task]} (every test fails until then)")
            continue
        for test in failed:
            name = "a hidden test" if test.visibility == "hidden" else test.name
            print(f"      failed: {name} ({plural(test.points, 'point')})")
            if verbose and test.feedback:
                feedback = shown_feedback(test)
                print(indent(feedback, 10))
        if not_run:
            print(f"      not run: {plural(len(not_run), 'test')} ({plural(sum(t.points for t in not_run), 'point')}): "
                  f"the task may take {result.clock.budget:g} s in all, and {used_up(result.clock)}. An endless "
                  f"loop in {TASK_FUNCTIONS[result.task]}?")
    counted = [result for result in results if not is_optional(result.task)]
    extra = [result for result in results if is_optional(result.task)]
    print(f"\n    {'total':<{width}}{sum(r.score for r in counted):>3} / {sum(r.maximum for r in counted)}")
    if extra:
        print(f"    {'optional':<{width}}{sum(r.score for r in extra):>3} / {sum(r.maximum for r in extra)}"
              f"  (extra credit: {', '.join(r.task for r in extra)}; not in the total)")
    print("\n" + "\n".join(next_step([task_progress(result) for result in results])))


def task_progress(result):
    """A task's result as progress.py sees it, for the "Next:" lines."""
    progress = TaskProgress(result.task, problem=result.problem)
    for test in result.tests:
        progress.record(test.name, test.passed, test.feedback)
    return progress


def shown_feedback(test):
    """A test's feedback as the student sees it: of a hidden test, only whether it ran out of time."""
    if test.visibility != "hidden":
        return test.feedback
    if test.unfinished:
        return (HIDDEN_FEEDBACK + " It did not finish within its time limit: an endless loop in "
                f"{TASK_FUNCTIONS[test.task]}?")
    if test.not_run:
        return HIDDEN_FEEDBACK + f" It was not run: the time for {test.task}'s tests was used up (see the others)."
    return HIDDEN_FEEDBACK


def plural(count, word):
    return f"{count} {word}{'' if count == 1 else 's'}"


def indent(text, spaces):
    return "\n".join(" " * spaces + line if line else "" for line in text.splitlines())


def gradescope_results(results, elapsed):
    """Gradescope's results.json: the score and one entry per test."""
    tests = []
    for result in results:
        if result.problem:
            tests.append({"name": f"{result.task}: builds", "score": 0, "max_score": result.maximum,
                          "status": "failed", "visibility": "visible", "output": result.problem})
            continue
        for test in result.tests:
            hidden = test.visibility == "hidden"
            tests.append({
                "name": f"{result.task}: " + ("hidden test" if hidden else test.name),
                "score": test.score, "max_score": test.points, "status": "passed" if test.passed else "failed",
                "visibility": test.visibility,
                "output": shown_feedback(test) or ("passed" if test.passed else ""),
            })
    return {
        "score": sum(result.score for result in results),
        "execution_time": round(elapsed, 1),
        "output": "Points per task: " + ", ".join(f"{r.task} {r.score}/{r.maximum}" + (" (optional)" if is_optional(r.task) else "")
                                            for r in results),
        "stdout_visibility": "hidden",
        "tests": tests,
    }


def junit_xml(results):
    suites = ET.Element("testsuites", name="billiard")
    for result in results:
        failures = sum(not test.passed for test in result.tests) + (1 if result.problem else 0)
        suite = ET.SubElement(suites, "testsuite", name=result.task, tests=str(max(len(result.tests), 1)),
                              failures=str(failures))
        ET.SubElement(suite, "properties").append(
            ET.Element("property", name="score", value=f"{result.score}/{result.maximum}"))
        if result.problem:
            case = ET.SubElement(suite, "testcase", classname=result.task, name="builds")
            ET.SubElement(case, "failure", message="does not build").text = result.problem
        for test in result.tests:
            hidden = test.visibility == "hidden"
            # A hidden test shows neither its name nor its suite's (which may name it too).
            case = ET.SubElement(suite, "testcase",
                                 classname=f"{result.task}.hidden" if hidden else f"{result.task}.{test.name.split('.')[0]}",
                                 name="hidden test" if hidden else test.name.split(".", 1)[1],
                                 time=f"{test.seconds:.3f}")
            if not test.passed:
                ET.SubElement(case, "failure", message=f"0 of {test.points} points").text = (
                    shown_feedback(test))
    ET.indent(suites)
    return ET.tostring(suites, encoding="unicode", xml_declaration=True) + "\n"


def write_atomically(path, text):
    path.parent.mkdir(parents=True, exist_ok=True)
    partial = path.with_name(path.name + ".partial")
    partial.write_text(text)
    os.replace(partial, path)


# --- Main --------------------------------------------------------------------------------------

def parse_arguments(argv):
    parser = argparse.ArgumentParser(prog="grade", description=__doc__.split("\n\n")[0])
    parser.add_argument("--submission", type=Path, default=REPO / "tasks",
                        help="folder with the task files <task>.cpp, or <task>.c for a C task (default: tasks/)")
    parser.add_argument("--results", type=Path, default=REPO / "build" / "grade" / "results",
                        help="folder for results.json and junit.xml (default: build/grade/results)")
    parser.add_argument("--build", type=Path, default=REPO / "build" / "grade" / "build",
                        help="build folder (default: build/grade/build)")
    parser.add_argument("--dependencies", choices=["reference", "submission"],
                        help="code for the other tasks of each suite: the reference solutions (default where "
                             "solutions/ exists) or the submission's own files")
    parser.add_argument("--task", action="append", choices=TASKS, help="grade only this task (repeatable)")
    parser.add_argument("--timeout", type=float, default=60.0, help="seconds per test (default 60)")
    parser.add_argument("--short-timeout", type=float, default=10.0,
                        help="seconds per test for the rest of a task's tests once one of them did not finish "
                             "within --timeout (default 10)")
    parser.add_argument("--task-budget", type=float, default=120.0,
                        help="seconds each task may take in all: compiling its file, linking its suite and running "
                             "its tests (their durations added up, also when two run at once); tests left when it is "
                             "used up fail without running. Grading takes at most the grader's own build plus one "
                             "budget per task (default 120)")
    parser.add_argument("--compile-timeout", type=float, default=60.0,
                        help="seconds per submitted file, within its task's budget (default 60)")
    parser.add_argument("--build-timeout", type=float, default=1800.0,
                        help="seconds for the grader's own build, which does not depend on the submission "
                             "(default 1800)")
    parser.add_argument("--jobs", type=int, default=2, help="tests run at once (default 2)")
    parser.add_argument("--user", help="run tests as this user (default: 'nobody' when run as root)")
    parser.add_argument("--protect-reference", action="store_true",
                        help="(as root, for the platforms' graders) make solutions/ and instructor-only tests "
                             "unreadable to the test user, and expand each submitted file's #include lines and "
                             "compile it as that user first, so that a submission cannot include the reference code "
                             "(with #include or the assembler's .incbin)")
    parser.add_argument("--brief", action="store_true", help="list failing tests without their messages")
    parser.add_argument("--require-full", action="store_true",
                        help="exit with status 1 unless every graded task has full points (for CI graders such "
                             "as GitHub Classroom's command grader)")
    parser.add_argument("--cache", type=Path,
                        help="folder to remember results by test and executable checksum, so that unchanged "
                             "suites are not run again (for grading many variants; not for untrusted setups)")
    arguments = parser.parse_args(argv)
    for folder in ["submission", "results", "build"]:  # the build's own records hold absolute paths
        setattr(arguments, folder, getattr(arguments, folder).absolute())
    if not arguments.submission.is_dir():
        fail(f"--submission {arguments.submission} is not a folder; give the folder that holds the task files")
    if arguments.dependencies is None:
        arguments.dependencies = "reference" if (REPO / "solutions" / "CMakeLists.txt").is_file() else "submission"
    if arguments.dependencies == "reference" and not (REPO / "solutions" / "CMakeLists.txt").is_file():
        fail("--dependencies reference needs the reference solutions in solutions/, which this copy does not have")
    if min(arguments.timeout, arguments.short_timeout, arguments.task_budget, arguments.compile_timeout,
           arguments.build_timeout) <= 0 or arguments.jobs < 1:
        fail("--timeout, --short-timeout, --task-budget, --compile-timeout and --build-timeout must be positive, "
             "and --jobs at least 1")
    if arguments.user is None and os.geteuid() == 0:
        arguments.user = "nobody"
    if arguments.protect_reference and not arguments.user:
        fail("--protect-reference needs an unprivileged test user: run as root, or give --user")
    if arguments.user:
        try:
            pwd.getpwnam(arguments.user)
        except KeyError:
            fail(f"--user {arguments.user} does not exist on this machine")
    return arguments


def stage_submission(submission, grading):
    """Copies the task files of a submission into the grader's own folder, grading/submission/,
    and returns it with {task: message} for the task files that cannot be graded (a folder, a
    link, a special or too large file). Only regular files are read, without following links,
    so that a submission cannot make the grader read files outside it. A file whose content is
    unchanged since the last run is left alone, so the build does not compile it again."""
    staged = grading / "submission"
    staged.mkdir(parents=True, exist_ok=True)
    problems = {}
    for task in TASKS:
        source, target = submission / f"{TASK_FILE[task]}", staged / f"{TASK_FILE[task]}"
        previous = grading / "previous" / f"{TASK_FILE[task]}"  # the submitted text behind `target`
        text, problem = read_task_file(source)
        if problem:
            problems[task] = (f"{TASK_FILE[task]} {problem}, so it was not graded (0 points for this task). Submit the file "
                              "itself.")
        if text is not None:
            if not (target.is_file() and previous.is_file() and previous.read_bytes() == text):
                previous.parent.mkdir(exist_ok=True)
                previous.write_bytes(text)
                target.write_bytes(text)
        else:
            target.unlink(missing_ok=True)
            previous.unlink(missing_ok=True)
    return staged, problems


def read_task_file(path):
    """(content, None) for a regular file of at most SUBMITTED_FILE_CAP bytes; else (None, why
    it cannot be graded, as in "<file> is a folder"; None when there is no such file). Links are
    not followed, and special files (a FIFO, a device, a socket) are not opened."""
    try:
        mode = os.lstat(path).st_mode
    except FileNotFoundError:
        return None, None
    except OSError:
        return None, "cannot be read"
    if not stat.S_ISREG(mode):
        return None, LINK if stat.S_ISLNK(mode) else FOLDER if stat.S_ISDIR(mode) else SPECIAL
    try:  # without following a link put in its place since, nor waiting on a FIFO
        descriptor = os.open(path, os.O_RDONLY | os.O_NOFOLLOW | os.O_NONBLOCK)
    except OSError:
        return None, "cannot be read"
    with os.fdopen(descriptor, "rb") as file:
        if not stat.S_ISREG(os.fstat(file.fileno()).st_mode):
            return None, SPECIAL
        text = file.read(SUBMITTED_FILE_CAP + 1)
    if len(text) > SUBMITTED_FILE_CAP:
        return None, TOO_LARGE
    return text, None


def grade(arguments):
    started = time.monotonic()
    tasks = arguments.task or TASKS
    grading = arguments.build.parent
    grading.mkdir(parents=True, exist_ok=True)

    # Only the task files are taken from the submission, into a folder of the grader's own.
    staged, problems = stage_submission(arguments.submission, grading)
    build = Build(arguments.build, staged, arguments.dependencies, arguments.compile_timeout, arguments.build_timeout)
    print(f"grade: building the grader's own code and the graded suites in {arguments.build} (a minute or two the "
          "first time, seconds after), with "
          f"{'the reference code for the other tasks' if arguments.dependencies == 'reference' else 'your code for every task'}",
          flush=True)
    # A task file that was not submitted is a stub from the start (its task scores 0).
    stubbed = [task for task in TASKS if not (staged / f"{TASK_FILE[task]}").is_file()]
    build.configure(stubbed=stubbed)
    build.prebuild(stubbed)
    own_build = time.monotonic() - started
    sandbox = Sandbox(arguments.user, memory_bytes=4 << 30, file_bytes=256 << 20)
    clocks = {task: TaskClock(task, arguments.task_budget, arguments.timeout, arguments.short_timeout)
              for task in TASKS}
    if arguments.protect_reference:
        private = [path for path in [REPO / "solutions", REPO / "tests" / "graded" / "hidden", REPO / "tests" / "mutants"]
                   if path.is_dir()]
        modes = {path: path.stat().st_mode for path in private}
        try:
            for path in private:
                os.chmod(path, 0o700)
            problems.update(preprocess_as(sandbox, build, [task for task in TASKS if task not in problems], clocks))
        finally:
            for path, mode in modes.items():
                os.chmod(path, mode)
    problems.update(compile_submission(build, [task for task in TASKS if task not in problems], clocks))
    if set(problems) - set(stubbed):
        build.configure(stubbed=sorted(problems))
        build.prebuild(sorted(problems))

    # Each task's suite is linked on its own, within its task's budget.
    results = []
    for task in tasks:
        result = TaskResult(task, clock=clocks[task])
        listed = catalog(build, task)
        result.maximum = sum(entry["points"] for entry in listed)
        if task in problems:
            result.problem = problems[task]
            results.append(result)
            continue
        # No unlink first: Ninja relinks only a suite whose task file changed (seconds saved for
        # every unchanged task), and a failed link is told by its status and a missing file.
        limit = max(min(arguments.compile_timeout, clocks[task].left), MINIMUM_TEST_SECONDS)
        print(f"grade: {task_name(task)}: linking its suite", flush=True)
        link_started = time.monotonic()
        ok, link_output, timed_out = build.build([f"grade_{task}"], timeout=limit,
                                                 memory_bytes=SUBMISSION_BUILD_MEMORY)
        clocks[task].spend(time.monotonic() - link_started, building=True)
        if timed_out:
            result.problem = (f"{TASK_FILE[task]} compiles, but linking the suite with it did not finish within {limit:.0f} "
                              "s. "
                              "A correct file links in about a second: does it define very large arrays?")
        elif (not ok or not build.executable(f"grade_{task}").is_file()) and task in PROGRAM_TASKS:
            result.problem = ("the grader could not build this task's suite (not your program's fault):\n"
                              + cap(compiler_messages(link_output), COMPILER_CAP))
        elif not ok or not build.executable(f"grade_{task}").is_file():
            result.problem = (f"{TASK_FILE[task]} compiles, but the suite does not link with it. Does it define "
                              f"{TASK_FUNCTIONS[task]} exactly as lib/include/billiard/course.hpp declares it, and "
                              "nothing the other tasks define? The linker says:\n"
                              + cap(compiler_messages(link_output), COMPILER_CAP))
        else:
            result.tests = [TestResult(task, entry["test"], entry["points"], entry["visibility"]) for entry in listed]
        results.append(result)

    # Run every test of every task in its own process, a few at a time, each task's within its
    # budget. The suites are copied out of the build (which may sit where the test user cannot
    # go, such as under /root) into a folder it can read but not change.
    scratch = Path(tempfile.mkdtemp(prefix="billiard-grade-"))
    os.chmod(scratch, 0o755)
    suites = {}
    for result in results:
        if result.tests:
            suites[result.task] = scratch / f"grade_{result.task}"
            shutil.copyfile(build.executable(f"grade_{result.task}"), suites[result.task])
            os.chmod(suites[result.task], 0o755)
            built = {"BILLIARD_PROGRAM_UNDER_TEST": build.executable(f"submission_{result.task}"),
                     "BILLIARD_EXPECTED_PROGRAM": build.folder / result.task}
            for name, copy in program_files(result.task, scratch).items():
                shutil.copyfile(built[name], copy)
                os.chmod(copy, 0o755)
    jobs = [(test, suites[test.task]) for result in results for test in result.tests]
    cache = ResultCache(arguments.cache, arguments.timeout) if arguments.cache else None
    if cache:
        jobs = [(test, executable) for test, executable in jobs if not cache.recall(test, executable)]
    print(f"grade: running {len(jobs)} tests, each in its own process, {arguments.jobs} at a time", flush=True)
    processes = Processes()
    try:
        with concurrent.futures.ThreadPoolExecutor(max_workers=arguments.jobs) as pool:
            running = {}  # task -> its tests' futures, in course order
            for test, executable in jobs:
                running.setdefault(test.task, []).append(
                    pool.submit(run_budgeted, test, executable, sandbox, scratch, processes, clocks[test.task]))
            for task, futures in running.items():
                for future in futures:
                    future.result()
                print(f"grade: {task_name(task)}: {len(futures)} tests run", flush=True)
    finally:
        shutil.rmtree(scratch, ignore_errors=True)
    if cache:
        for test, executable in jobs:
            cache.remember(test, executable)

    elapsed = time.monotonic() - started
    write_atomically(arguments.results / "results.json", json.dumps(gradescope_results(results, elapsed), indent=2) + "\n")
    write_atomically(arguments.results / "junit.xml", junit_xml(results))
    print_table(results, verbose=not arguments.brief)
    print(f"\nresults: {arguments.results / 'results.json'} (Gradescope) and {arguments.results / 'junit.xml'} (JUnit)")
    print(f"grade: {elapsed:.0f} s in all, of which {own_build:.0f} s for the grader's own build (each task may take "
          f"{arguments.task_budget:g} s more)")
    return results


def main(argv=None):
    arguments = parse_arguments(sys.argv[1:] if argv is None else argv)
    results = grade(arguments)
    if arguments.require_full and any(result.score < result.maximum for result in results):
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
