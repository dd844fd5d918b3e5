#!/usr/bin/python3
"""Grades the six course tasks of a submission and writes what the grading platforms read.

    /usr/bin/python3 tests/grader/grade.py [--submission DIR] [--results DIR] [options]

For each task it compiles the submitted file on its own (a file that does not compile scores 0
for its task, with the compiler's message as feedback), links the task's graded suite with it
(and, where the reference solutions exist, with the reference code of the other tasks, so a
mistake in one task cannot cost points in another), then runs every graded test in its own
process with a time limit, an output cap, resource limits and, when run as root, as an
unprivileged user. A test earns its points only if the suite's own main() reports it passed
with a secret token given to that process alone: an early exit(0), a crash, a hang or forged
output earns nothing.

Prints a table (task, points / maximum, and each failing test's message and hint), and writes
results.json (Gradescope's format) and junit.xml into --results. Exit status 0 when grading
completed (whatever the score), 2 for bad arguments.
"""

import argparse
import concurrent.futures
import hashlib
import json
import os
import pwd
import re
import resource
import secrets
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
TASKS = ["init_billiard", "init_velocities", "visualize_table", "propagate", "movie", "kinetic_energy"]
TASK_NUMBER = {task: number for number, task in enumerate(TASKS, start=1)}
HIDDEN_FEEDBACK = "This test is hidden: its details are not shown."
FEEDBACK_CAP = 8 * 1024  # characters of feedback kept per test
COMPILER_CAP = 6 * 1024  # characters of compiler output kept per task


@dataclass
class TestResult:
    task: str
    name: str  # "Suite.Name"
    points: int
    visibility: str
    passed: bool = False
    feedback: str = ""
    seconds: float = 0.0

    @property
    def score(self):
        return self.points if self.passed else 0


@dataclass
class TaskResult:
    task: str
    tests: list = field(default_factory=list)
    maximum: int = 0
    problem: str = ""  # why the task could not be tested (compile or link error), if so

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


def run_quietly(command, timeout, **kwargs):
    """Runs a build step; returns (ok, combined output)."""
    try:
        done = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                              errors="replace", timeout=timeout, **kwargs)
        return done.returncode == 0, done.stdout
    except subprocess.TimeoutExpired as expired:
        output = expired.stdout.decode(errors="replace") if isinstance(expired.stdout, bytes) else (expired.stdout or "")
        return False, output + f"\n(stopped after {timeout} s)"


# --- Building ----------------------------------------------------------------------------------

class Build:
    """The grader's CMake build of one submission (see tests/grader/CMakeLists.txt)."""

    def __init__(self, folder, submission, dependencies, compile_timeout):
        self.folder = folder
        self.submission = submission
        self.dependencies = dependencies
        self.compile_timeout = compile_timeout

    def configure(self, stubbed):
        command = [
            "cmake", "-S", str(REPO), "-B", str(self.folder), "-G", "Ninja", "-DCMAKE_BUILD_TYPE=Release",
            "-DBILLIARD_COURSE=" + ("solutions" if self.dependencies == "reference" else "tasks"),
            "-DBILLIARD_CHECK_STUBS=OFF", "-DBILLIARD_PYTHON=OFF", "-DCMAKE_EXPORT_COMPILE_COMMANDS=ON",
            f"-DBILLIARD_SUBMISSION={self.submission}",
            f"-DBILLIARD_GRADE_DEPENDENCIES={self.dependencies}", "-DBILLIARD_STUBBED_TASKS=" + ";".join(stubbed),
        ]
        ok, output = run_quietly(command, timeout=600)
        if not ok:
            raise RuntimeError("configuring the grader's build failed:\n" + output)

    def build(self, targets, timeout, keep_going=False):
        command = ["cmake", "--build", str(self.folder), "--target", *targets]
        return run_quietly(command + (["--", "-k", "0"] if keep_going else []), timeout=timeout)

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


