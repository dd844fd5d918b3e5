#!/usr/bin/python3
"""The test cases of one of the grader's test files, a line each, for CTest to register them
(tests/CMakeLists.txt): a test method written there runs without being listed anywhere else.

    /usr/bin/python3 tests/grader/tests/cases.py FILE            Class.test_name, each case
    /usr/bin/python3 tests/grader/tests/cases.py FILE --classes  Class, each class with a case

The file is read, never imported (its imports need not be installed when CMake configures). A
case is a method test_* of a class that is a unittest.TestCase, its own or inherited from a class
of the same file, in the file's order.
"""

import ast
import sys
from pathlib import Path


def test_cases(source):
    """[(class, [test methods])] of the TestCase classes in a file's source."""
    classes = {node.name: node for node in ast.parse(source).body if isinstance(node, ast.ClassDef)}

    def base_names(node):
        return [ast.unparse(base) for base in node.bases]

    def is_test_case(name, seen=()):
        node = classes.get(name)
        return node is not None and name not in seen and any(
            base in ("unittest.TestCase", "TestCase") or is_test_case(base, (*seen, name)) for base in base_names(node))

    def methods(name):
        node = classes[name]
        inherited = [method for base in base_names(node) if base in classes for method in methods(base)]
        own = [item.name for item in node.body
               if isinstance(item, (ast.FunctionDef, ast.AsyncFunctionDef)) and item.name.startswith("test")]
        return inherited + [method for method in own if method not in inherited]

    found = [(name, methods(name)) for name in classes if is_test_case(name)]
    return [(name, cases) for name, cases in found if cases]


def main(arguments):
    if len(arguments) not in (1, 2) or arguments[1:] not in ([], ["--classes"]):
        print("usage: cases.py FILE [--classes]", file=sys.stderr)
        return 2
    try:
        found = test_cases(Path(arguments[0]).read_text())
    except (OSError, SyntaxError) as error:
        print(f"cases.py: {arguments[0]}: {error}", file=sys.stderr)
        return 1
    if not found:
        print(f"cases.py: {arguments[0]} has no test case", file=sys.stderr)
        return 1
    for name, cases in found:
        print(*([name] if arguments[1:] else [f"{name}.{case}" for case in cases]), sep="\n")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
