#!/usr/bin/python3
"""Grades the course's tasks of a submission (tests/grader/course.txt: the six tasks and the
extension stages that are not switched off) and writes what the grading platforms read.

    /usr/bin/python3 tests/grader/grade.py [--submission DIR] [--results DIR] [options]

For each task it compiles the submitted file on its own, once (a file that does not compile
scores 0 for its task, with the compiler's message as feedback), links the task's graded suite
with it (and, where the reference solutions exist, with the reference code of the other tasks,
so a mistake in one task cannot cost points in another), then runs every graded test in its own
process with a time limit, an output cap, resource limits and, when run as root, as an
unprivileged user. A test earns its points only if the suite's own main() reports it passed
with a secret token given to that process alone: an early exit(0), a crash, a hang or forged
output earns nothing.

The time limits follow the machine where the reference solutions exist (time_limits.py: ten
times what the reference needs here, measured once per build folder); otherwise they are fixed
(--timeout, --task-budget). Either way each task has a budget for compiling its file, linking its
suite and running its tests, so a submission, however it misbehaves, is graded within the
grader's own build plus the sum of the budgets, and only the misbehaving task loses points.

Prints a table (task, points / maximum, and each failing test's message and hint), and writes
results.json (Gradescope's format), junit.xml and report.html into --results. A failing visible
test of a task where a state evolves draws its failing case (tests/support/failure_pictures.hpp):
the picture goes to --results/pictures/, its message names it, report.html shows it under the
message and results.json embeds it. Exit status 0 when grading completed (whatever the score), 2
for bad arguments.
"""

import argparse
import base64
import concurrent.futures
import ctypes
import functools
import hashlib
import html
import json
import math
import os
import pwd
import re
import resource
import secrets
import select
import shlex
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
import time_limits
from time_limits import TaskClock, fixed_limits, measured_limits, not_run_message, unfinished_message, used_up

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
# The C track's programs are linked with the maths library, as the build links them
# (billiard_add_program in CMakeLists.txt, grader_compile_c in tests/grader/CMakeLists.txt).
PROGRAM_LIBRARIES = ["-lm"]
COMPILED_KEPT = 400  # compiled task files remembered in a build folder (the oldest go first)
# Pictures of failing cases: the folder a test draws into (in its own folder, as the suites'
# BILLIARD_PICTURES) and the one they are kept in, in --results; the largest kept (a picture of
# fifty circles has 60 kB); the line of a message that names one.
PICTURES = "pictures"
PICTURE_CAP = 2 << 20
PICTURE_LINE = re.compile(r"^Picture: .*(\n|$)", re.MULTILINE)


@dataclass
class TestResult:
    task: str
    name: str  # "Suite.Name"
    points: int
    visibility: str
    passed: bool = False
    feedback: str = ""
    seconds: float = 0.0      # wall time
    cpu_seconds: float = 0.0  # what its process (and the processes it waited for) computed
    unfinished: bool = False  # stopped at its time limit
    not_run: bool = False     # its task's time budget was used up before it could start
    picture: str = ""         # the picture of its failing case, relative to the results folder

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
    compile_seconds: float = 0.0
    link_seconds: float = 0.0

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
        wait_for(process, max(timeout, 0.1))
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


def wait_for(process, timeout):
    """Popen.wait(timeout), without its polling (which adds up to 50 ms to every compilation):
    woken when the process ends, where the system can (Linux's pidfd)."""
    try:
        ended = os.pidfd_open(process.pid)
    except (AttributeError, OSError):
        return process.wait(timeout=timeout)
    try:
        if not select.select([ended], [], [], timeout)[0]:
            raise subprocess.TimeoutExpired(process.args, timeout)
    finally:
        os.close(ended)
    return process.wait()


def kill_group(process):
    """Kills a process started in its own group, and whatever it started, and waits for it."""
    try:
        os.killpg(process.pid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError):
        pass
    process.wait()


# --- Building ----------------------------------------------------------------------------------

class Build:
    """The grader's CMake build (see tests/grader/CMakeLists.txt): nothing in it depends on a
    submission; the compiled task files go to its submitted/ folder."""

    def __init__(self, folder, dependencies, build_timeout):
        self.folder = folder
        self.dependencies = dependencies
        self.build_timeout = build_timeout
        self.submitted = folder / "submitted"

    def configure(self):
        """Configures the build, unless it is configured so already (then Ninja runs CMake again
        by itself where the project's CMake files changed)."""
        options = {"BILLIARD_COURSE": "solutions" if self.dependencies == "reference" else "tasks",
                   "BILLIARD_GRADER_OBJECTS": str(self.submitted), "BILLIARD_GRADE_DEPENDENCIES": self.dependencies}
        try:
            cache = (self.folder / "CMakeCache.txt").read_text()
            if (self.folder / "build.ninja").is_file() and all(
                    re.search(rf"^{name}:\w+={re.escape(value)}$", cache, re.M) for name, value in options.items()):
                return
        except OSError:
            pass
        command = ["cmake", "-S", str(REPO), "-B", str(self.folder), "-G", "Ninja", "-DCMAKE_BUILD_TYPE=Release",
                   "-DBILLIARD_CHECK_STUBS=OFF", "-DBILLIARD_PYTHON=OFF", "-DCMAKE_EXPORT_COMPILE_COMMANDS=ON",
                   *[f"-D{name}={value}" for name, value in options.items()]]
        ok, output, _ = run_limited(command, timeout=self.build_timeout)
        if not ok:
            raise RuntimeError("configuring the grader's build failed:\n" + output)

    def build(self, targets, timeout, memory_bytes=BUILD_MEMORY):
        """Builds targets with the build's Ninja (not through `cmake --build`, which would start one
        more program for every suite linked); returns (ok, output, timed out)."""
        return run_limited([self.ninja, "-C", str(self.folder), *targets], timeout=timeout,
                           preexec=build_limits(memory_bytes))

    @functools.cached_property
    def ninja(self):
        found = re.search(r"^CMAKE_MAKE_PROGRAM:\w+=(.*)$", (self.folder / "CMakeCache.txt").read_text(), re.M)
        return found.group(1) if found else "ninja"

    def prebuild(self):
        """Builds everything that does not depend on the submission (the library, the suites'
        test code, the reference code, the stand-ins, the catalogs, the compile commands and the
        precompiled headers for the submitted files), so that the time of each task's budget goes
        to its own file and tests only."""
        targets = ["grader_compile_cxx", "grader_compile_c"]
        for task in TASKS:
            targets += [f"catalog_{task}", f"grader_stub_{task}"]
            if task in PROGRAM_TASKS:
                targets += [f"grade_{task}", task]  # the suite, and the command that gives the expected output
            elif self.dependencies == "reference":
                targets.append(f"billiard_solutions_{task}")
        ok, output, _ = self.build(targets, timeout=self.build_timeout)
        if not ok:
            raise RuntimeError("building the grader's own code failed:\n" + output[-20000:])
        self.submitted.mkdir(exist_ok=True)

    def executable(self, name):
        return self.folder / "tests" / "grader" / name

    @functools.cached_property
    def stubs(self):
        """{task: the stand-in for a task file that is missing or does not compile}: an object
        file, or a program for a program task (the build lists them, in a file stubs.txt)."""
        lines = (self.folder / "tests" / "grader" / "stubs.txt").read_text().splitlines()
        return {task: Path(path) for task, path in (line.split(" ", 1) for line in lines if line.strip())}

    def compiled(self, task):
        """Where the compiled task file goes: <task>.o, which grade_<task> links, or the program."""
        return self.submitted / (f"program_{task}" if task in PROGRAM_TASKS else f"{task}.o")


