#!/usr/bin/python3
"""The hostile suite: each submission of tests/grader/tests/hostile/attacks/ tries one way to break a
promise of the grader, and is graded end to end. Every attack must score 0 in its own task, change
no other task's points, show nothing of the reference code, the hidden tests or the repository's
history in any output, and leave nothing behind (no process and no file of a cell's user). The
attacks' files are listed in tests/grader/tests/hostile/README.md.

    /usr/bin/python3 tests/grader/tests/test_attacks.py BUILD_FOLDER [unittest arguments]

BUILD_FOLDER is the grader's build, shared with test_grader.py (CTest runs them one at a time).
"""

import json
import os
import re
import shutil
import sys
import tempfile
import unittest
from pathlib import Path

HERE = Path(__file__).resolve().parent
GRADER = HERE.parent  # the grader, whose tests these are
REPO = HERE.parents[2]
sys.path.insert(0, str(GRADER))
import cell  # noqa: E402
import test_grader  # noqa: E402
from course import TASK_FILE, TASKS  # noqa: E402

ATTACKS = HERE / "hostile" / "attacks"


# The sectors stage's efficiency tests (tests/graded/test_sectors.cpp): the count of pair tests
# gives the hint, the time limit on a large table the points.
EFFICIENCY_TESTS = ["Sectors.TestsAtLeast20TimesFewerPairsThanAllPairs",
                    "Sectors.TestsAtLeast100TimesFewerPairsGrowingLinearlyWithN"]


def attack(name, **paths):
    """The file of an attack; a template (.in) gets the given paths for its @NAME@ words."""
    folder = ATTACKS / name
    files = list(folder.iterdir())
    if len(files) != 1:
        raise AssertionError(f"{folder} must hold exactly one task file")
    source = files[0]
    if source.suffix != ".in":
        return source
    text = source.read_text()
    for word, path in paths.items():
        text = text.replace(f"@{word}@", str(path))
    if re.findall(r"@[A-Z]+@", text):
        raise AssertionError(f"{source}: {re.findall(r'@[A-Z]+@', text)} not given")
    target = Path(tempfile.mkdtemp(prefix="attack-")) / source.stem
    target.write_text(text)
    return target


def task_of(path):
    """The task a task file is for, by its name."""
    return next(task for task in TASKS if TASK_FILE[task] == Path(path).name)


def submission(base, attacks):
    """A submission folder: every task's file from `base` (solutions/ or tasks/), the attacks' in
    their tasks."""
    folder = Path(tempfile.mkdtemp(prefix="hostile-"))
    for task in TASKS:
        shutil.copyfile(REPO / base / TASK_FILE[task], folder / TASK_FILE[task])
    for path in attacks:
        shutil.copyfile(path, folder / Path(path).name)
    return folder


def platform_submission(repo, build):
    """{task file name: text}: a submission for a grading platform's package, with an attack in
    every task but two (forging a verdict, reading the reference code and the platform's copy of
    the course, stashing hidden inputs, swapping links), and the reference solutions of the
    package's course (`repo`, its grader's build `build`) in the other two. Returns it with the
    tasks attacked."""
    attacks = {"secret_in_memory": {}, "reads_reference": {"REPO": repo, "BUILD": build}, "operator_new": {},
               "stash_hidden_inputs": {}, "swapped_link": {"REPO": repo}, "verdict_at_exit": {},
               "fake_reporter": {}, "expected_output": {}}
    files = {TASK_FILE[task]: (Path(repo) / "solutions" / TASK_FILE[task]).read_text() for task in TASKS}
    attacked = []
    for name, paths in attacks.items():
        path = attack(name, **paths)
        if task_of(path) in TASKS:
            files[path.name] = path.read_text()
            attacked.append(task_of(path))
        if path.parent.name.startswith("attack-"):
            shutil.rmtree(path.parent)
    return files, attacked


