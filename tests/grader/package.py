#!/usr/bin/python3
"""Packages the course for the grading platforms, and exports the student release.

    /usr/bin/python3 tests/grader/package.py gradescope OUT.zip          Gradescope autograder zip
    /usr/bin/python3 tests/grader/package.py autolab OUT_DIR             autograde-Makefile, autograde.tar,
                                                                         autograding-image.sh
    /usr/bin/python3 tests/grader/package.py classroom [--check]         .github/workflows/classroom.yml
    /usr/bin/python3 tests/grader/package.py student-release OUT_DIR     the students' repository

The packages hold the project's source as git has it (tracked files and new files git does not
ignore; without git, every file), without build/ and tests/mutants/; the grading itself is
tests/grader/grade.py's, run with the reference code for the other tasks. gradescope, autolab
and classroom read each task's maximum points from the graded suites (`test_<task>
--list-graded`), built with the release preset unless --tests names a folder that holds them,
and print the points to set on the platform: the required tasks' total, and the optional tasks'
extra credit.

Inside the packages, the platforms run this script again (not for instructors' use):

    package.py gradescope-setup   setup.sh's work: build the grader, measure the reference
                                  solutions, check that they score full points
    package.py gradescope-run     run_autograder's work: find the task files, grade, results.json
    package.py autolab-setup      the autograding image's set-up: build the grader, measure the
                                  reference solutions, let the job's user use that build
    package.py autolab-run        the Autolab driver: find the task files in the handin, grade,
                                  print {"scores": {...}} as the last line
"""

import argparse
import difflib
import hashlib
import io
import json
import os
import re
import shutil
import stat
import subprocess
import sys
import tarfile
import tempfile
import textwrap
import time
import traceback
import zipfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
REPO = HERE.parents[1]
sys.path.insert(0, str(HERE))
import building  # noqa: E402  (how a task file is read)
import course  # noqa: E402  (the course's tasks)

TASKS = course.TASKS
GRADE = "tests/grader/grade.py"
WORKFLOW = ".github/workflows/classroom.yml"

# Left out of every package: build output and the mutants (instructors' test data).
ALWAYS_EXCLUDED = ["build/", "tests/mutants/"]
# Also left out of the student release: what would give answers away, and the instructors' tools.
STUDENT_EXCLUDED = [
    "solutions/",                     # the reference solutions
    "tests/graded/hidden/",           # instructor-only tests
    "tests/grader/tests/",            # the grader's own tests (hostile submissions, the reference's runs)
    "tests/grader/package.py",        # this script: Gradescope and Autolab packaging
    "tests/grader/grade_bench.py",    # the grader's benchmark (grades the reference solutions)
    "tests/grader/grade_class.py",    # grading a class (with the reference solutions)
    "tests/grader/grade_class_bench.py",  # ... its benchmark
    "tests/grader/class_report.py",   # ... the instructor's report of it
    "tests/grader/similarity.py",     # ... the copies in it
    "tests/grader/copies/",           # ... the copy finder's npm package
    "tests/grader/copies_bench.py",   # ... and its benchmark
    "tests/grader/class-report.png",  # ... and the instructors' guide's pictures of them
    "tests/grader/class-similarity.png",
    ".ci/",                           # the instructors' CI (it expects the reference solutions)
    ".github/workflows/ci.yml",       # ... and the same CI on GitHub
    "lib/README.md",                  # the library's guide (students read tasks/README.md)
    "tests/python/test_readme_examples.py",  # ... and the tests that run its examples
    "tests/python/test_install.py",
    "tests/grader/README.md",         # the instructors' guide
    ".github/CONTRIBUTING.md",        # the contributors' guide
    "tasks/README.md",                # the students' guide: it becomes the release's README.md
    "lib/app/movie-10-1-10.svg",      # the front page's picture (the reference solutions' movie)
]
# The release's README is the students' guide.
STUDENTS_GUIDE = "tasks/README.md"
# Blocks only for instructors, removed from the student release: in every .md file, and in
# build.sh (the class grader's set-up), between lines "# instructors" and "# /instructors".
INSTRUCTORS_BLOCK = re.compile(r"<!-- instructors -->.*?<!-- /instructors -->\n?", re.DOTALL)
INSTRUCTORS_LINES = re.compile(r"^# instructors\n.*?^# /instructors\n", re.DOTALL | re.MULTILINE)

