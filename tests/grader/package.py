#!/usr/bin/python3
"""Packages the course for the grading platforms, and exports the student release.

    /usr/bin/python3 tests/grader/package.py gradescope OUT.zip          Gradescope autograder zip
    /usr/bin/python3 tests/grader/package.py autolab OUT_DIR             autograde-Makefile, autograde.tar
    /usr/bin/python3 tests/grader/package.py classroom [--check]         .github/workflows/classroom.yml
    /usr/bin/python3 tests/grader/package.py student-release OUT_DIR     the students' repository

The packages hold the project's source as git has it (tracked files and new files git does not
ignore; without git, every file), without build/ and tests/mutants/; the grading itself is
tests/grader/grade.py's, run with the reference code for the other tasks. classroom and autolab
read each task's maximum points from the graded suites (`test_<task> --list-graded`), built
with the release preset unless --tests names a folder that holds them.

Inside the packages, the platforms run this script again (not for instructors' use):

    package.py gradescope-setup   setup.sh's work: check and pre-build the grader's build
    package.py gradescope-run     run_autograder's work: find the task files, grade, results.json
    package.py autolab-run        the Autolab driver: find the task files in the handin, grade,
                                  print {"scores": {...}} as the last line
"""

import argparse
import difflib
import json
import os
import re
import shutil
import subprocess
import sys
import tarfile
import tempfile
import time
import traceback
import zipfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
REPO = HERE.parents[1]
TASKS = ["init_billiard", "init_velocities", "visualize_table", "propagate", "movie", "kinetic_energy"]
GRADE = "tests/grader/grade.py"
WORKFLOW = ".github/workflows/classroom.yml"

# Left out of every package: build output and the mutants (instructors' test data).
ALWAYS_EXCLUDED = ["build/", "tests/mutants/"]
# Also left out of the student release: what would give answers away, and the instructors' tools.
STUDENT_EXCLUDED = [
    "solutions/",                     # the reference solutions
    "tests/graded/hidden/",           # instructor-only tests
    "tests/grader/hostile/",          # the grader's own tests: a misbehaving submission
    "tests/grader/test_grader.py",    # ... and the tests that need solutions/ and hostile/
    "tests/grader/package.py",        # this script: Gradescope and Autolab packaging
    "tests/grader/test_packages.py",  # ... and its tests
    ".ci/",                           # the instructors' CI (it expects the reference solutions)
]
# README blocks only for instructors, removed from the student release (in every .md file).
INSTRUCTORS_BLOCK = re.compile(r"<!-- instructors -->.*?<!-- /instructors -->\n?", re.DOTALL)

# Time limit per graded test on the platforms (grade.py's --timeout): the slowest test takes
# about 2 s, so this only stops endless loops sooner than grade.py's default.
PLATFORM_TEST_TIMEOUT = 20
# Overall limit for one grading run on the platforms, so that a results file is still written
# before the platform's own limit (set that to 20 minutes: see README.md).
PLATFORM_GRADE_TIMEOUT = 18 * 60
SUBMITTED_FILE_CAP = 1_000_000  # bytes; grade.py ignores larger files too


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


# --- GitHub Classroom --------------------------------------------------------------------------

def step_id(task):
    return task.replace("_", "-")