def preprocess_as(sandbox, build, tasks):
    """Expands each submitted file's #include lines as the unprivileged user, in place.

    With the reference solutions made unreadable to that user (--protect-reference), a file
    that tries `#include "../solutions/propagate.cpp"` (or any other file the user may not read)
    fails here, and the later compilation, as the grader, sees no #include left to follow.
    Returns {task: message} for the files that fail.
    """
    commands = {Path(entry["file"]).name: entry for entry in
                json.loads((build.folder / "compile_commands.json").read_text())
                if Path(entry["file"]).parent == build.submission}
    problems = {}
    for task in tasks:
        source = build.submission / f"{task}.cpp"
        if not source.is_file() or source.name not in commands:
            continue
        work = Path(tempfile.mkdtemp(prefix="preprocess-"))
        os.chmod(work, 0o755)
        sandbox.own(work)
        shutil.copyfile(source, work / source.name)
        sandbox.own(work / source.name)
        words = commands[source.name]["command"].split()
        flags = []  # the include paths, language standard and macros of the real compilation
        for at, word in enumerate(words[1:-1], start=1):
            if word.startswith("-I"):
                flags.append("-I" + str(readable_copy(Path(word[2:]), work)))
            elif word.startswith(("-std", "-D")):
                flags.append(word)
            elif word == "-isystem":
                flags += [word, str(readable_copy(Path(words[at + 1]), work))]
        command = [words[0], *flags, "-E", source.name, "-o", "expanded.cpp"]
        try:
            done = subprocess.run(command, cwd=work, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                                  errors="replace", timeout=build.compile_timeout, preexec_fn=sandbox.prepare)
            if done.returncode == 0:
                shutil.copyfile(work / "expanded.cpp", source)
            else:
                problems[task] = f"{task}.cpp does not compile:\n" + cap(done.stdout.replace(str(work) + "/", ""),
                                                                         COMPILER_CAP)
        except subprocess.TimeoutExpired:
            problems[task] = f"{task}.cpp does not compile: the preprocessor did not finish in time"
        finally:
            shutil.rmtree(work, ignore_errors=True)
    return problems


def compile_submission(build, tasks):
    """Compiles each submitted file alone; returns {task: compiler message} for those that fail."""
    problems = {}
    for task in tasks:
        source = build.submission / f"{task}.cpp"
        if not source.is_file():
            problems[task] = f"{task}.cpp was not submitted."
            continue
        ok, output = build.build([f"submission_{task}"], timeout=build.compile_timeout)
        if not ok:
            problems[task] = f"{task}.cpp does not compile:\n" + cap(compiler_messages(output), COMPILER_CAP)
    return problems


def compiler_messages(output):
    """The compiler's own lines from a build log (without ninja's progress and commands)."""
    keep = []
    for line in output.splitlines():
        if line.startswith("[") and "] Building" in line or line.startswith("ninja:") or line.startswith("FAILED:"):
            continue
        if line.startswith("/usr/bin/c++") or line.startswith("/usr/bin/g++"):
            continue
        keep.append(line.replace(str(REPO) + "/", ""))
    return "\n".join(keep).strip()


# --- Running one test --------------------------------------------------------------------------

