"""The cells of a grading: where every process that runs submitted code (its compilation, its
link, each test's worker) and the judges start, confined by the launcher tests/grader/cell/cell.c.

What confines a cell, by what the machine allows (grade.py prints which are in force):
  - always: a process of its own with resource limits; seccomp (Debian's libseccomp): no
    tracing, no reading another process's memory, no signals beyond its own group, no sockets,
    no shared memory or message queues, no namespaces, and for a test's worker no new processes;
  - Landlock, where the kernel has it: the cell reads the system's program folders and the paths
    it is given, writes only its own folder, opens no TCP connection, signals nothing outside;
  - as root: a user id of its own per cell, drawn at random from a range far above real users'
    and claimed on the kernel, not in a folder (UserIds), so that concurrent gradings never share
    one, not even from two roots (a chroot, a container) on one kernel: the kernel itself keeps
    cells apart; at its end every process of that user is stopped and its files in the machine's
    shared folders (/tmp, /dev/shm, ...) removed, and the judges run under another id than any cell.
"""

import dataclasses
import errno
import fcntl
import os
import re
import secrets
import select
import shutil
import socket
import stat
import subprocess
import tempfile
import threading
from dataclasses import dataclass
from pathlib import Path

# User ids the grader gives its cells as root: far above the ranges of real and system users,
# below 2^31 (which some tools read as negative). Each is drawn at random among them.
FIRST_CELL_USER = 1_900_000_000
CELL_USERS = 200_000_000
# The kernel-wide claim of a user id: an abstract Unix socket of this name, bound while the id is
# held. Its names are one per network namespace, which a chroot shares with the machine (unlike
# /run, where the lock files are); the kernel frees it when its holder ends, however it ends.
CLAIM_NAME = "billiard-grader-user-{uid}"
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
    """User ids for the cells of one grading, each held until release(), so that concurrent
    gradings never share one: on this machine and from other roots on its kernel (a chroot, a
    container). An id is drawn at random, and taken only if

      - its kernel-wide claim (an abstract socket, CLAIM_NAME) is free: no grading of this
        network namespace holds it, a chroot's included;
      - no process visible here runs under it (a grading of a container whose claims are apart);

    then its lock file in the pool folder marks it in use until release() stops its processes,
    removes its files and the lock file. A lock file left without its claim is a grading killed
    before it could give its ids back: the next grading clears those ids (clear_abandoned)."""

    def __init__(self, launcher):
        self.launcher = launcher
        self.held = {}  # uid -> (open lock file, claim socket or None)
        self.cleared = False  # the ids killed gradings left: cleared once, at the first take()

    @staticmethod
    def candidates():
        """The ids to try, in order (random; a test replaces this)."""
        while True:
            yield FIRST_CELL_USER + secrets.randbelow(CELL_USERS)

    def take(self):
        folder = pool_folder()
        if not self.cleared:
            self.clear_abandoned(folder)
            self.cleared = True
        for _, uid in zip(range(1000), self.candidates()):
            if uid in self.held or user_runs_processes(uid):
                continue
            claim = claim_user(uid)
            if claim is False:
                continue
            lock = open_lock(folder, uid)
            if lock is None:
                if claim:
                    claim.close()
                continue
            lock.truncate(0)
            lock.write("in use\n")
            lock.flush()
            self.held[uid] = (lock, claim)
            return uid
        raise RuntimeError("no free user id for the grader's cells after 1000 tries")

    def clear_abandoned(self, folder):
        """Clears the ids whose lock file a killed grading left: its processes and files."""
        for path in folder.glob("*.lock"):
            match = re.fullmatch(r"(\d+)\.lock", path.name)
            if not match:
                continue
            uid = int(match[1])
            claim = claim_user(uid)
            if claim is False:
                continue  # held: by a grading that runs
            lock = open_lock(folder, uid, create=False)
            if lock is not None:
                clear_user(self.launcher, uid)
                path.unlink(missing_ok=True)
                lock.close()
            if claim:
                claim.close()

    def release(self):
        clear_users(self.launcher, list(self.held))
        folder = pool_folder()
        for uid, (lock, claim) in self.held.items():
            (folder / f"{uid}.lock").unlink(missing_ok=True)  # while it is locked: see open_lock
            lock.close()
            if claim:
                claim.close()
        self.held = {}


