#!/usr/bin/python3
"""Tests of class grading (grade_class.py, ./build.sh grade --class DIR).

    /usr/bin/python3 tests/grader/tests/test_class.py WORK_FOLDER [Case.test ...]

A class is made from the project's own material (the reference solutions, the stubs, two
mutants of each of three tasks, one of propagate twice, the hostile files and a mix) and written in
each layout the class grader reads. It is graded in those three tasks (the cheapest to grade;
every step of the grading is the same for the others) and propagate (whose failures draw their
case) on a Dask LocalCluster of two worker processes that the test starts, interrupted part-way
and resumed, graded again with a worker killed part-way, and compared with grading each student
alone.
"""

import json
import os
import random
import re
import shutil
import signal
import subprocess
import sys
import tarfile
import time
import unittest
import zipfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
GRADER = HERE.parent  # the grader, whose tests these are
REPO = HERE.parents[2]
sys.path.insert(0, str(GRADER))
import browser  # noqa: E402
import grade_class  # noqa: E402
import package  # noqa: E402
from course import OPTIONAL, TASK_FILE  # noqa: E402
from disguises import hidden  # noqa: E402
from test_grader import mutant_source  # noqa: E402

WORK = None  # set from the command line
MUTATED = ["init_velocities", "visualize_table", "kinetic_energy"]  # some mutants of each are students
MUTANTS_PER_TASK = 3  # every mutant alone is grader.Mutants' job; the class needs a few per task
DRAWN = "propagate"  # two mutants of it, so that the class report links a failing case's picture
DRAWN_MUTANT = "whole_velocity_swap"
DRAWN_MUTANT_TOO = "full_reversal_at_wall"
GRADED = MUTATED + [DRAWN]
LAYOUTS = grade_class.LAYOUTS


def run(command, **options):
    done = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, errors="replace",
                          **options)
    return done.returncode, done.stdout


def the_class(mutants_per_task=MUTANTS_PER_TASK):
    """{student: {file name: bytes}}: the students' files for the graded tasks (every mutant of
    the three tasks with mutants_per_task None)."""
    def files(**sources):
        return {TASK_FILE[task]: path.read_bytes() if isinstance(path, Path) else path
                for task, path in sources.items()}
    reference = {task: REPO / "solutions" / TASK_FILE[task] for task in GRADED}
    stubs = {task: REPO / "tasks" / TASK_FILE[task] for task in GRADED}
    students = {"reference": files(**reference), "stubs": files(**stubs),
                "hostile": files(**{task: HERE / "hostile" / TASK_FILE[task] for task in GRADED})}
    for task in MUTATED:
        for mutant in sorted((REPO / "tests" / "mutants" / task).glob("*.mutant"))[:mutants_per_task]:
            students[f"{task}-{mutant.stem}"] = files(**{**reference, task: mutant_source(mutant).encode()})
    drawn = mutant_source(REPO / "tests" / "mutants" / DRAWN / f"{DRAWN_MUTANT}.mutant").encode()
    students[f"{DRAWN}-{DRAWN_MUTANT}"] = files(**{**reference, DRAWN: drawn})
    students[f"{DRAWN}-{DRAWN_MUTANT}-too"] = files(**{**reference, DRAWN: drawn})  # graded once, copied
    other = REPO / "tests" / "mutants" / DRAWN / f"{DRAWN_MUTANT_TOO}.mutant"
    students[f"{DRAWN}-{DRAWN_MUTANT_TOO}"] = files(**{**reference, DRAWN: mutant_source(other).encode()})
    mutant = sorted((REPO / "tests" / "mutants" / "kinetic_energy").glob("*.mutant"))[0]
    students["mixed"] = files(init_velocities=reference["init_velocities"], visualize_table=stubs["visualize_table"],
                              kinetic_energy=mutant_source(mutant).encode(), propagate=reference[DRAWN])
    # For the report's mistakes and the copies: the same files as another student's, a file that
    # does not compile, another correct propagate written apart (honest), and the reference's
    # propagate disguised: comments gone, names changed, functions in another order (a copier).
    students["reference-again"] = files(**reference)
    students["stubs-again"] = files(**stubs)
    students["does-not-compile"] = files(**{**reference, "kinetic_energy": b"double kinetic_energy( {\n"})
    students["honest"] = files(**{**reference, **{task: HERE / "honest" / TASK_FILE[task] for task in GRADED
                                                  if (HERE / "honest" / TASK_FILE[task]).is_file()}})
    students["copier"] = files(**{**reference, DRAWN: COPIER_FILE.encode()})
    return students


