#!/usr/bin/python3
"""Tests of the class grader's copy finder (tests/grader/similarity.py, Dolos), on files alone:
copies hidden as students hide them are flagged, solutions written apart are not, what many
students share is nobody's own, and a file that would stall the finder, or a finder that cannot
run, costs a note, never the comparison of the rest.

    /usr/bin/python3 tests/grader/tests/test_similarity.py [unittest arguments]
"""

import random
import sys
import tempfile
import time
import unittest
from pathlib import Path
from unittest import mock

HERE = Path(__file__).resolve().parent
GRADER = HERE.parent
REPO = HERE.parents[2]
sys.path.insert(0, str(GRADER))
import similarity  # noqa: E402
from course import TASK_FILE, TASKS  # noqa: E402
from disguises import DISGUISES, hidden, renamed  # noqa: E402


def reference(task):
    return (REPO / "solutions" / TASK_FILE[task]).read_bytes()


def stub(task):
    return (REPO / "tasks" / TASK_FILE[task]).read_bytes()


def flagged(pairs):
    """{(first, second)} of the near-copies among pairs."""
    return {(pair.first, pair.second) for pair in pairs if not pair.identical}


class Finder(unittest.TestCase):
    def setUp(self):
        problem = similarity.finder_problem()
        if problem and similarity.node_too_old():  # a system limit (Ubuntu 22.04), not a set-up gone wrong
            self.skipTest(f"Similarity: skipped: {problem}")
        if problem:
            self.fail(f"the copy finder cannot run here: {problem} (./build.sh test installs it)")

    def test_hidden_copies_are_flagged_in_every_task(self):
        # Each task's reference beside a copy hidden each way (one comparison per task): each copy
        # flagged beside it, with the share at least the threshold and the matching parts one to
        # one, on lines of both files. init_velocities (a dozen lines, the stub's hints spelled
        # out) is too small to tell a copy by.
        rng = random.Random(7)
        for task in TASKS:
            files = {"original": reference(task)}
            for kind, disguise in DISGUISES.items():
                copy = disguise(reference(task).decode(), rng).encode()
                if copy not in files.values():  # (one function: nothing to reorder)
                    files[kind] = copy
            pairs, notes = similarity.compare_task(task, files, stub(task))
            self.assertEqual(notes, [])
            beside = {pair.first if pair.second == "original" else pair.second: pair for pair in pairs
                      if "original" in (pair.first, pair.second) and not pair.identical}
            if task == "init_velocities":
                self.assertEqual(beside, {}, f"{task}: too small to tell, but flagged")
                continue
            for kind in set(files) - {"original"}:
                self.assertIn(kind, beside, f"{task}, {kind}: the hidden copy is not flagged")
                pair = beside[kind]
                self.assertGreaterEqual(pair.share, similarity.SHARE_FLAGGED, f"{task}, {kind}")
                self.assertTrue(pair.runs and all(a[0] <= a[1] and b[0] <= b[1] for a, b, _ in pair.runs), pair.runs)
                for side in (0, 1):  # the parts shown side by side: each line of a file in one at most
                    lines = [line for run in pair.runs for line in range(run[side][0], run[side][1] + 1)]
                    self.assertEqual(len(lines), len(set(lines)), f"{task}, {kind}: parts overlap: {pair.runs}")

    def test_solutions_written_apart_are_not_copies(self):
        # tests/grader/tests/honest/: propagate and kinetic_energy written another way, and
        # init_velocities in the one natural way, names alone differing from the reference.
        for path in sorted((HERE / "honest").iterdir()):
            task = next(task for task in TASKS if TASK_FILE[task] == path.name)
            pairs, _ = similarity.compare_task(task, {"reference": reference(task), "honest": path.read_bytes()},
                                               stub(task))
            self.assertEqual(pairs, [], f"{path.name}: written apart, but flagged")

    def test_what_many_students_share_is_nobodys_own(self):
        # Two renamed copies of propagate alone are flagged; among a dozen more, each renamed
        # apart, what they all share is the class's, as MOSS counts it: nobody is flagged. Two of
        # them who also share code of their own (a helper nobody else has) are flagged again.
        rng = random.Random(3)
        copies = {f"student-{number:02d}": renamed(reference("propagate").decode(), rng).encode() for number in range(14)}
        two = dict(list(copies.items())[:2])
        self.assertEqual(len(flagged(similarity.compare_task("propagate", two, stub("propagate"))[0])), 1)
        self.assertEqual(flagged(similarity.compare_task("propagate", copies, stub("propagate"))[0]), set())
        helper = (HERE / "honest" / "propagate.cpp").read_text().split("namespace billiard {", 1)[1]
        pair = {"student-00": copies["student-00"].decode(), "student-01": copies["student-01"].decode()}
        for name in pair:
            copies[name] = (pair[name].replace("namespace billiard {", "namespace billiard {\n" + helper
                                               .replace("}  // namespace billiard", "").replace("propagate(", "helper(")
                                               , 1)).encode()
        self.assertEqual(flagged(similarity.compare_task("propagate", copies, stub("propagate"))[0]),
                         {("student-00", "student-01")})

    def test_a_token_flood_is_left_out_with_a_note(self):
        # A file of a megabyte of one token (a class's whole comparison ran out of time on it
        # with the tester before): left out and named; the copy beside it is still found.
        largest = max(len(reference(task)) for task in TASKS)
        self.assertGreater(similarity.COMPARED_FILE_CAP, 4 * largest, "the cap would leave out real solutions")
        started = time.monotonic()
        files = {"flood": b"x;" * 500_000, "original": reference("propagate"),
                 "copier": hidden(reference("propagate").decode(), random.Random(1)).encode()}
        pairs, notes = similarity.compare_task("propagate", files, stub("propagate"))
        self.assertEqual(flagged(pairs), {("copier", "original")})
        self.assertEqual(len(notes), 1)
        self.assertIn("flood", notes[0])
        self.assertLess(time.monotonic() - started, 60)

    def test_a_file_that_does_not_build_is_left_out_with_a_note(self):
        # A hidden copy that does not build is not compared (whatever it holds, the finder need not
        # parse it); the pair of copies that build is still found, and so is an identical copy.
        original = reference("propagate")
        files = {"original": original, "copier": hidden(original.decode(), random.Random(3)).encode(),
                 "broken": hidden(original.decode(), random.Random(4)).encode() + b"\n}}} not C++",
                 "broken-twin": original}
        pairs, notes = similarity.compare_task("propagate", files, stub("propagate"), {"broken", "broken-twin"})
        self.assertEqual(flagged(pairs), {("copier", "original")})
        self.assertEqual([(p.first, p.second) for p in pairs if p.identical], [("broken-twin", "original")])
        self.assertEqual(len(notes), 1, notes)
        self.assertIn("does not build", notes[0])
        self.assertIn("broken, broken-twin", notes[0])

    def test_the_stub_and_identical_files(self):
        # The untouched stub is nobody's copy; identical files are a group whatever their size.
        files = {"a": stub("init_velocities"), "b": stub("init_velocities"), "c": reference("init_velocities"),
                 "d": reference("init_velocities")}
        pairs, _ = similarity.compare_task("init_velocities", files, stub("init_velocities"))
        self.assertEqual([(pair.first, pair.second, pair.identical) for pair in pairs], [("c", "d", True)])