# The driver's cut-off for one grading run, above the bound below (it only catches a grader that
# is itself broken) and below the platform's limit, so that results are still written:
# Gradescope's default limit is 10 minutes; Autolab's default autograding timeout is 180 s, which
# a job fits when the autograding image holds the grader, built (autograding-image.sh), and at
# most 899 s, which a job that builds the grader itself needs.
GRADESCOPE_CUTOFF = 9 * 60
AUTOLAB_CUTOFF = 14 * 60
AUTOLAB_TIMEOUT = 899  # what instructors set as the autograding timeout for jobs that build the grader
AUTOLAB_DEFAULT_TIMEOUT = 180
AUTOLAB_PREBUILT_CUTOFF = 170
# The grader itself ends this long before the cut-off, however busy the machine (grade.py
# --deadline): time to stop the tests still running and write the results.
RESULTS_ALLOWANCE = 20
# The grader's own work per submission besides the tasks, allowed for in the stated bounds: on
# Gradescope, setup.sh has built the grader and measured the reference solutions, so a submission
# only checks the build (seconds); an Autolab job builds the grader from scratch and measures the
# reference solutions on its machine (tests/grader/README.md gives the times measured on one core).
GRADESCOPE_BUILD_ALLOWANCE = 60
AUTOLAB_BUILD_ALLOWANCE = 300
AUTOLAB_PREBUILT_ALLOWANCE = 20  # a job with the image's grader: unpacking the handin, checking the build
# grade.py's time limits on the platforms (tests/grader/README.md, "Grading"): each test and each task
# may take ten times what the reference solutions need on the grading machine (time_limits.py),
# and the tasks' budgets together at most PLATFORM_TOTAL seconds (scaled down on a machine so slow
# that they would not fit), so a submission, however it misbehaves, is graded within the
# platform's limit, and only a misbehaving task loses points.
PLATFORM_TOTAL = 420
PLATFORM_GRADE_OPTIONS = ["--limits", "reference", "--total", str(PLATFORM_TOTAL)]
# An Autolab job with the image's grader fits Autolab's default timeout: the budgets add up to at
# most this (on a fast machine most budgets sit at their floor, so this costs correct code nothing).
AUTOLAB_PREBUILT_TOTAL = 140
AUTOLAB_PREBUILT_OPTIONS = ["--limits", "reference", "--total", str(AUTOLAB_PREBUILT_TOTAL)]
SUBMITTED_FILE_CAP = building.SUBMITTED_FILE_CAP  # bytes: larger task files are not graded
ARCHIVE_SCAN_CAP = 256 << 20  # bytes of an archive's (uncompressed) content looked through
ARCHIVE_MEMBER_CAP = 20_000  # entries of an archive looked at


def fail(message):
    print(f"package: {message}", file=sys.stderr)
    sys.exit(2)


# --- The project's files -----------------------------------------------------------------------

def excluded(path, prefixes):
    return any(path == prefix.rstrip("/") or path.startswith(prefix) if prefix.endswith("/") else path == prefix
               for prefix in prefixes)


def project_files(exclude=()):
    """Relative paths (str, sorted) of the files that make up the project."""
    prefixes = ALWAYS_EXCLUDED + list(exclude)
    paths = None
    if (REPO / ".git").exists() and shutil.which("git"):
        done = subprocess.run(["git", "-C", str(REPO), "ls-files", "-z", "--cached", "--others", "--exclude-standard"],
                              stdout=subprocess.PIPE, stderr=subprocess.DEVNULL)
        if done.returncode == 0:
            paths = [path for path in done.stdout.decode().split("\0") if path]
    if paths is None:  # no git: every file but git's own and the usual clutter
        paths = []
        for folder, folders, files in os.walk(REPO):
            folders[:] = [name for name in folders if name not in {".git", "__pycache__"}]
            for name in files:
                paths.append(str((Path(folder) / name).relative_to(REPO)))
    keep = set()
    for path in paths:
        full = REPO / path
        if excluded(path, prefixes) or full.is_symlink() or not full.is_file():
            continue  # deleted but still tracked, or not a plain file
        if "__pycache__" in Path(path).parts or path.endswith(".pyc"):
            continue
        keep.add(path)
    return sorted(keep)


def file_mode(path):
    return 0o755 if os.access(REPO / path, os.X_OK) else 0o644


def check_sources(files):
    missing = [path for path in [GRADE, "build.sh", "CMakeLists.txt"] if path not in files]
    if missing:
        fail(f"the project's files lack {', '.join(missing)}: run this from a complete checkout")


# --- Points per task ---------------------------------------------------------------------------

