#!/usr/bin/python3
"""Grades a whole class: every student's task files, graded exactly as the grading platforms
grade one submission, on Dask worker processes, resumable, with a report for the instructor.

    ./build.sh grade --class DIR [--results DIR] [--workers N] [--client tcp://HOST:8786] [--task T]

DIR (a folder, or a .zip or .tar of one) holds the class in one of these layouts, recognised in
this order:

  gradescope  Gradescope's "Export Submissions" download (the assignment's Review Grades page):
              a `submission_metadata.yml` next to one folder per submission, `submission_<id>/`.
              The YAML maps each folder's name to its submission, whose `:submitters` list holds
              each student's `:name`, `:email` and `:sid` (Ruby-style keys, with the colon). A
              submission is named after its submitters' names (else their e-mail, else the folder).
  autolab     Autolab's download of all handins: files named `<email>_<version>_<handin file>`,
              or a folder per e-mail address holding `<version>_<handin file>` (its handin
              folder's layout). A student's highest version is graded.
  classroom   GitHub Classroom's `gh classroom clone student-repos`: one git repository per
              student, `<assignment>-<github user>/`, all with the assignment's prefix; the
              student is the part after it.
  folders     anything else: one entry per student, a folder or an archive, named after them.

Each student's task files are found the way the platforms' packages find them (package.py's
find_task_files: at any depth, inside archives, a folder named `tasks` first). Each student is
graded by tests/grader/grade.py with the platforms' options (the reference code for the other
tasks, time limits from the reference solutions, the tests as an unprivileged user when run as
root), so a hostile or endless submission costs that student only. Each Dask worker grades in a
build folder of its own, built once: by default the workers are local processes (--workers,
default the cores this process may use); --client grades on a Dask cluster whose workers have a
copy of this repository at the same path (or --worker-repo).

Nothing is lost and nothing is done twice: a student's results are written as soon as they are
graded, task by task, with a key made of the task file's content and the task's suite (its
tests, the support code, the reference code of the other tasks, the grader). Running the same
command again grades only the tasks whose key changed, so an interrupted run is resumed by
running it again, and after a fix to one task's tests only that task is regraded. With --task,
only those tasks are graded (the others keep what earlier runs gave, or stay empty).

Written to --results (default build/grade/class/): students/<student>/ with the platforms'
results.json and junit.xml, report.html and the pictures of the failing cases (what the student
may see: hidden tests without name or message) and the grader's log; then what class_report.py
writes for the instructor: gradebook.csv, mistakes.csv, tests.csv, similarity.csv (the copies,
from similarity.py) and report.html.
"""

import collections
import concurrent.futures
import contextlib
import fcntl
import hashlib
import io
import json
import os
import re
import shutil
import signal
import socket
import stat
import subprocess
import sys
import tarfile
import time
import zipfile
from dataclasses import dataclass, field
from pathlib import Path

import building
import class_report
import grade
import package
import reports
import similarity
from course import TASK_FILE, TASKS

REPO = building.REPO
DEFAULT_RESULTS = REPO / "build" / "grade" / "class"
MAXIMA_ROW = class_report.MAXIMA_ROW
# Seconds one student's grading may take before it counts as failed (and is tried again on the
# next run): the platforms' bound, plus a worker's first build of the grader.
STUDENT_CUTOFF = package.AUTOLAB_CUTOFF
LAYOUTS = ("gradescope", "autolab", "classroom", "folders")
AUTOLAB_FILE = re.compile(r"^(?P<email>[^/]+@[^_/@]+)_(?P<version>\d+)_(?P<name>.+)$")  # a domain has no _
AUTOLAB_VERSIONED = re.compile(r"^(?P<version>\d+)_(?P<name>.+)$")


@dataclass
class Student:
    name: str              # as the gradebook shows it (two students may share one)
    places: list           # the files and folders that hold their task files
    folder: str = ""       # their folder under students/: the name made safe, unique; the key of
                           # their results everywhere
    ids: dict = field(default_factory=dict)     # what the platform's export identifies them by
    files: dict = field(default_factory=dict)   # task -> bytes of the file graded (the stub if none)
    notes: list = field(default_factory=list)   # what find_task_files says about their files


# --- Reading the class --------------------------------------------------------------------------