def command_words(entry):
    """A compile command from compile_commands.json, without its source and output: the compiler
    and its flags."""
    words = shlex.split(entry["command"])
    kept, skip = [], False
    for word in words:
        if skip:
            skip = False
        elif word in {"-o", "-c"}:
            skip = True
        else:
            kept.append(word)
    return kept


def defines_before_course_headers(text):
    """True when a C++ task file defines or undefines a macro before it includes the course's
    headers (or includes none of them): then the precompiled headers, which come first, could
    change what the file means, and it is compiled without them."""
    for line in text.decode(errors="replace").splitlines():
        if re.match(r"\s*#\s*include\s*[<\"]billiard/", line):
            return False
        if re.match(r"\s*#\s*(define|undef)\b", line):
            return True
    return True


class TaskFileCompiler:
    """Compiles submitted task files, each once, with the commands of the grader's build for them
    (grader_compile_cxx and grader_compile_c in compile_commands.json): the same flags as the
    course's own code, and for C++ the precompiled course headers.

    With the reference solutions made unreadable to the test user (--protect-reference), each file
    is compiled as that user, with copies of the project's headers it may read: a file that tries
    `#include "../solutions/propagate.cpp"`, or `asm(".incbin ...")` for the assembler, fails, and
    its object file is what the suite links. Otherwise a file whose text, command and headers are
    unchanged since an earlier grading in this build folder is not compiled again."""

    def __init__(self, build, sandbox, protect, scratch):
        commands = {Path(entry["file"]).name: entry for entry in
                    json.loads((build.folder / "compile_commands.json").read_text())}
        for name in ["submitted_file.cpp", "submitted_file.c"]:
            if name not in commands:  # never compile a file unchecked
                raise RuntimeError(f"the grader's build has no compile command for {name}")
        self.build = build
        self.sandbox = sandbox
        self.protect = protect
        self.commands = {".cpp": command_words(commands["submitted_file.cpp"]),
                         ".c": command_words(commands["submitted_file.c"])}
        self.words = self.commands  # as run: with --protect-reference, with readable copies of the headers
        self.work = scratch
        if protect:
            self.words = {suffix: self.readable(words) for suffix, words in self.words.items()}
        self.cache = build.submitted / "cache"
        self.cache.mkdir(exist_ok=True)

    def readable(self, words):
        """The command with the project's folders and files (which may sit where the test user
        cannot read, such as under /root) replaced by copies in the grading's scratch folder."""
        copies = self.work / "include"
        copies.mkdir(exist_ok=True)
        result = []
        for at, word in enumerate(words):
            option = "-I" if word.startswith("-I") else words[at - 1] if at else ""
            path = Path(word[2:] if option == "-I" else word)
            if option not in {"-I", "-isystem", "-include"} or not (path.is_relative_to(REPO) or
                                                                    path.is_relative_to(self.build.folder)):
                result.append(word)
                continue
            copy = copies / str(at)
            if option == "-include":  # a precompiled header: the header and its .gch beside it
                copy.mkdir()
                for source in path.parent.glob(path.name + "*"):
                    share(source, copy / source.name)
                result.append(str(copy / path.name))
            else:
                shutil.copytree(path, copy)
                result.append(f"-I{copy}" if option == "-I" else str(copy))
        for item in [copies, *copies.rglob("*")]:
            if item.is_dir() or item.stat().st_nlink == 1:  # not the build's own files, shared by a link
                os.chmod(item, 0o755 if item.is_dir() else 0o644)
        return result

    def command(self, task, text):
        words = self.words[Path(TASK_FILE[task]).suffix]
        if task not in PROGRAM_TASKS and defines_before_course_headers(text):
            without = []
            for at, word in enumerate(words):
                if word == "-Winvalid-pch" or word == "-include" or (at and words[at - 1] == "-include"):
                    continue
                without.append(word)
            words = without
        return words

    def compile(self, task, source, limit, remembered=True):
        """Compiles a task file into build.compiled(task), or takes it from the files compiled
        before (unless `remembered` is false); returns (problem message or "", seconds spent)."""
        text = source.read_bytes()
        words = self.command(task, text)
        target = self.build.compiled(task)
        key = hashlib.sha256(json.dumps([TASK_FILE[task], words]).encode() + b"\0" + text).hexdigest()
        if remembered and not self.protect and self.recall(key, target):
            return "", 0.0
        work = Path(tempfile.mkdtemp(prefix="compile-", dir=self.work))
        os.chmod(work, 0o755)
        self.sandbox.own(work)
        name = TASK_FILE[task]
        shutil.copyfile(source, work / name)
        self.sandbox.own(work / name)
        output_name = "program" if task in PROGRAM_TASKS else "compiled.o"
        command = [*words, *(["-c"] if task not in PROGRAM_TASKS else []), name, "-o", output_name,
                   "-MD", "-MF", "depends.d", *(PROGRAM_LIBRARIES if task in PROGRAM_TASKS else [])]
        started = time.monotonic()
        preexec = self.sandbox.preexec(limit, SUBMISSION_BUILD_MEMORY) if self.protect else build_limits(SUBMISSION_BUILD_MEMORY)
        try:
            ok, output, timed_out = run_limited(command, timeout=limit, cwd=work, preexec=preexec)
            seconds = time.monotonic() - started
            if timed_out:
                return (f"{name} does not compile: the compiler did not finish within {limit:.0f} s and was stopped. A "
                        "correct file compiles in a few seconds: does it include a file that never ends, or make the "
                        "compiler work without end?"), seconds
            if not ok:
                return does_not_compile(task, source, compiler_messages(output.replace(str(work) + "/", ""))), seconds
            self.put(work / output_name, target, key)
            if not self.protect:
                self.remember(key, work / output_name, work / "depends.d")
            return "", seconds
        finally:
            shutil.rmtree(work, ignore_errors=True)

    @staticmethod
    def put(compiled, target, key):
        """Puts a compiled file in place, unless the one there is the same (so its suite is not
        linked again)."""
        label = target.with_name(target.name + ".key")
        if target.is_file() and label.is_file() and label.read_text() == key:
            return
        label.unlink(missing_ok=True)
        partial = target.with_name(target.name + ".partial")  # a new file, whoever owned the old one
        shutil.copyfile(compiled, partial)
        os.chmod(partial, 0o755)
        os.replace(partial, target)
        write_atomically(label, key)

    def put_stub(self, task):
        stub = self.build.stubs[task]
        self.put(stub, self.build.compiled(task), f"stub {signature(stub)}")

    def remember(self, key, compiled, depends):
        """Keeps a compiled file with the state of every file its compilation read."""
        try:
            listed = depends.read_text().split(":", 1)[1].replace("\\\n", " ").split()
        except (OSError, IndexError):
            return
        headers = {path: signature(path) for path in listed if Path(path).is_absolute()}
        shutil.copyfile(compiled, self.cache / f"{key}.o")
        write_atomically(self.cache / f"{key}.json", json.dumps(headers))
        entries = sorted(self.cache.glob("*.json"), key=lambda path: path.stat().st_mtime)
        for old in entries[:-COMPILED_KEPT]:
            old.unlink(missing_ok=True)
            old.with_suffix(".o").unlink(missing_ok=True)

    def recall(self, key, target):
        """Puts a remembered compiled file in place if every file it was compiled from is unchanged."""
        entry = self.cache / f"{key}.json"
        try:
            headers = json.loads(entry.read_text())
        except (OSError, ValueError):
            return False
        if any(signature(path) != saved for path, saved in headers.items()) or not entry.with_suffix(".o").is_file():
            return False
        os.utime(entry)
        self.put(entry.with_suffix(".o"), target, key)
        return True


