#!/usr/bin/python3
"""Fuzzing of what students upload, run by CTest. Generated uploads (task files that are empty,
binary or huge, folders named like task files, links of every kind, FIFOs, odd names, .zip and
.tar files holding such entries, path traversal, archive bombs, damaged archives) go through
the platforms' search for the task files (package.py's find_task_files) and grade.py's own
reading of a submission folder, in-process, hundreds of them; a few go end to end through
Gradescope's run_autograder logic (package.py's gradescope_run) and grade.py, with a standard
input that never ends. Each must end with a clear message and a results.json, in bounded time,
and cost points only in the tasks it spoils.

    /usr/bin/python3 tests/grader/tests/test_uploads.py BUILD_FOLDER [unittest arguments]

BUILD_FOLDER is the grader's build folder, shared with test_grader.py (the end-to-end cases).
"""

import contextlib
import io
import json
import os
import random
import shutil
import socket
import stat
import sys
import tarfile
import tempfile
import time
import unittest
import warnings
import zipfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
GRADER = HERE.parent  # the grader, whose tests these are
REPO = HERE.parents[2]
sys.path.insert(0, str(GRADER))
import building  # noqa: E402  (the scripts under test)
import package  # noqa: E402
import course  # noqa: E402  (the course's tasks)
import test_grader  # noqa: E402  (grading a submission folder, reading grade.py's output)
import test_packages  # noqa: E402  (scores from a results.json)

TASKS = package.TASKS
TASK_FILE = course.TASK_FILE  # <task>.cpp, or <task>.c for a C task
CAP = package.SUBMITTED_FILE_CAP
SECRET = b"SECRET-OUTSIDE-THE-UPLOAD"  # in every file outside the upload that a link points to
CASE_SECONDS = 20  # the most one upload may take to look through (they take well under a second)
BUILD = None  # set from the command line


def stub(task):
    return (REPO / "tasks" / TASK_FILE[task]).read_bytes()


def solution(task):
    return (REPO / "solutions" / TASK_FILE[task]).read_bytes()


def files_under(folder):
    """Every path under a folder (links not followed)."""
    paths = []
    for parent, folders, names in os.walk(folder):
        paths += [os.path.relpath(os.path.join(parent, name), folder) for name in folders + names]
    return sorted(paths)


@contextlib.contextmanager
def endless_stdin():
    """Standard input that never ends (a pipe nobody writes to or closes), for this process and
    what it starts: a grader that reads it waits forever."""
    read_end, write_end = os.pipe()
    saved = os.dup(0)
    os.dup2(read_end, 0)
    try:
        yield
    finally:
        os.dup2(saved, 0)
        for descriptor in (saved, read_end, write_end):
            os.close(descriptor)


