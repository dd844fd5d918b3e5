"""Running the tests: each graded test in a judge process and a worker process of its own.

The judge is the task's graded suite linked with proxies for the course's functions
(tests/grader/judge/proxy.cpp): its assertions, its verdict and its pictures are computed where no
submitted code runs, as the judges' user id (as root). The worker is the task's file linked into
tests/grader/judge/worker_main.cpp (a program task's: its program, run by program_runner.cpp),
started for the test in the task's cell (cell.py); it only answers the judge's calls through a
pair of pipes. A test counts as passed only when the judge says so; whatever the worker does (exit,
crash, hang, print, forge) makes wrong answers at most.

A task's judge runs as a test server (tests/support/graded_main.cpp, --serve): it forks a process
per test from its state before any test ran, and the grader passes that process the test's pipes
to its worker (over a control socket of its own). A test's time is the CPU time of both processes; a test that sleeps or waits is
stopped after time_limits.WALL_SLACK times its limit of time neither computing nor waiting for a
processor, so a machine kept busy by other gradings costs no test its points.

Hidden tests run after every other test of the grading has ended, and after every process of the
cells has been stopped: nothing a hidden test's worker learns can reach a test whose messages are
shown.
"""

import concurrent.futures
import ctypes
import hashlib
import json
import os
import re
import select
import shutil
import signal
import socket
import subprocess
import threading
import time
from pathlib import Path

from building import REPO, file_digest
from cell import Limits, read_regular_file
from course import PROGRAM_TASKS, task_name
from reports import FEEDBACK_CAP, PICTURE_LINE, PICTURES, cap
from time_limits import NO_DEADLINE, not_run_message, unfinished_message

# The largest picture kept (a picture of fifty circles has 60 kB).
PICTURE_CAP = 2 << 20
# Limits of a judge process (which holds the student's answers to check) and of a worker.
JUDGE_MEMORY = 4 << 30
WORKER_MEMORY = 2 << 30
WORKER_FILE_BYTES = 64 << 20
WORKER_OPEN_FILES = 64
WORKER_PROCESSES = 256  # processes and threads of a task's cell (its tests run side by side)
# What a worker may keep in its folder (a movie's picture has some hundred kilobytes), looked at
# twice a second: a test that writes more is stopped.
WORKER_DISK_BYTES = 256 << 20
WORKER_DISK_ENTRIES = 10_000
SERVER_CPU_SECONDS = 600  # a backstop for a judge's own computing: its tests have their own limits
PRINTED_CAP = 2000  # characters of what the student's code printed, shown with a test's message
# The judges' proxies, and how they say that a worker ended during a call.
PROXY = "tests/grader/judge/proxy.cpp"
WORKER_GONE = "the process running your code ended during the call"

SIGNAL_HINTS = {
    signal.SIGSEGV: "a segmentation fault: the code read or wrote memory that is not its own, for example "
                    "a row or column past the end of a matrix, or a reference to a destroyed object",
    signal.SIGABRT: "an abort: often a failed assertion, an uncaught exception, or Eigen checking an index "
                    "(in a debug build)",
    signal.SIGFPE: "an arithmetic error, such as an integer division by zero",
    signal.SIGKILL: "being killed, usually for using too much memory or CPU time",
    signal.SIGXCPU: "using more CPU time than allowed: an endless loop?",
    signal.SIGXFSZ: "writing a file larger than allowed",
    signal.SIGSYS: "a system call the grader does not allow (such as one of another architecture)",
}


class Processes:
    """The grader's processes for tests, and the orphans they leave.

    A process may leave its process group (setsid) and keep running after its test. The grader is
    made a "child subreaper": such orphans become its children instead of init's, and are killed
    after each test (as root, the cells' user ids make sure of it)."""

    def __init__(self):
        self.lock = threading.Lock()
        self.running = set()
        try:
            libc = ctypes.CDLL(None, use_errno=True)
            libc.prctl(36, 1, 0, 0, 0)  # PR_SET_CHILD_SUBREAPER (Linux)
        except (OSError, AttributeError):
            pass

    def start(self, *arguments, **options):
        with self.lock:  # so that stop_orphans never takes a process being started for an orphan
            process = subprocess.Popen(*arguments, **options)
            self.running.add(process.pid)
        return process

    def finished(self, process):
        with self.lock:
            self.running.discard(process.pid)

    def stop_orphans(self):
        """Kills the grader's children that it did not start: the orphans of tests."""
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