class WithoutTheFinder(unittest.TestCase):
    def test_a_note_says_why_and_identical_files_are_still_found(self):
        with mock.patch.object(similarity, "FINDER_HOME", GRADER / "no-such-folder"):
            comparison = similarity.compare_class(
                {"a": {"propagate": reference("propagate")}, "b": {"propagate": reference("propagate")},
                 "c": {"propagate": hidden(reference("propagate").decode(), random.Random(2)).encode()}},
                {"propagate": stub("propagate")}, ["propagate"])
        self.assertEqual(len(comparison.notes), 1)
        self.assertIn("Near-copies were not looked for", comparison.notes[0])
        self.assertIn("./build.sh grade --class", comparison.notes[0])
        self.assertEqual([(p.first, p.second, p.identical) for p in comparison.pairs["propagate"]], [("a", "b", True)])

    def test_an_install_that_failed_says_what_npm_said(self):
        # A registry that could not be reached while ./build.sh installed the finder (here: a
        # proxy's certificate this system does not trust): the note says so, not only "install it".
        home = Path(tempfile.mkdtemp(prefix="billiard-finder-"))
        (home / "npm.log").write_text(
            "npm ERR! code SELF_SIGNED_CERT_IN_CHAIN\nnpm ERR! errno SELF_SIGNED_CERT_IN_CHAIN\n"
            "npm ERR! request to https://registry.npmjs.org/yallist failed, reason: self-signed certificate\n")
        with mock.patch.object(similarity, "FINDER_HOME", home), mock.patch.object(similarity, "node_too_old",
                                                                                   return_value=None):
            problem = similarity.finder_problem() if similarity.node() else None
        if problem is None:
            self.skipTest("Similarity: skipped: no Node.js here")
        self.assertIn("which failed here: request to https://registry.npmjs.org/yallist failed", problem)
        self.assertIn(str(home / "npm.log"), problem)


if __name__ == "__main__":
    unittest.main(verbosity=2)
