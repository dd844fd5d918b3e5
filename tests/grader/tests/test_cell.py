#!/usr/bin/python3
"""Tests of the cell (tests/grader/cell/cell.c): from inside a cell, cell_attempts tries what
submitted code might (cell_attempts.c), and each protection is checked on its own: seccomp alone,
Landlock where the kernel has it, and, as root, the cell's own user id. A second set runs the cell
as an unprivileged user, as a student's machine or GitHub Classroom does.

    /usr/bin/python3 tests/grader/tests/test_cell.py CELL CELL_ATTEMPTS [unittest arguments]
"""

import os
import pwd
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import unittest
import unittest.mock
from pathlib import Path

HERE = Path(__file__).resolve().parent
GRADER = HERE.parent  # the grader, whose tests these are
REPO = HERE.parents[2]
sys.path.insert(0, str(GRADER))
import cell  # noqa: E402  (its pool of user ids)
CELL = ATTEMPTS = None  # from the command line
ROOT = os.geteuid() == 0
CELL_USER = 1_900_099_999  # a user id of the grader's pool, far from any grading's
NOBODY = pwd.getpwnam("nobody").pw_uid if ROOT else None


def landlock():
    done = subprocess.run([CELL, "--probe"], stdout=subprocess.PIPE, text=True, check=True)
    return int(dict(line.split(" ", 1) for line in done.stdout.splitlines())["landlock"])


def as_nobody():
    os.setgroups([])
    os.setgid(NOBODY)
    os.setuid(NOBODY)


def attempt(name, argument=None, options=(), unprivileged=False):
    """What cell_attempts says of one attempt in a cell with `options`: "allowed", "denied
    ERRNO", or "killed SIGNAL" when the cell ended it."""
    done = subprocess.run([CELL, *options, "--", ATTEMPTS, name, *([str(argument)] if argument is not None else [])],
                          stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=60,
                          preexec_fn=as_nobody if unprivileged else None)
    if done.returncode < 0:
        return f"killed {signal.Signals(-done.returncode).name}"
    if done.returncode != 0:
        raise AssertionError(f"{name}: status {done.returncode}: {done.stderr}")
    return done.stdout.strip()


def attempt_outside_a_cell(name):
    """What cell_attempts says of an attempt run as a plain process: what the kernel itself allows."""
    done = subprocess.run([ATTEMPTS, name], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=60)
    return f"killed {signal.Signals(-done.returncode).name}" if done.returncode < 0 else done.stdout.strip()


class Seccomp(unittest.TestCase):
    """What the filter forbids, without Landlock, against a process of the same user: as root,
    two cells of one user id (two tests of a task); otherwise the user's own processes."""

    unprivileged = False

    def setUp(self):
        if self.unprivileged and not ROOT:
            self.skipTest("needs root to become another user")
        self.options = ["--no-landlock", "--no-fork"]
        neighbour = ["sleep", "60"]
        if ROOT and not self.unprivileged:
            self.options += ["--user", str(CELL_USER)]
            neighbour = [CELL, "--no-landlock", "--user", str(CELL_USER), "--", "/bin/sleep", "60"]
        self.neighbour = subprocess.Popen(neighbour, preexec_fn=as_nobody if self.unprivileged else None)

    def tearDown(self):
        self.neighbour.kill()
        self.neighbour.wait()

    def expect(self, name, outcome, argument=None):
        self.assertEqual(attempt(name, argument, self.options, self.unprivileged), outcome, name)

    def test_no_new_process_but_threads(self):
        self.expect("fork", "denied EPERM")
        self.expect("thread", "allowed")
        self.expect("clone3", "denied ENOSYS")

    def test_no_signal_beyond_its_own_group(self):
        self.expect("signal", "denied EPERM", self.neighbour.pid)
        self.expect("signal-everyone", "denied EPERM")
        self.expect("tgkill", "denied EPERM", self.neighbour.pid)
        self.expect("signal-self", "allowed")
        self.expect("raise", "allowed")

    def test_no_tracing_or_reading_another_process(self):
        self.expect("ptrace", "denied EPERM", self.neighbour.pid)
        self.expect("read-memory", "denied EPERM", self.neighbour.pid)

    def test_no_sockets_shared_memory_or_namespaces(self):
        for name in ["socket-inet", "socket-unix", "sysv-shared-memory", "memory-file", "user-namespace", "dumpable"]:
            self.expect(name, "denied EPERM")
        self.expect("socketpair", "allowed")
        self.expect("become-root", "denied EPERM")

    def test_calls_of_another_architecture_end_the_cell(self):
        # A kernel built or booted without 32-bit calls (ia32_emulation=0) refuses int 0x80 itself
        # with SIGSEGV, in a cell or not; where it runs them outside a cell, the filter ends the cell.
        outside = attempt_outside_a_cell("i386")
        self.assertIn(outside, ["allowed", "killed SIGSEGV"])
        self.expect("i386", "killed SIGSYS" if outside == "allowed" else "killed SIGSEGV")
        self.expect("x32", "killed SIGSYS")