CLOCK_TICKS = os.sysconf("SC_CLK_TCK")


def cpu_seconds(pid):
    """The CPU time of a process (running, or ended and not yet reaped): its threads' and that of
    the children it waited for."""
    try:
        fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    except (OSError, IndexError):
        return 0.0
    return sum(int(value) for value in fields[11:15]) / CLOCK_TICKS  # utime stime cutime cstime


def waiting_seconds(pid):
    """How long a process has waited, runnable, for a processor (its scheduler statistics), or None."""
    try:
        return int(Path(f"/proc/{pid}/schedstat").read_text().split()[1]) / 1e9
    except (OSError, IndexError, ValueError):
        return None


def pin(pid, cpu):
    """Keeps a process on one processor (where the system lets the grader choose)."""
    if cpu is None:
        return
    try:
        os.sched_setaffinity(pid, {cpu})
    except OSError:
        pass


def kill_process_group(pid):
    try:
        os.killpg(pid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError):
        pass


class Programs:
    """The programs the tests of a grading run, put in the cells' bin/ folder: the judges (and a
    program task's command that gives the expected output), readable by the grader alone and run
    by the judges' user; each task's worker was put there when it was linked."""

    def __init__(self, build, cells, tasks):
        self.build = build
        self.cells = cells
        self.judges = {}
        self.expected = {}
        for task in tasks:
            self.judges[task] = self.put(build.judge(task), f"judge_{task}")
            if task in PROGRAM_TASKS:
                self.expected[task] = self.put(build.expected_program(task), f"expected_{task}")
        self.runner = (cells.put_program(build.program_runner.read_bytes(), "program_runner")
                       if any(task in PROGRAM_TASKS for task in tasks) else None)

    def put(self, source, name):
        """The grader's own program in bin/judge/: a link to the build's file where they share a
        file system (a judge has megabytes), else a copy; executable, and readable by the grader
        alone."""
        folder = self.cells.bin / "judge"
        folder.mkdir(exist_ok=True)
        os.chmod(folder, 0o711)
        target = folder / name
        target.unlink(missing_ok=True)
        try:
            os.link(source, target)
            os.chmod(target, 0o711)
        except OSError:  # another file system, or the build's file is not ours (Autolab's image)
            target.unlink(missing_ok=True)
            shutil.copyfile(source, target)
            os.chmod(target, 0o711)
        return target

    def worker_command(self, task, work, pipes, cpu_limit):
        """The command that starts a test's worker in the task's cell, with the test's pipes from
        and to its judge (descriptors 3 and 4 there)."""
        if task in PROGRAM_TASKS:
            program = [self.runner, self.cells.bin / task / "program"]
            reads, no_fork = [self.runner, self.cells.bin / task], False
        else:
            program = [self.cells.bin / task / "worker"]
            reads, no_fork = [self.cells.bin / task], True
        return self.cells.command(
            task, program, directory=work, reads=reads, writes=[work], no_fork=no_fork,
            descriptors={pipes[0]: 3, pipes[1]: 4},
            limits=Limits(cpu_seconds=cpu_limit + 1, memory_bytes=WORKER_MEMORY, file_bytes=WORKER_FILE_BYTES,
                          open_files=WORKER_OPEN_FILES, processes=WORKER_PROCESSES))

    def digest(self, task):
        """What a task's results depend on: its judge and its worker (or program)."""
        files = [self.judges[task]]
        if task in PROGRAM_TASKS:
            files += [self.expected[task], self.runner, self.cells.bin / task / "program"]
        else:
            files.append(self.cells.bin / task / "worker")
        return hashlib.sha256("".join(file_digest(path) for path in files).encode()).hexdigest()


