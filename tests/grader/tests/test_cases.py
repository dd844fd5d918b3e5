#!/usr/bin/python3
"""Tests of cases.py, which CTest's registration of the grader's test cases reads: every case
unittest would run is registered, a mixin's or a base class's included, and nothing else.

    /usr/bin/python3 tests/grader/tests/test_cases.py
"""

import sys
import unittest
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parent))
import cases  # noqa: E402

# The files whose cases tests/CMakeLists.txt registers one by one.
REGISTERED_FILES = ["test_grader.py", "test_attacks.py", "test_packages.py", "test_uploads.py", "test_class.py"]


def unittest_cases(file):
    """Class.test_name of every case unittest's loader finds in a test file."""
    module = __import__(Path(file).stem)
    found = set()

    def walk(suite):
        for item in suite:
            if isinstance(item, unittest.TestSuite):
                walk(item)
            else:
                found.add(f"{type(item).__name__}.{item._testMethodName}")
    walk(unittest.defaultTestLoader.loadTestsFromModule(module))
    return found


class Cases(unittest.TestCase):
    def test_every_case_unittest_finds_is_registered(self):
        for file in REGISTERED_FILES:
            listed = [f"{name}.{case}" for name, names in cases.test_cases((HERE / file).read_text()) for case in names]
            self.assertEqual(len(listed), len(set(listed)), file)
            self.assertEqual(set(listed), unittest_cases(file), file)

    def test_bases_mixins_and_other_classes(self):
        source = '''
import unittest
class Helper:
    def test_not_a_case(self): pass
class Mixin:
    def test_from_the_mixin(self): pass
class First(unittest.TestCase):
    def test_one(self): pass
    def helper(self): pass
class Second(First):
    def test_two(self): pass
    def test_one(self): pass
class Third(Mixin, unittest.TestCase):
    def test_three(self): pass
class Empty(unittest.TestCase):
    def setUp(self): pass
'''
        self.assertEqual(cases.test_cases(source), [("First", ["test_one"]), ("Second", ["test_one", "test_two"]),
                                                    ("Third", ["test_from_the_mixin", "test_three"])])


if __name__ == "__main__":
    unittest.main()