class SeccompUnprivileged(Seccomp):
    """The same, with the cell started by an unprivileged user (a student's machine): the filter
    alone keeps the cell from its user's other processes."""

    unprivileged = True


class Landlock(unittest.TestCase):
    """What a cell may read and write with Landlock (where the kernel has it), as its own user."""

    def setUp(self):
        if landlock() == 0:
            self.skipTest("this kernel has no Landlock")
        self.folder = Path(tempfile.mkdtemp(prefix="cell-test-"))
        os.chmod(self.folder, 0o755)
        self.readable, self.writable = self.folder / "readable", self.folder / "writable"
        for folder in [self.readable, self.writable]:
            folder.mkdir()
            os.chmod(folder, 0o777)
        (self.readable / "file").write_text("readable\n")
        os.chmod(self.readable / "file", 0o644)
        (self.folder / "outside").write_text("outside\n")
        os.chmod(self.folder / "outside", 0o644)
        self.options = ["--read", str(self.readable), "--read", ATTEMPTS, "--write", str(self.writable), "--dir",
                        str(self.writable)]

    def tearDown(self):
        subprocess.run(["rm", "-rf", str(self.folder)])

    def expect(self, name, outcome, argument=None, unprivileged=False):
        self.assertEqual(attempt(name, argument, self.options, unprivileged), outcome, f"{name} {argument}")

    def test_reads_only_what_it_is_given(self):
        for unprivileged in [False, True] if ROOT else [False]:
            self.expect("read", "allowed", self.readable / "file", unprivileged)
            self.expect("read", "denied EACCES", self.folder / "outside", unprivileged)
            self.expect("list", "denied EACCES", REPO, unprivileged)
            self.expect("read", "denied EACCES", REPO / "README.md", unprivileged)
            self.expect("read", "denied EACCES", "/proc/1/cmdline", unprivileged)
            self.expect("read", "allowed", "/usr/include/stdio.h", unprivileged)

    def test_writes_only_its_own_folder(self):
        self.expect("write", "allowed", self.writable / "new")
        self.expect("write", "denied EACCES", self.readable / "new")
        self.expect("write", "denied EACCES", self.folder / "new")
        for shared in ["/tmp/billiard-cell-test", "/dev/shm/billiard-cell-test", "/var/tmp/billiard-cell-test"]:
            self.expect("write", "denied EACCES", shared)
            self.assertFalse(Path(shared).exists())

    def test_runs_the_system_programs(self):
        self.expect("execute", "allowed", "/bin/true")