class TestServer:
    """A task's judge running as the grader's test server (--serve in tests/support/graded_main.cpp)
    in the judges' cell: it forks a process for each test from its state before any test ran, so
    every test still runs alone while starting costs a fork instead of a new program. One server
    runs one test at a time; each of the grader's threads has its own."""

    def __init__(self, programs, task, processes, cpu=None):
        self.control, theirs = socket.socketpair(socket.AF_UNIX, socket.SOCK_SEQPACKET)
        cells = programs.cells
        environment = {"BILLIARD_EXPECTED_PROGRAM": programs.expected[task]} if task in programs.expected else {}
        try:
            self.process = processes.start(
                cells.command("judge", [programs.judges[task], "--serve=3", "--gtest_color=no", "--gtest_brief=0"],
                              directory=cells.judge, reads=[cells.bin / "judge"], writes=[cells.judge],
                              descriptors={theirs.fileno(): 3}, environment=environment,
                              limits=Limits(cpu_seconds=SERVER_CPU_SECONDS, memory_bytes=JUDGE_MEMORY,
                                            file_bytes=256 << 20)),
                stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, pass_fds=(theirs.fileno(),))
        finally:
            theirs.close()
        pin(self.process.pid, cpu)  # the tests it forks stay there
        self.cpu = cpu
        self.processes = processes
        self.output = self.process.stdout.fileno()
        self.control.setblocking(False)
        os.set_blocking(self.output, False)
        self.alive = True

    def run(self, name, folder, cpu_limit, wall_limit, variables, worker, worker_output, pipes, work,
            grading_deadline=NO_DEADLINE):
        """Runs one test (see --serve) within its limits and the grading's deadline, with `worker`
        (a process started for it in the folder `work`, its output on `worker_output`) at the
        other ends of `pipes` (to it, from it). Returns a Run."""
        run = Run()
        started = time.monotonic()
        looked = started
        judge_output, printed = bytearray(), bytearray()
        pid, deadline = None, None
        delays = {}  # pid -> seconds it waited for a processor

        def collect(descriptor, sink):
            """Keeps the first bytes of what a process printed; returns how many it dropped."""
            dropped = 0
            while True:
                try:
                    chunk = os.read(descriptor, 65536)
                except BlockingIOError:
                    return dropped
                if not chunk:
                    return dropped
                room = FEEDBACK_CAP * 4 - len(sink)
                sink.extend(chunk[:max(room, 0)])
                dropped += max(len(chunk) - max(room, 0), 0)

        message = " ".join([name, folder, f"{cpu_limit:.3f}", *variables]).encode()
        try:
            socket.send_fds(self.control, [message], list(pipes))
        except OSError:
            self.alive = False
        while run.status is None:
            for report in self.read_reports():
                words = report.split()
                if words[0] == "started":
                    pid = int(words[1])
                elif words[0] == "verdict":
                    run.verdict = words[1]
                elif words[0] == "ended":
                    run.status = os.waitstatus_to_exitcode(int(words[1])) if int(words[1]) >= 0 else -signal.SIGKILL
                    run.judge_cpu = int(words[2]) / 1e6
            if run.status is not None:
                break
            if not self.alive:  # the server ended, or stopped answering
                self.stop()
                run.status = -signal.SIGKILL
                break
            for process in [pid, worker.pid]:
                waited = waiting_seconds(process) if process else None
                if waited is not None:
                    delays[process] = waited
            spent = (cpu_seconds(pid) if pid else 0.0) + cpu_seconds(worker.pid)
            elapsed = time.monotonic() - started - sum(delays.values())
            left = min(cpu_limit - spent, wall_limit - elapsed)
            if grading_deadline.left() <= 0 and not run.stopped:
                run.out_of_time, left = True, 0
            if time.monotonic() - looked > 0.5 and not run.stopped:
                looked = time.monotonic()
                run.too_much_written = too_much_written(work)
            if (left <= 0 or run.too_much_written) and not run.stopped:
                run.stopped = True
                if pid:
                    kill_process_group(pid)
                stop_worker(worker)
                deadline = time.monotonic() + 5  # the server reports the end at once
                continue
            if run.stopped and time.monotonic() > deadline:
                self.stop()  # the server itself no longer answers
                continue
            ready, _, _ = select.select([self.control, self.output, worker_output], [], [],
                                        max(min(left, 0.5), 0.01) if not run.stopped else 0.1)
            if self.output in ready:
                run.dropped += collect(self.output, judge_output)
            if worker_output in ready:
                run.printed_dropped += collect(worker_output, printed)
        if pid:
            kill_process_group(pid)  # what the test started and left running
        run.worker_status = worker_exit(worker.pid)  # if it ended by itself
        run.worker_cpu, killed = stop_worker(worker)
        if run.worker_status is None:
            run.worker_status = killed
        self.processes.finished(worker)
        run.dropped += collect(self.output, judge_output)
        # The rest of what the worker printed: it has ended, so its pipe ends soon (a process it
        # left in another group cannot hold it longer than a second).
        until = time.monotonic() + 1
        while time.monotonic() < until and select.select([worker_output], [], [], until - time.monotonic())[0]:
            before = len(printed) + run.printed_dropped
            run.printed_dropped += collect(worker_output, printed)
            if len(printed) + run.printed_dropped == before:
                break  # the end of the pipe
        run.seconds = max(time.monotonic() - started - sum(delays.values()), 0.0)
        run.judge_output, run.printed = bytes(judge_output), bytes(printed)
        return run

    def read_reports(self):
        """The messages the server has sent since the last call."""
        reports = []
        while True:
            try:
                message = self.control.recv(4096)
            except BlockingIOError:
                return reports
            except OSError:
                message = b""
            if not message:
                self.alive = False
                return reports
            text = message.decode(errors="replace").strip()
            if text and text != "ready":
                reports.append(text)

    def stop(self):
        """Ends the server and every test it runs."""
        self.alive = False
        try:
            os.killpg(self.process.pid, signal.SIGKILL)
        except (ProcessLookupError, PermissionError):
            pass
        self.process.wait()
        self.processes.finished(self.process)

    def close(self):
        self.control.close()  # the server ends when its socket does
        try:
            self.process.wait(timeout=5)
        except subprocess.TimeoutExpired:
            pass
        self.stop()
        self.process.stdout.close()


