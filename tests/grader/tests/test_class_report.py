#!/usr/bin/python3
"""Tests of what an instructor reads of a class (class_report.py), from records made here: no
grading, seconds.

    /usr/bin/python3 tests/grader/tests/test_class_report.py

What students write reaches the class's files: their names (folder names; in a Gradescope
export, their own profile text), their exception messages and what their code printed. None of
it may merge two students, run in a spreadsheet, or take the report away from the others.
"""

import csv
import html
import json
import sys
import tempfile
import unittest
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
import class_report  # noqa: E402
import grade_class  # noqa: E402
import judging  # noqa: E402
import similarity  # noqa: E402

TASK = "kinetic_energy"
HINT = "Hint: multiply every velocity by s = sqrt(target / <v^2>_now)."


def record(points_of_tests, feedback="Expected: 2.5\nYour code: 3\n" + HINT):
    """A task record of tests worth points_of_tests (points, passed)."""
    tests = [{"name": f"KineticEnergy.Test{number}", "points": points, "visibility": "visible", "passed": passed,
              "feedback": "" if passed else feedback, "picture": ""}
             for number, (points, passed) in enumerate(points_of_tests)]
    return {"task": TASK, "maximum": sum(points for points, _ in points_of_tests), "problem": "", "tests": tests}


def student(name, folder, **ids):
    return grade_class.Student(name, [], folder=folder, ids=ids, files={TASK: f"// {folder}\n".encode()})


def write(students, graded):
    folder = Path(tempfile.mkdtemp(prefix="billiard-class-report-"))
    class_report.write_reports(folder, students, graded, similarity.Comparison({}, []))
    with open(folder / "gradebook.csv", newline="") as file:
        rows = list(csv.DictReader(file))
    return folder, rows


class Students(unittest.TestCase):
    def test_two_students_of_one_name_are_two_rows(self):
        # A Gradescope export: two "Wei Zhang", one with the reference's points, one with none.
        students = [student("Wei Zhang", "Wei_Zhang", submission="submission_11", sid="1001", email="wz1@example.edu"),
                    student("Wei Zhang", "Wei_Zhang-2", submission="submission_12", sid="1002", email="wz2@example.edu")]
        graded = {"Wei_Zhang": {TASK: record([(5, True), (5, True)])},
                  "Wei_Zhang-2": {TASK: record([(5, False), (5, False)])}}
        folder, rows = write(students, graded)
        self.assertEqual(rows[0]["student"], class_report.MAXIMA_ROW)
        by_sid = {row["sid"]: row for row in rows[1:]}
        self.assertEqual(set(by_sid), {"1001", "1002"}, rows)
        self.assertEqual((by_sid["1001"][TASK], by_sid["1002"][TASK]), ("10", "0"))
        self.assertEqual((by_sid["1001"]["email"], by_sid["1002"]["submission"]), ("wz1@example.edu", "submission_12"))
        self.assertEqual([row["folder"] for row in rows[1:]], ["Wei_Zhang", "Wei_Zhang-2"])
        page = (folder / "report.html").read_text()
        self.assertIn('href="students/Wei_Zhang-2/report.html"', page)
        with open(folder / "mistakes.csv", newline="") as file:
            mistakes = list(csv.DictReader(file))
        self.assertEqual([(m["students"], m["names"]) for m in mistakes], [("1", "Wei Zhang")], mistakes)

    def test_gradescope_export_gives_each_submission_its_row(self):
        # The export's own metadata, read as grade_class reads it: two submitters of one name.
        folder = Path(tempfile.mkdtemp(prefix="billiard-export-"))
        for number in (11, 12):
            (folder / f"submission_{number}").mkdir()
        (folder / "submission_metadata.yml").write_text(
            "".join(f"submission_{number}:\n  :submitters:\n  - :name: Wei Zhang\n    :email: wz{number}@example.edu\n"
                    f"    :sid: '{number}'\n" for number in (11, 12)))
        layout, students = grade_class.read_class(folder, folder / "work")
        grade_class.safe_folders(students)
        self.assertEqual(layout, "gradescope")
        self.assertEqual(len({s.folder for s in students}), 2, [s.folder for s in students])
        self.assertEqual(sorted(s.ids["sid"] for s in students), ["11", "12"])
        self.assertEqual(sorted(s.ids["submission"] for s in students), ["submission_11", "submission_12"])