# The copier's propagate: the reference's, its names renamed, its functions reordered, its
# comments replaced (tests/grader/tests/disguises.py).
COPIER_FILE = hidden((REPO / "solutions" / TASK_FILE[DRAWN]).read_text(), random.Random(5))


def write_layout(layout, students, folder):
    """Writes the class in a layout; returns {name the layout gives: student}."""
    shutil.rmtree(folder, ignore_errors=True)
    folder.mkdir(parents=True)
    names = {}
    for number, (student, files) in enumerate(sorted(students.items()), start=1):
        if layout == "folders":  # some in a tasks/ folder, some zipped, some loose
            if number % 3 == 0:
                with zipfile.ZipFile(folder / f"{student}.zip", "w") as archive:
                    for name, text in files.items():
                        archive.writestr(f"{student}-main/tasks/{name}", text)
            else:
                own = folder / student / ("tasks" if number % 3 == 1 else "")
                own.mkdir(parents=True, exist_ok=True)
                for name, text in files.items():
                    (own / name).write_bytes(text)
            names[student] = student
        elif layout == "gradescope":  # an export, zipped, with its metadata
            own = folder / "export" / f"submission_{1000 + number}"
            own.mkdir(parents=True)
            for name, text in files.items():
                (own / name).write_bytes(text)
            names[f"Student {student}"] = student
        elif layout == "autolab":  # a tar per handin, an older version of some
            email = f"{student}@example.edu"
            for version, content in ([(1, {}), (2, files)] if number % 2 else [(3, files)]):
                with tarfile.open(folder / f"{email}_{version}_handin.tar", "w") as archive:
                    for name, text in (content or {TASK_FILE["kinetic_energy"]: b"// an older version\n"}).items():
                        path = folder / "member"
                        path.write_bytes(text)
                        archive.add(path, arcname=f"tasks/{name}")
                        path.unlink()
            names[email] = student
        elif layout == "classroom":  # gh classroom clone student-repos: a git repository each
            own = folder / f"billiard-course-{student}"
            (own / ".git").mkdir(parents=True)
            (own / "tasks").mkdir()
            for name, text in files.items():
                (own / "tasks" / name).write_bytes(text)
            names[student] = student
    if layout == "gradescope":
        metadata = "".join(f"submission_{1000 + number}:\n  :submitters:\n  - :name: Student {student}\n"
                           f"    :email: {student}@example.edu\n    :sid: '{number}'\n  :score: 0.0\n"
                           for number, student in enumerate(sorted(students), start=1))
        (folder / "export" / "submission_metadata.yml").write_text(metadata)
        shutil.make_archive(str(folder / "assignment_export"), "zip", folder / "export")
        shutil.rmtree(folder / "export")
    return names


def gradebook(results, maxima=False):
    """{student: {task: points}} from a class's gradebook.csv (the graded tasks); with maxima, its
    first row instead, the maxima ({column: points})."""
    import csv
    with open(results / "gradebook.csv") as file:
        rows = list(csv.DictReader(file))
    if maxima:
        return {column: int(value) for column, value in rows[0].items() if column != "student" and value}
    assert rows[0]["student"] == grade_class.MAXIMA_ROW, rows[0]
    return {row["student"]: {task: int(row[task]) for task in GRADED} for row in rows[1:]}


def run_class(class_folder, results, *options, wait=True):
    command = ["/usr/bin/python3", str(GRADER / "grade.py"), "--class", str(class_folder), "--results", str(results),
               *[word for task in GRADED for word in ("--task", task)], *options]
    if not wait:
        # A process group of its own, as a command typed at a terminal has.
        return subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                                start_new_session=True)
    return run(command, timeout=1800)