class Run:
    """What one test's run gave."""
    status = None        # the judge's exit status, as Popen gives it
    verdict = ""         # "passed" or "failed", as the judge reported it
    judge_cpu = 0.0
    worker_cpu = 0.0
    worker_status = None  # the worker's exit status, as Popen gives it
    stopped = False      # at a time limit, or for writing too much
    out_of_time = False  # stopped at the grading's deadline
    too_much_written = False
    seconds = 0.0        # wall time less the time spent waiting for a processor
    dropped = 0          # bytes of the judge's output dropped
    printed_dropped = 0  # bytes of what the student's code printed dropped
    judge_output = b""
    printed = b""        # what the student's code printed


def too_much_written(folder):
    """Whether a worker's folder holds more than it may (WORKER_DISK_BYTES or WORKER_DISK_ENTRIES),
    counting only until it does."""
    total, entries, waiting = 0, 0, [folder]
    while waiting:
        try:
            listing = list(os.scandir(waiting.pop()))
        except OSError:
            continue
        for entry in listing:
            entries += 1
            try:
                if entry.is_dir(follow_symlinks=False):
                    waiting.append(entry.path)
                else:
                    total += entry.stat(follow_symlinks=False).st_size
            except OSError:
                pass
            if total > WORKER_DISK_BYTES or entries > WORKER_DISK_ENTRIES:
                return True
    return False


