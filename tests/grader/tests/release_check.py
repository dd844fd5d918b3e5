#!/usr/bin/python3
"""Checks that an exported student release names nothing it does not have.

    /usr/bin/python3 tests/grader/tests/release_check.py RELEASE_FOLDER

Run after the release has been built (its `./build.sh test` has run). Every command in the
release's README.md (code blocks and inline code) and in `./build.sh --help` is run in the
release, or, where running it would take minutes, checked piece by piece (the options of a
benchmark command against its --help). Every path the README shows, and every repository path
that a shipped text file cites (such as `tests/grader/grade.py` in a comment), must exist in the
release. Prints one line per check and, at the end, the problems; exit status 0 when there are
none, 1 otherwise, 2 for bad arguments.
"""

import glob
import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the grader, whose tests these are
from course import TASKS  # noqa: E402

# Values for the README's placeholders.
PLACEHOLDERS = {"<task>": "propagate", "<preset>": "tasks", "<notebook>": "01_tour", "<k>": "1"}
# Repository paths as prose cites them: a top-level folder of the project, then a path.
CITED_PATH = re.compile(r"(?<![\w/.$-])((?:\.github|\.ci|lib|tasks|tests|notebooks|solutions)/[\w.<>*/-]*[\w>*])")
# Commands, as a reader would type them, recognised by their first word.
COMMAND_START = re.compile(r"^(\./build\.sh|ctest|cmake|billiard|/usr/bin/python3|tar|jupyter|build/)\b")
# Tools the release only names, with the Debian package that has them (not installed by build.sh).
NAMED_ONLY = {"jupyter"}


def readme_commands(markdown):
    """Commands in the README's shell blocks (continuation lines joined) and inline code."""
    commands = []
    for block in re.findall(r"```sh\n(.*?)```", markdown, re.DOTALL):
        for line in block.replace("\\\n", " ").splitlines():
            if COMMAND_START.match(line.strip()):
                commands.append(line.strip())
    for span in re.findall(r"(?<!`)`([^`]+)`(?!`)", re.sub(r"```.*?```", "", markdown, flags=re.DOTALL)):
        span = " ".join(span.split())  # inline code may run over a line break
        words = span.split()
        if words[0] in ("cmake", "ctest") and not (len(words) > 1 and words[1].startswith("-")):
            continue  # a list of Debian packages, not a command
        if COMMAND_START.match(span) and (" " in span or span.startswith("./")):
            commands.append(span)
    return commands


def readme_paths(markdown):
    """Paths the README shows in inline code: `tasks/propagate.cpp`, `build/<preset>/python/`."""
    paths = []
    for span in re.findall(r"(?<!`)`([^`\n ]+)`(?!`)", markdown):
        # `billiard/...` names a file of the Python package, relative to lib/python/; `particles/...`,
        # `configuration/...` and `log/...` name the fields of a GSD trajectory
        if "/" in span and not span.startswith(("./", "/", "http", "billiard/", "particles/", "configuration/", "log/")):
            paths.append(span)
    return paths


def help_commands(text):
    """The commands `./build.sh --help` lists (each line's command part)."""
    return [re.split(r"\s{2,}", line.strip())[0] for line in text.splitlines() if line.strip().startswith("./build.sh")]


def fill(text):
    for name, value in PLACEHOLDERS.items():
        text = text.replace(name, value)
    return text


def is_usage(words):
    """A synopsis such as `billiard [TABLE_RADIUS ...] [--seed S]`, not a command to run."""
    return any(word.startswith("[") or re.fullmatch(r"[A-Z][A-Z_]+", word) for word in words[1:])


