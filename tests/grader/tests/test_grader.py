#!/usr/bin/python3
"""Tests of the grader (grade.py), run by CTest: it grades known submissions and checks the
scores and files it writes. All scenarios share one build folder (CTest runs them one at a
time through a resource lock), so each grading run rebuilds only what changed.

    /usr/bin/python3 tests/grader/tests/test_grader.py BUILD_FOLDER [unittest arguments]
"""

import fcntl
import html
import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
import unittest
import xml.etree.ElementTree as ET
from pathlib import Path

HERE = Path(__file__).resolve().parent
GRADER = HERE.parent  # the grader, whose tests these are
REPO = HERE.parents[2]
sys.path.insert(0, str(GRADER))
import browser  # noqa: E402
import package  # noqa: E402  (the platforms' time limits)
import course  # noqa: E402  (the course's tasks)
import judging  # noqa: E402  (the pointer to a task's first failure)
import reports  # noqa: E402  (what a hidden test shows)
import time_limits  # noqa: E402

TASKS = package.TASKS
BUILD = None  # set from the command line


def grade(submission, *options, temporary=None, results=None):
    """Runs the grader on a submission folder (with its temporary files in `temporary`, if given,
    and its results in `results`, kept, if given); returns (scores, maxima, results.json, junit
    root, stdout)."""
    keep = results is not None
    results = Path(results or tempfile.mkdtemp(prefix="grader-results-"))
    try:
        done = subprocess.run(
            ["/usr/bin/python3", str(GRADER / "grade.py"), "--submission", str(submission), "--build", str(BUILD),
             "--results", str(results), *options],
            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=3000,
            env=dict(os.environ, TMPDIR=str(temporary)) if temporary else None)
        if done.returncode != 0:
            raise AssertionError(f"grade.py failed with status {done.returncode}:\n{done.stdout[-5000:]}")
        report = json.loads((results / "results.json").read_text())
        junit = ET.parse(results / "junit.xml").getroot()
    finally:
        if not keep:
            shutil.rmtree(results, ignore_errors=True)
    scores = {task: 0 for task in TASKS}
    maxima = {task: 0 for task in TASKS}
    for test in report["tests"]:
        task = test["name"].split(":")[0]
        scores[task] += test["score"]
        maxima[task] += test["max_score"]
    return scores, maxima, report, junit, done.stdout


def own_build_seconds(output):
    """The time of the grader's own build (not the submission's), as grade.py prints it."""
    found = re.search(r"of which (\d+) s for the grader's own build", output)
    if not found:
        raise AssertionError(f"grade.py did not print the time of its own build:\n{output[-3000:]}")
    return int(found.group(1))


def temporary_folder():
    """A folder for one grading's temporary files, which the test user may enter: the suites run
    from there, so the processes of that grading are told from others' by their executable."""
    folder = Path(tempfile.mkdtemp(prefix="grading-"))
    os.chmod(folder, 0o755)
    return folder


def grade_alone(submission, *options):
    """Grades a submission folder (removed afterwards) with temporary files of its own; returns
    grade()'s results, the seconds it took, and the processes still running from its temporary
    folder (which a grading must not leave behind)."""
    temporary = temporary_folder()
    try:
        started = time.monotonic()
        results = grade(submission, *options, temporary=temporary)
        return results, time.monotonic() - started, processes_running_from(temporary)
    finally:
        shutil.rmtree(submission)
        shutil.rmtree(temporary)


def processes_running_from(folder):
    """Pids of the processes whose executable lies in `folder` (even if deleted since)."""
    pids = []
    for entry in Path("/proc").iterdir():
        try:
            if entry.name.isdigit() and os.readlink(entry / "exe").startswith(f"{folder}/"):
                pids.append(int(entry.name))
        except OSError:
            pass
    return pids


def mutant_source(mutant):
    """The source of a mutant (tests/mutants/<task>/<bug>.mutant): the reference solution of its
    task with each block's `solutions/...` lines replaced by its `mutant` lines. Every block's
    original lines must occur exactly once in the current reference solution, so a mutant that no
    longer fits the solutions fails loudly instead of testing stale code."""
    task = mutant.parent.name
    file = course.TASK_FILE[task]
    solution = (REPO / "solutions" / file).read_text()
    blocks = re.findall(r"^<<<<<<< solutions/(\w+\.c(?:pp)?)\n(.*?)^=======\n(.*?)^>>>>>>> mutant\n",
                        mutant.read_text(), re.DOTALL | re.MULTILINE)
    if not blocks:
        raise AssertionError(f"{mutant} has no replacement block")
    spots = []
    for block_file, original, replacement in blocks:
        if block_file != file:
            raise AssertionError(f"{mutant}: a block for solutions/{block_file} in the folder of task {task}")
        if solution.count(original) != 1:
            raise AssertionError(f"{mutant} no longer fits solutions/{file}: these lines occur "
                                 f"{solution.count(original)} times there, not once:\n{original}")
        start = solution.index(original)
        spots.append((start, start + len(original), replacement))
    spots.sort()
    pieces, at = [], 0
    for start, end, replacement in spots:
        if start < at:
            raise AssertionError(f"{mutant}: two blocks replace the same lines")
        pieces += [solution[at:start], replacement]
        at = end
    return "".join(pieces) + solution[at:]


# The tasks whose failing tests draw their case (tests/support/failure_pictures.hpp).
PICTURE_TASKS = [task for task in ["propagate", "movie", "gravity", "walls", "sectors"] if task in TASKS]
SVG_CIRCLES = os.environ.get("BILLIARD_SVG_CIRCLES", "")  # the suites' SVG reader as a program


def shown_text(entry):
    """A results.json test's output as text: an HTML one (a message with its picture) unwrapped."""
    if entry.get("output_format") != "html":
        return entry.get("output", "")
    return html.unescape(re.sub(r"<[^>]*>", "", entry["output"]))


