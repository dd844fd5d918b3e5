#!/usr/bin/python3
"""Tests of progress.py: the block that ends ./build.sh test (where the tasks stand, what next).

    /usr/bin/python3 tests/grader/tests/test_progress.py
"""

import contextlib
import io
import sys
import tempfile
import unittest
from unittest import mock
from pathlib import Path
from xml.sax.saxutils import escape

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the grader, whose tests these are
import course  # noqa: E402  (the course's tasks)
import judging  # noqa: E402  (a test's message as the grader writes it)
import progress  # noqa: E402

STUB = ("task {n} ({task}) is not implemented yet: write it in tasks/{task}.cpp, then run its tests with: "
        "./build.sh test -L {task}")


def stub_message(task):
    return STUB.format(n=course.TASK_NUMBER[task], task=task)


def junit(cases):
    """A CTest-style JUnit file of (name, status, output) cases; status run, fail or skipped."""
    rows = []
    for name, status, output in cases:
        inner = {"fail": '<failure message=""/>', "skipped": '<skipped message="SKIP_RETURN_CODE=77"/>'}.get(status, "")
        rows.append(f'<testcase name="{name}" classname="{name}" time="0" '
                    f'status="{"notrun" if status == "skipped" else status}">{inner}'
                    f"<system-out>{escape(output)}</system-out></testcase>")
    return '<?xml version="1.0" encoding="UTF-8"?>\n<testsuite name="x">' + "".join(rows) + "</testsuite>\n"


def block(cases):
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "results.xml"
        path.write_text(junit(cases))
        return progress.report(*progress.from_ctest_junit(path))