def claim_user(uid):
    """The kernel-wide claim of user id `uid` (CLAIM_NAME): a bound socket, to keep open while
    the id is held; False if another process holds it; None where this machine allows no such
    socket (the lock files alone then keep the gradings of this root apart)."""
    claim = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    try:
        claim.bind("\0" + CLAIM_NAME.format(uid=uid))
        return claim
    except OSError as error:
        claim.close()
        return False if error.errno == errno.EADDRINUSE else None


def open_lock(folder, uid, create=True):
    """The lock file of `uid`, open and locked, or None if another grading holds it (or, without
    `create`, if there is none). A lock file is removed while locked, so one opened before its
    removal no longer is the path's file: then it does not count."""
    path = folder / f"{uid}.lock"
    try:
        descriptor = os.open(path, os.O_RDWR | (os.O_CREAT if create else 0) | os.O_CLOEXEC, 0o600)
    except FileNotFoundError:
        return None
    lock = os.fdopen(descriptor, "r+")
    try:
        fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
        if os.fstat(lock.fileno()).st_ino != os.stat(path).st_ino:
            raise FileNotFoundError(path)
    except OSError:
        lock.close()
        return None
    return lock


def user_runs_processes(uid):
    """Whether a process visible here (this PID namespace's /proc) runs as user `uid`."""
    try:
        entries = os.listdir("/proc")
    except OSError:
        return False
    for entry in entries:
        if entry.isdigit():
            try:
                with open(f"/proc/{entry}/status") as status:
                    for line in status:
                        if line.startswith("Uid:"):
                            if int(line.split()[1]) == uid:
                                return True
                            break
            except (OSError, ValueError, IndexError):
                continue
    return False


def clear_user(launcher, uid, files=True):
    """Stops every process of user `uid` and (with `files`) removes its files from the shared
    folders."""
    clear_users(launcher, [uid], files)


def clear_users(launcher, uids, files=True):
    """clear_user for several users, with one look through the shared folders."""
    for uid in uids:
        subprocess.run([str(launcher), "--user", str(uid), "--kill-all"], stdin=subprocess.DEVNULL,
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, timeout=60)
    for entry in files_of(set(uids)) if files and uids else []:
        try:
            if entry.is_dir(follow_symlinks=False):
                shutil.rmtree(entry.path, ignore_errors=True)
            else:
                os.unlink(entry.path)
        except OSError:
            pass


# Folders below the shared ones looked into, at most this deep: a world-writable folder there
# (another system's root unpacked in /tmp, say: its /tmp, /var/tmp, /run/lock) is as open.
SHARED_DEPTH = 4


def files_of(uids, is_owner=None):
    """The entries (os.DirEntry) that users `uids` own in the shared folders and in every
    world-writable folder below them, the only places a cell without Landlock can leave files:
    each one's own folders whole, links never followed. is_owner(uid) replaces `uid in uids`."""
    is_owner = is_owner or uids.__contains__
    found, seen = [], set()

    def look(folder, depth):
        try:
            entries = list(os.scandir(folder))
        except OSError:
            return
        for entry in entries:
            try:
                status = entry.stat(follow_symlinks=False)
            except OSError:
                continue
            if is_owner(status.st_uid):
                found.append(entry)
            elif stat.S_ISDIR(status.st_mode) and depth > 0 and (status.st_dev, status.st_ino) not in seen:
                seen.add((status.st_dev, status.st_ino))
                # Into a folder anyone may write to; or one that may hold one (its owner's).
                if status.st_mode & stat.S_IWOTH or status.st_mode & stat.S_IXOTH:
                    look(entry.path, depth - 1)

    for shared in SHARED_FOLDERS:
        look(shared, SHARED_DEPTH)
    return found


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
