"""The cells of a grading: where every process that runs submitted code (its compilation, its
link, each test's worker) and the judges start, confined by the launcher tests/grader/cell/cell.c.

What confines a cell, by what the machine allows (grade.py prints which are in force):
  - always: a process of its own with resource limits; seccomp (Debian's libseccomp): no
    tracing, no reading another process's memory, no signals beyond its own group, no sockets,
    no shared memory or message queues, no namespaces, and for a test's worker no new processes;
  - Landlock, where the kernel has it: the cell reads the system's program folders and the paths
    it is given, writes only its own folder, opens no TCP connection, signals nothing outside;
  - as root: a user id of its own per cell, from a pool that concurrent gradings share without
    overlap (a lock file per id), so the kernel itself keeps cells apart; at its end every process
    of that user is stopped and its files in the machine's shared folders (/tmp, /dev/shm, ...)
    removed, and the judges run under another id than any cell.
"""

import dataclasses
import fcntl
import os
import select
import shutil
import stat
import subprocess
import tempfile
import threading
from dataclasses import dataclass
from pathlib import Path

# User ids the grader gives its cells as root: far above the ranges of real and system users.
FIRST_CELL_USER = 1_900_000_000
CELL_USERS = 100_000
# Folders every user may write to, where a cell's files could outlive it (without Landlock).
SHARED_FOLDERS = ["/tmp", "/var/tmp", "/dev/shm", "/dev/mqueue", "/run/lock", "/var/lock"]


@dataclass
class Protections:
    """What this machine lets a cell use (cell --probe)."""
    landlock: int  # Landlock's ABI version, 0 for none
    seccomp: bool
    user_ids: bool  # running as root: each cell gets a user id of its own

    def describe(self):
        """One line for the log: which protections are in force."""
        parts = ["each test's code in a process of its own, apart from the judge",
                 "seccomp" if self.seccomp else "NO seccomp (this kernel has none)"]
        parts.append(f"Landlock ABI {self.landlock} (files: the cell's own folder; no TCP; no signals out)"
                     if self.landlock else "no Landlock (older kernel, or not allowed here)")
        parts.append("a user id of its own per cell (root)" if self.user_ids
                     else "cells share your user id (not root)")
        return ", ".join(parts)


# Set (to anything) in the environment, the cells leave Landlock out: how the grader's tests try
# the other protections alone, as on a machine whose kernel has no Landlock.
WITHOUT_LANDLOCK = "BILLIARD_CELLS_WITHOUT_LANDLOCK"