def worker_exit(pid):
    """The exit status of a worker that has ended (without reaping it), else None."""
    try:
        ended = os.waitid(os.P_PID, pid, os.WEXITED | os.WNOHANG | os.WNOWAIT)
    except ChildProcessError:
        return None
    if ended is None:
        return None
    return -ended.si_status if ended.si_code in (os.CLD_KILLED, os.CLD_DUMPED) else ended.si_status


def stop_worker(worker):
    """Kills a worker (its cell made it a group of its own) and reaps it: (its CPU seconds, its exit
    status as Popen gives it); (0, None) if it was reaped already."""
    kill_process_group(worker.pid)
    if worker.returncode is not None:
        return 0.0, None
    try:
        _, status, usage = os.wait4(worker.pid, 0)
    except ChildProcessError:
        return 0.0, None
    worker.returncode = os.waitstatus_to_exitcode(status)
    return usage.ru_utime + usage.ru_stime, worker.returncode


class TestServers:
    """The test servers of one grading: one per task for each of the grader's threads."""

    def __init__(self, programs, processes):
        self.programs = programs
        self.processes = processes
        self.local = threading.local()
        self.all = []
        self.lock = threading.Lock()
        self.cpus = sorted(os.sched_getaffinity(0))
        self.slots = 0

    def get(self, task):
        """The test server of `task` for this thread, on this thread's processor: the grader's
        threads take the processors in turn, and a test's judge and worker share one."""
        servers = self.local.__dict__.setdefault("servers", {})
        if "cpu" not in self.local.__dict__:
            with self.lock:
                self.local.cpu = self.cpus[self.slots % len(self.cpus)]
                self.slots += 1
        server = servers.get(task)
        if server is None or not server.alive:
            server = TestServer(self.programs, task, self.processes, self.local.cpu)
            servers[task] = server
            with self.lock:
                self.all.append(server)
        return server

    def close(self):
        for server in self.all:
            server.close()


def run_test(test, programs, servers, processes, cpu_limit, wall_limit, why, clock):
    """Runs one graded test: its judge (forked by its suite's test server) and its worker, stopped
    after `cpu_limit` seconds of computing or `wall_limit` seconds neither computing nor waiting
    for a processor (why: see TaskClock.reserve); fills in test.passed, test.feedback and its times."""
    cells = programs.cells
    judged = cells.new_folder("judge", "test-")
    work = cells.new_folder(test.task, "test-")
    variables = [f"BILLIARD_TEST_TIME_LIMIT={wall_limit:g}"] if test.task in PROGRAM_TASKS else []
    if test.visibility != "hidden":  # a hidden test draws nothing, so nothing of it can show
        variables.append(f"BILLIARD_PICTURES={PICTURES}")
    # A pipe each way between judge and worker, and one for what the worker prints.
    from_judge, to_worker = os.pipe()
    from_worker, to_judge = os.pipe()
    output, output_end = os.pipe()
    server = servers.get(test.task)
    try:
        worker = processes.start(programs.worker_command(test.task, work, (from_judge, to_judge), cpu_limit),
                                 stdin=subprocess.DEVNULL, stdout=output_end, stderr=output_end,
                                 pass_fds=(from_judge, to_judge))
        pin(worker.pid, server.cpu)  # beside its judge: a call's round trip on one processor is cheap
    finally:
        for fd in (from_judge, to_judge, output_end):
            os.close(fd)
    os.set_blocking(output, False)
    try:
        run = server.run(test.name, judged.name, cpu_limit, wall_limit, variables, worker, output,
                         (to_worker, from_worker), work, clock.deadline)
    finally:
        for fd in (to_worker, from_worker, output):
            os.close(fd)
        processes.stop_orphans()  # what left its group
    test.seconds = run.seconds
    test.cpu_seconds = run.judge_cpu + run.worker_cpu
    test.passed = not run.stopped and run.status == 0 and run.verdict == "passed"
    # Stopped by the kernel for its CPU time (its limit there is a backstop, a second above the
    # test's: several busy threads, or a grader too busy to look in time) is not finishing either.
    test.unfinished = (run.stopped and not run.too_much_written) or run.worker_status == -signal.SIGXCPU or (
        run.worker_status == -signal.SIGKILL and run.worker_cpu >= cpu_limit)
    test.out_of_time = run.out_of_time
    test.feedback, googletest = readable_first(feedback(test, run, cpu_limit, "deadline" if run.out_of_time else why,
                                                        clock))
    test.feedback, test.googletest = cap(test.feedback, FEEDBACK_CAP), cap(googletest, FEEDBACK_CAP)
    test.picture = keep_picture(test, judged, cells.root)
    shutil.rmtree(judged, ignore_errors=True)
    shutil.rmtree(work, ignore_errors=True)