def signature(path):
    """A file's size and time of change, or None if it is gone."""
    try:
        info = os.stat(path)
    except OSError:
        return None
    return [info.st_size, info.st_mtime_ns]


def share(source, target):
    """A hard link of a file that anyone may read, where possible (the precompiled header is 100
    MB), else a copy."""
    try:
        if os.stat(source).st_mode & stat.S_IROTH:
            os.link(source, target)
            return
    except OSError:
        pass
    shutil.copyfile(source, target)


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
            cpu = math.ceil(seconds) + 1  # a backstop: the grader stops a test at its limit itself
            limits = [
                (resource.RLIMIT_CPU, (cpu, cpu + 1)),
                (resource.RLIMIT_AS, memory_bytes or self.memory_bytes),
                (resource.RLIMIT_FSIZE, self.file_bytes),
                (resource.RLIMIT_CORE, 0),
            ]
            if self.account:
                limits.append((resource.RLIMIT_NPROC, 512))
            for limit, value in limits:
                resource.setrlimit(limit, value if isinstance(value, tuple) else (value, value))
            if self.account:
                os.setgroups([])
                os.setgid(self.account.pw_gid)
                os.setuid(self.account.pw_uid)
        return prepare

    def own(self, path):
        if self.account:
            os.chown(path, self.account.pw_uid, self.account.pw_gid)


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
                orphans = [pid for pid in children(me) if pid not in self.running]
                if not orphans:
                    return
                for pid in orphans:
                    try:
                        os.kill(pid, signal.SIGKILL)
                        os.waitpid(pid, 0)
                    except (ProcessLookupError, ChildProcessError, PermissionError):
                        pass


def children(pid):
    """The pids of a process's children: from the children list of each of its threads (Linux),
    else by looking through every process's parent."""
    try:
        return [int(child) for task in os.listdir(f"/proc/{pid}/task")
                for child in Path(f"/proc/{pid}/task/{task}/children").read_text().split()]
    except (OSError, ValueError):
        pass
    found = []
    for entry in os.listdir("/proc"):
        try:
            status = Path(f"/proc/{entry}/stat").read_text() if entry.isdigit() else ""
        except OSError:
            continue
        if status and int(status[status.rindex(")") + 2:].split()[1]) == pid:  # the parent's pid
            found.append(int(entry))
    return found


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