class Layouts(unittest.TestCase):
    def test_every_layout_names_each_student_and_finds_their_files(self):
        students = the_class()
        self.assertGreaterEqual(len(students), 10)
        for layout in LAYOUTS:
            folder = WORK / "layouts" / layout
            names = write_layout(layout, students, folder)
            source = next(folder.iterdir()) if layout == "gradescope" else folder
            found, read = grade_class.read_class(source, WORK / "layouts" / f"{layout}-work")
            self.assertEqual(found, layout)
            self.assertEqual(sorted(student.name for student in read), sorted(names))
            grade_class.safe_folders(read)
            for student in read:
                grade_class.find_files(student, WORK / "layouts" / f"{layout}-work")
                expected = students[names[student.name]]
                self.assertEqual({TASK_FILE[task]: student.files[task] for task in GRADED}, expected,
                                 f"{layout}: {student.name}")

    def test_a_change_to_one_suite_changes_that_task_key_alone(self):
        copy = WORK / "fingerprints"
        shutil.rmtree(copy, ignore_errors=True)
        for part in ["CMakeLists.txt", "CMakePresets.json", "lib/include", "lib/src", "tests/support", "tests/graded",
                     "tests/CMakeLists.txt", "tests/grader", "solutions", "tasks"]:
            source, target = REPO / part, copy / part
            target.parent.mkdir(parents=True, exist_ok=True)
            (shutil.copytree if source.is_dir() else shutil.copyfile)(source, target)
        saved = grade_class.REPO
        try:
            grade_class.REPO = copy
            before = grade_class.suite_fingerprints()
            with open(copy / "tests" / "graded" / "test_kinetic_energy.cpp", "a") as file:
                file.write("\n// a fix to a test\n")
            after = grade_class.suite_fingerprints()
            self.assertEqual([task for task in before if before[task] != after[task]], ["kinetic_energy"])
            with open(copy / "tests" / "support" / "graded.cpp", "a") as file:
                file.write("\n// a fix to the support code\n")
            self.assertTrue(all(after[task] != value for task, value in grade_class.suite_fingerprints().items()))
        finally:
            grade_class.REPO = saved