def secrets():
    """Pieces of text that must never reach an output: lines of the reference solutions and of the
    hidden tests that no file a student has holds, and the hidden tests' names."""
    shared = set()
    for path in [*(REPO / "tasks").iterdir(), *(REPO / "tests" / "graded").glob("*.?pp")]:
        if path.is_file():
            shared |= {line.strip() for line in path.read_text(errors="replace").splitlines()}
    found = set()
    for path in [*(REPO / "solutions").glob("*.c*"), *(REPO / "tests" / "graded" / "hidden").glob("*.cpp")]:
        for line in path.read_text().splitlines():
            line = line.strip()
            if len(line) >= 40 and line not in shared:
                found.add(line)
        found |= set(re.findall(r"GRADED_TEST\(\w+,\s*(\w+),", path.read_text())) if "hidden" in str(path) else set()
    return found


def outputs(report, stdout, results):
    """Everything a grading wrote that someone reads: {where: text}."""
    written = {"the printed table": stdout, "results.json": json.dumps(report)}
    for path in results.rglob("*"):
        if path.is_file():
            written[str(path.relative_to(results))] = path.read_text(errors="replace")
    return written


def in_use(uid):
    """Whether a grading holds user id `uid` now (its claim, or its lock file; cell.UserIds)."""
    claim = cell.claim_user(uid)
    if claim is False:
        return True
    if claim:
        claim.close()
    lock = cell.open_lock(cell.pool_folder(), uid, create=False)
    if lock is None:
        return (cell.pool_folder() / f"{uid}.lock").exists()  # locked by the grading that holds it
    lock.close()
    return False


def leftovers():
    """What the cells of gradings that have ended left: their users' processes, and their files
    in the shared folders (gradings that run beside this test hold their user ids)."""
    first, last = cell.FIRST_CELL_USER, cell.FIRST_CELL_USER + cell.CELL_USERS
    found = []
    for entry in Path("/proc").iterdir():
        try:
            if entry.name.isdigit():
                uid = int(re.search(r"^Uid:\s+(\d+)", (entry / "status").read_text(), re.M).group(1))
                state = re.search(r"^State:\s+(\w)", (entry / "status").read_text(), re.M).group(1)
                if first <= uid < last and state not in "ZX" and not in_use(uid):
                    found.append(f"process {entry.name} of user {uid}")
        except (OSError, AttributeError):
            pass
    # Where the cells could write: the shared folders and the world-writable folders below them.
    for entry in cell.files_of(set(), is_owner=lambda owner: first <= owner < last and not in_use(owner)):
        found.append(f"{entry.path} of user {entry.stat(follow_symlinks=False).st_uid}")
    for shared in cell.SHARED_FOLDERS:
        try:
            for entry in os.scandir(shared):
                if "billiard-stash" in entry.name or "billiard-hog" in entry.name:
                    found.append(f"{entry.path} of user {entry.stat(follow_symlinks=False).st_uid}")
        except OSError:
            pass
    return found