@unittest.skipUnless(ROOT, "as root only: a cell of its own user id")
class UserIds(unittest.TestCase):
    def test_a_file_of_another_user_cannot_be_read_without_landlock(self):
        with tempfile.NamedTemporaryFile("w", prefix="cell-test-") as secret:
            secret.write("secret\n")
            secret.flush()
            os.chmod(secret.name, 0o600)
            self.assertEqual(attempt("read", secret.name, ["--no-landlock", "--user", str(CELL_USER)]), "denied EACCES")
            self.assertEqual(attempt("read", secret.name, ["--no-landlock"]), "allowed")

    def test_kill_all_stops_every_process_of_the_user(self):
        process = subprocess.Popen([CELL, "--no-landlock", "--user", str(CELL_USER), "--", "/bin/sleep", "60"])
        try:
            for _ in range(1000):  # until the cell has become that user
                status = Path(f"/proc/{process.pid}/status").read_text()
                if f"Uid:\t{CELL_USER}\t" in status:
                    break
                time.sleep(0.01)
            subprocess.run([CELL, "--user", str(CELL_USER), "--kill-all"], check=True, timeout=60)
            self.assertEqual(process.wait(timeout=10), -signal.SIGKILL)
        finally:
            process.kill()

    def test_clearing_a_user_removes_its_files_from_open_folders_below_the_shared_ones(self):
        # Another system's root unpacked in /tmp (a chroot's: its /tmp, /var/tmp, /run/lock) holds
        # folders anyone may write to, and a cell without Landlock wrote there once, past the
        # grading's end. Its file and folder go with the user; root's file and folder stay.
        root = Path(tempfile.mkdtemp(prefix="billiard-cell-root-", dir="/tmp"))
        try:
            os.chmod(root, 0o755)
            open_folder = root / "var" / "tmp"
            open_folder.mkdir(parents=True)
            os.chmod(open_folder, 0o1777)
            (open_folder / "roots").write_text("root's\n")
            script = f"echo x > {open_folder}/left && mkdir {open_folder}/folder && echo y > {open_folder}/folder/f"
            subprocess.run([CELL, "--no-landlock", "--user", str(CELL_USER), "--", "/bin/sh", "-c", script],
                           check=True, timeout=60)
            self.assertEqual({entry.name for entry in cell.files_of({CELL_USER})} & {"left", "folder"}, {"left", "folder"})
            cell.clear_user(CELL, CELL_USER)
            self.assertEqual(sorted(entry.name for entry in open_folder.iterdir()), ["roots"])
        finally:
            shutil.rmtree(root, ignore_errors=True)