class OnACluster(unittest.TestCase):
    def test_a_class_on_two_workers_resumes_and_reports(self):
        from distributed import LocalCluster
        students = the_class()
        folder = WORK / "class-folders"
        write_layout("folders", students, folder)
        results = WORK / "results-folders"
        shutil.rmtree(results, ignore_errors=True)

        # Interrupted part-way (Ctrl-C), with its own two local workers: what finished is kept.
        # (A task file several students hand in alike, such as the stub, is graded once.)
        process = run_class(folder, results, "--workers", "2", wait=False)
        records = results / "students"

        def graded_files():
            return {json.loads(path.read_text())["key"] for path in records.glob("*/records/*.json")}
        deadline = time.monotonic() + 900
        while time.monotonic() < deadline and process.poll() is None and len(graded_files()) < 6:
            time.sleep(0.2)
        os.killpg(process.pid, signal.SIGINT)  # Ctrl-C at a terminal: the whole process group
        output = process.communicate(timeout=300)[0]
        self.assertEqual(process.returncode, 130, output)
        self.assertIn("run the same command again to grade the rest", output)
        self.assertNotIn("Traceback", output, "Ctrl-C stops the grading in one line")
        # The gradebook and the report of those finished, marked partial.
        import csv
        with open(results / "gradebook.csv") as file:
            rows = list(csv.DictReader(file))[1:]
        finished = [row["student"] for row in rows if all(row[task] for task in GRADED)]
        self.assertTrue(rows and set(finished) < set(students), rows)
        self.assertIn(f"interrupted with {len(finished)} of {len(students)} students graded in every task", output)
        self.assertIn(f"Partial: the grading was interrupted with {len(finished)} of {len(students)} students graded "
                      "in every task", (results / "report.html").read_text())
        distinct = int(re.search(r"\((\d+) different task files", output)[1])
        kept = graded_files()
        self.assertGreaterEqual(len(kept), 6, output)
        self.assertLess(len(kept), distinct, output)

        # Run again on a cluster the test starts: only the rest is graded, and a worker killed
        # part-way is started again by Dask, which grades its student elsewhere.
        with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0") as cluster:
            process = run_class(folder, results, "--client", cluster.scheduler_address, wait=False)
            self.kill_a_worker_once_grading(cluster, records, process, after=len(list(records.glob("*/records/*.json"))))
            output = process.communicate(timeout=1800)[0]
            self.assertEqual(process.returncode, 0, output[-5000:])
            self.assertEqual(int(re.search(r"\((\d+) different task files", output)[1]), distinct - len(kept),
                             output[:2000])
        self.check_progress(output, students)
        points = gradebook(results)
        self.assertEqual(sorted(points), sorted(students))
        self.assertEqual(points["reference"], {task: max(row[task] for row in points.values()) for task in GRADED})
        # The gradebook's first row: each graded task's maximum (the reference's points), and the
        # totals of those (the others were not graded here).
        maxima = gradebook(results, maxima=True)
        required = [task for task in GRADED if task not in OPTIONAL]
        self.assertEqual(maxima, {**points["reference"], "total": sum(points["reference"][t] for t in required),
                                  "optional": sum(points["reference"][t] for t in GRADED if t in OPTIONAL)})
        self.assertEqual(set(points["stubs"].values()), {0})
        for correct in ["reference-again", "honest", "copier"]:  # correct code, whoever wrote it: full points
            self.assertEqual(points[correct], points["reference"], correct)
        for task in MUTATED:  # every mutant costs points in its own task only
            for student, row in points.items():
                if student.startswith(f"{task}-"):
                    self.assertLess(row[task], points["reference"][task], student)
                    self.assertEqual({t: row[t] for t in MUTATED if t != task},
                                     {t: points["reference"][t] for t in MUTATED if t != task}, student)
        (WORK / "points.json").write_text(json.dumps(points))  # for SameAsAlone, when it runs

        # A finished class: a run again grades nobody.
        status, output = run_class(folder, results, "--workers", "2")
        self.assertEqual(status, 0, output)
        self.assertIn(f"{len(students)} up to date, 0 to grade (0 different task files", output)

        # The instructor's files: every student's results, the tests' table and the report.
        for student in students:
            report = json.loads((results / "students" / student / "results.json").read_text())
            self.assertFalse([t for t in report["tests"] if t["visibility"] == "hidden" and t["name"] != f"{t['name'].split(':')[0]}: hidden test"])
        tests_csv = (results / "tests.csv").read_text()
        self.assertIn("most_common_failure", tests_csv.splitlines()[0])
        page = (results / "report.html").read_text()
        self.assertEqual(page.count("<svg"), 3)
        self.check_mistakes(results, points, students)
        self.check_copies(results, students)
        for student in students:  # every student linked to their own report
            self.assertIn(f'href="students/{student}/report.html"', page)
            self.assertTrue((results / "students" / student / "report.html").is_file(), student)
        # The students whose propagate fails (one graded, one copied): the pictures of their failing
        # cases, in their results and their own reports; tests.csv links one for each test they
        # fail most commonly, and so does the class report for those among the most-failed tests.
        for student in [f"{DRAWN}-{DRAWN_MUTANT}", f"{DRAWN}-{DRAWN_MUTANT}-too"]:
            drawn = results / "students" / student
            pictures = sorted(path.name for path in (drawn / "pictures").glob("*.svg"))
            self.assertTrue(pictures, f"{student}: the failing propagate tests drew nothing")
            own = json.loads((drawn / "results.json").read_text())
            self.assertEqual(len([t for t in own["tests"] if t.get("output_format") == "html"]), len(pictures))
            self.assertEqual((drawn / "report.html").read_text().count("data:image/svg+xml;base64,"), len(pictures))
        import csv
        with open(results / "tests.csv") as file:
            rows = list(csv.DictReader(file))
        linked = [row for row in rows if row["task"] == DRAWN and row["picture"]]
        self.assertTrue(linked, "tests.csv links no picture of a failing propagate test")
        links = [row["picture"] for row in rows if row["picture"]] + re.findall(r'href="(students/[^"]+\.svg)"', page)
        self.assertTrue(all((results / link).is_file() for link in links), links)
        self.check_drawn(results / "report.html")

    def check_progress(self, output, students):
        """The run's lines count every student to grade once, copies too, from 1 to the number the
        first line announced; the grader's build is a step of its own."""
        to_grade = int(re.search(r"(\d+) to grade", output)[1])
        lines = re.findall(r"^\[(\d+)/(\d+)\] ([^:]+):", output, flags=re.M)
        self.assertEqual([int(k) for k, _, _ in lines], list(range(1, to_grade + 1)), output[-5000:])
        self.assertEqual({int(n) for _, n, _ in lines}, {to_grade})
        self.assertEqual(len({name for _, _, name in lines}), to_grade, "a student graded twice, or not shown")
        self.assertTrue(set(name for _, _, name in lines) <= set(students))
        self.assertRegex(output, r"grade: the grader is ready on 1 machine for \d+ workers \(\d+ s\)")
        self.assertRegex(output, r"the same files as [^\n]*, graded once", "no student shown as a copy")

    def check_mistakes(self, results, points, students):
        """mistakes.csv: a row for every task with a failure; each mutant's mistake as a row that
        names it (its lead hint's words) with its student; the file that does not compile, the
        endless loop and the untouched stubs as mistakes of their own; shares of the class."""
        import csv
        from test_grader import lead_hint
        with open(results / "mistakes.csv") as file:
            mistakes = list(csv.DictReader(file))
        failing = {task for row in points.values() for task in GRADED if row[task] < points["reference"][task]}
        self.assertEqual({row["task"] for row in mistakes}, failing)
        self.assertTrue(all(int(row["of"]) == len(students) for row in mistakes), mistakes)

        def row_of(student, task):
            return next((row for row in mistakes if row["task"] == task and student in row["names"].split("; ")), None)
        for student in students:
            task = next((t for t in GRADED if student.startswith(t + "-")), None)
            if task is None:
                continue
            mutant = student[len(task) + 1:].removesuffix("-too")
            row = row_of(student, task)
            self.assertIsNotNone(row, f"{student}'s mistake in {task} is in no row")
            words = lead_hint(REPO / "tests" / "mutants" / task / f"{mutant}.mutant")
            if words:
                self.assertIn(words.lower(), row["mistake"].lower(), student)
        self.assertIn("does not compile", row_of("does-not-compile", "kinetic_energy")["mistake"])
        self.assertEqual(row_of("hostile", DRAWN)["mistake"], grade_class.class_report.TIMEOUT)
        for task in GRADED:
            self.assertEqual(row_of("stubs", task)["mistake"], grade_class.class_report.NOT_WRITTEN_YET)
            self.assertIn("stubs-again", row_of("stubs", task)["names"].split("; "))
        ranked = [(row["mistake"] == grade_class.class_report.NOT_WRITTEN_YET, -int(row["students"]),
                   -int(row["points_lost"])) for row in mistakes]
        self.assertEqual(ranked, sorted(ranked), "not ranked by students, then points, the stubs last")

    def check_copies(self, results, students):
        """similarity.csv: the disguised copy of the reference's propagate is flagged beside the
        reference, the honest propagate beside no one; identical files flagged; the stub never."""
        import csv
        with open(results / "similarity.csv") as file:
            pairs = list(csv.DictReader(file))

        def pair(first, second, task):
            return next((row for row in pairs if row["task"] == task and {row["first"], row["second"]} == {first, second}),
                        None)
        for task in GRADED:
            self.assertEqual(pair("reference", "reference-again", task)["identical"], "yes", task)
        self.assertEqual([row for row in pairs if {"stubs", "stubs-again"} & {row["first"], row["second"]}], [])
        if grade_class.similarity.node_too_old():  # Ubuntu 22.04: the report says so, in one line
            self.assertIn("Near-copies were not looked for", (results / "report.html").read_text())
            return
        copied = pair("copier", "reference", DRAWN)
        self.assertIsNotNone(copied, "the disguised copy is not flagged")
        self.assertEqual(copied["identical"], "no")
        self.assertGreaterEqual(max(int(copied["first_share"]), int(copied["second_share"])),
                                grade_class.similarity.SHARE_FLAGGED)
        self.assertTrue((results / copied["view"]).is_file())
        renamed = next(word for word in re.findall(r"\w+", COPIER_FILE) if re.fullmatch(r"[a-z]+_\w+_\d+", word))
        self.assertIn(renamed, (results / copied["view"]).read_text())
        self.assertEqual([row for row in pairs if "honest" in (row["first"], row["second"])], [])

    def kill_a_worker_once_grading(self, cluster, records, process, after=0):
        """Kills (SIGKILL) one of the cluster's worker processes once the run has saved a student
        (more than `after` records)."""
        from distributed import Client
        deadline = time.monotonic() + 900
        while time.monotonic() < deadline and process.poll() is None and \
                len(list(records.glob("*/records/*.json"))) <= after:
            time.sleep(0.2)
        self.assertIsNone(process.poll(), "the run ended before a worker could be killed")
        with Client(cluster.scheduler_address, timeout=30) as client:
            pids = client.run(os.getpid)
        os.kill(next(iter(pids.values())), signal.SIGKILL)

    def check_drawn(self, page):
        """Opens the page in Debian's headless chromium and checks what it draws: the figures'
        colours (the bars of the totals and of the most-failed tests) on a page that is not blank."""
        picture, output = browser.screenshot(page)
        self.assertIsNotNone(picture, output[-2000:])
        counts = browser.colour_counts(picture)
        green, red = browser.rgb("#2e7d32"), browser.rgb("#c62828")  # report_html's bar colours
        self.assertGreater(counts.get(green, 0), 2000, "the figures of the totals and tasks are not drawn")
        self.assertGreater(counts.get(red, 0), 2000, "the figure of the most-failed tests is not drawn")
        self.assertGreater(len(counts), 50, "the page is (nearly) blank")