class TestServer:
    """A task's graded suite running as the grader's test server (--serve in
    tests/support/graded_main.cpp), with the sandbox's limits and user: it forks a process for
    each test from its state before any test ran, so every test still runs alone (a crash, an
    exit or an endless loop ends that test only) while starting costs a fork instead of a new
    program. One server runs one test at a time; each of the grader's threads has its own."""

    def __init__(self, executable, sandbox, scratch, processes, environment):
        theirs = None
        reports, theirs = os.pipe()
        try:
            self.process = processes.start(
                [str(executable), f"--serve={theirs}", "--gtest_color=no", "--gtest_brief=0"], cwd=scratch,
                env=environment, stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                pass_fds=(theirs,), preexec_fn=sandbox.preexec(SERVER_CPU_SECONDS))
        finally:
            os.close(theirs)
        self.processes = processes
        self.reports = reports
        self.output = self.process.stdout.fileno()
        os.set_blocking(self.reports, False)
        os.set_blocking(self.output, False)
        self.received = b""
        self.ready = False
        self.alive = True

    def run(self, name, folder, token, cpu_limit, wall_limit, variables):
        """Runs one test (see --serve) within its limits; returns (exit status as Popen gives it,
        CPU seconds, stopped at a limit, output, bytes of output dropped)."""
        started = time.monotonic()
        output, dropped = bytearray(), 0
        pid, stopped, status, cpu = None, False, None, 0.0

        def collect():
            nonlocal dropped
            while True:
                try:
                    chunk = os.read(self.output, 65536)
                except BlockingIOError:
                    return
                if not chunk:
                    return
                room = FEEDBACK_CAP * 4 - len(output)
                output.extend(chunk[:max(room, 0)])
                dropped += max(len(chunk) - max(room, 0), 0)

        sent = False
        while status is None:
            if self.ready and not sent:
                try:
                    self.process.stdin.write(" ".join([name, folder, token, f"{cpu_limit:.3f}", *variables]).encode()
                                             + b"\n")
                    self.process.stdin.flush()
                except OSError:  # the server has ended: told below
                    self.alive = False
                sent = True
            for report in self.read_reports():
                words = report.split()
                if words == ["ready"]:
                    self.ready = True
                elif words[0] == "started":
                    pid = int(words[1])
                elif words[0] == "ended":
                    status, cpu = os.waitstatus_to_exitcode(int(words[1])) if int(words[1]) >= 0 else -signal.SIGKILL, \
                        int(words[2]) / 1e6
            if status is not None:
                break
            if self.ready and not sent:
                continue
            if not self.alive:  # the server ended (a crash before or in main()), or stopped answering
                try:
                    status = self.process.wait(timeout=5)
                except subprocess.TimeoutExpired:
                    kill_group(self.process)
                    status = self.process.returncode
                self.processes.finished(self.process)
                break
            # Before the test started, the server's own start counts (a submission's global
            # constructors run in it).
            spent = cpu_seconds(pid) if pid else cpu_seconds(self.process.pid) if not self.ready else 0.0
            left = min(cpu_limit - spent, wall_limit - (time.monotonic() - started))
            if left <= 0 and not stopped:
                stopped = True
                if pid:
                    kill_process_group(pid)
                    deadline = time.monotonic() + 5  # the server reports the end at once
                else:
                    self.stop()
                continue
            if stopped and pid and time.monotonic() > deadline:
                self.stop()  # the server itself no longer answers
                continue
            ready, _, _ = select.select([self.reports, self.output], [], [], max(min(left, 0.5), 0.01) if not stopped else 0.1)
            if self.output in ready:
                collect()
        if pid:
            kill_process_group(pid)  # what the test started and left running
        collect()
        return status, cpu, stopped, bytes(output), dropped

    def read_reports(self):
        """The complete lines the server has reported since the last call."""
        try:
            chunk = os.read(self.reports, 4096)
        except BlockingIOError:
            return []
        if not chunk:
            self.alive = False
            return []
        self.received += chunk
        *lines, self.received = self.received.split(b"\n")
        return [line.decode(errors="replace") for line in lines if line.strip()]

    def stop(self):
        """Ends the server and every test it runs."""
        self.alive = False
        kill_group(self.process)
        self.processes.finished(self.process)

    def close(self):
        try:
            self.process.stdin.close()
            self.process.wait(timeout=5)
        except (OSError, subprocess.TimeoutExpired):
            pass
        self.stop()
        os.close(self.reports)
        self.process.stdout.close()


SERVER_CPU_SECONDS = 600  # a backstop for a server's own computing: its tests have their own limits


def kill_process_group(pid):
    try:
        os.killpg(pid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError):
        pass


class TestServers:
    """The test servers of one grading: one per suite for each of the grader's threads."""

    def __init__(self, sandbox, scratch, processes):
        self.sandbox = sandbox
        self.scratch = scratch
        self.processes = processes
        self.local = threading.local()
        self.all = []
        self.lock = threading.Lock()

    def get(self, task, executable):
        servers = self.local.__dict__.setdefault("servers", {})
        server = servers.get(task)
        if server is None or not server.alive:
            environment = {"PATH": "/usr/bin:/bin", "LANG": "C.UTF-8"} | {
                name: str(path) for name, path in program_files(task, executable.parent).items()}
            server = TestServer(executable, self.sandbox, self.scratch, self.processes, environment)
            servers[task] = server
            with self.lock:
                self.all.append(server)
        return server

    def close(self):
        for server in self.all:
            server.close()


def run_test(test, executable, servers, sandbox, scratch, processes, cpu_limit, wall_limit, why, clock):
    """Runs one graded test in a process of its own (forked by its suite's test server), stopped
    after `cpu_limit` seconds of computing or `wall_limit` seconds in all (why: see
    TaskClock.reserve), and fills in test.passed, test.feedback and its times."""
    work = Path(tempfile.mkdtemp(prefix="test-", dir=scratch))
    sandbox.own(work)
    token = secrets.token_hex(16)
    # The suite's own limit on a program task's program then stays out of the way.
    variables = [f"BILLIARD_TEST_TIME_LIMIT={wall_limit:g}"] if test.task in PROGRAM_TASKS else []
    if test.visibility != "hidden":  # a hidden test draws nothing, so nothing of it can show
        variables.append(f"BILLIARD_PICTURES={PICTURES}")
    started = time.monotonic()
    server = servers.get(test.task, executable)
    try:
        status, cpu, stopped, output, dropped = server.run(test.name, work.name, token, cpu_limit, wall_limit, variables)
    finally:
        processes.stop_orphans()  # what left the test's group
    test.seconds = time.monotonic() - started
    test.cpu_seconds = cpu
    text = output.decode(errors="replace")
    result_file = work / "result.txt"
    try:
        reported = result_file.read_text(errors="replace").strip() if result_file.is_file() else ""
    except OSError:
        reported = ""
    test.passed = not stopped and status == 0 and reported == f"{token} passed"
    # Stopped by the kernel for its CPU time (several busy threads) is not finishing either.
    test.unfinished = stopped or status in (-signal.SIGXCPU, -signal.SIGKILL) and cpu >= cpu_limit

    messages = gtest_messages(text)
    if dropped:
        messages += f"\n... ({dropped} more bytes of output were dropped)"
    if test.unfinished:
        messages = unfinished_message(clock, test.name, cpu_limit, why) + "\n" + messages
    elif status < 0:
        number = -status
        name = signal.Signals(number).name if number in signal.Signals._value2member_map_ else f"signal {number}"
        messages = (f"The test program crashed with {name}, "
                    f"{SIGNAL_HINTS.get(number, 'an error the program could not recover from')}.\n" + messages)
    elif not test.passed and not reported and status == 0:
        messages = ("The test program ended before the test was over (did the code call exit()?), "
                    "so the test cannot count as passed.\n" + messages)
    test.picture = keep_picture(test, work, scratch)
    test.feedback = cap(messages.strip(), FEEDBACK_CAP)
    shutil.rmtree(work, ignore_errors=True)