class Upload:
    """One generated upload in `folder`, and what grading it must give: for each task, the
    contents that may be graded, whether one of them must be found, and the reasons the notes
    must give for entries named like the task's file that cannot be graded."""

    LINK_TARGETS = ["secret file", "/etc/passwd", "secret folder", "dangling", "loop", "itself", "upload file",
                    "/dev/zero", "/dev/stdin", "/dev/urandom"]

    def __init__(self, rng, folder, outside):
        self.rng = rng
        self.folder = folder
        self.outside = outside
        self.allowed = {task: set() for task in TASKS}  # contents that may be graded
        self.must_find = set()
        self.reasons = {task: set() for task in TASKS}  # reasons the notes must give
        self.kinds = {}  # entry kind -> count
        self.serial = 0

    def count(self, kind):
        self.kinds[kind] = self.kinds.get(kind, 0) + 1

    def content(self, task):
        """Unique text for a task file, or empty, or binary."""
        self.serial += 1
        kind = self.rng.choice(["text", "text", "text", "empty", "binary"])
        self.count(f"content: {kind}")
        if kind == "empty":
            return b""
        if kind == "binary":
            return self.rng.randbytes(self.rng.randrange(1, 5000)) + f"#{self.serial}".encode()
        return f"// {task} #{self.serial}\n".encode()

    def folder_name(self):
        """A folder path, relative, and whether files under it are looked at."""
        choice = self.rng.choice(["", "", "tasks", "billiard-main/tasks", "a/b/c", ".git", "__MACOSX", "dir with space",
                                  "new\nline", "bytes-\udcff\udcfe", "-leading", "ünïcödé", "deep", "too deep",
                                  "x" * 200, "propagate.cpp"])
        if choice == "deep":
            return "/".join(["d"] * 20), True
        if choice == "too deep":
            return "/".join(["d"] * 70), False
        return choice, not choice.startswith((".", "__MACOSX"))

    # --- entries in folders --------------------------------------------------------------------

    def add_file(self):
        task = self.rng.choice(TASKS)
        where, looked_at = self.folder_name()
        path = self.folder / where / TASK_FILE[task]
        if path.parent.is_symlink() or path.exists():
            return
        path.parent.mkdir(parents=True, exist_ok=True)
        size = self.rng.choice(["small"] * 8 + ["cap", "over cap", "huge"])
        self.count(f"file: {size}")
        if size == "small":
            data = self.content(task)
            path.write_bytes(data)
        else:
            data = f"// {task} sized\n".encode()
            with open(path, "wb") as file:  # sparse: no disk space for the zeros
                file.write(data)
                file.truncate({"cap": CAP, "over cap": CAP + 1, "huge": 50 * CAP}[size])
            data = path.read_bytes() if size == "cap" else None
        if data is not None:
            self.allowed[task].add(data)
            if looked_at:
                self.must_find.add(task)
        elif looked_at:
            self.reasons[task].add(building.TOO_LARGE)

    def add_folder(self):
        task = self.rng.choice(TASKS)
        path = self.folder / TASK_FILE[task]
        if path.exists() or path.is_symlink():
            return
        path.mkdir()
        self.count("folder named like a task file")
        self.reasons[task].add(building.FOLDER)
        if self.rng.random() < 0.3:  # with the task's file inside: that one counts
            data = self.content(task)
            (path / TASK_FILE[task]).write_bytes(data)
            self.allowed[task].add(data)
            self.must_find.add(task)

    def add_link(self):
        task = self.rng.choice(TASKS)
        where, looked_at = self.folder_name()
        path = self.folder / where / TASK_FILE[task]
        if path.exists() or path.is_symlink() or path.parent.is_symlink():
            return
        path.parent.mkdir(parents=True, exist_ok=True)
        target = self.rng.choice(self.LINK_TARGETS)
        self.count(f"link to {target}")
        if target == "loop":
            os.symlink(path.with_name("other-end"), path)
            os.symlink(path, path.with_name("other-end"))
        else:
            os.symlink({"secret file": self.outside / "secret.cpp", "secret folder": self.outside,
                        "dangling": self.outside / "nothing-here", "itself": path,
                        "upload file": self.folder / "elsewhere.txt"}.get(target, target), path)
        if looked_at:
            self.reasons[task].add(building.LINK)

    def add_folder_link(self):
        """A folder `tasks` that is a link to a folder outside, which holds task files."""
        path = self.folder / self.rng.choice(["tasks", "sub/tasks"])
        if path.exists() or path.is_symlink():
            return
        path.parent.mkdir(parents=True, exist_ok=True)
        os.symlink(self.outside, path)
        self.count("link to a folder of task files outside")

    def add_special(self):
        kind = self.rng.choice(["fifo", "fifo archive", "socket"])
        task = self.rng.choice(TASKS)
        path = self.folder / (TASK_FILE[task] if kind != "fifo archive" else "handin.zip")
        if path.exists() or path.is_symlink():
            return
        self.count(kind)
        if kind == "socket":
            with socket.socket(socket.AF_UNIX) as server:
                server.bind(str(path))
        else:
            os.mkfifo(path)
        if kind != "fifo archive":
            self.reasons[task].add(building.SPECIAL)

    def add_odd_file(self):
        name = self.rng.choice(["notes\n.txt", "\udcff\udcfe.bin", "-rf", " ", "a" * 255, "propagate.cpp.orig",
                                "PROPAGATE.CPP", "propagate.cpp ", "..propagate.cpp", "._propagate.cpp"])
        path = self.folder / name
        if not path.exists():
            path.write_bytes(self.rng.randbytes(100))
            self.count("odd name")

    # --- archives ------------------------------------------------------------------------------

    def archive_entries(self):
        """[(name, kind, data)] for an archive: kind is file, dir, link, huge or special."""
        entries = []
        for _ in range(self.rng.randrange(1, 8)):
            task = self.rng.choice(TASKS)
            prefix = self.rng.choice(["", "tasks/", "handin/tasks/", "../", "../../", "/", "./", "tasks\\",
                                      ".git/", "__MACOSX/", "._", "x\ny/", "ü/"])
            name = f"{prefix}{TASK_FILE[task]}"
            kind = self.rng.choice(["file"] * 6 + ["dir", "link", "huge", "special", "other"])
            if kind == "other":
                name = self.rng.choice(["README.md", "../../etc/cron.d/evil", "/tmp/evil", "a" * 300])
            entries.append((name, kind, self.content(task) if kind == "file" else b"/etc/passwd"))
        return entries

    def expect_entry(self, name, kind, data, intact):
        parts = [part for part in name.replace("\\", "/").split("/") if part]
        ignored = any(part.startswith(("__MACOSX", "._")) for part in parts)
        task = next((task for task in TASKS if parts and parts[-1] == TASK_FILE[task]), None)
        self.count(f"archive entry: {kind}")
        if task is None or ignored:
            return
        if kind == "file":
            self.allowed[task].add(data)
            if intact:
                self.must_find.add(task)
        elif intact:
            self.reasons[task].add({"dir": building.FOLDER, "link": building.LINK, "huge": building.TOO_LARGE,
                                    "special": building.SPECIAL}[kind])

    def add_zip(self):
        entries = self.archive_entries()
        buffer = io.BytesIO()
        with zipfile.ZipFile(buffer, "w", zipfile.ZIP_DEFLATED) as archive:
            for name, kind, data in entries:
                if kind == "special":
                    kind = "file"  # a zip has no FIFOs: an ordinary entry
                info = zipfile.ZipInfo(name.rstrip("/") + ("/" if kind == "dir" else ""))
                info.compress_type = zipfile.ZIP_DEFLATED
                if kind == "link":
                    info.create_system = 3
                    info.external_attr = (stat.S_IFLNK | 0o777) << 16
                if kind == "huge":
                    data = bytes(CAP + self.rng.choice([1, 20 * CAP]))  # zeros: a small bomb
                archive.writestr(info, b"" if kind == "dir" else data)
        data, intact = self.maybe_damage(buffer.getvalue())
        for name, kind, content in entries:
            self.expect_entry(name, "file" if kind == "special" else kind, content, intact)
        self.write_archive(data, ".zip")

    def add_tar(self):
        entries = self.archive_entries()
        compression = self.rng.choice(["", "gz", "bz2", "xz"])
        buffer = io.BytesIO()
        with tarfile.open(fileobj=buffer, mode=f"w:{compression}") as archive:
            for name, kind, data in entries:
                info = tarfile.TarInfo(name)
                if kind == "dir":
                    info.type = tarfile.DIRTYPE
                elif kind == "link":
                    info.type = self.rng.choice([tarfile.SYMTYPE, tarfile.LNKTYPE])
                    info.linkname = "/etc/passwd"
                elif kind == "special":
                    info.type = self.rng.choice([tarfile.FIFOTYPE, tarfile.CHRTYPE, tarfile.BLKTYPE])
                if kind == "huge":
                    data = bytes(CAP + 1)
                if info.type == tarfile.REGTYPE:
                    info.size = len(data)
                    archive.addfile(info, io.BytesIO(data))
                else:
                    archive.addfile(info)
        data, intact = self.maybe_damage(buffer.getvalue())
        for name, kind, content in entries:
            self.expect_entry(name, kind, content, intact)
        self.write_archive(data, self.rng.choice([".tar", ".tgz", ".zip", ""]))

    def maybe_damage(self, data):
        """The archive's bytes, cut short or with flipped bytes now and then; and whether intact."""
        roll = self.rng.random()
        if roll < 0.1:
            self.count("archive cut short")
            return data[:self.rng.randrange(1, len(data))], False
        if roll < 0.2 and data.startswith(b"PK"):  # a tar has no checksum of its content: zip only
            self.count("archive with flipped bytes")
            damaged = bytearray(data)
            for _ in range(5):
                damaged[self.rng.randrange(len(damaged))] ^= 0xFF
            return bytes(damaged), False
        return data, True

    def write_archive(self, data, suffix):
        where, _ = self.folder_name()
        if where.startswith((".", "__MACOSX")) or "d/d/d/d/d/d/d/d/d/d/d/d/d/d/d/d/d/d/d/d/d" in where:
            where = ""
        self.serial += 1
        path = self.folder / where / f"upload-{self.serial}{suffix}"
        if path.parent.is_symlink() or path.parent.is_file():
            path = self.folder / f"upload-{self.serial}{suffix}"
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_bytes(data)

    def build(self):
        warnings.filterwarnings("ignore", "Duplicate name", UserWarning)  # duplicates are on purpose
        makers = [self.add_file, self.add_file, self.add_folder, self.add_link, self.add_folder_link,
                  self.add_special, self.add_odd_file, self.add_zip, self.add_tar]
        for _ in range(self.rng.randrange(1, 9)):
            try:
                self.rng.choice(makers)()
            except (FileExistsError, NotADirectoryError):
                pass  # the place is taken by an earlier entry: nothing was added