def one_of_each_kind(students):
    """The students of the class that differ in kind (the reference, the stubs, the attacker, a
    mutant of each mutated task, a mix, a compile error, the honest and the copier): the others
    repeat one of these in another file of the same kind."""
    firsts = {task: min(name for name in students if name.startswith(task + "-")) for task in MUTATED}
    kinds = {"reference", "stubs", "hostile", "mixed", "does-not-compile", "honest", "copier",
             f"{DRAWN}-{DRAWN_MUTANT}", *firsts.values()}
    assert kinds <= set(students), kinds - set(students)
    return {name: files for name, files in students.items() if name in kinds}


class SameAsAlone(unittest.TestCase):
    """The class of OnACluster, one student of each kind, in the other layouts, graded on a
    cluster of two workers, gives the same points as in the folders layout; and so does each of
    them graded alone, as the platforms grade one submission (label platforms: some minutes; the
    points of OnACluster's run, where it ran in this build folder). Every student of the class in
    every layout is read by Layouts; the gradings behind a layout are the same."""

    def test_every_layout_and_each_student_alone_give_the_class_points(self):
        from distributed import LocalCluster
        whole = the_class()
        students = one_of_each_kind(whole)
        saved = WORK / "points.json"
        if not saved.is_file():  # OnACluster has not run in this build folder: the folders layout here
            write_layout("folders", whole, WORK / "class-folders")
            status, output = run_class(WORK / "class-folders", WORK / "results-folders", "--workers", "2")
            self.assertEqual(status, 0, output[-5000:])
            saved.write_text(json.dumps(gradebook(WORK / "results-folders")))
        points = json.loads(saved.read_text())
        with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0") as cluster:
            for layout in ["gradescope", "autolab", "classroom"]:
                names = write_layout(layout, students, WORK / f"class-{layout}")
                source = next((WORK / f"class-{layout}").iterdir()) if layout == "gradescope" else WORK / f"class-{layout}"
                shutil.rmtree(WORK / f"results-{layout}", ignore_errors=True)
                status, output = run_class(source, WORK / f"results-{layout}", "--client", cluster.scheduler_address)
                self.assertEqual(status, 0, output[-5000:])
                self.assertEqual({names[name]: value for name, value in gradebook(WORK / f"results-{layout}").items()},
                                 {student: points[student] for student in students}, layout)
        # Each student graded alone. (In propagate only those whose file is not the reference's: the
        # others' class points there must be the reference student's, and grading that file again
        # would only repeat it.)
        submission = WORK / "alone" / "submission"
        reference_drawn = (REPO / "solutions" / TASK_FILE[DRAWN]).read_bytes()
        for student, files in sorted(students.items()):
            tasks = MUTATED + ([DRAWN] if student == "reference" or files.get(TASK_FILE[DRAWN]) != reference_drawn else [])
            shutil.rmtree(submission.parent, ignore_errors=True)
            submission.mkdir(parents=True)
            for task in package.TASKS:
                (submission / TASK_FILE[task]).write_bytes(files.get(TASK_FILE[task])
                                                           or (REPO / "tasks" / TASK_FILE[task]).read_bytes())
            command = ["/usr/bin/python3", str(GRADER / "grade.py"), "--submission", str(submission), "--results",
                       str(submission.parent / "results"), "--build", str(WORK / "alone-build"),
                       *grade_class.grading_options(tasks)]
            if os.geteuid() == 0:
                command.append("--protect-reference")
            status, output = run(command, timeout=900)
            self.assertEqual(status, 0, output[-3000:])
            report = json.loads((submission.parent / "results" / "results.json").read_text())
            alone = {task: sum(test["score"] for test in report["tests"] if test["name"].startswith(task + ":"))
                     for task in tasks}
            self.assertEqual(alone, {task: points[student][task] for task in tasks}, student)
            if DRAWN not in tasks:
                self.assertEqual(points[student][DRAWN], points["reference"][DRAWN], student)