def picture_problems(picture, message):
    """What is wrong with the picture of a failing case, read back with the suites' SVG reader:
    the state it records (its metadata) must be drawn, every circle numbered once at its place; the
    legend must repeat the message's Expected and Your code lines; and the events must be marked:
    the expected one's circles (a pair touching, a circle on the table's wall or a straight wall,
    the point of contact on it), the circle the student's code named, or (of a movie) the discs
    shown elsewhere."""
    name = picture.name
    done = subprocess.run([SVG_CIRCLES, str(picture)], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                          timeout=60)
    if done.returncode != 0:
        return [f"{name}: the SVG reader refuses it: {done.stderr.strip()}"]
    circles = [json.loads(line) for line in done.stdout.splitlines()]
    root = ET.parse(picture).getroot()
    svg = "{http://www.w3.org/2000/svg}"
    case = json.loads(root.find(f"{svg}metadata").text)
    legend = " ".join(" ".join(element.itertext()) for element in root.iter(f"{svg}text"))
    R, a = case["table_radius"], case["circle_radius"]
    tolerance = 1e-6 * R
    problems = []

    def marked(kind):  # the drawing's circles of a class (not the legend's samples)
        return [c for c in circles if kind in c["attributes"].get("class", "").split()
                and "legend" not in c["attributes"].get("class", "").split()]

    def place(circle):
        return circle["x"], -circle["y"]  # the picture's y axis points down

    def distance(p, q):
        return math.hypot(p[0] - q[0], p[1] - q[1])

    numbered = {}
    for circle in marked("circle"):
        numbered.setdefault(int(circle["attributes"]["data-circle"]), []).append(circle)
    if sorted(numbered) != list(range(len(case["coordinates"]))) or any(len(c) != 1 for c in numbered.values()):
        problems.append(f"{name}: circles {sorted(numbered)} drawn, not each of the {len(case['coordinates'])} once")
    for i, centre in enumerate(case["coordinates"]):
        drawn = numbered.get(i, [None])[0]
        if drawn and (distance(place(drawn), centre) > tolerance or abs(drawn["radius"] - a) > tolerance):
            problems.append(f"{name}: circle {i} drawn at {place(drawn)}, radius {drawn['radius']}; it is at {centre}")
    # The student's message: its "Expected:" line is the one followed by "Your code:" (GoogleTest's
    # own lines, such as "Expected: true" of EXPECT_TRUE, come before it).
    words = " ".join(legend.split())
    lines = message.splitlines()
    at = next((k for k in range(len(lines) - 1)
               if lines[k].startswith("Expected: ") and lines[k + 1].startswith("Your code: ")), None)
    for line in lines[at:at + 2] if at is not None else []:
        if " ".join(line.split()) not in words:
            problems.append(f"{name}: the legend does not repeat the message's \"{line[:80]}...\"")

    def ghosts(kind, i):
        return [place(c) for c in marked(kind) if c["attributes"].get("data-circle") == str(i)]

    if re.search(r"\bline \d+:", message) and case["kind"] != "lines":
        problems.append(f"{name}: the message is about a line of the file, the picture shows a {case['kind']}")
    if case["kind"] == "step":
        expected, yours = case["expected"], case["yours"]
        if not expected["none"]:
            i, other = expected["circle"], expected["other"]
            if not ghosts("expected", i):
                problems.append(f"{name}: the expected event's circle {i} is not marked")
            contacts = [place(c) for c in circles if {"expected", "contact"} <= set(c["attributes"].get("class", "").split())]
            if other >= 0:
                if not ghosts("expected", other) or not ghosts("expected", i) or \
                        abs(distance(ghosts("expected", i)[0], ghosts("expected", other)[0]) - 2 * a) > tolerance:
                    problems.append(f"{name}: the expected circles {i} and {other} are not drawn touching")
            elif other == -1:
                if not contacts or abs(distance(contacts[0], (0, 0)) - R) > tolerance:
                    problems.append(f"{name}: the expected contact with the table's wall is not on it")
            else:
                ax, ay, bx, by = case["walls"][-2 - other]
                length2 = (bx - ax) ** 2 + (by - ay) ** 2
                def off_wall(p):
                    s = max(0.0, min(1.0, ((p[0] - ax) * (bx - ax) + (p[1] - ay) * (by - ay)) / length2))
                    return distance(p, (ax + s * (bx - ax), ay + s * (by - ay)))
                if not contacts or off_wall(contacts[0]) > tolerance:
                    problems.append(f"{name}: the expected contact with walls[{-2 - other}] is not on it")
        mine, after = yours["circle"], yours["coordinates"]
        placed = 0 <= mine < min(len(after), len(case["coordinates"])) and None not in after[mine]
        # A circle whose new velocity is not a number (or infinite) is crossed out where it was.
        crossed = any(element.get("data-circle") == str(mine) and "not-finite" in element.get("class", "").split()
                      for element in root.iter(f"{svg}line"))
        if not yours["error"] and placed and not ghosts("yours", mine) and not crossed:
            problems.append(f"{name}: the circle {mine} of the student's event is not marked")
    elif case["kind"] == "lines":  # a file's lines: the line the message names is shown and marked
        named = re.search(r"\bline (\d+):", message)
        if named and int(named[1]) not in case["marked_lines"]:
            problems.append(f"{name}: the message is about line {named[1]}, the picture marks {case['marked_lines']}")
        numbers = {element.text.strip() for element in root.iter(f"{svg}text") if (element.text or "").strip().isdigit()}
        missing = [line for line in case["marked_lines"] if str(line) not in numbers]
        if missing:
            problems.append(f"{name}: the marked lines {missing} are not shown")
    elif case["kind"] == "positions":
        # The moment drawn is the one the message reports.
        moment = re.search(r"\): (.*?), i\.e\. at fraction", message)
        if moment and moment[1] not in case["heading"]:
            problems.append(f"{name}: the message reports {moment[1]!r}, the picture shows {case['heading']!r}")
        elsewhere = [c for c in marked("yours") if "data-circle" in c["attributes"]]
        if not elsewhere:
            problems.append(f"{name}: no disc is marked where the movie shows it")
        for circle in elsewhere:
            i = int(circle["attributes"]["data-circle"])
            if not ghosts("expected", i) or distance(ghosts("expected", i)[0], case["coordinates"][i]) > tolerance:
                problems.append(f"{name}: disc {i}, shown elsewhere, is not marked at its place")
    return problems