def outside_folder(base):
    """Files outside the upload that links point to: all hold SECRET."""
    outside = base / "outside"
    outside.mkdir()
    (outside / "secret.cpp").write_bytes(SECRET + b"\n")
    for task in TASKS:
        (outside / TASK_FILE[task]).write_bytes(SECRET + f" {task}\n".encode())
    return outside


class FindTaskFiles(unittest.TestCase):
    def check_case(self, upload, places, base):
        """Looks through one upload; checks what was graded and what the student is told."""
        destination = base / "found"
        before = files_under(base)
        started = time.monotonic()
        found, notes = package.find_task_files(places, destination)
        seconds = time.monotonic() - started
        self.assertLess(seconds, CASE_SECONDS)
        self.assertEqual(files_under(base), sorted(before + ["found"] + [f"found/{TASK_FILE[t]}" for t in TASKS]),
                         "nothing is written outside the destination")
        for line in notes:
            self.assertNotIn("\n", line)
            line.encode("utf-8")  # printable: no undecodable bytes left in names
        report = "\n".join(notes)
        for task in TASKS:
            graded = destination / TASK_FILE[task]
            self.assertTrue(stat.S_ISREG(graded.lstat().st_mode))
            data = graded.read_bytes()
            self.assertNotIn(SECRET, data, f"{task}: read through a link out of the upload\n{report}")
            self.assertLessEqual(len(data), CAP)
            if task in found:
                self.assertIn(data, upload.allowed[task], f"{task}: graded something that was not uploaded\n{report}")
            else:
                self.assertEqual(data, stub(task))
                stubbed = "graded as not implemented (0 points)"
                self.assertTrue(any(line.startswith(f"  {TASK_FILE[task]}: ") and line.endswith(stubbed) for line in notes),
                                report)
            if task in upload.must_find:
                self.assertIn(task, found, f"{task}: an ordinary file was uploaded but not found\n{report}")
            for reason in upload.reasons[task]:
                self.assertTrue(any(line.strip().startswith("not graded:") and TASK_FILE[task] in line and reason in line
                                    for line in notes), f"{task}: the notes must say '{reason}'\n{report}")
        return seconds

    def test_fuzzed_uploads_are_handled(self):
        rng = random.Random(1)
        cases, slowest, kinds = 400, 0.0, {}
        for case in range(cases):
            base = Path(tempfile.mkdtemp(prefix="upload-"))
            try:
                outside = outside_folder(base)
                folder = base / "submission"
                folder.mkdir()
                (folder / "elsewhere.txt").write_text("a file inside the upload\n")
                upload = Upload(rng, folder, outside)
                upload.build()
                # Gradescope looks through the submission folder; Autolab through the files in
                # the job's folder.
                places = [folder] if case % 4 else sorted(folder.iterdir())
                with self.subTest(case=case):
                    slowest = max(slowest, self.check_case(upload, places, base))
                for kind, count in upload.kinds.items():
                    kinds[kind] = kinds.get(kind, 0) + count
            finally:
                shutil.rmtree(base, ignore_errors=True)
        print(f"find_task_files: {cases} fuzzed uploads, {sum(kinds.values())} entries, all handled "
              f"(slowest {slowest:.2f} s):", flush=True)
        for kind in sorted(kinds):
            print(f"  {kinds[kind]:5d}  {kind}")
        self.assertGreaterEqual(len(kinds), 30, "the fuzzing covers every kind of entry")

    def test_archive_bombs_are_cut_short(self):
        # A .tar.gz that unpacks to more than the grader looks through, and a .zip with more
        # entries than it looks at: both end in bounded time, with a note.
        base = Path(tempfile.mkdtemp(prefix="upload-"))
        try:
            folder = base / "submission"
            folder.mkdir()
            with tarfile.open(folder / "bomb.tar.gz", "w:gz", compresslevel=1) as archive:
                info = tarfile.TarInfo("zeros.bin")
                info.size = package.ARCHIVE_SCAN_CAP + (1 << 20)

                class Zeros(io.RawIOBase):
                    def readable(self):
                        return True

                    def readinto(self, buffer):
                        buffer[:] = bytes(len(buffer))
                        return len(buffer)
                archive.addfile(info, io.BufferedReader(Zeros()))
                propagate = tarfile.TarInfo("tasks/propagate.cpp")  # after the bomb: never reached
                propagate.size = 3
                archive.addfile(propagate, io.BytesIO(b"// \n"))
            with zipfile.ZipFile(folder / "many.zip", "w") as archive:
                for index in range(package.ARCHIVE_MEMBER_CAP + 10):
                    archive.writestr(f"f{index}.txt", b"")
            started = time.monotonic()
            found, notes = package.find_task_files([folder], base / "found")
            seconds = time.monotonic() - started
        finally:
            shutil.rmtree(base)
        print(f"archive bombs: {package.ARCHIVE_SCAN_CAP >> 20} MB of zeros and {package.ARCHIVE_MEMBER_CAP + 10} "
              f"entries looked through in {seconds:.1f} s", flush=True)
        self.assertLess(seconds, 60)
        self.assertEqual(found, {})
        self.assertEqual(sum("too many files" in line for line in notes), 2, notes)