def keep_picture(test, work, scratch):
    """The picture a failing visible test drew in its folder, copied into the grading's pictures
    folder before its own is removed: its name there ("pictures/Suite.Test.svg"), or ""."""
    drawn = work / PICTURES / f"{test.name}.svg"
    if test.passed or test.visibility == "hidden":
        return ""
    try:
        if drawn.is_symlink() or not drawn.is_file() or drawn.stat().st_size > PICTURE_CAP:
            return ""
        (scratch / PICTURES).mkdir(exist_ok=True)
        shutil.copyfile(drawn, scratch / PICTURES / drawn.name)
    except OSError:
        return ""
    return f"{PICTURES}/{drawn.name}"


def place_pictures(results, scratch, folder):
    """Moves the grading's pictures into folder/pictures (replacing the last grading's) and makes
    each message name its picture there; a message whose picture was not kept loses the line."""
    kept = folder / PICTURES
    shutil.rmtree(kept, ignore_errors=True)
    if (scratch / PICTURES).is_dir():
        shutil.copytree(scratch / PICTURES, kept)
    for result in results:
        for test in result.tests:
            if test.picture and not (folder / test.picture).is_file():
                test.picture = ""
            line = f"Picture: {folder / test.picture}\n" if test.picture else ""
            test.feedback = PICTURE_LINE.sub(lambda _: line, test.feedback).strip()


CLOCK_TICKS = os.sysconf("SC_CLK_TCK")


def cpu_seconds(pid):
    """The CPU time of a running process: its threads' and that of the children it waited for."""
    try:
        fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    except (OSError, IndexError):
        return 0.0
    return sum(int(value) for value in fields[11:15]) / CLOCK_TICKS  # utime stime cutime cstime


def run_budgeted(test, executable, servers, sandbox, scratch, processes, clock):
    """Runs one test within its task's budget, or marks it not run when the budget is used up."""
    reserved = clock.reserve(test.name)
    if reserved is None:
        test.not_run = True
        test.feedback = not_run_message(clock)
        return
    cpu_limit, wall_limit, why = reserved
    try:
        run_test(test, executable, servers, sandbox, scratch, processes, cpu_limit, wall_limit, why, clock)
    finally:
        clock.release(wall_limit, test.seconds, test.unfinished)


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

    def __init__(self, folder, limits):
        self.folder = folder
        self.limits = limits  # {task: TaskLimits}
        self.checksums = {}
        folder.mkdir(parents=True, exist_ok=True)

    def key(self, test, executable):
        if executable not in self.checksums:
            # A program task's suite is the same for every submission: its program counts too.
            files = [executable, *program_files(test.task, executable.parent).values()]
            self.checksums[executable] = hashlib.sha256(b"".join(hashlib.sha256(path.read_bytes()).digest()
                                                                 for path in files)).hexdigest()
        name = f"{self.checksums[executable]}-{test.name}-{self.limits[test.task].test(test.name):g}"
        return self.folder / (hashlib.sha256(name.encode()).hexdigest() + ".json")

    def recall(self, test, executable, scratch):
        entry = self.key(test, executable)
        if not entry.is_file():
            return False
        saved = json.loads(entry.read_text())
        test.passed, test.feedback, test.seconds = saved["passed"], saved["feedback"], saved["seconds"]
        test.cpu_seconds = saved["cpu_seconds"]
        test.picture = saved.get("picture", "")
        if test.picture:
            (scratch / PICTURES).mkdir(exist_ok=True)
            shutil.copyfile(entry.with_suffix(".svg"), scratch / test.picture)
        return True

    def remember(self, test, executable, scratch):
        if test.unfinished or test.not_run:
            return  # depends on the time left, not only on the executable
        entry = self.key(test, executable)
        if test.picture:
            shutil.copyfile(scratch / test.picture, entry.with_suffix(".svg"))
        write_atomically(entry, json.dumps(
            {"passed": test.passed, "feedback": test.feedback, "seconds": test.seconds, "cpu_seconds": test.cpu_seconds,
             "picture": test.picture}))


# --- Reports -----------------------------------------------------------------------------------

def catalog(build, task):
    """The graded tests of a task's suite, with points and visibility (no submitted code runs)."""
    done = subprocess.run([str(build.executable(f"catalog_{task}")), "--list-graded"], stdout=subprocess.PIPE,
                          stderr=subprocess.PIPE, text=True, timeout=60)
    if done.returncode != 0:
        raise RuntimeError(f"listing the tests of {task} failed:\n{done.stderr}")
    return [json.loads(line) for line in done.stdout.splitlines() if line.strip()]


def print_table(results, verbose, own_tasks=True):
    """The table of points per task, then what to do next: for a student grading their own tasks/,
    the next step; for whoever grades another folder (own_tasks false), a summary of it."""
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
            print(f"      not implemented yet: write it in tasks/{TASK_FILE[result.task]} (every test fails until then)"
                  if own_tasks else "      not implemented yet: the file is the untouched stub")
            continue
        for test in failed:
            name = "a hidden test" if test.visibility == "hidden" else test.name
            print(f"      failed: {name} ({plural(test.points, 'point')})")
            if verbose and test.feedback:
                feedback = shown_feedback(test)
                print(indent(feedback, 10))
        if not_run:
            print(f"      not run: {plural(len(not_run), 'test')} ({plural(sum(t.points for t in not_run), 'point')}): "
                  f"the task may take {result.clock.limits.budget:.0f} s in all here, and {used_up(result.clock)}. An "
                  f"endless loop in {TASK_FUNCTIONS[result.task]}?")
    counted = [result for result in results if not is_optional(result.task)]
    extra = [result for result in results if is_optional(result.task)]
    print(f"\n    {'total':<{width}}{sum(r.score for r in counted):>3} / {sum(r.maximum for r in counted)}")
    if extra:
        print(f"    {'optional':<{width}}{sum(r.score for r in extra):>3} / {sum(r.maximum for r in extra)}"
              f"  (extra credit: {', '.join(r.task for r in extra)}; not in the total)")
    if own_tasks:
        print("\n" + "\n".join(next_step([task_progress(result) for result in results])))
    else:
        print("\n" + "\n".join(grader_summary(results)))