def lead_hint(mutant):
    """The words the lead hint must hold, from the mutant's "Lead hint names: ..." line, or ""."""
    for line in mutant.read_text().splitlines():
        if line.startswith("Lead hint names: "):
            return line[len("Lead hint names: "):].strip()
    return ""


def submission_from_solutions(**replacements):
    """A temporary submission: the reference files, with some replaced by the given files
    (a .mutant file is applied to the reference solution of its task)."""
    folder = Path(tempfile.mkdtemp(prefix="submission-"))
    files = course.TASK_FILE
    for task in TASKS:
        shutil.copyfile(REPO / "solutions" / files[task], folder / files[task])
    for task, source in replacements.items():
        source = Path(source)
        if source.suffix == ".mutant":
            (folder / files[task]).write_text(mutant_source(source))
        else:
            shutil.copyfile(source, folder / files[task])
    return folder


class GradesKnownSubmissions(unittest.TestCase):
    def check_gradescope_format(self, report):
        self.assertIsInstance(report["score"], (int, float))
        self.assertEqual(report["score"], sum(test["score"] for test in report["tests"]))
        for test in report["tests"]:
            self.assertEqual(set(test) & {"name", "score", "max_score", "output", "visibility", "status"},
                             {"name", "score", "max_score", "output", "visibility", "status"}, test)
            self.assertIn(test["visibility"], {"visible", "hidden", "after_due_date", "after_published"})
            self.assertIn(test["status"], {"passed", "failed"})
            self.assertLessEqual(test["score"], test["max_score"])

    def test_stubs_score_zero_in_every_task(self):
        scores, maxima, report, junit, output = grade(REPO / "tasks")
        self.check_gradescope_format(report)
        self.assertEqual(scores, {task: 0 for task in TASKS})
        self.assertTrue(all(maxima[task] > 0 for task in TASKS), maxima)
        self.assertIn("not implemented yet", output)
        failures = sum(int(suite.get("failures")) for suite in junit.iter("testsuite"))
        cases = sum(1 for _ in junit.iter("testcase"))
        self.assertEqual(failures, cases)

    def test_solutions_score_full_marks(self):
        scores, maxima, report, junit, output = grade(REPO / "solutions")
        self.check_gradescope_format(report)
        self.assertEqual(scores, maxima)
        self.assertEqual(sum(int(suite.get("failures")) for suite in junit.iter("testsuite")), 0)
        # The table's total counts the required tasks; the optional stages are shown apart.
        counted = sum(points for task, points in maxima.items() if not course.is_optional(task))
        self.assertRegex(output, rf"total +{counted} / {counted}\n")
        optional = sum(points for task, points in maxima.items() if course.is_optional(task))
        if optional:
            self.assertRegex(output, rf"optional +{optional} / {optional} +\(extra credit")
        self.assertEqual(report["score"], sum(maxima.values()), "results.json's score includes the extra credit")

    def test_hostile_submission_gains_nothing_and_stops_nothing(self):
        hostile = {path.stem: path for path in (HERE / "hostile").glob("*.cpp")}
        timeout = 2
        (scores, maxima, report, _, _), elapsed, leftovers = grade_alone(
            submission_from_solutions(**hostile), "--limits", "fixed", "--timeout", str(timeout), "--task-budget", "30")
        self.check_gradescope_format(report)
        for task in ["init_billiard", "init_velocities", "propagate", "kinetic_energy", "walls"]:
            self.assertEqual(scores[task], 0, f"{task} misbehaves and must score 0")
        for task in ["visualize_table", "movie"]:
            self.assertEqual(scores[task], maxima[task], f"{task} is correct and must keep full points")
        # Bounded time: the endless loops cost one time limit per test, two tests at a time.
        propagate_tests = sum(1 for test in report["tests"] if test["name"].startswith("propagate:"))
        self.assertLess(elapsed, 600 + propagate_tests * timeout)
        outputs = {test["name"]: test["output"] for test in report["tests"]}
        loop = next(text for name, text in outputs.items() if name.startswith("propagate:"))
        self.assertIn("did not finish", loop)
        crash = next(text for name, text in outputs.items() if name.startswith("init_velocities:"))
        self.assertIn("SIGSEGV", crash)
        early = next(text for name, text in outputs.items() if name.startswith("init_billiard:"))
        self.assertIn("exit()", early)
        before_main = [text for name, text in outputs.items() if name.startswith("walls:")]
        self.assertTrue(before_main and all("exit()" in text or "hidden" in text for text in before_main), before_main)
        self.assertTrue(all(len(text) < 10_000 for text in outputs.values()), "feedback must be capped")
        self.assertEqual(leftovers, [], "the processes that left their tests are stopped")

    def test_endless_loop_costs_only_its_task_and_its_budget(self):
        # propagate loops forever (and leaves a detached process looping too), graded with the
        # platforms' limits: propagate's tests stop when its budget is used up, its detached
        # processes are stopped, and the other tasks keep full points.
        (scores, maxima, report, junit, output), elapsed, leftovers = grade_alone(
            submission_from_solutions(propagate=HERE / "hostile" / "propagate.cpp"), *package.PLATFORM_GRADE_OPTIONS)
        limits = time_limits.saved_limits(BUILD)
        self.check_gradescope_format(report)
        outputs = [test["output"] for test in report["tests"] if test["name"].startswith("propagate:")]
        # The budget this grading gave propagate, as its tests not run state it: the saved one, or
        # more where the grader found this machine slower than when the reference was measured.
        stated = {float(found) for text in outputs for found in re.findall(r"may take (\d+) s in all here", text)}
        self.assertEqual(len(stated), 1, outputs)
        budget = stated.pop()
        saved = sum(item.budget for item in limits.values())
        self.assertGreaterEqual(budget + 1, limits["propagate"].budget * min(1, package.PLATFORM_TOTAL / saved),
                                "a budget is scaled up on a slower machine, down only to fit --total")
        bound = float(re.search(r"budgets adding up to (\d+) s", output)[1])
        self.assertEqual(scores["propagate"], 0)
        for task in TASKS:
            if task != "propagate":
                self.assertEqual(scores[task], maxima[task], f"{task} is correct and must keep full points")
        # The stated bound: the grader's own build and the tasks' budgets; this submission, with
        # one task looping, needs one budget and the few seconds of the other tasks.
        tasks_time = elapsed - own_build_seconds(output)
        print(f"graded in {elapsed:.0f} s, {tasks_time:.0f} s after the grader's own build (bound: {bound:.0f} s; "
              f"propagate's budget {budget:.0f} s)", flush=True)
        self.assertLess(tasks_time, bound)
        self.assertLess(tasks_time, budget + 120)
        suite = next(suite for suite in junit.iter("testsuite") if suite.get("name") == "propagate")
        test_time = sum(float(case.get("time")) for case in suite.iter("testcase"))
        self.assertLessEqual(test_time, budget + 2, "propagate's tests together stay within its budget")
        stopped = [text for text in outputs if "did not finish within" in text]
        not_run = [text for text in outputs if "not run" in text]
        self.assertTrue(stopped and not_run, outputs)
        self.assertEqual(len(stopped) + len(not_run), len(outputs), "every test of propagate says why it failed")
        self.assertTrue(all("endless loop in propagate" in text for text in stopped))
        self.assertTrue(all("endless loop in propagate" in text or "hidden" in text for text in not_run))
        # Each stopped test says what its limit was made of: the reference's time on this machine.
        self.assertTrue(all("the reference solution needs" in text for text in stopped), stopped)
        self.assertIn("not run:", output)
        self.assertEqual(leftovers, [], "the processes that left their tests are stopped")

    def test_a_deadline_ends_a_grading_in_wall_time_with_its_results(self):
        # A platform's cutoff is wall time, which a busy machine eats into and the tasks' budgets
        # do not: with --deadline the grading ends there, results written, though propagate loops
        # with 300 s of budget left. Each of its tests says that the time ran out, not its code.
        deadline = 30
        (scores, maxima, report, junit, output), elapsed, leftovers = grade_alone(
            submission_from_solutions(propagate=HERE / "hostile" / "propagate.cpp"), "--task", "propagate",
            "--limits", "fixed", "--timeout", "200", "--task-budget", "300", "--deadline", str(deadline))
        print(f"graded in {elapsed:.0f} s with a deadline of {deadline} s", flush=True)
        self.check_gradescope_format(report)
        self.assertLess(elapsed, deadline + package.RESULTS_ALLOWANCE, "the results come before the platform's cut-off")
        self.assertEqual(scores["propagate"], 0)
        outputs = [test["output"] for test in report["tests"] if test["name"].startswith("propagate:")]
        self.assertTrue(outputs, report)
        stated = f"the time this grading has on the grading machine ({deadline} s)"
        stopped = [text for text in outputs if text.startswith("The test did not finish before " + stated)]
        not_run = [text for text in outputs if text.startswith("This test was not run: " + stated)]
        hidden = [text for text in outputs if text.startswith(reports.HIDDEN_FEEDBACK)]
        self.assertTrue(stopped, outputs)
        self.assertEqual(len(stopped) + len(not_run) + len(hidden), len(outputs), outputs)
        self.assertTrue(all("busy" in text and "Submit again" in text for text in outputs), outputs)
        self.assertEqual(leftovers, [], "the processes of the stopped tests are stopped")

    def test_a_slower_machine_scales_the_limits(self):
        # The reference's times as if measured on a machine eight times as fast as this one (as
        # when a platform sets the grader up on a faster machine than it grades on): the grader
        # finds this machine slower and scales the limits with it. (Eight times: the probe of a
        # machine's speed reads CPU time, which a busy sibling processor of a two-vCPU machine
        # stretches from one grading to the next, by 1.8 times once in CI.)
        limits = time_limits
        path = BUILD / limits.REFERENCE_TIMES
        grade(REPO / "solutions", "--task", "init_billiard")  # the reference's times are measured
        saved = path.read_text()
        record = json.loads(saved)
        normal = limits.saved_limits(BUILD)["init_billiard"].budget
        for times in record["tasks"].values():
            times["speed"] /= 8
        try:
            path.write_text(json.dumps(record))
            scores, maxima, _, _, output = grade(REPO / "solutions", "--task", "init_billiard")
        finally:
            path.write_text(saved)
        self.assertEqual(scores["init_billiard"], maxima["init_billiard"])
        found = re.search(r"this machine is ([\d.]+) times slower", output)
        self.assertTrue(found, output[-2000:])
        self.assertGreater(float(found.group(1)), 2.5)
        budget = float(re.search(r"budgets adding up to (\d+) s", output).group(1))
        self.assertGreater(budget, 2.5 * normal, f"init_billiard's budget: {normal:.0f} s, scaled {budget:.0f} s")
        # And with the times of this machine, no scaling beyond that noise.
        _, _, _, _, output = grade(REPO / "solutions", "--task", "init_billiard")
        found = re.search(r"this machine is ([\d.]+) times slower", output)
        self.assertTrue(found is None or float(found.group(1)) < 2, output[-2000:])

    def test_the_reference_is_measured_in_the_graded_tasks_only(self):
        # A grading measures the reference's times in the tasks it grades that miss them, adds
        # them to what the build folder has, and measures nothing a second time.
        path = BUILD / time_limits.REFERENCE_TIMES
        grade(REPO / "solutions", "--task", "kinetic_energy")
        saved = path.read_text()
        record = json.loads(saved)
        kept = record["tasks"]["kinetic_energy"]
        record["tasks"] = {"kinetic_energy": kept}
        try:
            path.write_text(json.dumps(record))
            _, _, _, _, output = grade(REPO / "solutions", "--task", "visualize_table")
            measured = json.loads(path.read_text())["tasks"]
            _, _, _, _, again = grade(REPO / "solutions", "--task", "visualize_table", "--task", "kinetic_energy")
        finally:
            path.write_text(saved)
        self.assertIn("measuring what the reference solutions need on this machine in visualize_table (", output)
        self.assertEqual(sorted(measured), ["kinetic_energy", "visualize_table"])
        self.assertEqual(measured["kinetic_energy"], kept)
        self.assertNotIn("measuring", again)

    def test_a_compile_error_or_a_missing_file_costs_only_its_own_task(self):
        broken = Path(tempfile.mkdtemp(prefix="broken-")) / "propagate.cpp"
        broken.write_text((REPO / "solutions" / "propagate.cpp").read_text().replace("return next;", "return nxt;"))
        submission = submission_from_solutions(propagate=broken)
        (submission / course.TASK_FILE["kinetic_energy"]).unlink()  # not handed in at all
        try:
            scores, maxima, report, _, output = grade(submission)
        finally:
            shutil.rmtree(submission)
            shutil.rmtree(broken.parent)
        self.assertEqual(scores["propagate"], 0)
        self.assertEqual(scores["kinetic_energy"], 0)
        # Another folder than tasks/: the report ends with a summary for whoever grades it.
        self.assertNotIn("Next:", output)
        self.assertIn(f"Summary: full points in {len(TASKS) - 2} of {len(TASKS)} tasks", output)
        summary = output[output.index("Summary:"):output.index("\nresults:")].strip().splitlines()
        self.assertEqual(len(summary), 3, summary)
        self.assertIn("propagate: propagate.cpp does not compile (the whole message is above)", summary[1] + summary[2])
        # A missing file is called missing everywhere: the table, the summary, the platform's results.
        missing = f"{course.TASK_FILE['kinetic_energy']} was not submitted"
        self.assertIn(f"kinetic_energy: {missing}", "\n".join(summary))
        table = output[:output.index("Summary:")]
        self.assertIn(missing, table[table.index("kinetic_energy"):])
        for line in [line for line in output.splitlines() if "kinetic_energy" in line]:
            self.assertNotRegex(line, "compil|does not build", line)
        entry = next(test for test in report["tests"] if test["name"].startswith("kinetic_energy:"))
        self.assertIn(missing, entry["output"])
        self.assertNotIn("compil", entry["output"])
        entry = next(test for test in report["tests"] if test["name"].startswith("propagate:"))
        self.assertIn("nxt", entry["output"])
        self.assertEqual(entry["max_score"], maxima["propagate"])
        self.assertGreater(maxima["propagate"], 0)
        for task in TASKS:
            if task not in ("propagate", "kinetic_energy"):
                self.assertEqual(scores[task], maxima[task], task)


    def test_hidden_tests_never_leak_their_content(self):
        # The instructor-only tests in tests/graded/hidden/ are marked `hidden`. A mutant per task
        # that has them fails them; the student must see their points and nothing else: no name,
        # no message.
        hidden = {}
        for source in (REPO / "tests" / "graded" / "hidden").glob("test_*.cpp"):
            found = re.findall(r"GRADED_TEST\((\w+),\s*(\w+),\s*(\d+),\s*(\w+)\)", source.read_text())
            self.assertTrue(found, f"{source} has no graded test")
            self.assertTrue(all(shown == "hidden" for *_, shown in found), f"{source}: every test there must be hidden")
            hidden[source.stem[len("test_"):]] = [(suite, name, int(points)) for suite, name, points, _ in found]
        failing_hidden = {"propagate": "whole_velocity_swap", "kinetic_energy": "factor_without_sqrt",
                          "gravity": "reflect_before_gravity_kick", "walls": "end_points_forgotten",
                          "sectors": "no_crossing_events", "particles": "larger_root"}
        graded = [task for task in failing_hidden if task in TASKS]
        self.assertGreaterEqual(set(hidden), set(graded))
        submission = submission_from_solutions(**{task: REPO / "tests" / "mutants" / task / f"{failing_hidden[task]}.mutant"
                                                  for task in graded})
        results = Path(tempfile.mkdtemp(prefix="hidden-results-"))
        records = Path(tempfile.mkdtemp(prefix="hidden-records-")) / "records.json"
        try:
            scores, maxima, report, junit, output = grade(submission, *[word for task in graded for word in ("--task", task)],
                                                          "--records", str(records), results=results)
            written = {str(path.relative_to(results)): path.read_text(errors="replace")
                       for path in results.rglob("*") if path.is_file()}
            kept = json.loads(records.read_text())
        finally:
            shutil.rmtree(submission)
            shutil.rmtree(results)
            shutil.rmtree(records.parent)
        self.check_gradescope_format(report)
        # The hidden tests count (with their points) and fail on these mutants ...
        for task in graded:
            entries = [test for test in report["tests"]
                       if test["name"].startswith(task + ":") and test["visibility"] == "hidden"]
            self.assertEqual(sorted(test["max_score"] for test in entries),
                             sorted(points for *_, points in hidden[task]), task)
            self.assertTrue(any(test["status"] == "failed" for test in entries), f"{task}: a hidden test must fail here")
        # ... and their own feedback, which only the instructor's records keep, says what the hidden
        # case is (so leaving it out matters).
        held_out = [test["feedback"] for record in kept if record["task"] == "propagate" for test in record["tests"]
                    if test["name"].startswith("Propagate.HeldOut") and not test["passed"]]
        self.assertTrue(held_out and all("held-out table" in text for text in held_out), held_out)
        # No picture of a hidden test anywhere in the results (the grader never asks for one).
        self.assertTrue(any(name.startswith("pictures/") for name in written), "the visible failures draw theirs")
        for name, content in written.items():
            for secret in ["held-out", "HeldOut", "hidden/test_"] + [n for task in hidden for _, n, _ in hidden[task]]:
                self.assertNotIn(secret, name, f"the results hold {name}, a file of a hidden test")
                self.assertFalse(secret in content, f"{name} shows '{secret}' of a hidden test")
        # Visible failures keep their messages; nothing of a hidden test reaches the student.
        self.assertTrue(any("Expected:" in test["output"] for test in report["tests"] if test["visibility"] != "hidden"))
        secrets = ["held-out", "HeldOut", "hidden/test_"] + [name for task in hidden for _, name, _ in hidden[task]]
        places = {"results.json": json.dumps(report), "junit.xml": ET.tostring(junit, encoding="unicode"),
                  "the printed table": output}
        for place, content in places.items():
            for secret in secrets:
                self.assertNotIn(secret, content, f"{place} shows '{secret}' of a hidden test")

    def test_report_shows_each_failing_case_drawn(self):
        """A submission's report.html, drawn by Debian's headless chromium: the failing visible
        tests' pictures are on the page (the table's fill and both accounts' colours)."""
        task = next(iter(PICTURE_TASKS), None)
        if task is None:
            self.skipTest("this course has no task whose failures draw a picture")
        mutant = sorted(mutant for mutant in (REPO / "tests" / "mutants" / task).glob("*.mutant") if lead_hint(mutant))[0]
        submission = submission_from_solutions(**{task: mutant})
        results = Path(tempfile.mkdtemp(prefix="report-results-"))
        try:
            _, _, report, _, output = grade(submission, "--task", task, results=results)
            self.assertIn(str(results / "report.html"), output)  # the closing block names it
            page = (results / "report.html").read_text()
            drawn = [test for test in report["tests"] if test.get("output_format") == "html"]
            self.assertTrue(drawn, f"{mutant.name}: no failing test of {task} drew its case")
            self.assertEqual(page.count("data:image/svg+xml;base64,"), len(drawn))
            picture, chromium = browser.screenshot(results / "report.html", height=3000)
            self.assertIsNotNone(picture, chromium[-2000:])
            counts = browser.colour_counts(picture)
            # failure_pictures.cpp's table fill and the two accounts' colours.
            for colour, what in [("#f1f8e9", "the table"), ("#1565c0", "the expected event"),
                                 ("#e65100", "the student's event")]:
                self.assertGreater(counts.get(browser.rgb(colour), 0), 50 if colour != "#f1f8e9" else 20000,
                                   f"{what} is not drawn on the page")
            # A picture opened alone in a window smaller than it, of another shape: all of it in view,
            # the table whole and the legend's last line above a white margin at the bottom.
            alone = next((results / "pictures").glob("*.svg"))
            for width, height in [(600, 600), (1100, 500), (400, 900)]:
                page = alone.with_name(f"window-{width}x{height}.svg")
                shutil.copyfile(alone, page)
                picture, chromium = browser.screenshot(page, width=width, height=height)
                self.assertIsNotNone(picture, chromium[-2000:])
                box = browser.colour_box(picture, "#f1f8e9")
                self.assertIsNotNone(box, f"{width}x{height}: no table drawn")
                self.assertTrue(box[0] > 0 and box[1] > 0 and box[2] < width - 1 and box[3] < height - 1,
                                f"{width}x{height}: the table is cut at the window's edge: {box}")
                self.assertTrue(browser.blank_rows(picture, 0.02), f"{width}x{height}: the legend is cut at the bottom")
        finally:
            shutil.rmtree(submission)
            shutil.rmtree(results)

    def test_pictures_show_each_kind_of_mistake(self):
        """Three kinds of mistake as the student sees them, drawn by headless chromium in a square
        window: a velocity that is not a number, crossed out and said; a pair's exchange of the
        wrong sign, whose arrows differ in length on the screen; a movie file a browser cannot
        play, shown as its lines with the one at fault marked, and no table. Each picture whole in
        the window, legend included."""
        if not {"propagate", "movie"} <= set(TASKS):
            self.skipTest("this course has no propagate and movie tasks")
        mutants = REPO / "tests" / "mutants"
        gradings = [{"propagate": mutants / "propagate" / "normal_divided_by_gap_to_wall.mutant",
                     "movie": mutants / "movie" / "key_times_not_cumulative.mutant"},
                    {"propagate": mutants / "propagate" / "exchange_with_wrong_sign.mutant"}]
        drawn = {}
        work = Path(tempfile.mkdtemp(prefix="pictures-"))
        try:
            for number, replacements in enumerate(gradings):
                submission = submission_from_solutions(**replacements)
                results = work / f"results-{number}"
                try:
                    grade(submission, *[word for task in replacements for word in ("--task", task)], results=results)
                finally:
                    shutil.rmtree(submission)
                for picture in (results / "pictures").glob("*.svg"):
                    drawn[picture.stem] = picture
            width = height = 800
            shots = {}
            for test in ["Propagate.CircleFromCentreHitsWallAtTimeNine", "Propagate.HeadOnCollisionAtTimeFour",
                         "Movie.AnimationShowsTheDiscsAtEveryCollision"]:
                self.assertIn(test, drawn, f"{test} drew no picture")
                shots[test], chromium = browser.screenshot(drawn[test], width=width, height=height)
                self.assertIsNotNone(shots[test], chromium[-2000:])
                self.assertTrue(browser.blank_rows(shots[test], 0.01), f"{test}: the legend is cut at the bottom")
            orange, blue, table = browser.rgb("#e65100"), browser.rgb("#1565c0"), browser.rgb("#f1f8e9")

            nan = drawn["Propagate.CircleFromCentreHitsWallAtTimeNine"].read_text()
            self.assertIn('class="yours not-finite" data-circle="0"', nan)
            self.assertIn(">NaN<", nan)
            self.assertIn("velocity is NaN (not a number)", nan)  # the legend says it
            self.assertGreater(browser.colour_counts(shots["Propagate.CircleFromCentreHitsWallAtTimeNine"]).get(orange, 0),
                               200, "the crossed-out circle is not on the screen")

            sign = drawn["Propagate.HeadOnCollisionAtTimeFour"]
            root = ET.parse(sign).getroot()
            svg = "{http://www.w3.org/2000/svg}"
            x, y, box_width, box_height = map(float, root.get("viewBox").split())
            pixels_per_unit = min(width / box_width, height / box_height)
            lengths = {"expected": [], "yours": []}
            start = None
            for element in root.iter():
                classes = element.get("class", "").split()
                if "velocity" not in classes or not ({"expected", "yours"} & set(classes)):
                    continue
                if element.tag == f"{svg}line":
                    start = (float(element.get("x1")), float(element.get("y1")))
                elif element.tag == f"{svg}polygon" and start:
                    tip = tuple(map(float, element.get("points").split()[0].split(",")))
                    lengths["expected" if "expected" in classes else "yours"].append(
                        math.dist(start, tip) * pixels_per_unit)
                    start = None
            self.assertTrue(lengths["expected"] and lengths["yours"], lengths)
            self.assertGreater(min(lengths["yours"]) - max(lengths["expected"]), 20,
                               f"speeds 3 and 1 drawn with arrows of {lengths} pixels")
            counts = browser.colour_counts(shots["Propagate.HeadOnCollisionAtTimeFour"])
            self.assertGreater(counts.get(orange, 0), 50)
            self.assertGreater(counts.get(blue, 0), 50)

            movie = shots["Movie.AnimationShowsTheDiscsAtEveryCollision"]
            counts = browser.colour_counts(movie)
            self.assertEqual(counts.get(table, 0), 0, "a file that a browser cannot play is drawn as a table")
            self.assertGreater(counts.get(browser.rgb("#ffe0b2"), 0), 1000, "the line at fault is not marked")
            text = drawn["Movie.AnimationShowsTheDiscsAtEveryCollision"].read_text()
            self.assertIn("keyTimes", text)
        finally:
            shutil.rmtree(work)

    @unittest.skipUnless(os.geteuid() == 0, "needs root to run the submission as another user")
    def test_including_the_reference_solution_gains_nothing(self):
        cheat = Path(tempfile.mkdtemp(prefix="cheat-"))
        (cheat / "propagate.cpp").write_text(f'#include "{REPO}/solutions/propagate.cpp"\n')
        (cheat / "kinetic_energy.cpp").write_text('#include "../../../../solutions/kinetic_energy.cpp"\n')
        # And at run time: init_velocities reads the reference code and the grader's build of it,
        # and puts what it read in its failure message, which the student would see.
        reference_object = next((BUILD / "solutions").rglob("init_velocities.cpp.o"))
        (cheat / "init_velocities.cpp").write_text(f"""#include <fstream>
#include <sstream>
#include <stdexcept>
#include "billiard/course.hpp"
namespace billiard {{
Velocities init_velocities(int, const Coordinates&, Rng&) {{
  std::ostringstream seen;
  for (const char* path : {{"{REPO}/solutions/init_velocities.cpp", "{reference_object}"}}) {{
    std::ifstream file(path);
    seen << "read " << path << ": " << (file ? "yes" : "no") << "; " << file.rdbuf() << "\\n";
  }}
  throw std::runtime_error(seen.str());
}}
}}  // namespace billiard
""")
        submission = submission_from_solutions(propagate=cheat / "propagate.cpp",
                                               kinetic_energy=cheat / "kinetic_energy.cpp",
                                               init_velocities=cheat / "init_velocities.cpp")
        modes = {path: path.stat().st_mode for path in [REPO / "solutions", BUILD]}
        try:
            scores, maxima, report, _, output = grade(submission, "--protect-reference", "--task", "propagate",
                                                      "--task", "kinetic_energy", "--task", "movie",
                                                      "--task", "init_velocities")
        finally:
            shutil.rmtree(submission)
            shutil.rmtree(cheat)
        self.assertEqual(scores["propagate"], 0)
        self.assertEqual(scores["kinetic_energy"], 0)
        self.assertEqual(scores["init_velocities"], 0)
        self.assertEqual(scores["movie"], maxima["movie"])
        feedback = "\n".join(test["output"] for test in report["tests"] if test["name"].startswith("init_velocities:"))
        self.assertIn("read ", feedback)  # the test did run and say what it read
        self.assertNotIn(": yes", feedback, "a test read the reference code")
        self.assertNotIn("reference solution", feedback)
        for path, mode in modes.items():
            self.assertEqual(path.stat().st_mode, mode, f"the permissions of {path} are restored")

    def test_a_shared_build_never_changes_under_a_grading(self):
        """Gradings may share a build folder (the class grader's workers on a machine). One that
        builds there waits until no other grading uses it, and one given --prebuilt grades from
        it without building while another builds, never with it half-built."""
        submission = REPO / "solutions"
        grade(submission, "--task", "init_billiard")  # built and ready
        lock_path = BUILD.parent / f"{BUILD.name}.lock"
        command = ["/usr/bin/python3", str(GRADER / "grade.py"), "--submission", str(submission), "--build", str(BUILD),
                   "--task", "init_billiard"]
        started_lines = ["building the grader's own code", "grading with the grader built in"]
        for held, options, waits_to in [(fcntl.LOCK_SH, [], "build"), (fcntl.LOCK_EX, ["--prebuilt"], "grade")]:
            results = Path(tempfile.mkdtemp(prefix="grader-results-"))
            log = results.with_suffix(".log")
            with open(lock_path, "a") as lock, open(log, "w") as output_file:
                fcntl.flock(lock, held)  # as a grading that uses the folder, or one that builds it
                grading = subprocess.Popen([*command, *options, "--results", str(results)], stdout=output_file,
                                           stderr=subprocess.STDOUT, text=True)
                time.sleep(3)
                so_far = log.read_text()
                still_ready = (BUILD / "grader-ready.json").is_file()
            grading.wait(timeout=600)
            output = log.read_text()
            shutil.rmtree(results, ignore_errors=True)
            log.unlink()
            self.assertFalse([line for line in started_lines if line in so_far],
                             f"a grading did not wait to {waits_to}:\n{so_far[-3000:]}")
            self.assertTrue(still_ready, f"a grading waiting to {waits_to} took the build's ready mark")
            self.assertEqual(grading.returncode, 0, output[-3000:])
        self.assertIn("grade: grading with the grader built in", output)  # the last, --prebuilt: ready, not built
        self.assertNotIn("building the grader's own code", output)