class Sandbox:
    """Limits for one test process; as root, also an unprivileged user."""

    def __init__(self, user, timeout, memory_bytes, file_bytes):
        self.account = pwd.getpwnam(user) if user else None
        self.timeout = timeout
        self.memory_bytes = memory_bytes
        self.file_bytes = file_bytes

    def prepare(self):
        """Runs in the child between fork and exec."""
        os.setsid()  # its own process group, killed as a whole afterwards
        limits = [
            (resource.RLIMIT_CPU, int(self.timeout) + 5),
            (resource.RLIMIT_AS, self.memory_bytes),
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

    def own(self, path):
        if self.account:
            os.chown(path, self.account.pw_uid, self.account.pw_gid)


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


def run_test(test, executable, sandbox, scratch):
    """Runs one graded test in its own process and fills in test.passed and test.feedback."""
    work = Path(tempfile.mkdtemp(prefix="test-", dir=scratch))
    sandbox.own(work)
    token = secrets.token_hex(16)
    result_file = work / "result.txt"
    environment = {
        "PATH": "/usr/bin:/bin", "HOME": str(work), "TMPDIR": str(work), "LANG": "C.UTF-8",
        "BILLIARD_GRADER_TOKEN": token,
    }
    command = [str(executable), f"--gtest_filter={test.name}", f"--graded-result={result_file}",
               "--gtest_color=no", "--gtest_brief=0"]
    started = time.monotonic()
    process = subprocess.Popen(command, cwd=work, env=environment, stdin=subprocess.DEVNULL,
                               stdout=subprocess.PIPE, stderr=subprocess.STDOUT, preexec_fn=sandbox.prepare)
    captured = []
    reader = threading.Thread(target=read_capped, args=(process.stdout, FEEDBACK_CAP * 4, captured), daemon=True)
    reader.start()
    timed_out = False
    try:
        process.wait(timeout=sandbox.timeout)
    except subprocess.TimeoutExpired:
        timed_out = True
    finally:
        try:
            os.killpg(process.pid, signal.SIGKILL)  # the test and anything it started
        except (ProcessLookupError, PermissionError):
            pass
        process.wait()
    reader.join(timeout=5)
    test.seconds = time.monotonic() - started
    output, dropped = captured[0] if captured else (b"", 0)
    text = output.decode(errors="replace")

    try:
        reported = result_file.read_text(errors="replace").strip() if result_file.is_file() else ""
    except OSError:
        reported = ""
    test.passed = not timed_out and process.returncode == 0 and reported == f"{token} passed"

    messages = gtest_messages(text)
    if dropped:
        messages += f"\n... ({dropped} more bytes of output were dropped)"
    if timed_out:
        messages = (f"The test did not finish within {sandbox.timeout:g} seconds and was stopped. "
                    "Is there an endless loop, or a loop whose end depends on a condition that never holds?\n"
                    + messages)
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
            self.checksums[executable] = hashlib.sha256(executable.read_bytes()).hexdigest()
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
        print(f"{TASK_NUMBER[result.task]:>2}  {result.task:<{width}}{result.score:>3} / {result.maximum}")
        if result.problem:
            print(indent(result.problem, 6))
            continue
        failed = [test for test in result.tests if not test.passed]
        if failed and len(failed) == len(result.tests) and all("not implemented yet" in t.feedback for t in failed):
            print(f"      not implemented yet: write it in {result.task}.cpp (every test fails until then)")
            continue
        for test in failed:
            name = "a hidden test" if test.visibility == "hidden" else test.name
            print(f"      failed: {name} ({test.points} point{'s' if test.points != 1 else ''})")
            if verbose and test.feedback:
                feedback = HIDDEN_FEEDBACK if test.visibility == "hidden" else test.feedback
                print(indent(feedback, 10))
    total = sum(result.score for result in results)
    maximum = sum(result.maximum for result in results)
    print(f"\n    {'total':<{width}}{total:>3} / {maximum}")


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
                "output": HIDDEN_FEEDBACK if hidden else (test.feedback or ("passed" if test.passed else "")),
            })
    return {
        "score": sum(result.score for result in results),
        "execution_time": round(elapsed, 1),
        "output": "Points per task: " + ", ".join(f"{r.task} {r.score}/{r.maximum}" for r in results),
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
            case = ET.SubElement(suite, "testcase", classname=f"{result.task}.{test.name.split('.')[0]}",
                                 name="hidden test" if hidden else test.name.split(".", 1)[1],
                                 time=f"{test.seconds:.3f}")
            if not test.passed:
                ET.SubElement(case, "failure", message=f"0 of {test.points} points").text = (
                    HIDDEN_FEEDBACK if hidden else test.feedback)
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
                        help="folder with the task files <task>.cpp (default: tasks/)")
    parser.add_argument("--results", type=Path, default=REPO / "build" / "grade" / "results",
                        help="folder for results.json and junit.xml (default: build/grade/results)")
    parser.add_argument("--build", type=Path, default=REPO / "build" / "grade" / "build",
                        help="build folder (default: build/grade/build)")
    parser.add_argument("--dependencies", choices=["reference", "submission"],
                        help="code for the other tasks of each suite: the reference solutions (default where "
                             "solutions/ exists) or the submission's own files")
    parser.add_argument("--task", action="append", choices=TASKS, help="grade only this task (repeatable)")
    parser.add_argument("--timeout", type=float, default=60.0, help="seconds per test (default 60)")
    parser.add_argument("--compile-timeout", type=float, default=300.0, help="seconds per file (default 300)")
    parser.add_argument("--jobs", type=int, default=2, help="tests run at once (default 2)")
    parser.add_argument("--user", help="run tests as this user (default: 'nobody' when run as root)")
    parser.add_argument("--protect-reference", action="store_true",
                        help="(as root, for the platforms' graders) make solutions/ and instructor-only tests "
                             "unreadable to the test user and expand each submitted file's #include lines as that "
                             "user, so that a submission cannot include the reference code")
    parser.add_argument("--brief", action="store_true", help="list failing tests without their messages")
    parser.add_argument("--require-full", action="store_true",
                        help="exit with status 1 unless every graded task has full points (for CI graders such "
                             "as GitHub Classroom's command grader)")
    parser.add_argument("--cache", type=Path,
                        help="folder to remember results by test and executable checksum, so that unchanged "
                             "suites are not run again (for grading many variants; not for untrusted setups)")
    arguments = parser.parse_args(argv)
    if not arguments.submission.is_dir():
        fail(f"--submission {arguments.submission} is not a folder; give the folder that holds the task files")
    if arguments.dependencies is None:
        arguments.dependencies = "reference" if (REPO / "solutions" / "CMakeLists.txt").is_file() else "submission"
    if arguments.dependencies == "reference" and not (REPO / "solutions" / "CMakeLists.txt").is_file():
        fail("--dependencies reference needs the reference solutions in solutions/, which this copy does not have")
    if arguments.timeout <= 0 or arguments.jobs < 1:
        fail("--timeout must be positive and --jobs at least 1")
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