def feedback(test, run, cpu_limit, why, clock):
    """A test's message: why it ended, if not as tests do; the judge's messages; what the
    student's code printed."""
    messages = gtest_messages(run.judge_output.decode(errors="replace"))
    if run.dropped:
        messages += f"\n... ({run.dropped} more bytes of output were dropped)"
    lead = ""
    if run.too_much_written:
        lead = (f"Your code wrote more than {WORKER_DISK_BYTES >> 20} MB, or more than {WORKER_DISK_ENTRIES:,} files, "
                "into its folder, and the test was stopped. A task writes one picture of some kilobytes at most.")
    elif test.unfinished:
        lead = unfinished_message(clock, test.name, cpu_limit, why)
    elif WORKER_GONE in messages and run.worker_status is not None:
        if run.worker_status < 0:
            number = -run.worker_status
            name = signal.Signals(number).name if number in signal.Signals._value2member_map_ else f"signal {number}"
            lead = (f"Your code crashed with {name}, "
                    f"{SIGNAL_HINTS.get(number, 'an error the program could not recover from')}.")
        else:
            lead = (f"Your code ended the process it runs in (exit status {run.worker_status}) before the test was "
                    "over: did it call exit()? The test cannot count as passed.")
    elif run.status is not None and run.status < 0 and not test.passed:
        number = -run.status
        name = signal.Signals(number).name if number in signal.Signals._value2member_map_ else f"signal {number}"
        lead = (f"The test's judge ended with {name} while checking your code's answers: were they very large? "
                "If not, tell your instructor: this is the grader's fault.")
    printed = run.printed.decode(errors="replace").strip()
    size = len(run.printed) + run.printed_dropped
    shown = ""
    if printed:
        shown = ("\nWhat your code printed" + (f" ({size:,} bytes; the first {PRINTED_CAP:,} characters)"
                                               if len(printed) > PRINTED_CAP else "") + f":\n  {student_text(printed[:PRINTED_CAP])}")
    return "\n".join(part for part in [lead, messages] if part).strip() + shown


def keep_picture(test, judged, root):
    """The picture a failing visible test's judge drew in its folder, copied into the grading's
    pictures folder (root/pictures) before its own is removed: its name there
    ("pictures/Suite.Test.svg"), or "". Read without following links."""
    if test.passed or test.visibility == "hidden":
        return ""
    content = read_regular_file(judged / PICTURES / f"{test.name}.svg", PICTURE_CAP)
    if content is None:
        return ""
    kept = root / PICTURES
    kept.mkdir(exist_ok=True)
    (kept / f"{test.name}.svg").write_bytes(content)
    return f"{PICTURES}/{test.name}.svg"


def place_pictures(results, root, folder):
    """Moves the grading's pictures into folder/pictures (replacing the last grading's) and makes
    each message name its picture there; a message whose picture was not kept loses the line."""
    kept = folder / PICTURES
    shutil.rmtree(kept, ignore_errors=True)
    if (root / PICTURES).is_dir():
        shutil.copytree(root / PICTURES, kept)
    for result in results:
        for test in result.tests:
            if test.picture and not (folder / test.picture).is_file():
                test.picture = ""
            line = f"Picture: {folder / test.picture}\n" if test.picture else ""
            test.feedback = PICTURE_LINE.sub(lambda _: line, test.feedback).strip()