def grader_summary(results):
    """For whoever grades a submission: which tasks have full points, which lose points and where
    first (the first failing visible test), which are not written, which do not build."""
    full = [r.task for r in results if r.score == r.maximum and r.maximum > 0]
    lines = [f"Summary: full points in {len(full)} of {len(results)} tasks"
             + (f" ({', '.join(full)})" if full else "")]
    for result in results:
        if result.score == result.maximum and result.maximum > 0:
            continue
        if result.problem:
            why = "does not build (the compiler's message is above)"
        elif task_progress(result).missing == result.task:
            why = "not written (the untouched stub)"
        else:
            failed = [t for t in result.tests if not t.passed]
            visible = [t for t in failed if t.visibility != "hidden"]
            first = f", first {visible[0].name}" if visible else ""
            why = f"{result.score} / {result.maximum}: {plural(len(failed), 'test')} fail{'s' if len(failed) == 1 else ''}{first}"
        lines.append(f"  {TASK_NUMBER[result.task]:>2} {result.task}: {why}")
    return lines


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


def picture_html(test, folder):
    """A visible test's picture as an <img> with the SVG inside it (a data: address, so the page
    needs no other file and the picture cannot run anything), or "" if it has none."""
    if not test.picture or test.visibility == "hidden" or folder is None:
        return ""
    try:
        data = base64.b64encode((folder / test.picture).read_bytes()).decode()
    except OSError:
        return ""
    return (f'<img alt="the failing case of {html.escape(test.name)}, drawn" style="max-width: 100%" '
            f'src="data:image/svg+xml;base64,{data}">')


def gradescope_results(results, elapsed, folder=None):
    """Gradescope's results.json: the score and one entry per test. A visible test with a picture
    (in `folder`) is written as HTML, the message in <pre> and the picture under it: Gradescope's
    output_format "html" (its autograder specification, "Output String Formatting") renders
    sanitised HTML, and images embedded as base64 data are what its documentation's discussions
    show working; elsewhere the text stays text, without the picture's line (a path on the
    grading machine)."""
    tests = []
    for result in results:
        if result.problem:
            tests.append({"name": f"{result.task}: builds", "score": 0, "max_score": result.maximum,
                          "status": "failed", "visibility": "visible", "output": result.problem})
            continue
        for test in result.tests:
            hidden = test.visibility == "hidden"
            entry = {
                "name": f"{result.task}: " + ("hidden test" if hidden else test.name),
                "score": test.score, "max_score": test.points, "status": "passed" if test.passed else "failed",
                "visibility": test.visibility,
                "output": PICTURE_LINE.sub("", shown_feedback(test)).strip() or ("passed" if test.passed else ""),
            }
            picture = picture_html(test, folder)
            if picture:
                entry["output"] = f"<pre>{html.escape(entry['output'])}</pre>\n<p>{picture}</p>"
                entry["output_format"] = "html"
            tests.append(entry)
    return {
        "score": sum(result.score for result in results),
        "execution_time": round(elapsed, 1),
        "output": "Points per task: " + ", ".join(f"{r.task} {r.score}/{r.maximum}" + (" (optional)" if is_optional(r.task) else "")
                                            for r in results),
        "stdout_visibility": "hidden",
        "tests": tests,
    }


REPORT_STYLE = """
body { font-family: sans-serif; max-width: 60em; margin: 2em auto; color: #212121; }
table { border-collapse: collapse; } td, th { padding: 0.2em 0.8em; text-align: left; }
tr.lost td { color: #b71c1c; } pre { white-space: pre-wrap; background: #f5f5f5; padding: 0.6em; }
section.test { border-top: 1px solid #bdbdbd; margin-top: 1.5em; }
"""


def submission_report(results, folder, submission):
    """report.html: one page a browser opens from the file, with the points per task and each
    failing visible test's message above the picture of its failing case (of a hidden test, only
    that it failed)."""
    rows, sections = [], []
    for result in results:
        lost = result.score < result.maximum
        optional = " (optional)" if is_optional(result.task) else ""
        rows.append(f'<tr class="{"lost" if lost else "full"}"><td>{TASK_NUMBER[result.task]}</td>'
                    f"<td>{result.task}{optional}</td><td>{result.score} / {result.maximum}</td></tr>")
        if result.problem:
            sections.append(f'<section class="test"><h3>{task_name(result.task)} does not build</h3>'
                            f"<pre>{html.escape(result.problem)}</pre></section>")
            continue
        for test in result.tests:
            if test.passed:
                continue
            if test.visibility == "hidden":
                sections.append(f'<section class="test"><h3>{task_name(result.task)}: a hidden test '
                                f"({plural(test.points, 'point')})</h3><p>{html.escape(shown_feedback(test))}</p></section>")
                continue
            picture = picture_html(test, folder)
            sections.append(f'<section class="test" id="{html.escape(test.name)}"><h3>{task_name(result.task)}: '
                            f"{html.escape(test.name)} ({plural(test.points, 'point')})</h3>"
                            f"<pre>{html.escape(PICTURE_LINE.sub('', test.feedback).strip())}</pre>"
                            + (f"<p>{picture}</p>" if picture else "") + "</section>")
    counted = [r for r in results if not is_optional(r.task)]
    total = f"{sum(r.score for r in counted)} / {sum(r.maximum for r in counted)}"
    return (f'<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8"><title>Grading of '
            f"{html.escape(submission)}: {total}</title><style>{REPORT_STYLE}</style></head><body>\n"
            f"<h1>Grading of {html.escape(submission)}: {total} points</h1>\n"
            "<table><tr><th></th><th>task</th><th>points</th></tr>\n" + "\n".join(rows) + "</table>\n"
            + ("<h2>What failed</h2>\n" + "\n".join(sections) if sections else "<p>Every test passed.</p>")
            + "\n</body></html>\n")


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


def task_records(results):
    """Every task's result in full, hidden tests' names and messages included (for the
    instructor's class report, never for a student): a JSON-ready list, one entry per task."""
    return [{"task": result.task, "maximum": result.maximum, "problem": result.problem,
             "tests": [{key: value for key, value in vars(test).items() if key != "task"} for test in result.tests]}
            for result in results]