def grade(arguments):
    started = time.monotonic()
    tasks = arguments.task or TASKS
    grading = arguments.build.parent
    grading.mkdir(parents=True, exist_ok=True)

    # Only the task files are taken from the submission, into a folder of the grader's own.
    # A file whose content is unchanged since the last run is left alone, so the build does not
    # compile it again.
    staged = grading / "submission"
    staged.mkdir(parents=True, exist_ok=True)
    for task in TASKS:
        source, target = arguments.submission / f"{task}.cpp", staged / f"{task}.cpp"
        previous = grading / "previous" / f"{task}.cpp"  # the submitted text behind `target`
        if source.is_file() and source.stat().st_size < 1_000_000:
            text = source.read_bytes()
            if not (target.is_file() and previous.is_file() and previous.read_bytes() == text):
                previous.parent.mkdir(exist_ok=True)
                previous.write_bytes(text)
                target.write_bytes(text)
        else:
            target.unlink(missing_ok=True)
            previous.unlink(missing_ok=True)

    build = Build(arguments.build, staged, arguments.dependencies, arguments.compile_timeout)
    print(f"grade: building the graded suites ({'reference code for the other tasks' if arguments.dependencies == 'reference' else 'your code for every task'})",
          flush=True)
    # A task file that was not submitted is a stub from the start (its task scores 0).
    build.configure(stubbed=[task for task in TASKS if not (staged / f"{task}.cpp").is_file()])
    sandbox = Sandbox(arguments.user, arguments.timeout, memory_bytes=4 << 30, file_bytes=256 << 20)
    problems = {}
    if arguments.protect_reference:
        private = [path for path in [REPO / "solutions", REPO / "tests" / "graded" / "hidden", REPO / "tests" / "mutants"]
                   if path.is_dir()]
        modes = {path: path.stat().st_mode for path in private}
        try:
            for path in private:
                os.chmod(path, 0o700)
            problems = preprocess_as(sandbox, build, TASKS)
        finally:
            for path, mode in modes.items():
                os.chmod(path, mode)
    problems.update(compile_submission(build, [task for task in TASKS if task not in problems]))
    if problems:
        build.configure(stubbed=sorted(problems))
    for task in tasks:
        build.executable(f"grade_{task}").unlink(missing_ok=True)
    targets = [f"grade_{task}" for task in tasks if task not in problems] + [f"catalog_{task}" for task in tasks]
    _, link_output = build.build(targets, timeout=1200, keep_going=True)  # one failed link spoils no other

    results = []
    for task in tasks:
        result = TaskResult(task)
        listed = catalog(build, task)
        result.maximum = sum(entry["points"] for entry in listed)
        if task in problems:
            result.problem = problems[task]
        elif not build.executable(f"grade_{task}").is_file():
            result.problem = f"{task}.cpp compiles, but the suite does not link with it:\n" + cap(
                compiler_messages(link_output), COMPILER_CAP)
        else:
            result.tests = [TestResult(task, entry["test"], entry["points"], entry["visibility"]) for entry in listed]
        results.append(result)

    # Run every test of every task in its own process, a few at a time.
    # The suites are copied out of the build (which may sit where the test user cannot go, such
    # as under /root) into a folder it can read but not change.
    scratch = Path(tempfile.mkdtemp(prefix="billiard-grade-"))
    os.chmod(scratch, 0o755)
    suites = {}
    for result in results:
        if result.tests:
            suites[result.task] = scratch / f"grade_{result.task}"
            shutil.copyfile(build.executable(f"grade_{result.task}"), suites[result.task])
            os.chmod(suites[result.task], 0o755)
    jobs = [(test, suites[test.task]) for result in results for test in result.tests]
    cache = ResultCache(arguments.cache, arguments.timeout) if arguments.cache else None
    if cache:
        jobs = [(test, executable) for test, executable in jobs if not cache.recall(test, executable)]
    print(f"grade: running {len(jobs)} tests, each in its own process", flush=True)
    try:
        with concurrent.futures.ThreadPoolExecutor(max_workers=arguments.jobs) as pool:
            for future in [pool.submit(run_test, test, executable, sandbox, scratch) for test, executable in jobs]:
                future.result()
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
    return results


def main(argv=None):
    arguments = parse_arguments(sys.argv[1:] if argv is None else argv)
    results = grade(arguments)
    if arguments.require_full and any(result.score < result.maximum for result in results):
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