@unittest.skipUnless(ROOT, "as root only: the pool of user ids")
class UserIdPool(unittest.TestCase):
    """cell.UserIds: gradings on one kernel never share a user id, whatever root each runs in."""

    def pool(self, folder, sequence):
        """A grading's pool whose lock files are in `folder` (each root has its own /run) and whose
        ids are drawn in the order of `sequence`."""
        ids = cell.UserIds(CELL)
        ids.candidates = lambda: iter(sequence)
        return ids

    def test_two_roots_on_one_kernel_never_share_an_id(self):
        # Two gradings, each with its own pool folder (a chroot beside the machine), draw the same ids.
        folders = [Path(tempfile.mkdtemp(prefix="pool-")) for _ in range(2)]
        wanted = CELL_USER - 10
        claim = cell.claim_user(wanted)
        if claim is None:
            self.skipTest("this machine allows no abstract Unix sockets: the lock files alone keep one root's "
                          "gradings apart")
        claim.close()
        with unittest.mock.patch.object(cell, "pool_folder", return_value=folders[0]):
            one = self.pool(folders[0], [wanted, wanted + 1])
            self.assertEqual(one.take(), wanted)
        try:
            with unittest.mock.patch.object(cell, "pool_folder", return_value=folders[1]):
                other = self.pool(folders[1], [wanted, wanted, wanted + 1])
                self.assertEqual(other.take(), wanted + 1, "the other root's grading holds it")
                other.release()
        finally:
            with unittest.mock.patch.object(cell, "pool_folder", return_value=folders[0]):
                one.release()
        self.assertEqual([list(folder.iterdir()) for folder in folders], [[], []], "lock files left")

    def test_an_id_whose_user_runs_a_process_is_not_taken(self):
        # A grading whose claims this one cannot see (a container's own network) runs a cell as
        # `wanted`: its process is seen, and the id is passed over.
        folder = Path(tempfile.mkdtemp(prefix="pool-"))
        wanted = CELL_USER - 20
        process = start_as(wanted)
        try:
            with unittest.mock.patch.object(cell, "pool_folder", return_value=folder), \
                    unittest.mock.patch.object(cell, "claim_user", return_value=None):
                ids = self.pool(folder, [wanted, wanted + 1])
                self.assertEqual(ids.take(), wanted + 1)
                ids.release()
        finally:
            process.kill()
            process.wait()

    def test_a_killed_gradings_ids_are_cleared_by_the_next(self):
        # A lock file says "in use", nobody claims its id, and a process of that user still runs:
        # the grading that held it was killed. The next grading stops the process, removes the file.
        folder = Path(tempfile.mkdtemp(prefix="pool-"))
        left = CELL_USER - 30
        (folder / f"{left}.lock").write_text("in use\n")
        process = start_as(left)
        try:
            with unittest.mock.patch.object(cell, "pool_folder", return_value=folder):
                ids = self.pool(folder, [left + 1])
                self.assertEqual(ids.take(), left + 1)
                self.assertEqual(process.wait(timeout=30), -signal.SIGKILL)
                self.assertFalse((folder / f"{left}.lock").exists())
                ids.release()
        finally:
            process.kill()
            process.wait()


def start_as(uid):
    """A process of user `uid` in a cell, sleeping; returns once it runs as that user."""
    process = subprocess.Popen([CELL, "--no-landlock", "--user", str(uid), "--", "/bin/sleep", "60"])
    for _ in range(1000):
        try:
            if f"Uid:\t{uid}\t" in Path(f"/proc/{process.pid}/status").read_text():
                return process
        except OSError:
            pass
        time.sleep(0.01)
    process.kill()
    raise AssertionError(f"the cell did not become user {uid}")


class Options(unittest.TestCase):
    def test_bad_options_are_refused_with_a_message(self):
        for options in [["--fd", "3"], ["--cpu", "-1"], ["--bogus"], ["--dir"], []]:
            done = subprocess.run([CELL, *options, *(["--", "/bin/true"] if options[:1] != ["--dir"] and options else [])],
                                  stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=60)
            self.assertEqual(done.returncode, 125, options)
            self.assertTrue(done.stderr.startswith("cell: ") and done.stderr.count("\n") == 1, done.stderr)

    def test_probe_says_what_the_machine_allows(self):
        done = subprocess.run([CELL, "--probe"], stdout=subprocess.PIPE, text=True, check=True)
        values = dict(line.split(" ", 1) for line in done.stdout.splitlines())
        self.assertEqual(set(values), {"landlock", "seccomp", "user-ids"})
        self.assertEqual(values["seccomp"], "1")
        self.assertEqual(values["user-ids"], "1" if ROOT else "0")


if __name__ == "__main__":
    if len(sys.argv) < 3:
        print(__doc__)
        sys.exit(2)
    # Copies anyone may run: the build may lie where other users cannot go (a grading as root
    # beside these tests makes the repository its own while it runs).
    programs = Path(tempfile.mkdtemp(prefix="cell-programs-"))
    os.chmod(programs, 0o755)
    CELL, ATTEMPTS = (str(shutil.copy(Path(sys.argv.pop(1)), programs)) for _ in range(2))
    try:
        result = unittest.main(verbosity=2, exit=False).result
    finally:
        shutil.rmtree(programs)
    sys.exit(0 if result.wasSuccessful() else 1)