def unpack(archive, destination):
    """Unpacks a .zip or .tar of a class into destination: regular files only, paths inside it,
    at most package.ARCHIVE_MEMBER_CAP entries and package.ARCHIVE_SCAN_CAP bytes."""
    total = 0

    def target(name):
        parts = [part for part in re.split(r"[/\\]", name) if part not in ("", ".", "..")]
        return destination.joinpath(*parts) if parts else None

    def write(name, read, size):
        nonlocal total
        total += size
        path = target(name)
        if path is None or total > package.ARCHIVE_SCAN_CAP:
            return
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_bytes(read())

    if zipfile.is_zipfile(archive):
        with zipfile.ZipFile(archive) as members:
            for info in members.infolist()[:package.ARCHIVE_MEMBER_CAP]:
                if not info.is_dir() and not stat.S_ISLNK(info.external_attr >> 16):
                    write(info.filename, lambda info=info: members.read(info), info.file_size)
    elif tarfile.is_tarfile(archive):
        with tarfile.open(archive) as members:
            for count, member in enumerate(members):
                if count >= package.ARCHIVE_MEMBER_CAP:
                    break
                if member.isfile():
                    write(member.name, lambda member=member: members.extractfile(member).read(), member.size)
    else:
        raise ValueError(f"{archive} is neither a folder nor a .zip or .tar archive")
    return destination


def class_folder(path, work):
    """The folder that holds the class: path itself, or its unpacked copy if it is an archive;
    then the one folder inside where that is all an archive holds, or where it holds a
    Gradescope export's metadata (an export's own top folder)."""
    unpacked = path.is_file()
    if unpacked:
        path = unpack(path, work / "unpacked")
    entries = [entry for entry in path.iterdir() if not entry.name.startswith((".", "__MACOSX"))]
    if len(entries) == 1 and entries[0].is_dir() and (unpacked or (entries[0] / "submission_metadata.yml").is_file()):
        return entries[0]
    return path


def is_archive(path):
    return path.is_file() and (zipfile.is_zipfile(path) or tarfile.is_tarfile(path))


def read_class(path, work):
    """(layout, [Student]) of the class in path (a folder or an archive)."""
    folder = class_folder(path, work)
    entries = sorted(entry for entry in folder.iterdir() if not entry.name.startswith((".", "__MACOSX")))
    if (folder / "submission_metadata.yml").is_file():
        return "gradescope", gradescope_students(folder)
    if entries and all(AUTOLAB_FILE.match(entry.name) or (entry.is_dir() and "@" in entry.name)
                       for entry in entries):
        return "autolab", autolab_students(entries)
    repositories = [entry for entry in entries if entry.is_dir() and (entry / ".git").exists()]
    prefix = os.path.commonprefix([entry.name for entry in repositories])
    prefix = prefix[:prefix.rfind("-") + 1]
    if len(repositories) >= 2 and repositories == entries and prefix:
        return "classroom", [Student(entry.name[len(prefix):], [entry], ids={"repository": entry.name})
                             for entry in entries]
    return "folders", [Student(re.sub(r"(\.tar\.gz|\.tgz|\.tar|\.zip)$", "", entry.name), [entry])
                       for entry in entries if entry.is_dir() or is_archive(entry)]


def gradescope_students(folder):
    import yaml  # Debian's python3-yaml, as build.sh installs it
    metadata = yaml.safe_load((folder / "submission_metadata.yml").read_text()) or {}
    students = []
    for name in sorted(metadata, key=str):
        if "/" in str(name) or str(name).startswith("."):
            continue  # only the export's own folders
        submission = folder / str(name)
        if not submission.is_dir():
            continue
        entry = metadata[name] if isinstance(metadata[name], dict) else {}
        submitters = entry.get(":submitters") or entry.get("submitters") or []
        people = [person for person in submitters if isinstance(person, dict)]

        def each(field_name):
            return "; ".join(str(value) for person in people
                             if (value := person.get(f":{field_name}") or person.get(field_name)))
        named = [str(person.get(":name") or person.get("name") or person.get(":email") or person.get(":sid") or "")
                 for person in people]
        students.append(Student(", ".join(n for n in named if n) or str(name), [submission],
                                ids={"submission": str(name), "sid": each("sid"), "email": each("email")}))
    return students