def classroom_workflow(points):
    """The workflow's text: GitHub Classroom's own layout, one command-grader step per task."""
    lines = [
        "# GitHub Classroom autograding: one step per task; a step earns the task's points when every",
        "# graded test of the task passes (grade.py --require-full exits 0). In the student repository",
        "# there is no solutions/, so each task's suite runs with the student's code for the other tasks.",
        "# Generated by `/usr/bin/python3 tests/grader/package.py classroom` from the points of the graded",
        "# suites: do not edit by hand (a test checks that this file is up to date).",
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
    for number, task in enumerate(TASKS, start=1):
        name = f"Task {number} {task}"
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
    text = classroom_workflow(task_points(arguments.tests, hidden=False))
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
    return 0


# --- Gradescope --------------------------------------------------------------------------------

GRADESCOPE_SETUP = """#!/usr/bin/env bash
# Gradescope runs this once, as root, when it builds the autograder (the zip is unpacked into
# /autograder/source): install the Debian packages the grader needs (the list is build.sh's),
# then build the grader's build and check that the reference solutions score full points, so
# that each submission only compiles its own files. Generated by tests/grader/package.py.
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


def command_gradescope(arguments):
    out = Path(arguments.out).resolve()
    files = project_files()
    check_sources(files)
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
    return 0


def add_to_zip(archive, name, data, mode):
    info = zipfile.ZipInfo(name, date_time=time.localtime()[:6])
    info.compress_type = zipfile.ZIP_DEFLATED
    info.external_attr = (0o100000 | mode) << 16  # a regular file with these permissions (unzip sets them)
    info.create_system = 3  # Unix, so that the permissions count
    archive.writestr(info, data)


def autograder_root():
    return Path(os.environ.get("AUTOGRADER_ROOT", "/autograder"))


def command_gradescope_setup(arguments):
    """Builds the grader's build with the reference solutions, and checks they score full points."""
    results = Path(tempfile.mkdtemp(prefix="billiard-setup-"))
    try:
        done = subprocess.run(["/usr/bin/python3", str(REPO / GRADE), "--submission", str(REPO / "solutions"),
                               "--results", str(results), "--dependencies", "reference", "--require-full", "--brief"])
    finally:
        shutil.rmtree(results, ignore_errors=True)
    if done.returncode != 0:
        print("package: the reference solutions do not score full points here: the autograder is not usable",
              file=sys.stderr)
        return 1
    return 0


def command_gradescope_run(arguments):
    root = autograder_root()
    results_folder = root / "results"
    results_folder.mkdir(parents=True, exist_ok=True)
    results = results_folder / "results.json"
    results.unlink(missing_ok=True)
    work = Path(tempfile.mkdtemp(prefix="billiard-submission-"))
    try:
        _, notes = find_task_files([root / "submission"], work)
        print("\n".join(notes), flush=True)
        done = run_grader(work, results_folder)
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


def run_grader(submission, results_folder):
    """Runs grade.py with the reference code for the other tasks; its output goes to ours. None if it
    did not finish within PLATFORM_GRADE_TIMEOUT. As root (Gradescope), the tests run as an
    unprivileged user, to whom the reference solutions are unreadable while the submitted files'
    #include lines are expanded (--protect-reference); Autolab runs jobs unprivileged, so there a
    handin could include them."""
    command = ["/usr/bin/python3", str(REPO / GRADE), "--submission", str(submission), "--results",
               str(results_folder), "--dependencies", "reference", "--timeout", str(PLATFORM_TEST_TIMEOUT)]
    if os.geteuid() == 0:
        command.append("--protect-reference")
    sys.stdout.flush()
    try:
        done = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, errors="replace",
                              timeout=PLATFORM_GRADE_TIMEOUT)
    except subprocess.TimeoutExpired as expired:
        output = expired.stdout.decode(errors="replace") if isinstance(expired.stdout, bytes) else (expired.stdout or "")
        print(output + f"\npackage: the grader did not finish within {PLATFORM_GRADE_TIMEOUT} s", flush=True)
        return None
    print(done.stdout, end="", flush=True)
    return done


# --- Finding the submitted task files ----------------------------------------------------------

def find_task_files(places, destination):
    """Looks for <task>.cpp by name in the given files and folders, at any depth, also inside .zip
    and .tar archives (whatever their name); copies the chosen file of each task to destination.
    Where a name occurs more than once, a file in a folder named tasks wins, then the one nearest
    the top. Returns ({task: where it came from}, lines for the student)."""
    candidates = {task: [] for task in TASKS}  # task -> [(rank, where, read)]
    others = 0

    def consider(where, read, size):
        nonlocal others
        parts = Path(where).parts
        name = parts[-1] if parts else ""
        task = name[:-4] if name.endswith(".cpp") else None
        if task not in candidates or size > SUBMITTED_FILE_CAP or any(part.startswith(("__MACOSX", "._")) for part in parts):
            others += 1
            return
        rank = (0 if len(parts) > 1 and parts[-2] == "tasks" else 1, len(parts), where)
        candidates[task].append((rank, where, read))

    def look_in_archive(path, label):
        nonlocal others
        try:
            if zipfile.is_zipfile(path):
                with zipfile.ZipFile(path) as archive:
                    for info in archive.infolist():
                        if not info.is_dir():
                            consider(f"{label}:{info.filename}", lambda info=info: read_zip_member(path, info),
                                     info.file_size)
                return True
            if tarfile.is_tarfile(path):
                with tarfile.open(path) as archive:
                    for member in archive.getmembers():
                        if member.isfile():
                            consider(f"{label}:{member.name}", lambda member=member: read_tar_member(path, member),
                                     member.size)
                return True
        except (OSError, zipfile.BadZipFile, tarfile.TarError, EOFError):
            pass
        return False

    for place in places:
        place = Path(place)
        if place.is_file():
            if not look_in_archive(place, place.name):
                consider(place.name, lambda place=place: place.read_bytes(), place.stat().st_size)
            continue
        for folder, folders, names in os.walk(place):
            folders[:] = sorted(name for name in folders if not name.startswith((".", "__MACOSX")))  # .git too
            for name in sorted(names):
                path = Path(folder) / name
                if path.is_symlink() or not path.is_file():
                    continue
                where = str(path.relative_to(place))
                if name.endswith(".cpp"):
                    consider(where, lambda path=path: path.read_bytes(), path.stat().st_size)
                elif not look_in_archive(path, where):
                    others += 1

    destination.mkdir(parents=True, exist_ok=True)
    found, notes = {}, ["Files graded:"]
    for task in TASKS:
        if not candidates[task]:
            # grade.py needs every file to configure its build: the course's untouched stub
            # stands in, so the task scores 0 with "not implemented yet".
            shutil.copyfile(REPO / "tasks" / f"{task}.cpp", destination / f"{task}.cpp")
            notes.append(f"  {task}.cpp: not found in your submission, graded as not implemented (0 points)")
            continue
        candidates[task].sort(key=lambda candidate: candidate[0])
        _, where, read = candidates[task][0]
        (destination / f"{task}.cpp").write_bytes(read())
        found[task] = where
        also = f" (also found, not graded: {', '.join(c[1] for c in candidates[task][1:])})" if len(candidates[task]) > 1 else ""
        notes.append(f"  {task}.cpp: {where}{also}")
    if others:
        notes.append(f"Other files, ignored: {others}.")
    return found, notes