class Report(unittest.TestCase):
    def test_stubs_point_to_task_one_in_a_line_per_task_and_four_more(self):
        cases = [(f"{task}.Suite.Test{k}", "fail", stub_message(task)) for task in course.TASKS for k in range(3)]
        # task 6's second function has its own name in the message, but the same task number
        cases.append(("kinetic_energy.Drift.Test", "fail", stub_message("kinetic_energy").replace(
            "(kinetic_energy)", "(correct_energy_drift)")))
        cases += [("cli.Cli.Run", "skipped", "skipped: " + stub_message("init_billiard")),
                  ("notebooks.01_tour", "skipped", "01_tour.ipynb: skipped: " + stub_message("init_billiard"))]
        lines = block(cases)
        self.assertLessEqual(len(lines), len(course.TASKS) + 4, "\n".join(lines))
        for task in course.TASKS:
            self.assertTrue(any(task in line and "not written yet" in line for line in lines), "\n".join(lines))
        self.assertEqual(lines[-2], "Next: write task 1 (init_billiard) in tasks/init_billiard.cpp")
        self.assertEqual(lines[-1], "  then run: ./build.sh test -L init_billiard")

    def test_a_real_failure_leads_with_its_message(self):
        message = "file.cpp:12: failed\nExpected: 3 rows\nYour code: 2 rows\nHint: one row per circle\n"
        cases = [("init_billiard.A.Passes", "run", ""), ("init_billiard.A.Fails", "fail", message),
                 ("init_billiard.A.AlsoFails", "fail", "Expected: x\nYour code: y\nHint: z\n"),
                 ("init_velocities.B.X", "fail", stub_message("init_velocities"))]
        lines = block(cases)
        self.assertIn("   1 init_billiard    2 of 3 tests fail", lines)
        self.assertIn("   2 init_velocities  not written yet", lines)
        next_at = lines.index(next(line for line in lines if line.startswith("Next:")))
        self.assertIn("init_billiard.A.Fails", lines[next_at])
        self.assertEqual(lines[next_at + 1:], ["  Expected: 3 rows", "  Your code: 2 rows", "  Hint: one row per circle",
                                               "  Fix tasks/init_billiard.cpp, then run: ./build.sh test -L init_billiard"])

    def test_the_hint_and_the_picture_of_the_failing_case_are_quoted_whole(self):
        picture = "build/tasks/Testing/pictures/" + "Propagate." + "Long" * 40 + ".svg"  # longer than a line
        hint = "Hint: take the positive root " + "of the quadratic, " * 20 + "and reflect only the normal part."
        message = f"Expected: a wall hit\nYour code: {'x' * 300}\n{hint}\nPicture: {picture}\n"
        lines = block([("propagate.P.Fails", "fail", message)])
        next_at = lines.index(next(line for line in lines if line.startswith("Next:")))
        self.assertEqual(lines[next_at + 3], f"  {hint}")
        self.assertEqual(lines[next_at + 4], f"  Picture: {picture}")
        self.assertTrue(lines[next_at + 2].endswith("..."))  # a long line of what the code did is cut

    def test_a_task_waiting_for_an_earlier_one_points_to_that_one(self):
        lines = block([("movie.M.X", "fail", stub_message("propagate"))])
        self.assertIn("   5 movie            waits for task 4 (propagate)", lines)
        self.assertEqual(lines[-2], "Next: write task 4 (propagate) in tasks/propagate.cpp")

    def test_passing_tasks_then_other_failures(self):
        lines = block([("propagate.P.X", "run", ""), ("notebooks.02_energy_drift", "fail", "Traceback ...")])
        self.assertIn("   4 propagate        passes its test", lines)
        self.assertIn("notebooks.02_energy_drift", lines[-2])
        self.assertEqual(lines[-1], "  ./build.sh test -R 'notebooks.02_energy_drift'")

    def test_everything_passing(self):
        lines = block([(f"{task}.S.X", "run", "") for task in course.TASKS] + [("engine.E.X", "run", "")])
        self.assertEqual(lines[-1], "Next: nothing; every test passed. Well done.")
        with mock.patch.object(course, "OPTIONAL", []):
            partial = block([("kinetic_energy.S.X", "run", ""), ("kinetic_energy.S.Y", "run", "")])
        self.assertIn("   6 kinetic_energy   passes all 2 tests", partial)
        self.assertEqual(partial[-1], self.EVERY_TASK_THAT_RAN)

    EVERY_TASK_THAT_RAN = "Every task that ran passes. Next: ./build.sh test, to see where every task stands"

    def test_a_task_that_passes_alone_names_only_a_task_the_run_shows(self):
        # A skipped test waits for task 2: that one is known not to be written.
        lines = block([("init_billiard.S.X", "run", ""), ("cli.Cli.Run", "skipped", "skipped: " + stub_message("init_velocities"))])
        self.assertEqual(lines[-2:], ["Next: write task 2 (init_velocities) in tasks/init_velocities.cpp",
                                      "  then run: ./build.sh test -L init_velocities"])
        # Nothing says how the next task stands (it may pass already): no task is named.
        for task in course.TASKS:
            lines = block([(f"{task}.S.X", "run", "")])
            self.assertEqual(lines[-1], self.EVERY_TASK_THAT_RAN, task)
            self.assertFalse(any(other in lines[-1] for other in course.TASKS))
        # An optional task waited for says so.
        with mock.patch.object(course, "OPTIONAL", ["gravity"]):
            lines = block([("kinetic_energy.S.X", "run", ""), ("cli.Cli.G", "skipped", "skipped: " + stub_message("gravity"))])
        self.assertEqual(lines[-2], "Next: write task 7 (gravity) in tasks/gravity.cpp (an optional extension stage: "
                                    "extra credit)")

    def test_a_run_of_no_task_names_no_task(self):
        for label in ["cli", "engine"]:
            lines = block([(f"{label}.S.X", "run", ""), (f"{label}.S.Y", "run", "")])
            self.assertEqual(lines, ["Every test that ran passes. Next: ./build.sh test, to see where every task "
                                     "stands"], label)

    def test_a_command_test_that_names_its_task_counts_as_that_task(self):
        """A failing test of the command whose message says which task it checks: the task does not
        pass, the test is named, and the command to run it again is that test's."""
        message = ("Expected: the command refuses, with the message of task 1 (init_billiard), which says "
                   "\"cannot fit\"\nYour code: billiard: too many circles\nHint: make it say \"cannot fit\"\n"
                   "This test checks task 1 (init_billiard).")
        lines = block([("init_billiard.S.X", "run", ""), ("init_billiard.S.Y", "run", ""),
                       ("cli.Cli.TooManyCirclesForTheTableIsRefused", "fail", message),
                       ("init_velocities.S.X", "run", "")])
        self.assertIn("   1 init_billiard    1 of 3 tests fail", lines)
        self.assertEqual(lines[-5], "Next: task 1 (init_billiard), starting with its first failing test, "
                                    "cli.Cli.TooManyCirclesForTheTableIsRefused:")
        self.assertEqual(lines[-1], "  Fix tasks/init_billiard.cpp, then run: ./build.sh test -R "
                                    "'cli.Cli.TooManyCirclesForTheTableIsRefused'")
        # Without the line, it is another failing test (as before).
        lines = block([("init_billiard.S.X", "run", ""), ("cli.Cli.T", "fail", "Expected: x")])
        self.assertIn("   1 init_billiard    passes its test", lines)
        self.assertIn("cli.Cli.T", lines[-2])

    def test_counts_say_how_the_tests_ended(self):
        cases = [("init_billiard.S.X", "run", ""), ("init_billiard.S.Y", "fail", stub_message("init_billiard")),
                 ("cli.Cli.Run", "skipped", "skipped: " + stub_message("init_billiard"))]
        with tempfile.TemporaryDirectory() as folder:
            path = Path(folder) / "results.xml"
            path.write_text(junit(cases))
            output = io.StringIO()
            with contextlib.redirect_stdout(output):
                self.assertEqual(progress.main(["--counts", str(path)]), 0)
        lines = output.getvalue().splitlines()
        self.assertEqual(lines[1], "3 tests: 1 passed, 1 failed, 1 skipped (waiting for a task)")
        self.assertEqual(lines[2], "Where the tasks stand:")

    def test_an_optional_stage_comes_after_the_six_tasks_and_says_so(self):
        stages = {"gravity": 7, "walls": 8}
        with mock.patch.object(progress, "TASKS", course.TASKS[:6] + list(stages)), \
                mock.patch.object(course, "OPTIONAL", ["gravity"]), \
                mock.patch.dict(course.TASK_NUMBER, stages):
            done = [(f"{task}.S.X", "run", "") for task in course.TASKS[:6]]
            lines = block(done + [("walls.W.X", "fail", stub_message("walls")),
                                  ("gravity.G.X", "fail", stub_message("gravity"))])
            self.assertIn("  7 gravity          not written yet (optional)", lines)
            self.assertIn("  8 walls            not written yet", lines)
            self.assertEqual(lines[-2], "Next: write task 7 (gravity) in tasks/gravity.cpp "
                                        "(an optional extension stage: extra credit)")
            self.assertEqual(lines[-1], "  then run: ./build.sh test -L gravity")
            # Before the six tasks pass, they come first.
            lines = block([("propagate.P.X", "fail", stub_message("propagate")),
                           ("gravity.G.X", "fail", stub_message("gravity"))])
            self.assertEqual(lines[-2], "Next: write task 4 (propagate) in tasks/propagate.cpp")

    def test_unreadable_results_exit_2(self):
        with tempfile.TemporaryDirectory() as folder:
            self.assertEqual(progress.main([str(Path(folder) / "missing.xml")]), 2)
        self.assertEqual(progress.main([]), 2)

    def test_no_test_run_prints_nothing(self):
        with tempfile.TemporaryDirectory() as folder:
            path = Path(folder) / "results.xml"
            path.write_text(junit([]))
            output = io.StringIO()
            with contextlib.redirect_stdout(output):
                self.assertEqual(progress.main([str(path)]), 0)
            self.assertEqual(output.getvalue(), "")