class Hostile(unittest.TestCase):
    def test_attackers_beside_honest_students_cost_them_nothing(self):
        """A class of two honest students, each graded beside an attacker on two workers: one
        attacker kills every process it can signal and reads and overwrites the other students'
        files (tests/grader/tests/hostile/attacks/class_neighbours), the other holds memory and
        processors (memory_and_processes). The honest students keep full points, the attackers
        score 0 in the attacked tasks, and no attacker's output holds another student's file."""
        import test_attacks
        results = WORK / "results-hostile"
        shutil.rmtree(results, ignore_errors=True)
        neighbours = test_attacks.attack("class_neighbours", CLASS=results, REPO=REPO)
        memory = test_attacks.attack("memory_and_processes")
        tasks = ["kinetic_energy", test_attacks.task_of(memory)]
        reference = {task: (REPO / "solutions" / TASK_FILE[task]).read_text() for task in tasks}
        students = {
            # Each honest student's files are their own (graded, not copied from another's).
            "honest-ada": {TASK_FILE[task]: text + "\n// ada's own\n" for task, text in reference.items()},
            "honest-bob": {TASK_FILE[task]: text + "\n// bob's own\n" for task, text in reference.items()},
            "attacker-neighbours": {**{TASK_FILE[task]: text for task, text in reference.items()},
                                    TASK_FILE["kinetic_energy"]: neighbours.read_text()},
            "attacker-memory": {**{TASK_FILE[task]: text for task, text in reference.items()},
                                memory.name: memory.read_text()},
        }
        shutil.rmtree(neighbours.parent)
        folder = WORK / "class-hostile"
        shutil.rmtree(folder, ignore_errors=True)
        for student, files in students.items():
            (folder / student).mkdir(parents=True)
            for name, text in files.items():
                (folder / student / name).write_text(text)
        status, output = run(["/usr/bin/python3", str(GRADER / "grade.py"), "--class", str(folder), "--results",
                              str(results), "--workers", "2", *[word for task in tasks for word in ("--task", task)]],
                             timeout=1800)
        self.assertEqual(status, 0, output[-5000:])
        import csv
        with open(results / "gradebook.csv") as file:
            rows = {row["student"]: row for row in csv.DictReader(file) if row["student"] in students}
        maxima = {task: sum(test["max_score"] for test in json.loads(
            (results / "students" / "honest-ada" / "results.json").read_text())["tests"] if test["name"].startswith(task + ":"))
            for task in tasks}
        for honest in ["honest-ada", "honest-bob"]:
            self.assertEqual({task: int(rows[honest][task]) for task in tasks}, maxima, honest)
        self.assertEqual(int(rows["attacker-neighbours"]["kinetic_energy"]), 0)
        self.assertEqual(int(rows["attacker-neighbours"][tasks[1]]), maxima[tasks[1]])
        self.assertEqual(int(rows["attacker-memory"][tasks[1]]), 0)
        self.assertEqual(int(rows["attacker-memory"]["kinetic_energy"]), maxima["kinetic_energy"])
        for attacker in ["attacker-neighbours", "attacker-memory"]:
            written = "".join(path.read_text(errors="replace") for path in (results / "students" / attacker).rglob("*")
                              if path.is_file())
            self.assertNotIn("ada's own", written)
            self.assertNotIn("bob's own", written)
        self.assertEqual(test_attacks.leftovers(), [])

    def test_students_who_spoil_the_class_files_spoil_nothing(self):
        """A Gradescope export with two students of one name (one hands in the reference, one the
        stub), names that are spreadsheet formulas (a Gradescope name is the student's own profile
        text), a file that prints the judge's kind of lines and throws a message of broken mathtext
        (hostile/attacks/mathtext_message) and a megabyte of one token: every student a row of
        their own, keyed by their submission, formulas text, the report with its figures and a line
        about the file left out of the comparison, the mistakes worded by the judge."""
        import csv
        import test_attacks
        task = "init_velocities"
        reference = (REPO / "solutions" / TASK_FILE[task]).read_text()
        submitters = [  # (name, sid, file)
            ("Wei Zhang", "1", reference + "\n// Wei's own\n"),
            ("Wei Zhang", "2", (REPO / "tasks" / TASK_FILE[task]).read_text()),
            ('=HYPERLINK("http://example.com/","open me")', "3", reference + "\n// a formula's own\n"),
            ("@SUM(A1:A9)", "4", test_attacks.attack("mathtext_message").read_text()),
            ("+1 Flood", "5", "x;" * 500_000),
        ]
        folder, results = WORK / "class-spoilers", WORK / "results-spoilers"
        for path in (folder, results):
            shutil.rmtree(path, ignore_errors=True)
        metadata = ""
        for number, (name, sid, text) in enumerate(submitters, start=1):
            (folder / f"submission_{number}").mkdir(parents=True)
            (folder / f"submission_{number}" / TASK_FILE[task]).write_text(text)
            metadata += (f"submission_{number}:\n  :submitters:\n  - :name: {json.dumps(name)}\n"
                         f"    :email: s{sid}@example.edu\n    :sid: '{sid}'\n")
        (folder / "submission_metadata.yml").write_text(metadata)
        status, output = run(["/usr/bin/python3", str(GRADER / "grade.py"), "--class", str(folder), "--results",
                              str(results), "--workers", "2", "--task", task], timeout=1800)
        self.assertEqual(status, 0, output[-5000:])
        with open(results / "gradebook.csv", newline="") as file:
            rows = list(csv.DictReader(file))
        maximum = int(rows[0][task])
        by_sid = {row["sid"]: row for row in rows[1:]}
        self.assertEqual(sorted(by_sid), ["1", "2", "3", "4", "5"], rows)
        self.assertEqual({sid: int(row[task]) for sid, row in by_sid.items()},
                         {"1": maximum, "2": 0, "3": maximum, "4": 0, "5": 0})
        self.assertEqual([by_sid[sid]["student"] for sid in "12"], ["Wei Zhang", "Wei Zhang"])
        self.assertEqual(by_sid["3"]["student"], "'" + submitters[2][0])
        self.assertEqual(by_sid["1"]["submission"], "submission_1")
        for name in ["gradebook.csv", "mistakes.csv", "tests.csv", "similarity.csv"]:
            with open(results / name, newline="") as file:
                for row in csv.reader(file):
                    for cell in row:
                        self.assertFalse(cell.startswith(grade_class.class_report.FORMULA_START), f"{name}: {cell!r}")
        page = (results / "report.html").read_text()
        self.assertEqual(page.count("<figure><svg"), 3, "the totals, the tasks and the mistakes are drawn")
        self.assertNotIn("The figure of", page)
        self.assertIn("not compared", page, "the flood is left out with a line saying so")
        with open(results / "mistakes.csv", newline="") as file:
            mistakes = list(csv.DictReader(file))
        self.assertTrue(mistakes)
        for mistake in mistakes:
            self.assertNotIn("everything is right", mistake["mistake"], "a hint of the student's own leads")
        self.assertIn("Wei Zhang", {mistake["names"] for mistake in mistakes})
        self.assertEqual(test_attacks.leftovers(), [])


def main():
    global WORK
    if len(sys.argv) < 2:
        print("usage: test_class.py WORK_FOLDER [Case.test ...]", file=sys.stderr)
        return 2
    WORK = Path(sys.argv[1]).absolute() / "class-tests"
    WORK.mkdir(parents=True, exist_ok=True)
    program = unittest.main(argv=[sys.argv[0], "-v", *sys.argv[2:]], exit=False)
    return 0 if program.result.wasSuccessful() else 1


if __name__ == "__main__":
    sys.exit(main())