def read_zip_member(path, info):
    with zipfile.ZipFile(path) as archive:
        return archive.read(info)


def read_tar_member(path, member):
    with tarfile.open(path) as archive:
        return archive.extractfile(member).read()


# --- Autolab -----------------------------------------------------------------------------------

AUTOLAB_FOLDER = "billiard-autograde"


def autolab_makefile():
    zeros = json.dumps({"scores": {task: 0 for task in TASKS}})
    return f"""# Autolab's autograder for the billiard course, generated by tests/grader/package.py autolab.
# Autolab copies this file (as Makefile), autograde.tar and the student's handin (a .tar or .zip
# with the task files <task>.cpp, at any depth) into an empty folder and runs `make`. The last
# line of the output is always the scores, {{"scores": {{"<task>": points, ...}}}}; the lines
# before it are the grader's report, with compiler errors and failing tests, for the student.
all:
\t@tar -xf autograde.tar && /usr/bin/python3 {AUTOLAB_FOLDER}/tests/grader/package.py autolab-run . \\
\t  || (echo "The autograder failed before it could grade the handin; tell the course staff."; echo '{zeros}')
"""


def command_autolab(arguments):
    out = Path(arguments.out).resolve()
    files = project_files()
    check_sources(files)
    points = task_points(arguments.tests)
    out.mkdir(parents=True, exist_ok=True)
    (out / "autograde-Makefile").write_text(autolab_makefile())
    partial = out / "autograde.tar.partial"
    with tarfile.open(partial, "w", format=tarfile.PAX_FORMAT) as archive:
        for path in files:
            info = archive.gettarinfo(str(REPO / path), arcname=f"{AUTOLAB_FOLDER}/{path}")
            info.mode = file_mode(path)
            info.uid = info.gid = 0
            info.uname = info.gname = ""
            with open(REPO / path, "rb") as source:
                archive.addfile(info, source)
    os.replace(partial, out / "autograde.tar")
    print(f"wrote {out / 'autograde-Makefile'} and {out / 'autograde.tar'} ({len(files)} files of the project)")
    print("Autolab problems (names and maximum scores):")
    for task in TASKS:
        print(f"  {task}  {points[task]}")
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
        done = run_grader(work / "submission", results)
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


def command_student_release(arguments):
    out = Path(arguments.out).resolve()
    if out.exists() and (not out.is_dir() or any(out.iterdir())):
        fail(f"{out} exists and is not empty: give a new folder")
    files = project_files(STUDENT_EXCLUDED)
    check_sources(files)
    if WORKFLOW not in files:
        fail(f"{WORKFLOW} is missing: generate it first with /usr/bin/python3 tests/grader/package.py classroom")
    out.mkdir(parents=True, exist_ok=True)
    for path in files:
        target = out / path
        target.parent.mkdir(parents=True, exist_ok=True)
        if path.endswith(".md"):
            target.write_text(students_text((REPO / path).read_text()))
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
    command = commands.add_parser("autolab-run", help="(inside the Autolab package) grade the handin in FOLDER")
    command.add_argument("folder", metavar="FOLDER")
    return parser.parse_args(argv)


def main(argv=None):
    arguments = parse_arguments(sys.argv[1:] if argv is None else argv)
    handler = {
        "gradescope": command_gradescope, "autolab": command_autolab, "classroom": command_classroom,
        "student-release": command_student_release, "gradescope-setup": command_gradescope_setup,
        "gradescope-run": command_gradescope_run, "autolab-run": command_autolab_run,
    }[arguments.command]
    return handler(arguments)


if __name__ == "__main__":
    sys.exit(main())