class Course(unittest.TestCase):
    """course.txt: the tasks in order, and which count."""

    def read(self, text):
        with tempfile.TemporaryDirectory() as folder:
            path = Path(folder) / "course.txt"
            path.write_text(text)
            return course.read_course(path)

    def core(self):
        return "".join(f"{n} {task} required\n" for n, task in enumerate(course.TASKS[:6], start=1))

    def test_the_committed_course_has_the_six_tasks_first_then_the_stages(self):
        names = [name for _, name, _ in course.COURSE]
        self.assertEqual(names, ["init_billiard", "init_velocities", "visualize_table", "propagate", "movie",
                                 "kinetic_energy", "gravity", "walls", "sectors", "particles"])
        self.assertEqual(course.PROGRAM_TASKS, ["particles"])
        self.assertEqual(course.TASK_FILE["particles"], "particles.c")
        self.assertEqual(course.TASK_FILE["propagate"], "propagate.cpp")
        self.assertEqual(course.TASKS, [name for _, name, status in course.COURSE if status != "off"])

    def test_comments_blank_lines_and_statuses(self):
        course = self.read("# a comment\n\n" + self.core() + "7 gravity optional\n8 walls off\n9 sectors required\n")
        self.assertEqual(course[6:], [(7, "gravity", "optional"), (8, "walls", "off"), (9, "sectors", "required")])

    def test_the_c_track_alone_switches_every_cpp_task_off(self):
        names = [name for _, name, _ in course.COURSE]
        c_track = "".join(f"{n} {name} {'required' if name == 'particles' else 'off'}\n"
                          for n, name in enumerate(names, start=1))
        self.assertEqual([(name, status) for _, name, status in self.read(c_track) if status != "off"],
                         [("particles", "required")])
        # A C++ task left on needs the core: then the six core tasks stay required.
        with self.assertRaises(ValueError) as raised:
            self.read(c_track.replace("8 walls off", "8 walls optional"))
        self.assertIn("must stay required", str(raised.exception))

    def test_bad_lines_are_named(self):
        for text, words in [(self.core() + "7 gravity maybe\n", "line 7"),
                            (self.core() + "8 gravity optional\n", "should be task 7"),
                            (self.core().replace("4 propagate required", "4 propagate optional"), "must stay required"),
                            ("1 init_billiard\n", "line 1"),
                            (self.core() + "7 gravity optional uses walls\n", "not an earlier task"),
                            (self.core() + "7 gravity optional needs propagate\n", "line 7")]:
            with self.assertRaises(ValueError) as raised:
                self.read(text)
            self.assertIn(words, str(raised.exception))

    def test_what_a_task_may_call_is_declared_once(self):
        # movie calls propagate; no other task calls another's functions (the stages contain
        # tasks 4 and 6: they may not call them).
        self.assertEqual({task: uses for task, uses in course.USES.items() if uses}, {"movie": ["propagate"]})
        with tempfile.TemporaryDirectory() as folder:
            path = Path(folder) / "course.txt"
            path.write_text(self.core().replace("5 movie required", "5 movie required uses propagate,init_billiard"))
            self.assertEqual(course.read_catalogue(path)[1]["movie"], ["propagate", "init_billiard"])