def task_points(tests_folder=None, hidden=True):
    """{task: maximum points}, from the graded suites' --list-graded; without the hidden
    (instructor-only) tests when `hidden` is false: the points a student's repository can earn."""
    if tests_folder is None:
        for command in (["cmake", "--preset", "release"],
                        ["cmake", "--build", "--preset", "release", "--target", *[f"test_{task}" for task in TASKS]]):
            done = subprocess.run(command, cwd=REPO, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
            if done.returncode != 0:
                fail(f"building the graded suites to read their points failed ({' '.join(command)}):\n{done.stdout}")
        tests_folder = REPO / "build" / "release" / "tests"
    points = {}
    for task in TASKS:
        executable = Path(tests_folder) / f"test_{task}"
        if not executable.is_file():
            fail(f"{executable} does not exist: build the graded suites first, or leave out --tests")
        done = subprocess.run([str(executable), "--list-graded"], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                              text=True, timeout=120)
        if done.returncode != 0:
            fail(f"{executable} --list-graded failed:\n{done.stderr}")
        tests = [json.loads(line) for line in done.stdout.splitlines() if line.strip()]
        points[task] = sum(test["points"] for test in tests if hidden or test["visibility"] != "hidden")
    return points


def points_to_enter(points, platform, total_counts_optional=False):
    """The lines that tell the instructor what to set on the platform: the assignment's total (the
    required tasks' points) and the optional tasks' points, extra credit on top of it; or, where
    the platform adds every task into its total (total_counts_optional), that total and its parts."""
    required = [task for task in TASKS if not course.is_optional(task)]
    optional = [task for task in TASKS if course.is_optional(task)]

    def total(tasks):
        return sum(points[task] for task in tasks)

    def each(tasks):
        return ", ".join(f"{task} {points[task]}" for task in tasks)
    if total_counts_optional:
        lines = [f"{platform}: the steps add up to {total(TASKS)} points: {total(required)} for the required tasks "
                 f"({each(required)})"]
        if optional:
            lines.append(f"  and {total(optional)} for the optional ones ({each(optional)}), which {platform} "
                         "counts in its total")
    else:
        lines = [f"{platform}: set the assignment's total to {total(required)} points, the required tasks' "
                 f"({each(required)})"]
        if optional:
            lines.append(f"  the optional tasks' {total(optional)} points ({each(optional)}) come on top as extra "
                         "credit")
    return "\n".join(lines)


# --- GitHub Classroom --------------------------------------------------------------------------

def step_id(task):
    return task.replace("_", "-")


def classroom_workflow(points):
    """The workflow's text: GitHub Classroom's own layout, one command-grader step per task."""
    lines = [
        "# GitHub Classroom autograding: one step per task; a step earns the task's points when every",
        "# graded test of the task passes (grade.py --require-full exits 0). In the student repository",
        "# there is no solutions/, so each task's suite runs with the student's code for the other tasks.",
        "# Generated by the instructors' packaging script (`package.py classroom`) from the points of the",
        "# graded suites: do not edit by hand (the instructors' tests check that it is up to date).",
        "name: Autograding Tests",
        "'on':",
        "- push",
        "- repository_dispatch",
        "permissions:",
        "  checks: write",
        "  actions: read",
        "  contents: read",
        "jobs:",
        "  run-autograding-tests:",
        "    runs-on: ubuntu-latest",
        "    if: github.actor != 'github-classroom[bot]'",
        "    steps:",
        "    - name: Checkout code",
        "      uses: actions/checkout@v4",
    ]
    for task in TASKS:
        name = f"Task {course.TASK_NUMBER[task]} {task}" + (" (optional)" if course.is_optional(task) else "")
        lines += [
            f"    - name: {name}",
            f"      id: {step_id(task)}",
            "      uses: classroom-resources/autograding-command-grader@v1",
            "      with:",
            f"        test-name: {name}",
            "        setup-command: ./build.sh setup",
            f"        command: ./build.sh grade --task {task} --require-full",
            # minutes; the first step also installs the packages and builds every suite
            "        timeout: 15",
            f"        max-score: {points[task]}",
        ]
    lines += [
        "    - name: Autograding Reporter",
        "      uses: classroom-resources/autograding-grading-reporter@v1",
        "      env:",
    ]
    lines += [f"        {step_id(task).upper()}_RESULTS: \"${{{{steps.{step_id(task)}.outputs.result}}}}\"" for task in TASKS]
    lines += [
        "      with:",
        "        runners: " + ",".join(step_id(task) for task in TASKS),
    ]
    return "\n".join(lines) + "\n"


def command_classroom(arguments):
    # The steps run in the student's repository, which has no hidden tests (tests/graded/hidden/).
    points = task_points(arguments.tests, hidden=False)
    text = classroom_workflow(points)
    target = REPO / WORKFLOW
    if arguments.check:
        current = target.read_text() if target.is_file() else ""
        if current != text:
            sys.stdout.writelines(difflib.unified_diff(current.splitlines(True), text.splitlines(True),
                                                       f"{WORKFLOW} (committed)", f"{WORKFLOW} (generated)"))
            print(f"package: {WORKFLOW} is out of date: run /usr/bin/python3 tests/grader/package.py classroom",
                  file=sys.stderr)
            return 1
        print(f"{WORKFLOW} is up to date")
        return 0
    target.parent.mkdir(parents=True, exist_ok=True)
    target.write_text(text)
    print(f"wrote {target}")
    print(points_to_enter(points, "GitHub Classroom", total_counts_optional=True))
    return 0


# --- Gradescope --------------------------------------------------------------------------------

GRADESCOPE_SETUP = f"""#!/usr/bin/env bash
# Gradescope runs this once, as root, when it builds the autograder (the zip is unpacked into
# /autograder/source): install the Debian packages the grader needs (the list is build.sh's),
# then build the grader's build, measure what the reference solutions need on this machine (the
# time limits are ten times that) and check that they score full points within those limits, so
# that each submission only compiles its own files. Generated by tests/grader/package.py.
# Time per submission, however it misbehaves: the tasks' budgets, at most {PLATFORM_TOTAL} s together
# (it prints what they are here), plus a check of this build; the driver stops the grader after
# {GRADESCOPE_CUTOFF} s, within Gradescope's default limit of 10 minutes.
set -euo pipefail
cd "$(dirname "$0")"
./build.sh setup
/usr/bin/python3 tests/grader/package.py gradescope-setup
"""

GRADESCOPE_RUN = r"""#!/usr/bin/env bash
# Gradescope runs this for every submission (as /autograder/run_autograder). It always leaves
# a results.json: the grader's, or one with score 0 and the error for the student. Generated by
# tests/grader/package.py; AUTOGRADER_ROOT (default /autograder) is for testing it elsewhere.
root=${AUTOGRADER_ROOT:-/autograder}
results=$root/results/results.json
mkdir -p "$root/results"
log=$(mktemp)
/usr/bin/python3 "$root/source/tests/grader/package.py" gradescope-run 2>&1 | tee "$log"
status=${PIPESTATUS[0]}
if [ "$status" -ne 0 ] || ! /usr/bin/python3 -c 'import json, sys; json.load(open(sys.argv[1]))["score"]' "$results" 2>/dev/null; then
  # The driver itself failed: report that, with the end of its output.
  /usr/bin/python3 - "$results" "$log" "$status" <<'EOF' || printf '%s\n' '{"score": 0, "output": "The autograder failed before it could grade your files. Please tell the course staff."}' >"$results"
import json, sys
results, log, status = sys.argv[1], sys.argv[2], sys.argv[3]
tail = open(log, errors="replace").read()[-6000:]
json.dump({"score": 0, "output": "The autograder failed (status " + status + ") before it could grade your files; "
           "this is not your fault. Please tell the course staff. Its last output:\n" + tail}, open(results, "w"))
EOF
fi
rm -f "$log"
exit 0
"""


def gradescope_bound():
    return (f"Grading one submission takes at most {PLATFORM_TOTAL + GRADESCOPE_BUILD_ALLOWANCE} s, however it "
            f"misbehaves: the {len(TASKS)} tasks' budgets (ten times what the reference solutions need on the "
            f"grading machine, measured by setup.sh, which prints them; at most {PLATFORM_TOTAL} s together) plus "
            f"{GRADESCOPE_BUILD_ALLOWANCE} s for checking the grader's build, so Gradescope's default timeout of "
            f"10 minutes is enough (on a busy machine the grader ends after {GRADESCOPE_CUTOFF - RESULTS_ALLOWANCE} s, "
            f"stopping the tests still running, and is stopped after {GRADESCOPE_CUTOFF} s, so results are always "
            "written).")


def command_gradescope(arguments):
    out = Path(arguments.out).resolve()
    files = project_files()
    check_sources(files)
    points = task_points(arguments.tests)
    out.parent.mkdir(parents=True, exist_ok=True)
    partial = out.with_name(out.name + ".partial")
    with zipfile.ZipFile(partial, "w", zipfile.ZIP_DEFLATED) as archive:
        for name, text in [("setup.sh", GRADESCOPE_SETUP), ("run_autograder", GRADESCOPE_RUN)]:
            add_to_zip(archive, name, text.encode(), 0o755)
        for path in files:
            if path in {"setup.sh", "run_autograder"}:
                continue
            add_to_zip(archive, path, (REPO / path).read_bytes(), file_mode(path))
    os.replace(partial, out)
    print(f"wrote {out}: setup.sh, run_autograder and {len(files)} files of the project")
    print(points_to_enter(points, "Gradescope"))
    print(gradescope_bound())
    return 0


def add_to_zip(archive, name, data, mode):
    info = zipfile.ZipInfo(name, date_time=time.localtime()[:6])
    info.compress_type = zipfile.ZIP_DEFLATED
    info.external_attr = (0o100000 | mode) << 16  # a regular file with these permissions (unzip sets them)
    info.create_system = 3  # Unix, so that the permissions count
    archive.writestr(info, data)


def autograder_root():
    return Path(os.environ.get("AUTOGRADER_ROOT", "/autograder"))


def reference_scores_full(limits):
    """A platform's set-up: grades the reference solutions with the platform's limits (building
    the grader and measuring the reference on the way); says so and returns False unless they
    score full points."""
    results = Path(tempfile.mkdtemp(prefix="billiard-setup-"))
    try:
        done = subprocess.run([sys.executable, str(REPO / GRADE), "--submission", str(REPO / "solutions"),
                               "--results", str(results), "--dependencies", "reference", "--require-full", "--brief",
                               *limits])
    finally:
        shutil.rmtree(results, ignore_errors=True)
    if done.returncode != 0:
        print("package: the reference solutions do not score full points here: the autograder is not usable",
              file=sys.stderr)
    return done.returncode == 0


def command_gradescope_setup(arguments):
    """Builds the grader's build with the reference solutions, and checks they score full points."""
    if not reference_scores_full(PLATFORM_GRADE_OPTIONS):
        return 1
    print(gradescope_bound())
    return 0


def command_gradescope_run(arguments):
    return gradescope_run(autograder_root())


def gradescope_run(root, grade_options=()):
    """run_autograder's work for the fake or real /autograder folder `root`: grades
    root/submission, writes root/results/results.json. grade_options go to grade.py (the
    tests give their own build folder)."""
    results_folder = root / "results"
    results_folder.mkdir(parents=True, exist_ok=True)
    results = results_folder / "results.json"
    results.unlink(missing_ok=True)
    work = Path(tempfile.mkdtemp(prefix="billiard-submission-"))
    try:
        _, notes = find_task_files([root / "submission"], work)
        print("\n".join(notes), flush=True)
        done = run_grader(work, results_folder, GRADESCOPE_CUTOFF, grade_options)
        report = json.loads(results.read_text()) if results.is_file() else None
        if done is None or done.returncode != 0 or not isinstance(report, dict) or "score" not in report:
            reason = "did not finish in time" if done is None else f"failed with status {done.returncode}"
            details = notes + ([] if done is None else ["", "The end of its output:", done.stdout[-4000:]])
            write_gradescope_failure(results, f"The grader {reason}, so your files could not be graded; this is "
                                     "not a problem of your code. Please tell the course staff.", details)
        else:
            report["output"] = "\n".join(notes) + "\n\n" + report.get("output", "")
            results.write_text(json.dumps(report, indent=2) + "\n")
    except Exception:  # whatever happens, Gradescope gets a results.json
        traceback.print_exc()
        write_gradescope_failure(results, "The autograder failed before it could grade your files; this is not a "
                                 "problem of your code. Please tell the course staff.",
                                 [traceback.format_exc(limit=3)])
    finally:
        shutil.rmtree(work, ignore_errors=True)
    return 0


def write_gradescope_failure(results, message, details):
    report = {"score": 0, "output": message + "\n\n" + "\n".join(details), "stdout_visibility": "hidden", "tests": []}
    results.write_text(json.dumps(report, indent=2) + "\n")


def run_grader(submission, results_folder, cutoff, grade_options=(), limits=tuple(PLATFORM_GRADE_OPTIONS)):
    """Runs grade.py with the reference code for the other tasks and the platforms' time limits;
    its output goes to ours; it ends RESULTS_ALLOWANCE seconds before `cutoff` even on a busy
    machine, and None is returned if it did not finish within `cutoff` seconds. As root
    (Gradescope), the submitted files are compiled and the tests run as an unprivileged user, to
    whom the reference solutions and the grader's build are unreadable while grading
    (--protect-reference); Autolab runs jobs unprivileged, so there a handin could include them."""
    command = [sys.executable, str(REPO / GRADE), "--submission", str(submission), "--results",
               str(results_folder), "--dependencies", "reference", "--audience", "student", *limits,
               "--deadline", str(cutoff - RESULTS_ALLOWANCE), *grade_options]
    if os.geteuid() == 0:
        command.append("--protect-reference")
    sys.stdout.flush()
    try:
        done = subprocess.run(command, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                              text=True, errors="replace", timeout=cutoff)
    except subprocess.TimeoutExpired as expired:
        output = expired.stdout.decode(errors="replace") if isinstance(expired.stdout, bytes) else (expired.stdout or "")
        print(output + f"\npackage: the grader did not finish within {cutoff} s", flush=True)
        return None
    print(done.stdout, end="", flush=True)
    return done


# --- Finding the submitted task files ----------------------------------------------------------

def shown(name, limit=200):
    """A file name as the student may read it: control characters and undecodable bytes written
    as escapes (a name may hold a newline, or bytes that are not UTF-8), long names cut."""
    text = "".join(c if c.isprintable() else repr(c)[1:-1] for c in name)
    if len(text) <= limit:
        return text
    return text[:limit // 3] + "..." + text[-(limit - limit // 3):]  # the end holds the file's name


def find_task_files(places, destination):
    """Looks for the task files (<task>.cpp, <task>.c for a C task) by name in the given files and folders, at any depth, also inside .zip
    and .tar archives (whatever their name; compressed ones too); copies the chosen file of each
    task to destination. Where a name occurs more than once, a file in a folder named tasks wins,
    then the one nearest the top. Links are never followed (in folders and in archives), and only
    ordinary files of at most SUBMITTED_FILE_CAP bytes count: the others named like a task file
    are listed for the student. Returns ({task: where it came from}, lines for the student)."""
    candidates = {task: [] for task in TASKS}  # task -> [(rank, where, read)]
    passed_over = {task: [] for task in TASKS}  # task -> ["<where> <why it is not graded>"]
    others = 0
    cut_short = []  # archives and folders only partly looked through

    by_file = {course.TASK_FILE[task]: task for task in TASKS}

    def task_of(parts):
        name = parts[-1] if parts else ""
        if any(part.startswith(("__MACOSX", "._")) for part in parts):
            return None
        return by_file.get(name)

    def consider(where, parts, read, size):
        nonlocal others
        task = task_of(parts)
        if task is None:
            others += 1
        elif size > SUBMITTED_FILE_CAP:
            passed_over[task].append(f"{shown(where)} {building.TOO_LARGE}")
        else:
            rank = (0 if len(parts) > 1 and parts[-2] == "tasks" else 1, len(parts), where)
            candidates[task].append((rank, where, read))

    def pass_over(where, parts, why):
        """An entry that cannot be graded: listed for the student if it is named like a task file."""
        task = task_of(parts)
        if task is not None:
            passed_over[task].append(f"{shown(where)} {why}")

    def member_parts(label, name):
        # archives made on Windows may separate folders with backslashes
        return [*label.split("/"), *[part for part in re.split(r"[/\\]", name) if part]]

    def look_in_archive(path, label):
        """Looks through a .zip or .tar file; False if it is neither."""
        try:
            if zipfile.is_zipfile(path):
                with zipfile.ZipFile(path) as archive:
                    members = archive.infolist()
                    if len(members) > ARCHIVE_MEMBER_CAP:
                        cut_short.append(label)
                    for info in members[:ARCHIVE_MEMBER_CAP]:
                        where, parts = f"{label}:{info.filename}", member_parts(label, info.filename)
                        if info.is_dir():
                            pass_over(where, parts, building.FOLDER)
                        elif stat.S_ISLNK(info.external_attr >> 16):
                            pass_over(where, parts, building.LINK)
                        else:
                            consider(where, parts, lambda info=info: read_zip_member(path, info), info.file_size)
                return True
            if tarfile.is_tarfile(path):
                with tarfile.open(path) as archive:
                    for count, member in enumerate(archive):
                        # a compressed archive may unpack to far more than was uploaded
                        if count >= ARCHIVE_MEMBER_CAP or archive.offset > ARCHIVE_SCAN_CAP:
                            cut_short.append(label)
                            break
                        where, parts = f"{label}:{member.name}", member_parts(label, member.name)
                        if member.isfile():
                            consider(where, parts, lambda member=member: read_tar_member(path, member), member.size)
                        elif member.isdir():
                            pass_over(where, parts, building.FOLDER)
                        elif member.issym() or member.islnk():
                            pass_over(where, parts, building.LINK)
                        else:
                            pass_over(where, parts, building.SPECIAL)
                return True
        except Exception:  # a damaged archive: whatever was found in it so far still counts
            return True
        return False

    def read_file(path):
        text, why = building.read_task_file(path)
        if text is None:
            raise OSError(why or "is gone")
        return text

    for place in places:
        place = Path(place)
        if place.is_symlink() or not (place.is_file() or place.is_dir()):
            pass_over(place.name, [place.name], building.LINK if place.is_symlink() else building.SPECIAL)
            continue
        if place.is_file():
            if not look_in_archive(place, place.name):
                consider(place.name, [place.name], lambda place=place: read_file(place), place.stat().st_size)
            continue
        pass_over(place.name, [place.name], building.FOLDER)
        looked_at = 0
        folders = [(place, 0)]
        while folders:  # not os.walk: it would recurse as deep as the folders go, and follow nothing anyway
            folder, depth = folders.pop()
            try:
                entries = sorted(os.scandir(folder), key=lambda entry: entry.name, reverse=True)
            except OSError:
                continue
            for entry in entries:
                looked_at += 1
                if looked_at > ARCHIVE_MEMBER_CAP * 5:
                    cut_short.append(shown(str(place.name)))
                    folders = []
                    break
                path = Path(entry.path)
                where = str(path.relative_to(place))
                parts = where.split("/")
                try:
                    if entry.is_symlink():
                        pass_over(where, parts, building.LINK)
                    elif entry.is_dir():
                        if entry.name.startswith((".", "__MACOSX")):  # .git too
                            continue
                        pass_over(where, parts, building.FOLDER)
                        if depth < 64:
                            folders.append((path, depth + 1))
                    elif not entry.is_file():
                        pass_over(where, parts, building.SPECIAL)
                    elif entry.name.endswith((".cpp", ".c")):
                        consider(where, parts, lambda path=path: read_file(path), entry.stat().st_size)
                    elif not look_in_archive(path, where):
                        others += 1
                except OSError:
                    others += 1

    destination.mkdir(parents=True, exist_ok=True)
    found, notes = {}, ["Files graded:"]
    for task in TASKS:
        chosen = None
        for rank, where, read in sorted(candidates[task], key=lambda candidate: candidate[0]):
            try:
                text = read()
            except Exception:  # a damaged archive member, a file that went away: the next one
                passed_over[task].append(f"{shown(where)} could not be read")
                continue
            if len(text) > SUBMITTED_FILE_CAP:
                passed_over[task].append(f"{shown(where)} {building.TOO_LARGE}")
                continue
            (destination / course.TASK_FILE[task]).write_bytes(text)
            chosen = where
            break
        skipped = [shown(where) for _, where, _ in candidates[task] if where != chosen]
        if chosen is None:
            # grade.py needs every file to configure its build: the course's untouched stub
            # stands in, so the task scores 0 with "not implemented yet".
            shutil.copyfile(REPO / "tasks" / course.TASK_FILE[task], destination / course.TASK_FILE[task])
            missing = "no file of this name that can be graded" if passed_over[task] else "not found in your submission"
            notes.append(f"  {course.TASK_FILE[task]}: {missing}, graded as not implemented (0 points)")
        else:
            found[task] = chosen
            notes.append(f"  {course.TASK_FILE[task]}: {shown(chosen)}"
                         + (f" (also found, not graded: {', '.join(skipped)})" if skipped else ""))
        for line in passed_over[task]:
            notes.append(f"    not graded: {line}")
    if others:
        notes.append(f"Other files, ignored: {others}.")
    for label in cut_short:
        notes.append(f"{label} holds too many files (or too many bytes): only its first files were looked at.")
    return found, notes


def read_zip_member(path, info):
    with zipfile.ZipFile(path) as archive:
        with archive.open(info) as member:
            return member.read(SUBMITTED_FILE_CAP + 1)


def read_tar_member(path, member):
    with tarfile.open(path) as archive:
        return archive.extractfile(member).read(SUBMITTED_FILE_CAP + 1)


# --- Autolab -----------------------------------------------------------------------------------

AUTOLAB_FOLDER = "billiard-autograde"


AUTOLAB_IMAGE_FOLDER = f"/opt/{AUTOLAB_FOLDER}"  # where autograding-image.sh puts the grader
PACKAGE_ID = ".package-id"  # in the package's folder: which package it is


def autolab_makefile(package_id):
    zeros = json.dumps({"scores": {task: 0 for task in TASKS}})
    return f"""# Autolab's autograder for the billiard course, generated by tests/grader/package.py autolab.
# Autolab copies this file (as Makefile), autograde.tar and the student's handin (a .tar or .zip
# with the task files <task>.cpp or <task>.c, at any depth) into an empty folder and runs `make`. The last
# line of the output is always the scores, {{"scores": {{"<task>": points, ...}}}}; the lines
# before it are the grader's report, with compiler errors and failing tests, for the student.
# Where the autograding image holds the grader of this very package (autograding-image.sh), a
# job grades with it; otherwise it unpacks autograde.tar and builds the grader first.
{textwrap.fill(autolab_bound(), 96, initial_indent="# ", subsequent_indent="# ")}
BILLIARD_GRADER ?= {AUTOLAB_IMAGE_FOLDER}
all:
\t@if [ "$$(cat $(BILLIARD_GRADER)/{PACKAGE_ID} 2>/dev/null)" = "{package_id}" ]; then \\
\t  /usr/bin/python3 $(BILLIARD_GRADER)/tests/grader/package.py autolab-run . --prebuilt; \\
\telse \\
\t  tar -xf autograde.tar && /usr/bin/python3 {AUTOLAB_FOLDER}/tests/grader/package.py autolab-run .; \\
\tfi || (echo "The autograder failed before it could grade the handin; tell the course staff."; echo '{zeros}')
"""


AUTOLAB_IMAGE_SCRIPT = f"""#!/bin/sh
# Sets up Autolab's autograding image for the billiard course: run it once, as root, where the
# image is built, e.g. in its Dockerfile:
#     COPY autograde.tar autograding-image.sh /tmp/
#     RUN sh /tmp/autograding-image.sh /tmp/autograde.tar
# It installs the Debian packages the grader needs, unpacks the course into
# {AUTOLAB_IMAGE_FOLDER} (BILLIARD_GRADER sets another folder), builds the grader, measures what the
# reference solutions need on this machine (the time limits are ten times that), checks that they
# score full points, and lets the job's user use that build. Each job then only grades, within
# Autolab's default autograding timeout of {AUTOLAB_DEFAULT_TIMEOUT} s. Generated by tests/grader/package.py autolab.
set -eu
package=$(cd "$(dirname "${{1:?usage: autograding-image.sh AUTOGRADE_TAR}}")" && pwd)/$(basename "$1")
folder=${{BILLIARD_GRADER:-{AUTOLAB_IMAGE_FOLDER}}}
rm -rf "$folder"
mkdir -p "$folder"
tar -xf "$package" -C "$folder" --strip-components=1
cd "$folder"
./build.sh setup
/usr/bin/python3 tests/grader/package.py autolab-setup
"""


def autolab_bound():
    return (f"With the grader in the autograding image (autograding-image.sh), a job takes at most "
            f"{AUTOLAB_PREBUILT_TOTAL + AUTOLAB_PREBUILT_ALLOWANCE} s, however the handin misbehaves: the {len(TASKS)} "
            f"tasks' budgets (ten times what the reference solutions need on the image's machine; at most "
            f"{AUTOLAB_PREBUILT_TOTAL} s together) plus {AUTOLAB_PREBUILT_ALLOWANCE} s for the rest; the driver stops "
            f"the grader after {AUTOLAB_PREBUILT_CUTOFF} s, within Autolab's default autograding timeout of "
            f"{AUTOLAB_DEFAULT_TIMEOUT} s. Without it, a job takes at most {PLATFORM_TOTAL + AUTOLAB_BUILD_ALLOWANCE} s on "
            f"one core: the grader's build from scratch and the measuring of the reference solutions on the job's "
            f"machine (allowed {AUTOLAB_BUILD_ALLOWANCE} s) plus the tasks' budgets (at most {PLATFORM_TOTAL} s "
            f"together); the driver stops the grader after {AUTOLAB_CUTOFF} s, so the scores line always comes before "
            f"an autograding timeout of {AUTOLAB_TIMEOUT} s.")


def command_autolab(arguments):
    out = Path(arguments.out).resolve()
    files = project_files()
    check_sources(files)
    points = task_points(arguments.tests)
    out.mkdir(parents=True, exist_ok=True)
    digest = hashlib.sha256()
    for path in files:
        digest.update(path.encode() + b"\0" + (REPO / path).read_bytes() + b"\0")
    package_id = digest.hexdigest()[:16]
    partial = out / "autograde.tar.partial"
    with tarfile.open(partial, "w", format=tarfile.PAX_FORMAT) as archive:
        for path in files:
            info = archive.gettarinfo(str(REPO / path), arcname=f"{AUTOLAB_FOLDER}/{path}")
            info.mode = file_mode(path)
            info.uid = info.gid = 0
            info.uname = info.gname = ""
            with open(REPO / path, "rb") as source:
                archive.addfile(info, source)
        info = tarfile.TarInfo(f"{AUTOLAB_FOLDER}/{PACKAGE_ID}")
        info.size, info.mode = len(package_id), 0o644
        archive.addfile(info, io.BytesIO(package_id.encode()))
    os.replace(partial, out / "autograde.tar")
    (out / "autograde-Makefile").write_text(autolab_makefile(package_id))
    (out / "autograding-image.sh").write_text(AUTOLAB_IMAGE_SCRIPT)
    os.chmod(out / "autograding-image.sh", 0o755)
    print(f"wrote {out / 'autograde-Makefile'}, {out / 'autograde.tar'} ({len(files)} files of the project) and "
          f"{out / 'autograding-image.sh'}")
    print("Autolab problems (names and maximum scores):")
    for task in TASKS:
        print(f"  {task}  {points[task]}" + ("  (optional: extra credit)" if course.is_optional(task) else ""))
    print(points_to_enter(points, "Autolab"))
    print(f"Autolab settings: handin file name handin.tar. Autograding image: run autograding-image.sh where it is "
          f"built; then the default autograding timeout of {AUTOLAB_DEFAULT_TIMEOUT} s is enough. Without it, set "
          f"the timeout to {AUTOLAB_TIMEOUT} s (the most Autolab allows).")
    print(autolab_bound())
    return 0


def command_autolab_setup(arguments):
    """The autograding image's set-up (autograding-image.sh): grades the reference solutions with
    the limits of a job (building the grader and measuring them on the way), then lets any user,
    the job's among them, use the grader's build."""
    if not reference_scores_full(AUTOLAB_PREBUILT_OPTIONS):
        return 1
    # Each job runs in a container of its own, as an unprivileged user, and writes into the build.
    grading = REPO / "build" / "grade"
    for path in [grading, *grading.rglob("*")]:
        if not path.is_symlink():
            os.chmod(path, path.stat().st_mode | (0o777 if path.is_dir() else 0o666))
    print(autolab_bound())
    return 0


def command_autolab_run(arguments):
    """The Autolab driver: grades the handin found in the job's folder; the last line printed is
    always the scores."""
    scores = {task: 0 for task in TASKS}
    work = Path(tempfile.mkdtemp(prefix="billiard-handin-"))
    try:
        folder = Path(arguments.folder).resolve()
        package = {AUTOLAB_FOLDER, "autograde.tar", "Makefile", "autograde-Makefile"}
        handins = [path for path in sorted(folder.iterdir()) if path.name not in package and not path.name.startswith(".")]
        if not handins:
            print("No handin was found: hand in a .tar or .zip with your task files.")
        _, notes = find_task_files(handins, work / "submission")
        print("\n".join(notes), flush=True)
        results = work / "results"
        if arguments.prebuilt:
            done = run_grader(work / "submission", results, AUTOLAB_PREBUILT_CUTOFF,
                              limits=tuple(AUTOLAB_PREBUILT_OPTIONS))
        else:
            done = run_grader(work / "submission", results, AUTOLAB_CUTOFF)
        if done is None or done.returncode != 0 or not (results / "results.json").is_file():
            print("The grader failed, so the handin could not be graded; this is not a problem of your code. "
                  "Please tell the course staff.")
        else:
            report = json.loads((results / "results.json").read_text())
            for test in report["tests"]:
                task = test["name"].split(":")[0]
                if task in scores:
                    scores[task] += test["score"]
    except Exception:
        traceback.print_exc(file=sys.stdout)
        print("The autograder failed; this is not a problem of your code. Please tell the course staff.")
        scores = {task: 0 for task in TASKS}
    finally:
        shutil.rmtree(work, ignore_errors=True)
    sys.stdout.flush()
    sys.stderr.flush()
    print(json.dumps({"scores": scores}), flush=True)
    return 0


# --- Student release ---------------------------------------------------------------------------

def students_text(markdown):
    """A README without its instructors' blocks (and without the blank lines they leave)."""
    text = INSTRUCTORS_BLOCK.sub("", markdown)
    return re.sub(r"\n{3,}", "\n\n", text).rstrip("\n") + "\n"


def stages_off_files():
    """The files of the stages course.txt switches off: left out of the student release."""
    return [path for stage in course.OFF
            for path in (f"tasks/{course.TASK_FILE[stage]}", f"tests/graded/test_{stage}.cpp",
                         f"tests/graded/{stage}_support.hpp")]


def command_student_release(arguments):
    out = Path(arguments.out).resolve()
    if out.exists() and (not out.is_dir() or any(out.iterdir())):
        fail(f"{out} exists and is not empty: give a new folder")
    files = project_files(STUDENT_EXCLUDED + stages_off_files())
    check_sources(files)
    if WORKFLOW not in files:
        fail(f"{WORKFLOW} is missing: generate it first with /usr/bin/python3 tests/grader/package.py classroom")
    out.mkdir(parents=True, exist_ok=True)
    for path in files:
        target = out / path
        target.parent.mkdir(parents=True, exist_ok=True)
        if path == "README.md":
            target.write_text(students_text((REPO / STUDENTS_GUIDE).read_text()))
        elif path.endswith(".md"):
            target.write_text(students_text((REPO / path).read_text()))
        elif path == "build.sh":
            target.write_text(INSTRUCTORS_LINES.sub("", (REPO / path).read_text()))
        else:
            shutil.copyfile(REPO / path, target)
        os.chmod(target, file_mode(path))
    print(f"wrote the student release to {out} ({len(files)} files)")
    if arguments.no_git or not shutil.which("git"):
        return 0
    git = ["git", "-C", str(out), "-c", "user.name=billiard course", "-c", "user.email=billiard@localhost",
           "-c", "commit.gpgsign=false"]
    for command in (["init", "-q", "-b", "main"], ["add", "-A"], ["commit", "-q", "-m", "billiard: the course project"]):
        done = subprocess.run(git + command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        if done.returncode != 0:
            fail(f"git {' '.join(command)} failed in {out}:\n{done.stdout}")
    print(f"{out} is a git repository with one commit")
    return 0


# --- Main --------------------------------------------------------------------------------------

def parse_arguments(argv):
    parser = argparse.ArgumentParser(prog="package", description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter,
                                     epilog=__doc__.split("\n\n", 1)[1])
    commands = parser.add_subparsers(dest="command", required=True)
    tests_help = "folder with the built graded suites test_<task> (default: build them with the release preset)"
    command = commands.add_parser("gradescope", help="the Gradescope autograder zip")
    command.add_argument("out", metavar="OUT.zip")
    command.add_argument("--tests", type=Path, help=tests_help)
    command = commands.add_parser("autolab", help="Autolab's autograde-Makefile and autograde.tar")
    command.add_argument("out", metavar="OUT_DIR")
    command.add_argument("--tests", type=Path, help=tests_help)
    command = commands.add_parser("classroom", help=f"(re)generate {WORKFLOW}")
    command.add_argument("--tests", type=Path, help=tests_help)
    command.add_argument("--check", action="store_true", help="only check that the file is up to date (exit 1 if not)")
    command = commands.add_parser("student-release", help="export the students' repository")
    command.add_argument("out", metavar="OUT_DIR")
    command.add_argument("--no-git", action="store_true", help="do not make it a git repository")
    commands.add_parser("gradescope-setup", help="(inside the Gradescope package) setup.sh's work")
    commands.add_parser("gradescope-run", help="(inside the Gradescope package) run_autograder's work")
    commands.add_parser("autolab-setup", help="(inside the Autolab package) autograding-image.sh's work")
    command = commands.add_parser("autolab-run", help="(inside the Autolab package) grade the handin in FOLDER")
    command.add_argument("folder", metavar="FOLDER")
    command.add_argument("--prebuilt", action="store_true", help="with the grader the autograding image holds")
    return parser.parse_args(argv)


def main(argv=None):
    arguments = parse_arguments(sys.argv[1:] if argv is None else argv)
    handler = {
        "gradescope": command_gradescope, "autolab": command_autolab, "classroom": command_classroom,
        "student-release": command_student_release, "gradescope-setup": command_gradescope_setup,
        "gradescope-run": command_gradescope_run, "autolab-run": command_autolab_run,
        "autolab-setup": command_autolab_setup,
    }[arguments.command]
    return handler(arguments)


if __name__ == "__main__":
    sys.exit(main())