class Attacks(unittest.TestCase):
    def grade(self, folder, *options):
        """Grades a hostile submission (removed afterwards); returns (scores, maxima, report,
        {where: text} of every output, the instructor's records of every test, hidden ones with
        their messages)."""
        results = Path(tempfile.mkdtemp(prefix="hostile-results-"))
        records = results.with_name(results.name + "-records.json")
        try:
            scores, maxima, report, _, stdout = test_grader.grade(folder, *options, "--records", str(records),
                                                                  results=results)
            return scores, maxima, report, outputs(report, stdout, results), json.loads(records.read_text())
        finally:
            shutil.rmtree(folder)
            shutil.rmtree(results, ignore_errors=True)
            records.unlink(missing_ok=True)

    def assert_nothing_leaks(self, written, records=()):
        """Nothing of the reference, the hidden tests, the repository or the judges in any output;
        no stash of a hidden test's inputs (what the stash attack printed as "STASHING:" in a hidden
        test, and in no test shown) in any output; nothing left behind."""
        shown = {line for record in records for test in record["tests"] if test["visibility"] != "hidden"
                 for line in test["feedback"].splitlines() if line.startswith("STASHING: ")}
        hidden_inputs = {line[len("STASHING: "):] for record in records for test in record["tests"]
                         if test["visibility"] == "hidden" for line in test["feedback"].splitlines()
                         if line.startswith("STASHING: ") and line not in shown}
        for where, text in written.items():
            for secret in [*secrets(), *hidden_inputs]:
                self.assertNotIn(secret, text, f"{where} shows '{secret}'")
            for line in text.splitlines():
                if line.startswith(("READ ", "LISTED ")):
                    self.assertNotRegex(line, rf"{re.escape(str(REPO))}|{re.escape(str(test_grader.BUILD))}|/proc/|judge",
                                        f"{where}: an attack read {line}")
        self.assertEqual(leftovers(), [], "the cells left processes or files behind")

    def test_forging_a_verdict_gains_nothing(self):
        """The verdict rewritten at exit, a constructor that speaks the judge's protocol, main()
        and the C library replaced, the secret searched in memory, operator new replaced,
        GoogleTest's reporter installed, the C program printing the expected output: each scores 0
        in its task, and the tasks beside them keep full points."""
        attacks = {name: attack(name) for name in ["verdict_at_exit", "protocol_in_constructor", "defines_main",
                                                   "libc_interposition", "secret_in_memory", "operator_new",
                                                   "fake_reporter", "expected_output"]}
        attacked = {task_of(path) for path in attacks.values()}
        self.assertEqual(len(attacked), len(attacks), "one attack per task")
        scores, maxima, report, written, _ = self.grade(submission("solutions", attacks.values()))
        for task in TASKS:
            if task in attacked:
                self.assertEqual(scores[task], 0, f"{task} is attacked and must score 0")
            else:
                self.assertEqual(scores[task], maxima[task], f"{task} is correct and must keep full points")
        shown = {test["name"].split(":")[0]: test["output"] for test in report["tests"] if test["status"] == "failed"}
        self.assertIn("main()", shown[task_of(attacks["defines_main"])])
        self.assertIn("operator new", shown[task_of(attacks["operator_new"])])
        self.assertIn("wait4, a function of the C library", shown[task_of(attacks["libc_interposition"])])
        self.assertIn("GoogleTest", shown[task_of(attacks["fake_reporter"])])
        for text in written.values():  # the memory search found no secret, if it got as far as saying so
            found = re.search(r"FOUND-SECRETS-BEGIN\n(.*?)FOUND-SECRETS-END", text, re.S)
            self.assertTrue(found is None or not found.group(1).strip(), found and found.group(1))
        self.assert_nothing_leaks(written)

    def test_other_tasks_and_files_stay_out_of_reach(self):
        """A task's code that tries to outlive its test and take over the later tasks' tests (they
        are the untouched stubs here: any point they gain would be forged), one that reads the
        reference code, the hidden tests, the repository's history and the judges' programs and
        folders, one that swaps links into where pictures are drawn, and one that stashes the hidden
        tests' inputs where a later test could show them: every task scores 0 and nothing leaks."""
        attacks = [attack("later_tasks"), attack("reads_reference", REPO=REPO, BUILD=test_grader.BUILD),
                   attack("stash_hidden_inputs"), attack("swapped_link", REPO=REPO)]
        try:
            scores, _, _, written, records = self.grade(submission("tasks", attacks))
        finally:
            for path in attacks:
                if path.parent.name.startswith("attack-"):
                    shutil.rmtree(path.parent)
        self.assertEqual(scores, {task: 0 for task in TASKS})
        self.assertTrue(any("not computed" in text for text in written.values()), "the attacks ran")
        self.assertTrue(any("STASHING: " in test["feedback"] for record in records for test in record["tests"]
                            if test["visibility"] == "hidden"), "the stash attack ran in a hidden test")
        self.assert_nothing_leaks(written, records)

    def test_another_tasks_reference_code_answers_for_no_task(self):
        """propagate.cpp that calls the walls stage with no walls (refused, with a message naming
        the call), and kinetic_energy.cpp that looks through its own program's memory for what
        only the gravity stage's reference code holds (code it could reach without naming it):
        the stages' reference code would answer for tasks 4 and 6. Each scores 0, neither finds
        another task's reference code in its process, and the tasks beside them (movie, which may
        call propagate, among them) keep full points."""
        attacks = [attack("another_tasks_reference"), attack("looks_for_a_stage_in_its_memory")]
        attacked = {task_of(path) for path in attacks}
        scores, maxima, report, written, _ = self.grade(submission("solutions", attacks))
        for task in TASKS:
            self.assertEqual(scores[task], 0 if task in attacked else maxima[task], task)
        shown = {task: "\n".join(test["output"] for test in report["tests"] if test["name"].startswith(task + ":"))
                 for task in attacked}
        self.assertIn("propagate_walls", shown["propagate"])
        self.assertIn("task 8 (walls), which propagate.cpp may not call", shown["propagate"])
        self.assertIn("no other task's reference code here", shown["kinetic_energy"], "the search ran")
        for where, text in written.items():
            self.assertNotIn("FOUND: the gravity stage's reference code", text, where)
        self.assert_nothing_leaks(written)

    def test_a_forged_pair_count_earns_no_efficiency_point(self):
        """sectors.cpp that tests all pairs with a formula of its own and calls pair_time n times on
        (i, i): the count, which lives in its process, looks linear. Every efficiency test still
        fails, stopped at its time limit on the table of 200,000 circles (the time read from
        outside the worker), and says why; the other tasks keep full points."""
        path = attack("forged_pair_count")
        task = task_of(path)
        scores, maxima, report, written, _ = self.grade(submission("solutions", [path]))
        efficiency = {name: test for name, test in ((test["name"].split(": ", 1)[-1], test) for test in report["tests"]
                                                    if test["name"].startswith(task + ":"))
                      if name in EFFICIENCY_TESTS}
        self.assertEqual(sorted(efficiency), sorted(EFFICIENCY_TESTS), "the suite's efficiency tests are in the report")
        for name, test in efficiency.items():
            self.assertEqual(test["status"], "failed", f"{name} earns points on the forged count")
        shown = [test["output"] for test in efficiency.values() if test["visibility"] != "hidden" and test["output"]]
        self.assertTrue(any("did not finish within" in text and "dilute table of 200000 circles" in text
                            for text in shown), shown)
        self.assertLessEqual(scores[task], maxima[task] - sum(test["max_score"] for test in efficiency.values()))
        for other in TASKS:
            if other != task:
                self.assertEqual(scores[other], maxima[other], f"{other} is correct and must keep full points")
        self.assert_nothing_leaks(written)

    def test_holding_memory_and_processors_costs_only_its_own_task(self):
        """A task whose code starts processes that hold memory, busy threads, allocates beyond its
        limit and fills shared memory: it scores 0, every other task keeps full points, and nothing
        of it is left once the grading is over."""
        path = attack("memory_and_processes")
        # Fixed limits keep the attack's time short: 5 s per test (the slowest reference test needs
        # 2 s, busy machine included), 30 s for its task.
        scores, maxima, _, written, _ = self.grade(submission("solutions", [path]), "--limits", "fixed", "--timeout",
                                                   "5", "--task-budget", "30")
        task = task_of(path)
        self.assertEqual(scores[task], 0)
        self.assertTrue(any("wrote more than" in text for text in written.values()), "the folder's limit stopped it")
        for other in TASKS:
            if other != task:
                self.assertEqual(scores[other], maxima[other], f"{other} is correct and must keep full points")
        self.assert_nothing_leaks(written)


@unittest.skipUnless(os.geteuid() == 0, "as root only: user ids of their own are what holds without Landlock")
class AttacksWithoutLandlock(Attacks):
    """The same attacks with the cells' Landlock left out, as on a grading machine whose kernel has
    none (Gradescope's, say): as root, the cells' own user ids and the protected repository hold
    alone."""

    def setUp(self):
        os.environ[cell.WITHOUT_LANDLOCK] = "1"

    def tearDown(self):
        del os.environ[cell.WITHOUT_LANDLOCK]

    def grade(self, folder, *options):
        found = super().grade(folder, *options)
        self.assertTrue(any("no Landlock" in text for text in found[3].values()), "the cells ran without Landlock")
        return found


if __name__ == "__main__":
    if len(sys.argv) < 2:
        print(__doc__)
        sys.exit(2)
    test_grader.BUILD = Path(sys.argv.pop(1)).resolve()
    unittest.main(verbosity=2)