class Messages(unittest.TestCase):
    def test_the_readable_message_comes_first_and_googletest_lines_go_apart(self):
        """A failure in the student's form keeps that form alone; GoogleTest's own lines before it
        (the assertion's place and values) go to the second text; a failure without the form, and
        what came before any failure, stay whole."""
        text = ("The code threw an exception: x\n"
                "tests/graded/test_k.cpp:64: Failure\nThe difference between got and 12.5 is 6.25\n"
                "got evaluates to 6.25\n\nExpected: <v^2> = 12.5\nYour code: returned 6.25\nHint: the mean itself\n"
                "tests/graded/test_k.cpp:70: Failure\nExpected: (error) <= (kRel), actual: 4 vs 1e-12\n\n"
                "Expected: (2, 0)\nYour code: (2.8, 0)\nHint: one factor\nPicture: build/p.svg\n"
                "tests/graded/test_k.cpp:80: Failure\nValue of: ok\n  Actual: false\n")
        shown, raw = judging.readable_first(text)
        self.assertEqual(shown, "The code threw an exception: x\n\nExpected: <v^2> = 12.5\nYour code: returned 6.25\n"
                                "Hint: the mean itself\n\nExpected: (2, 0)\nYour code: (2.8, 0)\nHint: one factor\n"
                                "Picture: build/p.svg\n\ntests/graded/test_k.cpp:80: Failure\nValue of: ok\n  Actual: false")
        self.assertEqual(raw, "tests/graded/test_k.cpp:64: Failure\nThe difference between got and 12.5 is 6.25\n"
                              "got evaluates to 6.25\n\ntests/graded/test_k.cpp:70: Failure\n"
                              "Expected: (error) <= (kRel), actual: 4 vs 1e-12")
        # Why the test ended, before any failure of GoogleTest's, stays with the message after it.
        ended = "Your code crashed with SIGSEGV.\nExpected: a\nYour code: b"
        self.assertEqual(judging.readable_first(ended), (ended, ""))

if __name__ == "__main__":
    unittest.main()