def run_budgeted(test, programs, servers, processes, clock):
    """Runs one test within its task's budget, or marks it not run when the budget is used up."""
    reserved = clock.reserve(test.name)
    if reserved is None:
        test.not_run = True
        test.out_of_time = clock.out_of_time
        test.feedback = not_run_message(clock)
        return
    cpu_limit, wall_limit, why = reserved
    try:
        run_test(test, programs, servers, processes, cpu_limit, wall_limit, why, clock)
    finally:
        clock.release(wall_limit, test.seconds, test.unfinished)


FAILURE_PLACE = re.compile(r"^\S+:\d+: Failure$")  # how GoogleTest starts each failure it reports


def readable_first(text):
    """(a test's message for the student, GoogleTest's own lines): each failure that has the
    student's form ("Expected: ...", "Your code: ...", "Hint: ..."; tests/support/student_messages.hpp)
    keeps that part alone, and the assertion's place and values GoogleTest printed before it go to
    the second text (grade.py's googletest.log). A failure without that form stays whole."""
    shown, raw = [], []
    chunk = []
    for line in text.splitlines() + [None]:
        if line is not None and not (FAILURE_PLACE.match(line) and chunk):
            chunk.append(line)
            continue
        # (what comes before GoogleTest's first failure, such as why the test ended, stays whole)
        readable = next((at for at in range(len(chunk) - 2, -1, -1) if chunk[at].startswith("Expected: ")
                         and next((line for line in chunk[at + 1:] if not line.startswith("  ")), "")
                         .startswith("Your code: ")), None) \
            if chunk and FAILURE_PLACE.match(chunk[0]) else None
        if readable is None:
            shown.append("\n".join(chunk).strip())
        else:
            shown.append("\n".join(chunk[readable:]).strip())
            raw.append("\n".join(chunk[:readable]).strip())
        chunk = [line]
    return "\n\n".join(part for part in shown if part), "\n\n".join(part for part in raw if part)


def student_text(text):
    """Text of the student's (an exception's message, what their code printed) inside a message:
    each of its lines after the first indented, so that none of them reads as one of the judge's
    own lines ("Hint: ...", "Expected: ...", "Picture: ..."), which start a line."""
    return text.replace("\n", "\n  ")


def gtest_messages(text):
    """GoogleTest's output without its banner lines: the failure messages and anything printed."""
    noise = ("[==========]", "[----------]", "[ RUN      ]", "[       OK ]", "Note: Google Test filter",
             "[  PASSED  ]", "[  FAILED  ]", "[  SKIPPED ]")
    text = re.sub(r'unknown file: Failure\nC\+\+ exception with description "(.*?)" thrown in the test body\.',
                  lambda match: "The code threw an exception: " + student_text(match[1]), text, flags=re.DOTALL)
    # A call whose worker ended fails with the proxy's message (its place in the proxy says nothing
    # to a student), and GoogleTest adds a line for the exception that ends the test.
    text = re.sub(r"unknown file: Failure\nUnknown C\+\+ exception thrown in the test body\.\n?", "", text)
    text = re.sub(rf"^\S*{re.escape(PROXY)}:\d+: Failure\nFailed\n\n?", "", text, flags=re.MULTILINE)
    lines = [line for line in text.splitlines() if not line.startswith(noise)]
    while lines and not lines[-1].strip():
        lines.pop()
    return "\n".join(line.replace(str(REPO) + "/", "") for line in lines
                     if not line.strip().endswith("FAILED TEST") and not line.strip().endswith("FAILED TESTS"))