def autolab_students(entries):
    latest = {}  # email -> (version, [places])
    for entry in entries:
        match = AUTOLAB_FILE.match(entry.name)
        if match:
            email, version, places = match["email"], int(match["version"]), [entry]
        else:  # a handin folder: <email>/<version>_<handin file>
            versions = [(int(m["version"]), item) for item in entry.iterdir()
                        if (m := AUTOLAB_VERSIONED.match(item.name)) and "autograde" not in m["name"]]
            if not versions:
                continue
            version = max(v for v, _ in versions)
            email, places = entry.name, [item for v, item in versions if v == version]
        if email not in latest or version > latest[email][0]:
            latest[email] = (version, places)
    return [Student(email, places, ids={"email": email}) for email, (_, places) in sorted(latest.items())]


def safe_folders(students):
    """Gives each student a folder name of safe characters, unique in the class."""
    taken = set()
    for student in students:
        base = re.sub(r"[^A-Za-z0-9._@+-]+", "_", student.name).strip("._") or "student"
        name, count = base[:80], 1
        while name.lower() in taken:
            count += 1
            name = f"{base[:76]}-{count}"
        taken.add(name.lower())
        student.folder = name


def find_files(student, work):
    """The student's task files as the platforms find them (the stub where one is missing)."""
    staged = work / "staged" / student.folder
    shutil.rmtree(staged, ignore_errors=True)
    with contextlib.redirect_stdout(io.StringIO()):  # its notes are kept, not printed
        _, student.notes = package.find_task_files(student.places, staged)
    student.files = {task: (staged / TASK_FILE[task]).read_bytes() for task in TASKS}
    shutil.rmtree(staged, ignore_errors=True)


# --- What changed: a key per student and task -------------------------------------------------------

def suite_fingerprints():
    """{task: hash of everything its grading depends on but the student's file}: the suite's own
    tests and support code, the course's library, the reference code of the other tasks, the
    grader and the build files. A change to one task's tests changes that task's alone."""
    shared = hashlib.sha256()
    common = ["CMakeLists.txt", "CMakePresets.json", "tests/CMakeLists.txt", "tests/grader/CMakeLists.txt",
              "tests/grader/course.txt", "tests/grader/grade.py", "tests/grader/building.py", "tests/grader/cell.py",
              "tests/grader/judging.py", "tests/grader/reports.py", "tests/grader/time_limits.py",
              "tests/grader/progress.py", "tests/grader/not_implemented.cpp", "tests/grader/not_implemented.c"]
    paths = [REPO / path for path in common]
    for folder in ["lib/include", "lib/src", "tests/support", "tests/grader/cell", "tests/grader/judge", "tasks"]:
        paths += sorted(path for path in (REPO / folder).rglob("*") if path.is_file())
    for path in paths:
        if path.is_file() and not path.name.endswith(".md"):
            shared.update(str(path.relative_to(REPO)).encode() + b"\0" + path.read_bytes())
    prints = {}
    for task in TASKS:
        digest = shared.copy()
        own = [REPO / "tests" / "graded" / f"test_{task}.cpp", REPO / "tests" / "graded" / "hidden" / f"test_{task}.cpp",
               REPO / "tests" / "graded" / f"{task}_support.hpp"]
        others = sorted(path for path in (REPO / "solutions").rglob("*")
                        if path.is_file() and path.name != TASK_FILE[task])
        for path in own + others + sorted((REPO / "tests" / "graded").glob("*_support.hpp")):
            if path.is_file():
                digest.update(str(path.relative_to(REPO)).encode() + b"\0" + path.read_bytes())
        prints[task] = digest.hexdigest()
    return prints


def task_key(student, task, fingerprints):
    return hashlib.sha256(fingerprints[task].encode() + b"\0" + student.files[task]).hexdigest()


# --- Grading one student, on a worker --------------------------------------------------------------