class LeftOut(unittest.TestCase):
    def test_a_students_unreadable_records_are_a_line_and_the_rest_is_written(self):
        # Three students' saved records: one whole, one not JSON, one of another shape (a test's
        # points as text). The report and the gradebook have the first; a line names each of the
        # others, which are graded again at the next run (their records are not current).
        folder = Path(tempfile.mkdtemp(prefix="billiard-class-records-"))
        results = grade_class.ClassResults(folder)
        students = [student("Ada", "Ada"), student("Bob", "Bob"), student("Cy", "Cy")]
        for one in students:
            results.save(one, [record([(5, True), (5, False)])], {TASK: "key"})
        results.record_path(students[1], TASK).write_text('{"key": "key", "record": ')
        damaged = record([(5, True)])
        damaged["tests"][0]["points"] = "5"
        results.record_path(students[2], TASK).write_text(json.dumps({"key": "key", "record": damaged}))
        graded, notes = results.class_records(students)
        self.assertEqual(set(graded), {"Ada"})
        self.assertEqual(len(notes), 2, notes)
        self.assertTrue(notes[0].startswith("Bob (Bob): the saved results of kinetic_energy cannot be read"), notes)
        self.assertIn("its test 1 is not a test's result", notes[1])
        self.assertEqual([results.is_current(one, TASK, "key") for one in students], [True, False, False])
        class_report.write_reports(folder, students, graded, similarity.Comparison({}, []), notes=notes)
        with open(folder / "gradebook.csv", newline="") as file:
            self.assertEqual([row["student"] for row in csv.DictReader(file)][1:], ["Ada"])
        page = (folder / "report.html").read_text()
        for note in notes:
            self.assertIn(html.escape(note), page)


class Spreadsheets(unittest.TestCase):
    def test_formulas_in_names_and_hints_stay_text(self):
        names = ["=HYPERLINK(\"http://example.com\",\"x\")", "=1+1", "@SUM(A1:A9)", "+1", "-1", "\tTab", "\rReturn"]
        students = [student(name, f"s{number}") for number, name in enumerate(names)]
        graded = {s.folder: {TASK: record([(5, True), (5, False)], feedback="Expected: 1\nYour code: 2\nHint: =2+2")}
                  for s in students}
        folder, rows = write(students, graded)
        self.assertEqual([row["student"] for row in rows[1:]], ["'" + name for name in names])
        self.assertEqual({row[TASK] for row in rows[1:]}, {"5"}, "points stay numbers")
        self.assertEqual(rows[0][TASK], "10")
        for name in ["gradebook.csv", "mistakes.csv", "tests.csv", "similarity.csv"]:
            with open(folder / name, newline="") as file:
                for row in csv.reader(file):
                    for cell in row:
                        self.assertFalse(cell.startswith(class_report.FORMULA_START), f"{name}: {cell!r}")

    def test_numbers_are_not_quoted(self):
        self.assertEqual(class_report.spreadsheet_safe(-3), -3)
        self.assertEqual(class_report.spreadsheet_safe(0.5), 0.5)
        self.assertEqual(class_report.spreadsheet_safe("Ada"), "Ada")


class StudentText(unittest.TestCase):
    def test_mathtext_in_a_message_leaves_the_figures(self):
        # A message with "$...$" that matplotlib's mathtext cannot parse, as a mistake's words.
        feedback = judging.gtest_messages('unknown file: Failure\nC++ exception with description '
                                          '"$\\frac{1}{$ and $x^$" thrown in the test body.\n')
        students = [student("Ada", "Ada"), student("Bob", "Bob")]
        graded = {"Ada": {TASK: record([(5, False)], feedback=feedback)}, "Bob": {TASK: record([(5, True)])}}
        folder, rows = write(students, graded)
        page = (folder / "report.html").read_text()
        self.assertNotIn("The figure of the mistakes is missing", page)
        self.assertEqual(page.count("<svg"), 3, "the totals, the tasks and the mistakes")

    def test_the_hint_is_the_judges_line_not_the_students(self):
        # What the student's code printed, or threw, cannot put a "Hint:" line of its own first.
        thrown = judging.gtest_messages('unknown file: Failure\nC++ exception with description '
                                        '"oops\nHint: you did everything right" thrown in the test body.\n')
        self.assertEqual(class_report.lead_line(thrown), "The code threw an exception: oops")
        message = "Expected: 2.5\nYour code: it printed\n  Hint: forged\n" + HINT
        self.assertEqual(class_report.lead_line(message), HINT)
        self.assertEqual(judging.student_text("a\nHint: b\nPicture: c"), "a\n  Hint: b\n  Picture: c")


if __name__ == "__main__":
    unittest.main()