def probe(launcher):
    """The protections `launcher` (the cell program) can apply on this machine."""
    done = subprocess.run([str(launcher), "--probe"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                          timeout=60)
    if done.returncode != 0:
        raise RuntimeError(f"the grader's cell does not start here:\n{done.stderr}")
    values = dict(line.split(" ", 1) for line in done.stdout.splitlines() if " " in line)
    landlock = 0 if os.environ.get(WITHOUT_LANDLOCK) else int(values.get("landlock", 0))
    protections = Protections(landlock, values.get("seccomp") == "1", values.get("user-ids") == "1")
    if not protections.seccomp:
        raise RuntimeError("the grader cannot confine submitted code here: this kernel has no seccomp")
    return protections


def pool_folder():
    """Where the lock files of the user ids in use are: one place for every grading on the machine."""
    for folder in [Path("/run/billiard-grader"), Path(tempfile.gettempdir()) / "billiard-grader-root"]:
        try:
            folder.mkdir(mode=0o700, exist_ok=True)
            if folder.stat().st_uid == 0 and os.access(folder, os.W_OK):
                os.chmod(folder, 0o700)
                return folder
        except OSError:
            continue
    raise RuntimeError("no folder for the grader's user-id locks (/run or the temporary folder)")


class UserIds:
    """User ids for the cells of one grading, each held (a lock file, released when this process
    ends, however it ends) until release(), so that concurrent gradings never share one. An id is
    cleared (its processes stopped, its files in the shared folders removed) when it is given
    back, and when taken after a grading that was killed before it could give it back (its lock
    file says it was in use)."""

    def __init__(self, launcher):
        self.launcher = launcher
        self.held = {}  # uid -> open lock file

    def take(self):
        folder = pool_folder()
        for uid in range(FIRST_CELL_USER, FIRST_CELL_USER + CELL_USERS):
            if uid in self.held:
                continue
            lock = open(folder / f"{uid}.lock", "a+")
            try:
                fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except OSError:
                lock.close()
                continue
            lock.seek(0)
            if lock.read():  # left in use by a grading that was killed
                clear_user(self.launcher, uid)
            lock.truncate(0)
            lock.write("in use\n")
            lock.flush()
            self.held[uid] = lock
            return uid
        raise RuntimeError("every user id of the grader's pool is in use")

    def release(self):
        clear_users(self.launcher, list(self.held))
        for lock in self.held.values():
            lock.truncate(0)
            lock.close()
        self.held = {}


def clear_user(launcher, uid, files=True):
    """Stops every process of user `uid` and (with `files`) removes its files from the shared
    folders."""
    clear_users(launcher, [uid], files)


def clear_users(launcher, uids, files=True):
    """clear_user for several users, with one look through the shared folders."""
    for uid in uids:
        subprocess.run([str(launcher), "--user", str(uid), "--kill-all"], stdin=subprocess.DEVNULL,
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, timeout=60)
    for shared in SHARED_FOLDERS if files and uids else []:
        try:
            entries = list(os.scandir(shared))
        except OSError:
            continue
        for entry in entries:
            try:
                if entry.stat(follow_symlinks=False).st_uid not in uids:
                    continue
                if entry.is_dir(follow_symlinks=False):
                    shutil.rmtree(entry.path, ignore_errors=True)
                else:
                    os.unlink(entry.path)
            except OSError:
                pass


@dataclass
class Limits:
    """Resource limits of a cell's processes (None: none set)."""
    cpu_seconds: float = None
    memory_bytes: int = None
    file_bytes: int = None
    open_files: int = None
    processes: int = None  # of the cell's user id (as root)


def command(launcher, program, *, directory, uid=None, reads=(), writes=(), no_fork=False, descriptors=None,
            environment=None, limits=Limits()):
    """The command that starts `program` (a list: the program and its arguments) in a cell:
    working folder `directory`, user id `uid` (as root), Landlock access to `reads` and `writes`,
    descriptors {from: to} kept (all others closed), only `environment` and the basics set."""
    words = [str(launcher), "--dir", str(directory), *(["--no-landlock"] if os.environ.get(WITHOUT_LANDLOCK) else [])]
    if uid is not None:
        words += ["--user", str(uid)]
    if limits.cpu_seconds is not None:
        words += ["--cpu", str(max(1, int(limits.cpu_seconds + 0.999)))]
    for option, value in [("--memory", limits.memory_bytes), ("--file-size", limits.file_bytes),
                          ("--open-files", limits.open_files), ("--processes", limits.processes)]:
        if value is not None:
            words += [option, str(int(value))]
    for path in reads:
        words += ["--read", str(path)]
    for path in writes:
        words += ["--write", str(path)]
    if no_fork:
        words.append("--no-fork")
    for source, target in (descriptors or {}).items():
        words += ["--fd", f"{source}:{target}"]
    for name, value in (environment or {}).items():
        words += ["--env", f"{name}={value}"]
    return words + ["--", *[str(word) for word in program]]


def own_folder(path, uid, mode=0o700):
    """Makes `path` a folder of user `uid` (as root; otherwise the caller's) with `mode`."""
    path.mkdir(parents=True, exist_ok=True)
    if uid is not None:
        os.chown(path, uid, uid)
    os.chmod(path, mode)
    return path


def read_regular_file(path, limit):
    """The content of a file a cell made, read without following a link put in its place: None
    unless it is a regular file of at most `limit` bytes."""
    try:
        descriptor = os.open(path, os.O_RDONLY | os.O_NOFOLLOW | os.O_NONBLOCK)
    except OSError:
        return None
    with os.fdopen(descriptor, "rb") as file:
        if not stat.S_ISREG(os.fstat(file.fileno()).st_mode):
            return None
        content = file.read(limit + 1)
    return content if len(content) <= limit else None


class Cells:
    """The cells of one grading, under one scratch folder (made here, removed by close()):

      bin/       programs the cells run (the judges, each task's worker or program), readable by
                 the grader alone and executable by the cells (so none can copy another's);
      objects/   what a task's worker is linked from: the harness, the course's libraries, the
                 other tasks' code (compiled objects only) and the compiled task files;
      include/   copies of the course's headers that a task file is compiled with;
      judge/     the judges' folder, a test's folder each: no cell can enter it;
      cell-TASK/ each task's cell: its compilation, its link, each test's worker, a folder each.

    As root, the judges run as one user id and each task's cell as another (UserIds)."""

    def __init__(self, launcher, tasks):
        self.launcher = launcher
        self.protections = probe(launcher)
        self.ids = UserIds(launcher) if self.protections.user_ids else None
        self.lock = threading.Lock()
        self.uids = {}
        self.root = Path(tempfile.mkdtemp(prefix="billiard-grade-"))
        try:
            os.chmod(self.root, 0o711)
            self.bin = own_folder(self.root / "bin", None, 0o711)
            self.objects = own_folder(self.root / "objects", None, 0o755)
            self.include = own_folder(self.root / "include", None, 0o755)
            self.judge = own_folder(self.root / "judge", self.uid("judge"))
            for task in tasks:
                own_folder(self.root / f"cell-{task}", self.uid(task))
        except BaseException:
            self.close()
            raise

    def uid(self, role):
        """The user id of a task's cell, or of the judges ("judge"); None when not root."""
        if self.ids is None:
            return None
        with self.lock:
            if role not in self.uids:
                self.uids[role] = self.ids.take()
            return self.uids[role]

    def folder(self, task):
        return self.root / f"cell-{task}"

    def new_folder(self, role, prefix):
        """A new folder of a task's cell or of the judges, for one compilation, link or test."""
        parent = self.judge if role == "judge" else self.folder(role)
        path = Path(tempfile.mkdtemp(prefix=prefix, dir=parent))
        return own_folder(path, self.uid(role))

    def put_program(self, content, name, folder="."):
        """Writes a program into bin/ (readable by the grader alone, executable by the cells)."""
        target = own_folder(self.bin / folder, None, 0o711) / name
        partial = target.with_name(name + ".partial")
        partial.write_bytes(content)
        os.chmod(partial, 0o711)
        os.replace(partial, target)
        return target

    def command(self, role, program, limits=Limits(), **options):
        """The command that starts `program` in the cell of `role` (see command()). A limit on
        processes counts those of the cell's own user id: without one (not root), none is set."""
        uid = self.uid(role)
        if uid is None:
            limits = dataclasses.replace(limits, processes=None)
        return command(self.launcher, program, uid=uid, limits=limits, **options)

    def stop(self, role):
        """Stops every process of a task's cell (as root; otherwise each process is stopped alone);
        its files in the shared folders go when the grading ends."""
        if self.uid(role) is not None:
            clear_user(self.launcher, self.uid(role), files=False)

    def close(self):
        if self.ids is not None:
            self.ids.release()
        shutil.rmtree(self.root, ignore_errors=True)

    def __enter__(self):
        return self

    def __exit__(self, *_):
        self.close()


# --- Running a cell's processes -----------------------------------------------------------------

def run_limited(command, timeout, cwd=None, output_cap=4 << 20):
    """Runs a command (the cell sets its session and limits) with stdin from /dev/null (a file that
    includes /dev/stdin reads nothing), stopped with its whole group at the time limit, keeping the
    first `output_cap` bytes of its output. Returns (ok, output, timed out)."""
    process = subprocess.Popen(command, cwd=cwd, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                               stderr=subprocess.STDOUT, start_new_session=True)
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
        os.killpg(process.pid, 9)
    except (ProcessLookupError, PermissionError):
        pass
    process.wait()


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