class StageSubmission(unittest.TestCase):
    """grade.py's own reading of a submission folder (./build.sh grade, and any grader that
    calls grade.py directly)."""

    KINDS = ["text", "empty", "binary", "cap", "over cap", "huge", "missing", "folder", "folder with the file",
             "fifo", "socket", "link to a secret file", "link to /etc/passwd", "link to a folder", "dangling link",
             "link loop", "link to /dev/zero", "link to /dev/stdin", "link to /dev/urandom", "link to a file inside"]

    def make(self, rng, folder, outside, task, kind):
        """Puts a task file of this kind into the folder; returns the content to grade, or the
        reason it cannot be graded (None: missing)."""
        path = folder / TASK_FILE[task]
        links = {"link to a secret file": outside / "secret.cpp", "link to /etc/passwd": "/etc/passwd",
                 "link to a folder": outside, "dangling link": outside / "nothing", "link loop": path,
                 "link to /dev/zero": "/dev/zero", "link to /dev/stdin": "/dev/stdin",
                 "link to /dev/urandom": "/dev/urandom", "link to a file inside": folder / "inside.txt"}
        if kind in links:
            os.symlink(links[kind], path)
            return building.LINK
        if kind == "missing":
            return None
        if kind.startswith("folder"):
            path.mkdir()
            if kind == "folder with the file":
                (path / TASK_FILE[task]).write_bytes(solution(task))
            return building.FOLDER
        if kind == "fifo":
            os.mkfifo(path)
            return building.SPECIAL
        if kind == "socket":
            with socket.socket(socket.AF_UNIX) as server:
                server.bind(str(path))
            return building.SPECIAL
        if kind in {"cap", "over cap", "huge"}:
            with open(path, "wb") as file:
                file.write(b"// sized\n")
                file.truncate({"cap": CAP, "over cap": CAP + 1, "huge": 50 * CAP}[kind])
            return path.read_bytes() if kind == "cap" else building.TOO_LARGE
        data = {"text": f"// {task} {rng.random()}\n".encode(), "empty": b"", "binary": rng.randbytes(3000)}[kind]
        path.write_bytes(data)
        return data

    def test_fuzzed_submission_folders_are_read_safely(self):
        rng = random.Random(2)
        base = Path(tempfile.mkdtemp(prefix="stage-"))
        grading = base / "grading"  # one grading folder for every case, as a reused build has
        cases, seen, slowest = 200, set(), 0.0
        try:
            outside = outside_folder(base)
            for case in range(cases):
                folder = base / f"case-{case}"
                folder.mkdir()
                (folder / "inside.txt").write_text("inside\n")
                expected = {}
                for task in TASKS:
                    kind = rng.choice(self.KINDS)
                    seen.add(kind)
                    expected[task] = self.make(rng, folder, outside, task, kind)
                started = time.monotonic()
                with endless_stdin():
                    staged, problems = building.stage_submission(folder, grading)
                slowest = max(slowest, time.monotonic() - started)
                for task in TASKS:
                    target = staged / TASK_FILE[task]
                    if isinstance(expected[task], bytes):
                        self.assertEqual(target.read_bytes(), expected[task], f"case {case}: {task}")
                        self.assertNotIn(task, problems)
                    else:
                        self.assertFalse(target.exists(), f"case {case}: {task} must not be staged")
                        if expected[task] is None:
                            self.assertNotIn(task, problems)
                        else:
                            self.assertIn(expected[task], problems[task], f"case {case}: {task}")
                            self.assertIn("0 points", problems[task])
                    if target.exists():
                        self.assertNotIn(SECRET, target.read_bytes())
                shutil.rmtree(folder)
        finally:
            shutil.rmtree(base)
        print(f"stage_submission: {cases} fuzzed submission folders ({cases * len(TASKS)} task files of "
              f"{len(seen)} kinds), all handled (slowest {slowest:.2f} s)", flush=True)
        self.assertLess(slowest, CASE_SECONDS)
        self.assertEqual(seen, set(self.KINDS))