class Mutants(unittest.TestCase):
    """Every mutant loses points only in its own task, in at least one test the student sees before
    the due date (visibility "visible"), and the first visible test of its task that
    fails leads with a hint naming the bug, for every mutant that models a student's mistake (its
    "Lead hint names:" line); at least five such mutants per task. In a task where a state
    evolves, that test draws its failing case: the picture is read back and checked against the
    message (picture_problems). The test command grades one mutant of each required task (the
    first with a lead hint); every mutant of every task runs with the long runs (label stress)."""

    def test_a_mutant_of_each_required_task_loses_points_only_in_its_own_task(self):
        tasks = [task for task in TASKS if not course.is_optional(task)]
        self.assertTrue(tasks, "course.txt requires no task")
        self.check_mutants(tasks, at_least=20, one_per_task=True)

    def test_every_mutant_of_a_required_task_loses_points_only_in_its_own_task(self):
        tasks = [task for task in TASKS if not course.is_optional(task)]
        self.assertTrue(tasks, "course.txt requires no task")
        self.check_mutants(tasks, at_least=20)

    def test_every_mutant_of_an_optional_task_loses_points_only_in_its_own_task(self):
        tasks = [task for task in TASKS if course.is_optional(task)]
        if not tasks:
            self.skipTest("course.txt has no optional task")
        self.check_mutants(tasks, at_least=5 * len(tasks))

    def check_mutants(self, tasks, at_least, one_per_task=False):
        self.assertTrue(Path(SVG_CIRCLES).is_file() or not PICTURE_TASKS, "BILLIARD_SVG_CIRCLES names no program")
        # The mutants of these tasks (course.txt may switch stages off).
        mutants = sorted(mutant for mutant in (REPO / "tests" / "mutants").glob("*/*.mutant")
                         if mutant.parent.name in tasks)
        self.assertGreaterEqual(len(mutants), at_least)
        if one_per_task:
            mutants = [next(mutant for mutant in mutants if mutant.parent.name == task and lead_hint(mutant))
                       for task in tasks]
        problems = []
        later_hints = []
        with_lead = {task: 0 for task in tasks}
        pictures = 0
        for mutant in mutants:
            task = mutant.parent.name
            submission = submission_from_solutions(**{task: mutant})
            results = Path(tempfile.mkdtemp(prefix="mutant-results-"))
            try:
                # Unchanged suites (all but the mutant's own) are remembered, not run again.
                scores, maxima, report, _, _ = grade(submission, "--brief", "--cache",
                                                     str(BUILD.parent / "grader-cache"), results=results)
                # Points lost with no reason the student can read before the due date are a puzzle.
                failing = [test for test in report["tests"] if test["name"].startswith(task + ":")
                           and test["status"] == "failed"]
                seen_before_due_date = any(test["visibility"] == "visible" for test in failing)
                first_failing = next((test["name"] for test in failing if test["visibility"] != "hidden"), "none")
                lead = lead_hint(mutant)
                if lead:
                    with_lead[task] += 1
                    first = next((test for test in report["tests"] if test["name"].startswith(task + ":")
                                  and test["status"] == "failed" and test["visibility"] != "hidden"), None)
                    message = shown_text(first or {})
                    hint = next((line for line in message.splitlines() if line.startswith("Hint:")), "")
                    if lead.lower() not in hint.lower():
                        problems.append(f"{task}/{mutant.name}: the first failing test "
                                        f"{first['name'] if first else '(none)'} leads with \"{hint}\", which does not "
                                        f"name the bug (\"{lead}\")")
                    # The later failing tests: a hint that speaks of something else must come after
                    # the pointer to the first failing test, so that read alone it does not mislead.
                    later = [test for test in failing if test is not first and test["visibility"] != "hidden"]
                    elsewhere = [test for test in later
                                 if lead.lower() not in next((line for line in shown_text(test).splitlines()
                                                              if line.startswith("Hint:")), "").lower()]
                    pointer = judging.FIRST_FAILURE.format(first=first["name"].split(": ", 1)[1]) if first else None
                    problems += [f"{task}/{mutant.name}: the later failing test {test['name']} hints elsewhere and does "
                                 f"not lead with the pointer to the first ({first['name'] if first else '(none)'})"
                                 for test in elsewhere if not shown_text(test).lstrip().startswith(pointer or "\0")]
                    later_hints.append(f"{task}/{mutant.name}: {len(later) - len(elsewhere)} of {len(later)} later "
                                       "hints name the bug, the others point to the first failing test"
                                       + (f" ({', '.join(t['name'].split(': ', 1)[1] for t in elsewhere)})"
                                          if elsewhere else ""))
                    if first and task in PICTURE_TASKS:
                        drawn = results / "pictures" / f"{first['name'].split(': ', 1)[1]}.svg"
                        if not drawn.is_file() or first.get("output_format") != "html":
                            problems.append(f"{task}/{mutant.name}: the first failing test {first['name']} "
                                            "draws no picture")
                        else:
                            pictures += 1
                            problems += [f"{task}/{mutant.name}: {problem}" for problem in picture_problems(drawn, message)]
            finally:
                shutil.rmtree(submission)
                shutil.rmtree(results, ignore_errors=True)
            line = f"{task}/{mutant.name}: " + ", ".join(f"{t} {scores[t]}/{maxima[t]}" for t in TASKS)
            print(line, flush=True)
            if scores[task] >= maxima[task]:
                problems.append(f"{task}/{mutant.name} keeps full points in {task}")
            elif not seen_before_due_date:
                problems.append(f"{task}/{mutant.name} loses points only in tests a student sees after the due date "
                                f"(or never): make one that catches it visible (the first: {first_failing})")
            for other in TASKS:
                if other != task and scores[other] != maxima[other]:
                    problems.append(f"{task}/{mutant.name} costs points in {other}")
        print("mutants with a lead hint: " + ", ".join(f"{task} {count}" for task, count in with_lead.items())
              + f"; {pictures} pictures of their first failures read back", flush=True)
        print("\n".join(later_hints), flush=True)
        problems += [f"{task}: only {count} mutants check the lead hint (5 wanted)"
                     for task, count in with_lead.items() if count < (1 if one_per_task else 5)]
        self.assertEqual(problems, [], "\n".join(problems))


if __name__ == "__main__":
    if len(sys.argv) < 2:
        print(__doc__)
        sys.exit(2)
    BUILD = Path(sys.argv.pop(1)).resolve()
    unittest.main(verbosity=2)