class ResultCache:
    """Results of tests by (the task's judge and worker, test, time limit): the suites are
    deterministic, so unchanged programs give the same results. Used when grading many variants of
    one submission, such as the mutants."""

    def __init__(self, folder, limits):
        self.folder = folder
        self.limits = limits  # {task: TaskLimits}
        self.digests = {}
        folder.mkdir(parents=True, exist_ok=True)

    def key(self, test, programs):
        if test.task not in self.digests:
            self.digests[test.task] = programs.digest(test.task)
        name = f"{self.digests[test.task]}-{test.name}-{self.limits[test.task].test(test.name):g}"
        return self.folder / (hashlib.sha256(name.encode()).hexdigest() + ".json")

    def recall(self, test, programs):
        entry = self.key(test, programs)
        if not entry.is_file():
            return False
        saved = json.loads(entry.read_text())
        test.passed, test.feedback, test.seconds = saved["passed"], saved["feedback"], saved["seconds"]
        test.googletest = saved.get("googletest", "")
        test.cpu_seconds = saved["cpu_seconds"]
        test.picture = saved.get("picture", "")
        if test.picture:
            (programs.cells.root / PICTURES).mkdir(exist_ok=True)
            shutil.copyfile(entry.with_suffix(".svg"), programs.cells.root / test.picture)
        return True

    def remember(self, test, programs):
        if test.unfinished or test.not_run:
            return  # depends on the time left, not only on the programs
        entry = self.key(test, programs)
        if test.picture:
            shutil.copyfile(programs.cells.root / test.picture, entry.with_suffix(".svg"))
        partial = entry.with_name(entry.name + ".partial")
        partial.write_text(json.dumps(
            {"passed": test.passed, "feedback": test.feedback, "seconds": test.seconds, "cpu_seconds": test.cpu_seconds,
             "picture": test.picture, "googletest": test.googletest}))
        os.replace(partial, entry)


def run_tests(results, build, cells, clocks, jobs, cache, quiet=False):
    """Runs every test of every task, each in a judge and a worker of its own, `jobs` at a time,
    each task's within its budget: the visible tests and those shown after the due date first,
    then, once they have all ended and the cells' processes are stopped, the hidden ones."""
    tasks = [result.task for result in results if result.tests]
    programs = Programs(build, cells, tasks)
    for result in results:
        for test in result.tests:
            test.passed, test.not_run, test.unfinished, test.feedback, test.picture = False, False, False, "", ""
    work = [test for result in results for test in result.tests]
    if cache:
        work = [test for test in work if not cache.recall(test, programs)]
    if not quiet:
        print(f"grade: running {len(work)} tests, each in a judge and a worker of its own, {jobs} at a time",
              flush=True)
    processes = Processes()
    servers = TestServers(programs, processes)
    try:
        for phase in [[test for test in work if test.visibility != "hidden"],
                      [test for test in work if test.visibility == "hidden"]]:
            with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as pool:
                running = {}  # task -> its tests' futures, in course order
                for test in phase:
                    running.setdefault(test.task, []).append(
                        pool.submit(run_budgeted, test, programs, servers, processes, clocks[test.task]))
                for task, futures in running.items():
                    for future in futures:
                        future.result()
                    if not quiet:
                        print(f"grade: {task_name(task)}: {len(futures)} tests run", flush=True)
            for task in tasks:
                cells.stop(task)
    finally:
        servers.close()
        processes.stop_orphans()
    if cache:
        for test in work:
            cache.remember(test, programs)
    for result in results:
        point_to_the_first_failure(result)


def point_to_the_first_failure(result):
    """A task's later failing tests often fail because of the mistake its first failing test
    names, while their own hints speak of what they check: each of them says to fix the first one
    first, so that no hint read alone (on Gradescope each test is read alone) points away from the
    mistake."""
    failed = [test for test in result.tests
              if not test.passed and test.visibility != "hidden" and test.feedback and not test.out_of_time]
    for test in failed[1:]:
        test.feedback = FIRST_FAILURE.format(first=failed[0].name) + "\n" + test.feedback


# The first line of a task's later failing tests (point_to_the_first_failure).
FIRST_FAILURE = ("First fix {first}, this task's first failing test: this one may fail for the same reason, and "
                 "pass with it.")