class Checker:
    def __init__(self, folder):
        self.folder = folder
        self.problems = []
        self.checked = 0
        self.output_folders = set()

    def run(self, words, timeout=900):
        done = subprocess.run(words, cwd=self.folder, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                              errors="replace", timeout=timeout, env={**os.environ, "PAGER": "cat"})
        return done.returncode, done.stdout

    def expect(self, ok, where, what, output=""):
        self.checked += 1
        print(f"{'ok  ' if ok else 'FAIL'} {where}: {what}", flush=True)
        if not ok:
            self.problems.append(f"{where}: {what}" + (f"\n{output[-1500:]}" if output else ""))

    def exists(self, path, where):
        path = fill(path).rstrip("/")
        if any(path == folder or path.startswith(folder + "/") for folder in self.output_folders):
            return  # written by a command the README shows, not by the build
        self.expect(bool(glob.glob(str(self.folder / re.sub(r"<[^>]*>", "*", path)))), where, f"{path} exists")

    def command(self, text, where):
        try:
            words = [fill(word) for word in shlex.split(text, comments=True)]
        except ValueError as error:
            self.expect(False, where, f"`{text}` parses ({error})")
            return
        if not words:
            return
        for option in ("--output-dir", "--output"):
            if option in words[:-1]:
                self.output_folders.add(words[words.index(option) + 1].rstrip("/"))
        head = words[0]
        if head in NAMED_ONLY:
            self.expect(True, where, f"`{text}` names a tool the README says how to install")
        elif head == "./build.sh":
            self.build_sh(words, text, where)
        elif head in ("ctest", "cmake"):
            self.cmake_tool(words, text, where)
        elif head == "billiard" or head.endswith("/billiard"):
            exe = str(self.folder / "build" / "tasks" / "billiard")
            arguments = ["--help"] if is_usage(words) else words[1:]
            status, output = self.run([exe, *arguments])
            self.expect(status in (0, 1), where, f"`{text}` runs (exit {status})", output)
        elif head == "/usr/bin/python3":
            self.python(words, text, where)
        elif head == "tar":
            status, output = self.run(["bash", "-c", text + " && rm -f handin.tar"])
            self.expect(status == 0, where, f"`{text}` works", output)
        elif head.startswith("build/"):
            self.exists(head, where)
        else:
            self.expect(False, where, f"`{text}`: no check for this kind of command")

    def build_sh(self, words, text, where):
        sub = words[1] if len(words) > 1 else ""
        if is_usage(words):
            status, output = self.run(["./build.sh", sub, "--help"] if sub in ("grade", "bench") else ["./build.sh", "--help"])
            self.expect(status == 0 and sub in output, where, f"`{text}`: ./build.sh knows `{sub}`", output)
        elif sub == "bench":
            # The benchmark runs for minutes: its options are checked against its --help.
            status, output = self.run(["./build.sh", "bench", "--help"])
            unknown = [word for word in words[2:] if word.startswith("--") and word.split("=")[0] not in output]
            self.expect(status == 0 and not unknown, where, f"`{text}`: options the benchmark knows"
                        + (f" (not: {' '.join(unknown)})" if unknown else ""), output)
        elif sub == "test" and not any(word in ("-L", "-R") or word.startswith("--label") for word in words[2:]):
            self.expect(True, where, f"`{text}`: the full run (done before this check)")
        elif sub == "test" and not set(words[2:]) & set(TASKS):
            # Other labels (the engine's, the long stress run): built, and their tests listed.
            status, output = self.run([*words, "-N"])
            found = re.search(r"Total Tests: (\d+)", output)
            self.expect(status == 0 and found and int(found.group(1)) > 0, where, f"`{text}` finds tests", output)
        else:
            status, output = self.run(words)
            failing_tests_only = sub == "test" and "tests failed out of" in output
            self.expect(status == 0 or (sub == "run" and status == 1) or failing_tests_only, where,
                        f"`{text}` works (exit {status})", output)
            if sub == "test":
                self.expect("No tests were found" not in output, where, f"`{text}` runs tests", output)

    def cmake_tool(self, words, text, where):
        if words[0] == "ctest":
            status, output = self.run([*words, "-N"])
            found = re.search(r"Total Tests: (\d+)", output)
            self.expect(status == 0 and found and int(found.group(1)) > 0, where, f"`{text}` finds tests", output)
        else:
            status, output = self.run(words)
            self.expect(status == 0, where, f"`{text}` works (exit {status})", output)

    def python(self, words, text, where):
        if words[1:2] == ["-m"]:
            status, output = self.run([words[0], "-m", words[2], "--help"])
            self.expect(status == 0, where, f"`{text}`: module {words[2]} is there", output)
        elif words[1:2] == ["-c"]:
            status, output = self.run(words)
            self.expect(status == 0, where, f"`{text}` works", output)
        else:
            self.exists(words[1], where)
            status, output = self.run([words[0], words[1], "--help"])
            self.expect(status == 0, where, f"`{words[0]} {words[1]} --help` works", output)

    def cited_paths(self):
        """Repository paths cited by the release's own text files."""
        for path in sorted(self.folder.rglob("*")):
            relative = path.relative_to(self.folder)
            if not path.is_file() or relative.parts[0] in ("build", ".git"):
                continue
            try:
                text = path.read_text()
            except (UnicodeDecodeError, OSError):
                continue
            for cited in sorted(set(CITED_PATH.findall(text))):
                self.exists(cited, str(relative))


def check(folder):
    checker = Checker(folder)
    readme = (folder / "README.md").read_text()
    status, help_text = checker.run(["./build.sh", "--help"])
    checker.expect(status == 0, "./build.sh --help", "works", help_text)
    status, alone = checker.run(["./build.sh"])  # no command: its help, as a mistake
    checker.expect(status == 2 and alone == help_text, "./build.sh", "prints its help (exit 2)", alone)
    for command in readme_commands(readme):
        checker.command(command, "README.md")
    for command in help_commands(help_text):
        checker.command(command, "./build.sh --help")
    for path in readme_paths(readme):
        checker.exists(path, "README.md")
    checker.cited_paths()
    return checker


def main(argv):
    if len(argv) != 1 or not (Path(argv[0]) / "build.sh").is_file():
        print(__doc__.strip().splitlines()[0] + "\nusage: release_check.py RELEASE_FOLDER (a built student release)",
              file=sys.stderr)
        return 2
    checker = check(Path(argv[0]).resolve())
    print(f"release check: {checker.checked} checks, {len(checker.problems)} problems")
    for problem in checker.problems:
        print("PROBLEM " + problem)
    return 0 if not checker.problems else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