def results_from_records(records):
    """The TaskResults that task_records wrote (without their clocks)."""
    return [TaskResult(record["task"], [TestResult(record["task"], **test) for test in record["tests"]],
                       record["maximum"], record["problem"]) for record in records]


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
                        help="seconds the tasks' budgets may add up to at most (a platform's time limit for a "
                             "submission, less its other work): larger budgets are scaled down to fit")
    parser.add_argument("--build-timeout", type=float, default=1800.0,
                        help="seconds for the grader's own build, which does not depend on the submission "
                             "(default 1800)")
    parser.add_argument("--jobs", type=int,
                        help="tests run at once (default: the cores this process may use)")
    parser.add_argument("--user", help="run tests as this user (default: 'nobody' when run as root)")
    parser.add_argument("--protect-reference", action="store_true",
                        help="(as root, for the platforms' graders) make solutions/ and instructor-only tests "
                             "unreadable to the test user, and compile each submitted file as that user, so that a "
                             "submission cannot include the reference code (with #include or the assembler's "
                             ".incbin)")
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
    for folder in ["submission", "results", "build"]:  # the build's own records hold absolute paths
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
           1 if arguments.total is None else arguments.total) <= 0 or arguments.jobs < 1:
        fail("--timeout, --task-budget, --compile-timeout, --total and --build-timeout must be positive, and --jobs "
             "at least 1")
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


def stage_submission(submission, grading, name="submission"):
    """Copies the task files of a submission into the grader's own folder, grading/<name>/, and
    returns it with {task: message} for the task files that cannot be graded (a folder, a link, a
    special or too large file). Only regular files are read, without following links, so that a
    submission cannot make the grader read files outside it."""
    staged = grading / name
    staged.mkdir(parents=True, exist_ok=True)
    problems = {}
    for task in TASKS:
        source, target = submission / f"{TASK_FILE[task]}", staged / f"{TASK_FILE[task]}"
        text, problem = read_task_file(source)
        if problem:
            problems[task] = (f"{TASK_FILE[task]} {problem}, so it was not graded (0 points for this task). Submit the file "
                              "itself.")
        if text is None:
            target.unlink(missing_ok=True)
        elif not (target.is_file() and target.read_bytes() == text):
            target.write_bytes(text)
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
    build = Build(arguments.build, arguments.dependencies, arguments.build_timeout)
    print(f"grade: building the grader's own code and the graded suites in {arguments.build} (a minute or two the "
          "first time, seconds after), with "
          f"{'the reference code for the other tasks' if arguments.dependencies == 'reference' else 'your code for every task'}",
          flush=True)
    build.configure()
    build.prebuild()
    sandbox = Sandbox(arguments.user, memory_bytes=4 << 30, file_bytes=256 << 20)
    scratch = Path(tempfile.mkdtemp(prefix="billiard-grade-"))
    os.chmod(scratch, 0o755)
    try:
        with protected(arguments.protect_reference, build):
            compiler = TaskFileCompiler(build, sandbox, arguments.protect_reference, scratch)
            limits, factor, slower = task_limits(arguments, build, compiler, sandbox, scratch, grading)
            own_build = time.monotonic() - started  # the grader's own work, whatever the submission
            clocks = {task: TaskClock(limits[task]) for task in TASKS}
            results = build_suites(build, compiler, staged, problems, tasks, clocks)
            cache = ResultCache(arguments.cache, limits) if arguments.cache else None
            run_tests(results, build, sandbox, scratch, clocks, arguments.jobs, cache)
            place_pictures(results, scratch, arguments.results)
    finally:
        shutil.rmtree(scratch, ignore_errors=True)

    elapsed = time.monotonic() - started
    write_atomically(arguments.results / "results.json",
                     json.dumps(gradescope_results(results, elapsed, arguments.results), indent=2) + "\n")
    write_atomically(arguments.results / "junit.xml", junit_xml(results))
    write_atomically(arguments.results / "report.html",
                     submission_report(results, arguments.results, arguments.submission.resolve().name))
    if arguments.records:
        write_atomically(arguments.records.absolute(), json.dumps(task_records(results)) + "\n")
    audience = arguments.audience or ("student" if arguments.submission.resolve() == (REPO / "tasks").resolve()
                                      else "grader")
    print_table(results, verbose=not arguments.brief, own_tasks=audience == "student")
    print(f"\nresults: {arguments.results / 'report.html'} (open it in a browser: each failing test with the picture "
          f"of its case), {arguments.results / 'results.json'} (Gradescope) and {arguments.results / 'junit.xml'} (JUnit)")
    print(f"grade: {elapsed:.0f} s in all, of which {own_build:.0f} s for the grader's own build; "
          + limits_summary(limits, tasks, factor, slower))
    return results


class protected:
    """With --protect-reference: while grading, the reference solutions, the instructor-only tests
    and the grader's build folder (which holds the reference code's objects) are readable by the
    grader alone, not by the test user; their permissions are restored afterwards.

    Several gradings may run at once (the class grader's workers): the shared folders' original
    modes and the gradings protecting them are kept in one file under a lock, so the folders
    stay protected until the last grading ends and then get their original modes back, also
    after a grading that was killed (its process is gone)."""

    STATE = REPO / "build" / "grade" / "protected.json"

    def __init__(self, protect, build):
        self.shared = [path for path in [REPO / "solutions", REPO / "tests" / "graded" / "hidden",
                                         REPO / "tests" / "mutants"] if protect and path.is_dir()]
        self.own = build.folder if protect and build.folder.is_dir() else None
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


def task_limits(arguments, build, compiler, sandbox, scratch, grading):
    """{task: TaskLimits}, the factor by which --total scaled the budgets down (1 if not), and how
    many times slower this machine is than where the reference's times were measured (1 if not
    slower). Limits that follow the machine come from the reference's times in the build folder,
    measured first if they are missing or out of date."""
    slower = 1.0
    if arguments.limits == "fixed":
        limits = {task: fixed_limits(task, arguments.timeout, arguments.task_budget, arguments.compile_timeout)
                  for task in TASKS}
    else:
        saved = reference_times(build, compiler, sandbox, scratch, grading, arguments.jobs)
        slower = time_limits.slower_than_measured(saved)
        limits = {task: measured_limits(task, saved["tasks"][task], slower) for task in TASKS}
    factor = time_limits.fit_total(limits, arguments.total) if arguments.total else 1.0
    return limits, factor, slower