class EndToEnd(unittest.TestCase):
    """Hostile uploads graded for real, with the platforms' time limits, in the build folder of
    test_grader.py; standard input never ends."""

    def gradescope(self, files):
        """Grades an upload as run_autograder does, in a fake /autograder folder: files is
        {relative path: bytes, or a callable that makes the entry at the path}. Returns
        (scores, results.json, output, seconds after the grader's own build)."""
        root = Path(tempfile.mkdtemp(prefix="autograder-"))
        try:
            submission = root / "submission"
            for relative, content in files.items():
                path = submission / relative
                path.parent.mkdir(parents=True, exist_ok=True)
                if callable(content):
                    content(path)
                else:
                    path.write_bytes(content)
            output = io.StringIO()
            started = time.monotonic()
            with endless_stdin(), contextlib.redirect_stdout(output):
                package.gradescope_run(root, ["--build", str(BUILD)])
            elapsed = time.monotonic() - started
            print(output.getvalue()[-4000:], flush=True)
            report = json.loads((root / "results" / "results.json").read_text())
        finally:
            shutil.rmtree(root)
        text = output.getvalue()
        self.assertLess(elapsed - test_grader.own_build_seconds(text), package.PLATFORM_TOTAL)
        return test_packages.scores_of(report), report, text

    def builds_message(self, report, task):
        return next(test["output"] for test in report["tests"] if test["name"].startswith(task + ":"))

    def check_scores(self, scores, full, report):
        maxima = {task: sum(test["max_score"] for test in report["tests"] if test["name"].startswith(task + ":"))
                  for task in TASKS}
        self.assertEqual(scores, {task: maxima[task] if task in full else 0 for task in TASKS})
        self.assertEqual(report["score"], sum(scores.values()))

    def test_devices_links_folders_and_junk(self):
        junk = random.Random(3).randbytes(4000)

        def bomb_zip(path):
            with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as archive:
                archive.writestr("../../init_billiard.cpp", b"not the graded one: tasks/ wins\n")
                archive.writestr("movie.cpp", bytes(30 * CAP))  # too large to grade
        files = {
            "billiard/tasks/init_billiard.cpp": solution("init_billiard"),
            "extra.zip": bomb_zip,
            "init_velocities.cpp": lambda path: os.symlink("/etc/passwd", path),
            "tasks/init_velocities.cpp": solution("init_velocities"),
            "visualize_table.cpp": junk,
            "propagate.cpp": b'#include "/dev/stdin"\n',
            "movie.cpp": lambda path: path.mkdir(),
            "kinetic_energy.cpp": b'#include "/dev/zero"\n',
        }
        scores, report, output = self.gradescope(files)
        self.check_scores(scores, {"init_billiard", "init_velocities"}, report)
        for note in ["init_velocities.cpp is a symbolic link", "movie.cpp is a folder", "movie.cpp is larger than"]:
            self.assertIn(note, report["output"])
        self.assertIn("does not compile", self.builds_message(report, "visualize_table"))
        self.assertIn("does not compile", self.builds_message(report, "kinetic_energy"))
        self.assertIn("Does it define propagate", self.builds_message(report, "propagate"))
        self.assertIn("not implemented", self.builds_message(report, "movie"))

    def test_archives_odd_names_and_the_assembler(self):
        reference_lines = [line.strip() for line in solution("movie").decode().splitlines() if len(line.strip()) > 30]
        leak = (f'#include <cstdio>\n#include <stdexcept>\n#include "billiard/course.hpp"\n'
                f'asm(".section .rodata\\n.global leaked\\nleaked:\\n.incbin \\"{REPO}/solutions/movie.cpp\\"\\n'
                f'.byte 0\\n.previous");\nextern "C" const char leaked[];\nnamespace billiard {{\n'
                f'void movie(double, double, int, Coordinates&, Velocities&, int, const std::filesystem::path&) {{\n'
                f'  std::puts(leaked);\n  throw std::runtime_error(leaked);\n}}\n}}\n').encode()

        def tar_gz(path):
            with tarfile.open(path, "w:gz") as archive:
                for name, data in [("tasks/init_billiard.cpp", b""),
                                   ("tasks/visualize_table.cpp", solution("visualize_table")),
                                   ("tasks/kinetic_energy.cpp", b'#include "/dev/urandom"\n'),
                                   ("tasks/movie.cpp", leak)]:
                    info = tarfile.TarInfo(name)
                    info.size = len(data)
                    archive.addfile(info, io.BytesIO(data))
                link = tarfile.TarInfo("visualize_table.cpp")
                link.type, link.linkname = tarfile.SYMTYPE, "/etc/passwd"
                archive.addfile(link)

        def windows_zip(path):
            with zipfile.ZipFile(path, "w") as archive:
                archive.writestr("tasks\\propagate.cpp", solution("propagate"))
        files = {"handin.tar.gz": tar_gz, "windows.zip": windows_zip,
                 "new\nline \udcff/init_velocities.cpp": solution("init_velocities")}
        scores, report, output = self.gradescope(files)
        self.check_scores(scores, {"init_velocities", "visualize_table", "propagate"}, report)
        self.assertIn("visualize_table.cpp is a symbolic link", report["output"])
        self.assertIn("new\\nline \\udcff/init_velocities.cpp", report["output"])
        self.assertIn("Does it define init_billiard", self.builds_message(report, "init_billiard"))
        if os.geteuid() == 0:  # the reference solutions are protected only where the tests run as another user
            self.assertIn("does not compile", self.builds_message(report, "movie"))
            text = json.dumps(report)
            self.assertEqual([line for line in reference_lines if json.dumps(line)[1:-1] in text], [],
                             "the reference solution leaked")

    def test_grade_py_reads_no_links_folders_or_fifos(self):
        submission = test_grader.submission_from_solutions()
        try:
            for task in ["init_billiard", "init_velocities", "visualize_table", "propagate"]:
                (submission / TASK_FILE[task]).unlink()
            os.symlink(REPO / "solutions" / "init_billiard.cpp", submission / "init_billiard.cpp")
            (submission / "init_velocities.cpp").mkdir()
            (submission / "init_velocities.cpp" / "init_velocities.cpp").write_bytes(solution("init_velocities"))
            (submission / "visualize_table.cpp").write_bytes(solution("visualize_table") + b"\n" * (CAP + 1))
            os.mkfifo(submission / "propagate.cpp")
            started = time.monotonic()
            with endless_stdin():
                scores, maxima, report, _, output = test_grader.grade(submission, *package.PLATFORM_GRADE_OPTIONS)
            elapsed = time.monotonic() - started
        finally:
            shutil.rmtree(submission)
        self.assertLess(elapsed - test_grader.own_build_seconds(output), package.PLATFORM_TOTAL)
        unreadable = {"init_billiard", "init_velocities", "visualize_table", "propagate"}
        self.check_scores(scores, set(TASKS) - unreadable, report)
        for task, reason in [("init_billiard", building.LINK), ("init_velocities", building.FOLDER),
                             ("visualize_table", building.TOO_LARGE), ("propagate", building.SPECIAL)]:
            self.assertIn(reason, self.builds_message(report, task))


if __name__ == "__main__":
    if len(sys.argv) < 2:
        print(__doc__)
        sys.exit(2)
    BUILD = Path(sys.argv.pop(1)).resolve()
    test_grader.BUILD = BUILD
    unittest.main(verbosity=2)