def grade_on_worker(repo, files, options, cutoff):
    """Runs on a Dask worker: grades one student's task files ({file name: bytes}) with
    grade.py and the given options, in this worker's build folder, and returns (records,
    seconds, log, pictures: {file name: bytes} of the failing cases drawn); with files None, only
    builds the grader there (grade.py --prepare: records and pictures empty). It uses the standard
    library only, so that a worker needs nothing of this file but the repository."""
    repo = Path(repo)
    try:
        from distributed import get_worker
        worker = str(get_worker().name)
    except (ImportError, ValueError):
        worker = str(os.getpid())
    # One build of the grader per machine, made by the preparing step and shared by the machine's
    # workers (grade.py --prebuilt: it never builds there while a grading uses it); a folder of its
    # own per worker for the rest.
    machine = repo / "build" / "grade" / "workers" / re.sub(r"[^A-Za-z0-9._-]", "_", socket.gethostname())
    here = machine.with_name(f"{machine.name}-{re.sub(r'[^A-Za-z0-9._-]', '_', worker)}")
    here.mkdir(parents=True, exist_ok=True)
    with open(here / "lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)  # one grading at a time in a build folder
        submission = here / "submission"
        shutil.rmtree(submission, ignore_errors=True)
        submission.mkdir()
        for name, text in (files or {}).items():
            (submission / name).write_bytes(text)
        records = here / "records.json"
        records.unlink(missing_ok=True)
        command = [sys.executable, str(repo / "tests" / "grader" / "grade.py"), "--submission", str(submission),
                   "--results", str(here / "results"), "--build", str(machine / "build"), "--work", str(here),
                   "--prebuilt", "--records", str(records),
                   *options, *(["--prepare"] if files is None else [])]
        if os.geteuid() == 0:
            command.append("--protect-reference")
        processor = own_processor(machine) if files is not None else None  # a build takes every processor
        if processor:  # a grading with one job keeps its tests on one processor: each worker its own
            command = ["taskset", "--cpu-list", str(processor[0]), *command]
        started = time.monotonic()
        try:
            # grade.py holds the lock too: if this worker is killed, a grading it started goes on
            # and the worker that Dask starts in its place waits for it, never sharing the folder.
            done = subprocess.run(command, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                  text=True, errors="replace", timeout=cutoff, pass_fds=(lock.fileno(),))
            log, status = done.stdout, done.returncode
        except subprocess.TimeoutExpired as expired:
            log, status = str(expired.stdout or ""), None
        seconds = time.monotonic() - started
        if processor:
            processor[1].close()
        if files is None and status == 0:
            return [], seconds, log, {}
        if status != 0 or not records.is_file():
            why = "did not finish" if status is None else f"exited with status {status}"
            raise RuntimeError(f"grade.py {why} on {socket.gethostname()}:\n{log[-3000:]}")
        drawn = here / "results" / "pictures"  # grade.py's PICTURES, replaced by each grading
        pictures = {path.name: path.read_bytes() for path in drawn.glob("*.svg")} if drawn.is_dir() else {}
        return json.loads(records.read_text()), seconds, log, pictures


def own_processor(machine):
    """(a processor no other grading on this machine holds, the open lock that holds it), or None
    when every one is taken. A grading with one job runs its tests on the first processor it may
    use; without this, every worker's would be the same one."""
    for processor in sorted(os.sched_getaffinity(0)):
        lock = open(machine.with_name(f"{machine.name}.processor-{processor}.lock"), "w")
        try:
            fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
            return processor, lock
        except OSError:
            lock.close()
    return None


def grading_options(tasks, jobs=None):
    """grade.py's options for one student of the class: the platforms' grading, for the given
    tasks; `jobs` tests at once (a worker takes one core: the class runs on many)."""
    return ["--dependencies", "reference", "--audience", "grader", "--brief", *package.PLATFORM_GRADE_OPTIONS,
            *[word for task in tasks for word in ("--task", task)], *(["--jobs", str(jobs)] if jobs else [])]


# --- The class ------------------------------------------------------------------------------------

class ClassResults:
    """The results folder: each student's task records (with their keys) and files."""

    def __init__(self, folder):
        self.folder = folder
        (folder / "students").mkdir(parents=True, exist_ok=True)

    def record_path(self, student, task):
        return self.folder / "students" / student.folder / "records" / f"{task}.json"

    def saved(self, student, task):
        """A student's saved task entry ({"key", "student", "record"}), or None: not graded yet, or
        a file that cannot be read (the task is then graded again)."""
        return self.read(student, task)[0]

    def read(self, student, task):
        """(the saved entry or None, why a saved file cannot be read or None)."""
        path = self.record_path(student, task)
        if not path.exists():
            return None, None
        try:
            entry = json.loads(path.read_text())
        except (OSError, ValueError) as error:
            return None, f"{type(error).__name__}: {str(error)[:100]}"
        if not isinstance(entry, dict) or not isinstance(entry.get("key"), str):
            return None, "it has no key"
        problem = reports.record_problem(entry.get("record"))
        if problem is None and entry["record"]["task"] != task:
            problem = f"it holds task {entry['record']['task']}"
        return (None, problem) if problem else (entry, None)

    def is_current(self, student, task, key):
        saved = self.saved(student, task)
        return saved is not None and saved.get("key") == key

    def save(self, student, records, keys, log=None, pictures=None):
        """A student's new task records with the pictures of their failing cases ({file name:
        bytes}), then their results.json, junit.xml and report.html from every task."""
        own = self.folder / "students" / student.folder
        pictures = pictures or {}
        for record in records:
            for test in record["tests"]:
                drawn = own / reports.PICTURES / f"{test['name']}.svg"  # grade.py names a test's picture so
                drawn.unlink(missing_ok=True)  # the last grading's
                if test.get("picture") and drawn.name in pictures:
                    drawn.parent.mkdir(parents=True, exist_ok=True)
                    drawn.write_bytes(pictures[drawn.name])
                    line = f"Picture: {drawn}\n"
                else:
                    test["picture"], line = "", ""
                test["feedback"] = reports.PICTURE_LINE.sub(lambda _: line, test["feedback"]).strip()
            reports.write_atomically(self.record_path(student, record["task"]),
                                   json.dumps({"key": keys[record["task"]], "student": student.name, "record": record}))
        if log is not None:
            reports.write_atomically(own / "grade.log", "\n".join(student.notes) + "\n\n" + log)
        saved = [record for task in TASKS if (record := self.saved(student, task))]
        results = reports.results_from_records([entry["record"] for entry in saved])
        reports.write_atomically(own / "results.json",
                               json.dumps(reports.gradescope_results(results, 0, own), indent=2) + "\n")
        reports.write_atomically(own / "junit.xml", reports.junit_xml(results))
        reports.write_atomically(own / "report.html", reports.submission_report(results, own, student.name))

    def pictures_of(self, student_folder, record):
        """The pictures a saved record's tests name, from the folder of the student who has them."""
        own = self.folder / "students" / student_folder
        found = {}
        for test in record["tests"]:
            if test.get("picture") and (own / test["picture"]).is_file():
                found[Path(test["picture"]).name] = (own / test["picture"]).read_bytes()
        return found

    def class_records(self, students):
        """({student's folder: {task: record}} of the tasks each student has been graded in, [a
        line for each saved record that cannot be read, left out])."""
        found, notes = {}, []
        for student in students:
            saved = {}
            for task in TASKS:
                entry, problem = self.read(student, task)
                if entry:
                    saved[task] = entry["record"]
                elif problem:
                    notes.append(f"{student.name} ({student.folder}): the saved results of {task} cannot be read "
                                 f"({problem}) and are left out; run the same command again to grade them again.")
            if saved:
                found[student.folder] = saved
        return found, notes


class LocalWorkers:
    """What the class grading asks of a Dask client, from a pool of this machine's processes: for
    a Python without Dask (its gradings are the same, grade_on_worker in a process of its own,
    each process in a build folder of its own)."""

    def __init__(self, count):
        self.pool = concurrent.futures.ProcessPoolExecutor(count, initializer=signal.signal,
                                                            initargs=(signal.SIGINT, signal.SIG_IGN))

    def scheduler_info(self):
        return {"workers": {"local": {"host": socket.gethostname()}}}

    def submit(self, function, *arguments, **_dask_options):
        return LocalFuture(self.pool.submit(function, *arguments))

    @staticmethod
    def as_completed(futures):
        by_inner = {future.inner: future for future in futures}
        return (by_inner[inner] for inner in concurrent.futures.as_completed(by_inner))

    def cancel(self, futures):
        for future in futures:
            future.inner.cancel()

    def close(self):
        self.pool.shutdown(wait=True, cancel_futures=True)


@dataclass(eq=False)
class LocalFuture:
    """A LocalWorkers' grading, as Dask's future shows it."""
    inner: concurrent.futures.Future

    @property
    def status(self):
        return "finished" if self.inner.exception() is None else "error"

    def result(self):
        return self.inner.result()

    def exception(self):
        return self.inner.exception()

    def release(self):
        pass


def start_client(arguments, pending):
    """A Dask client: of --client's cluster, or of local worker processes; without Dask, local
    processes of this machine's (LocalWorkers)."""
    workers = max(1, min(arguments.workers, pending))
    try:
        from distributed import Client
    except ImportError:
        if arguments.client:
            grade.fail("--client needs Dask: install python3-distributed (./build.sh grade --class installs it)")
        print(f"grade: Dask is not installed for {sys.executable}: grading on {workers} processes of this machine "
              "(python3-distributed grades on a cluster)", flush=True)
        return LocalWorkers(workers)
    if arguments.client:
        try:
            return Client(arguments.client, timeout=30)
        except (OSError, TimeoutError, ValueError) as error:
            grade.fail(f"--client: no Dask scheduler answers at {arguments.client} ({error}); start one with "
                       "`dask scheduler` and workers with `dask worker ADDRESS` on machines with a copy of this "
                       "repository")
    import logging
    # Ctrl-C at the terminal reaches the local workers too (one process group): they start with
    # it ignored (Python keeps an ignored SIGINT so), and this process alone stops the grading.
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        return Client(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=":0",
                      silence_logs=logging.ERROR)
    finally:
        signal.signal(signal.SIGINT, previous)


def grade_class(arguments):
    started = time.monotonic()
    results_folder = (arguments.results or DEFAULT_RESULTS).absolute()
    work = results_folder / "work"
    shutil.rmtree(work, ignore_errors=True)
    work.mkdir(parents=True)
    try:
        layout, students = read_class(arguments.class_folder.absolute(), work)
    except (OSError, ValueError) as error:
        grade.fail(f"--class {arguments.class_folder}: {error}")
    if not students:
        grade.fail(f"--class {arguments.class_folder} holds no student: give a folder with one entry per student, "
                   "a Gradescope export, an Autolab download or a folder of GitHub Classroom repositories")
    safe_folders(students)
    for student in students:
        find_files(student, work)
    tasks = arguments.task or TASKS
    fingerprints = suite_fingerprints()
    results = ClassResults(results_folder)
    # Grading is deterministic: a task file that several students hand in alike (the untouched
    # stub of a stage, a shared copy) is graded once, and its record copied to the others.
    known = {(task, saved["key"]): (saved["record"], student.folder) for student in students for task in TASKS
             if (saved := results.saved(student, task))}
    pending, copies, claimed = [], [], set()  # (student, [tasks to grade], {task: key}); (student, task, key)
    stale_students = 0
    for student in students:
        keys = {task: task_key(student, task, fingerprints) for task in TASKS}
        stale = [task for task in tasks if not results.is_current(student, task, keys[task])]
        stale_students += bool(stale)
        own = []
        for task in stale:
            if (task, keys[task]) in known or (task, keys[task]) in claimed:
                copies.append((student, task, keys))
            else:
                claimed.add((task, keys[task]))
                own.append(task)
        if own:
            pending.append((student, own, keys))
    copy_only = {student.folder for student in students if any(entry[0] is student for entry in copies)} - \
        {student.folder for student, _, _ in pending}
    print(f"grade: {len(students)} students ({layout} layout) in {arguments.class_folder}; "
          f"{len(students) - stale_students} up to date, {stale_students} to grade "
          f"({len(claimed)} different task files; {len(copy_only)} of those students hand in only files another "
          "student hands in too, each graded once)", flush=True)
    progress = ClassProgress(stale_students, results, copies, known, students, pending)
    failures, interrupted = [], False
    try:
        progress.release()  # whoever hands in only what an earlier run graded
        if pending:
            failures = run_pending(arguments, results, pending, progress)
    except Interrupted as stop:
        failures, interrupted = stop.failures, True
    # Also when interrupted: what was graded is copied to whoever handed in the same, and the
    # reports show everyone finished so far.
    failures += progress.fill_the_rest(failures)
    graded, notes = results.class_records(students)
    for note in notes:
        print(f"grade: {note}", flush=True)
    if failures:  # said at the end here, and in the report
        notes.append(f"{len(failures)} students could not be graded ({', '.join(failures[:20])}"
                     f"{', ...' if len(failures) > 20 else ''}): run the same command again to try them again; "
                     "their grade.log says why.")
    complete = sum(all(task in graded.get(student.folder, {}) for task in tasks) for student in students)
    class_report.write_reports(results_folder, students, graded, compare_files(students, tasks, graded),
                               partial=(complete, len(students)) if interrupted else None, notes=notes)
    shutil.rmtree(work, ignore_errors=True)
    if interrupted:
        print(f"\ngrade: interrupted with {complete} of {len(students)} students graded in every task; what was "
              f"graded is kept, in a partial gradebook and report in {results_folder}: run the same command again "
              "to grade the rest", flush=True)
        return 130
    print(f"grade: {time.monotonic() - started:.0f} s; gradebook {results_folder / 'gradebook.csv'}, "
          f"tests {results_folder / 'tests.csv'}, report {results_folder / 'report.html'}", flush=True)
    if failures:
        print(f"grade: {len(failures)} students could not be graded ({', '.join(failures[:5])}"
              f"{', ...' if len(failures) > 5 else ''}): run the same command again to try them again; their "
              "grade.log says why", flush=True)
        return 1
    return 0


def compare_files(students, tasks, graded):
    """The copies and near-copies among the students' files (a similarity.Comparison), the files
    that do not build (graded: {folder: {task: record}}) left out of the near-copies; what the
    finder left out is printed too."""
    stubs = {task: (REPO / "tasks" / TASK_FILE[task]).read_bytes() for task in tasks}
    unbuilt = {task: {folder for folder, records in graded.items() if task in records and records[task]["problem"]}
               for task in tasks}
    copies = similarity.compare_class({student.folder: student.files for student in students}, stubs, tasks, unbuilt)
    for note in copies.notes:
        print(f"grade: {note}", flush=True)
    return copies


class ClassProgress:
    """Saves what is graded and prints a line per student to grade, "[k/n]" counting each one:
    a student whose files are graded, with their own grading time, and a student who hands in
    only files another student hands in too, as soon as those are graded (their records are
    copied, never graded twice)."""

    def __init__(self, total, results, copies, known, students, pending):
        self.total, self.done = total, 0
        self.results, self.known = results, known   # known: {(task, key): (record, holder's folder)}
        self.names = {student.folder: student.name for student in students}
        self.copies = collections.defaultdict(list)  # folder -> [(student, task, keys)]
        for student, task, keys in copies:
            self.copies[student.folder].append((student, task, keys))
        self.graded_folders = set()
        self.pending = {student.folder for student, _, _ in pending}  # graded in tasks of their own

    def line(self, text):
        self.done += 1
        print(f"[{self.done}/{self.total}] {text}", flush=True)

    def graded(self, student, keys, records, seconds, log, pictures, built):
        self.results.save(student, records, keys, log, pictures)
        self.graded_folders.add(student.folder)
        for record in records:
            self.known[(record["task"], keys[record["task"]])] = (record, student.folder)
        copied = self.fill(student.folder) or []
        points = sum(test["points"] for record in records + copied for test in record["tests"] if test["passed"])
        tasks = [record["task"] for record in records] + [record["task"] for record in copied]
        self.line(f"{student.name}: {points} points in {', '.join(tasks)} ({seconds:.0f} s"
                  + (f"; this worker first built the grader, {built:.0f} s" if built >= 5 else "") + ")")
        self.release()

    def failed(self, student, error):
        own = self.results.folder / "students" / student.folder
        reports.write_atomically(own / "grade.log", f"{type(error).__name__}: {error}\n")
        self.line(f"{student.name}: not graded ({type(error).__name__}; see {own / 'grade.log'})")

    def release(self):
        """Lines for the students who hand in only files graded by now."""
        for folder in [folder for folder in self.copies if folder not in self.pending | self.graded_folders]:
            entries = self.copies[folder]
            holders = sorted({self.names[self.known[(task, keys[task])][1]] for _, task, keys in entries
                              if (task, keys[task]) in self.known})
            copied = self.fill(folder)
            if copied is not None:
                points = sum(test["points"] for record in copied for test in record["tests"] if test["passed"])
                self.line(f"{entries[0][0].name}: {points} points in {', '.join(r['task'] for r in copied)}: the same "
                          f"files as {', '.join(holders)}, graded once (0 s)")

    def fill(self, folder):
        """Saves a student's copied records if every one is known; the records, or None."""
        entries = self.copies.get(folder)
        if not entries or any((task, keys[task]) not in self.known for _, task, keys in entries):
            return None
        student, keys = entries[0][0], entries[0][2]
        pictures, records = {}, []
        for _, task, _ in entries:
            record, holder = self.known[(task, keys[task])]
            pictures |= self.results.pictures_of(holder, record)
            records.append(json.loads(json.dumps(record)))
        self.results.save(student, records, keys, None if folder in self.graded_folders
                          else "graded like another student's same files", pictures)
        del self.copies[folder]
        self.graded_folders.add(folder)
        return records

    def fill_the_rest(self, failures):
        """Saves what can still be copied (after an interruption, or a failed grading); the names of
        the students with a copy missing, not yet in failures."""
        missing = []
        for folder in list(self.copies):
            entries = self.copies[folder]
            ready = [(student, task, keys) for student, task, keys in entries if (task, keys[task]) in self.known]
            if len(ready) < len(entries) and self.names[folder] not in failures:
                missing.append(self.names[folder])
            self.copies[folder] = ready
            if not ready or self.fill(folder) is None:
                del self.copies[folder]
        return missing


def run_pending(arguments, results, pending, progress):
    """Grades the pending students on Dask, each saved as it finishes (progress); the names that
    failed. First each worker builds the grader, as a step of its own."""
    client = start_client(arguments, len(pending))
    if isinstance(client, LocalWorkers):
        as_completed = client.as_completed
    else:
        from distributed import as_completed
        import cloudpickle
        cloudpickle.register_pickle_by_value(sys.modules[__name__])  # workers need not import this file
    repo = str(arguments.worker_repo or REPO)
    failures = []
    futures = {}
    try:
        prepare(client, repo, sorted({task for _, stale, _ in pending for task in stale}, key=TASKS.index))
        for student, stale, keys in pending:
            files = {TASK_FILE[task]: text for task, text in student.files.items()}
            future = client.submit(grade_on_worker, repo, files, grading_options(stale, jobs=1), STUDENT_CUTOFF, pure=False,
                                   key=f"grade-{student.folder}-{time.time_ns()}")
            futures[future] = (student, keys)
        for future in as_completed(list(futures)):
            student, keys = futures[future]
            problem = None
            if future.status == "finished":
                records, seconds, log, pictures = future.result()
                problem = next((f"grade.py wrote a record that cannot be read ({why})" for record in records
                                if (why := reports.record_problem(record))), None)
            if future.status == "finished" and problem is None:
                built = own_build_seconds(log)
                progress.graded(student, keys, records, seconds - built, log, pictures, built)
            else:
                failures.append(student.name)
                progress.failed(student, ValueError(problem) if problem else future.exception())
            future.release()
    except KeyboardInterrupt:
        client.cancel(list(futures))
        raise Interrupted(failures)
    finally:
        client.close()
    return failures


def prepare(client, repo, tasks):
    """Has the grader built (and the reference's times measured in the tasks to grade) once on each
    machine, before grading: one progress step with its time, not hidden in the first student's."""
    started = time.monotonic()
    workers = client.scheduler_info()["workers"]
    one_per_machine = list({info["host"]: address for address, info in workers.items()}.values())
    machines = f"{len(one_per_machine)} machine{'s' if len(one_per_machine) > 1 else ''}"
    print(f"grade: building the grader once on {machines} for {len(workers)} workers (a few minutes the first time, "
          "seconds after)", flush=True)
    futures = [client.submit(grade_on_worker, repo, None, grading_options(tasks), STUDENT_CUTOFF, pure=False, workers=[address],
                             allow_other_workers=False, key=f"prepare-{address}-{time.time_ns()}")
               for address in one_per_machine]
    try:
        for future in futures:
            future.result()
    except Exception as error:  # its machine's first grading builds it again, and its log says why
        print(f"grade: a machine could not build the grader ({type(error).__name__}); its first student's log will "
              "say why", flush=True)
    print(f"grade: the grader is ready on {machines} for {len(workers)} workers ({time.monotonic() - started:.0f} s)",
          flush=True)


def own_build_seconds(log):
    """What grade.py says its run spent on the grader's own build (0 if it does not say)."""
    found = re.search(r"of which (\d+) s for the grader's own build", log)
    return float(found[1]) if found else 0.0


class Interrupted(Exception):
    """Ctrl-C during the grading; holds the names of the students whose grading failed before."""

    def __init__(self, failures):
        super().__init__("interrupted")
        self.failures = failures


def main(arguments):
    return grade_class(arguments)