def reference_times(build, compiler, sandbox, scratch, grading, jobs):
    """What the reference solutions need (the saved record, see time_limits.save_reference_times),
    from the build folder, or measured now by grading them (every test twice, keeping the longer
    time) and saved there."""
    catalogs = [build.executable(f"catalog_{task}") for task in TASKS]
    solutions = [REPO / "solutions" / TASK_FILE[task] for task in TASKS]
    expected = time_limits.fingerprint(catalogs + solutions, compiler.commands)
    saved = time_limits.load_reference_times(build.folder, expected)
    if saved:
        return saved
    print("grade: measuring what the reference solutions need on this machine (once for this build folder)",
          flush=True)
    staged, problems = stage_submission(REPO / "solutions", grading, name="reference")
    os.chmod(staged, 0o700)  # the reference code, for the grader's eyes only
    generous = {task: fixed_limits(task, 60.0, 600.0, 120.0) for task in TASKS}
    clocks = {task: TaskClock(generous[task]) for task in TASKS}
    results = build_suites(build, compiler, staged, problems, TASKS, clocks, remembered=False, quiet=True)
    longest = {}
    for _ in range(2):
        for clock in clocks.values():
            clock.left = clock.limits.budget
        run_tests(results, build, sandbox, scratch, clocks, jobs, cache=None, quiet=True)
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


def catalog_of(build, task, cache={}):
    """The graded tests of a task's suite, listed once per grading."""
    key = (build.folder, task)
    if key not in cache:
        cache[key] = catalog(build, task)
    return cache[key]


def build_suites(build, compiler, staged, problems, tasks, clocks, remembered=True, quiet=False):
    """Compiles the task files (those of `tasks`, or every task's where each suite links them all)
    and links each task's suite, within its task's budget; returns a TaskResult per task of
    `tasks`, with its tests to run or the problem that stops them."""
    problems = dict(problems)
    compile_seconds = {}
    for task in tasks if build.dependencies == "reference" else TASKS:
        source = staged / TASK_FILE[task]
        if task not in problems and not source.is_file():
            problems[task] = f"{TASK_FILE[task]} was not submitted."
        if task in problems:
            compiler.put_stub(task)
            continue
        if not quiet:
            print(f"grade: {task_name(task)}: compiling {TASK_FILE[task]}", flush=True)
        limit = max(min(clocks[task].limits.compile, clocks[task].left), time_limits.MINIMUM_START_SECONDS)
        problem, compile_seconds[task] = compiler.compile(task, source, limit, remembered=remembered)
        clocks[task].spend(compile_seconds[task], building=True)
        if problem:
            problems[task] = problem
            compiler.put_stub(task)

    results = []
    for task in tasks:
        result = TaskResult(task, clock=clocks[task], compile_seconds=compile_seconds.get(task, 0.0))
        listed = catalog_of(build, task)
        result.maximum = sum(entry["points"] for entry in listed)
        results.append(result)
        if task in problems:
            result.problem = problems[task]
            continue
        if task not in PROGRAM_TASKS:  # a program task's suite is the grader's own, built already
            # Ninja links only a suite whose compiled task file changed (seconds saved for every
            # unchanged task); a failed link is told by its status and a missing file.
            limit = max(min(clocks[task].limits.compile, clocks[task].left), time_limits.MINIMUM_START_SECONDS)
            link_started = time.monotonic()
            ok, link_output, timed_out = build.build([f"grade_{task}"], timeout=limit,
                                                     memory_bytes=SUBMISSION_BUILD_MEMORY)
            result.link_seconds = time.monotonic() - link_started
            clocks[task].spend(result.link_seconds, building=True)
            if timed_out:
                result.problem = (f"{TASK_FILE[task]} compiles, but linking the suite with it did not finish within "
                                  f"{limit:.0f} s. A correct file links in about a second: does it define very large "
                                  "arrays?")
                continue
            if not ok or not build.executable(f"grade_{task}").is_file():
                result.problem = (f"{TASK_FILE[task]} compiles, but the suite does not link with it. Does it define "
                                  f"{TASK_FUNCTIONS[task]} exactly as lib/include/billiard/course.hpp declares it, "
                                  "and nothing the other tasks define? The linker says:\n"
                                  + cap(compiler_messages(link_output), COMPILER_CAP))
                continue
        result.tests = [TestResult(task, entry["test"], entry["points"], entry["visibility"]) for entry in listed]
    return results


def run_tests(results, build, sandbox, scratch, clocks, jobs, cache, quiet=False):
    """Runs every test of every task in a process of its own, `jobs` at a time, each task's within its
    budget. The suites are copied out of the build (which may sit where the test user cannot go,
    such as under /root) into a folder it can read but not change."""
    suites = {}
    for result in results:
        if not result.tests:
            continue
        suites[result.task] = scratch / f"grade_{result.task}"
        shutil.copyfile(build.executable(f"grade_{result.task}"), suites[result.task])
        os.chmod(suites[result.task], 0o755)
        built = {"BILLIARD_PROGRAM_UNDER_TEST": build.compiled(result.task),
                 "BILLIARD_EXPECTED_PROGRAM": build.folder / result.task}
        for name, copy in program_files(result.task, scratch).items():
            shutil.copyfile(built[name], copy)
            os.chmod(copy, 0o755)
    for result in results:
        for test in result.tests:
            test.passed, test.not_run, test.unfinished, test.feedback, test.picture = False, False, False, "", ""
    work = [(test, suites[test.task]) for result in results for test in result.tests]
    if cache:
        work = [(test, executable) for test, executable in work if not cache.recall(test, executable, scratch)]
    if not quiet:
        print(f"grade: running {len(work)} tests, each in a process of its own, {jobs} at a time", flush=True)
    processes = Processes()
    servers = TestServers(sandbox, scratch, processes)
    try:
        with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as pool:
            running = {}  # task -> its tests' futures, in course order
            for test, executable in work:
                running.setdefault(test.task, []).append(
                    pool.submit(run_budgeted, test, executable, servers, sandbox, scratch, processes, clocks[test.task]))
            for task, futures in running.items():
                for future in futures:
                    future.result()
                if not quiet:
                    print(f"grade: {task_name(task)}: {len(futures)} tests run", flush=True)
    finally:
        servers.close()
        processes.stop_orphans()
    if cache:
        for test, executable in work:
            cache.remember(test, executable, scratch)


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
