"""Building a submission: the grader's own build (once, nothing in it depends on a submission),
then for each task its file compiled in the task's cell, its symbols checked, and its worker
linked there from the file, the harness and the other tasks' code.

Only regular files are taken from a submission (stage_submission), each compiled once with the
commands of the grader's build for them (the same flags as the course's own code, the course's
headers precompiled). The compiler runs in the task's cell (cell.py) with copies of the headers it
may read, so that a file that tries `#include "../solutions/propagate.cpp"`, or the assembler's
`.incbin`, reads nothing it may not. A task file may define only what its task's file may define
(the task's functions and helpers of its own): one that defines main(), a function of the C
library, operator new or delete, a GoogleTest name or a name of the grader's own code is refused
with a message that says which, before it is linked. The worker is linked in the cell too, and
only as objects: the harness (tests/grader/judge/worker_main.cpp), the task file and the other
tasks' code, so nothing in it is a library member a submission could replace.
"""

import fcntl
import functools
import hashlib
import json
import os
import re
import shlex
import shutil
import stat
import subprocess
import time
from pathlib import Path

import cell
from cell import Limits, read_regular_file, run_limited
from course import PROGRAM_TASKS, TASK_FILE, TASK_FUNCTIONS, TASKS, USES, task_name
from reports import TaskResult, TestResult, cap

REPO = Path(__file__).resolve().parents[2]
COMPILER_CAP = 6 * 1024  # characters of compiler output kept per task
SUBMITTED_FILE_CAP = 1_000_000  # bytes: a larger task file is not graded
# Why a task file cannot be graded, after its name.
LINK = "is a symbolic link, which the grader does not follow"
FOLDER = "is a folder, not a file"
SPECIAL = "is not an ordinary file"
TOO_LARGE = f"is larger than the {SUBMITTED_FILE_CAP:,} bytes the grader accepts (a task file has a few kilobytes)"
# Limits of a compilation or a link of submitted code (the reference files need less than 300
# MB), and the largest file either may make.
SUBMISSION_BUILD_MEMORY = 2 << 30
BUILT_FILE_CAP = 256 << 20
BUILD_PROCESSES = 64  # the compiler driver, the compiler proper, the assembler, the linker
# The C track's programs are linked with the maths library, as the build links them
# (billiard_add_program in CMakeLists.txt, grader_compile_c in tests/grader/CMakeLists.txt).
PROGRAM_LIBRARIES = ["-lm"]
KEPT = 400  # compiled task files and linked workers remembered in a build folder (the oldest go first)


class Build:
    """The grader's CMake build (see tests/grader/CMakeLists.txt): nothing in it depends on a
    submission."""

    def __init__(self, folder, dependencies, build_timeout):
        self.folder = folder
        self.dependencies = dependencies
        self.build_timeout = build_timeout
        self.submitted = folder / "submitted"

    def configure(self):
        """Configures the build, unless it is configured so already (then Ninja runs CMake again
        by itself where the project's CMake files changed)."""
        options = {"BILLIARD_COURSE": "solutions" if self.dependencies == "reference" else "tasks",
                   "BILLIARD_GRADER_OBJECTS": str(self.submitted), "BILLIARD_GRADE_DEPENDENCIES": self.dependencies}
        try:
            cache = (self.folder / "CMakeCache.txt").read_text()
            if (self.folder / "build.ninja").is_file() and all(
                    re.search(rf"^{name}:\w+={re.escape(value)}$", cache, re.M) for name, value in options.items()):
                return
        except OSError:
            pass
        command = ["cmake", "-S", str(REPO), "-B", str(self.folder), "-G", "Ninja", "-DCMAKE_BUILD_TYPE=Release",
                   "-DBILLIARD_CHECK_STUBS=OFF", "-DBILLIARD_PYTHON=OFF", "-DCMAKE_EXPORT_COMPILE_COMMANDS=ON",
                   *[f"-D{name}={value}" for name, value in options.items()]]
        ok, output, _ = run_limited(command, timeout=self.build_timeout)
        if not ok:
            raise RuntimeError("configuring the grader's build failed:\n" + output)

    def build(self, targets, timeout):
        """Builds targets with the build's Ninja (not through `cmake --build`, which would start one
        more program); returns (ok, output, timed out)."""
        return run_limited([self.ninja, "-C", str(self.folder), *targets], timeout=timeout)

    @functools.cached_property
    def ninja(self):
        found = re.search(r"^CMAKE_MAKE_PROGRAM:\w+=(.*)$", (self.folder / "CMakeCache.txt").read_text(), re.M)
        return found.group(1) if found else "ninja"

    def prebuild(self):
        """Builds everything that does not depend on the submission (the cell, the judges, the
        workers' harness and libraries, the reference code, the stand-ins, the compile commands
        and the precompiled headers for the submitted files), so that the time of each task's
        budget goes to its own file and tests only."""
        targets = ["grader_compile_cxx", "grader_compile_c", "billiard_cell", "billiard_worker_harness",
                   "billiard_judge_wire_objects", "billiard_course_support", "billiard_engine"]
        for task in TASKS:
            targets += [f"judge_{task}", f"grader_stub_{task}"]
            if task in PROGRAM_TASKS:
                targets += ["program_runner", task]  # the command that gives the expected output
            elif self.dependencies == "reference":
                targets.append(f"billiard_solutions_{task}")
        ok, output, _ = self.build(targets, timeout=self.build_timeout)
        if not ok:
            raise RuntimeError("building the grader's own code failed:\n" + output[-20000:])
        self.submitted.mkdir(exist_ok=True)

    @property
    def ready_stamp(self):
        return self.folder / "grader-ready.json"

    def is_ready(self):
        """Whether a grading finished building this folder, with these dependencies, and nothing
        has started building it since."""
        try:
            return json.loads(self.ready_stamp.read_text()) == {"dependencies": self.dependencies}
        except (OSError, ValueError):
            return False

    def mark_ready(self, ready):
        if ready:
            write_text(self.ready_stamp, json.dumps({"dependencies": self.dependencies}))
        else:
            self.ready_stamp.unlink(missing_ok=True)

    def judge(self, task):
        """The task's graded suite with proxies for the course's functions (no submitted code)."""
        return self.folder / "tests" / "grader" / f"judge_{task}"

    @property
    def launcher(self):
        return self.folder / "tests" / "grader" / "cell" / "cell"

    @property
    def program_runner(self):
        return self.folder / "tests" / "grader" / "judge" / "program_runner"

    def expected_program(self, task):
        """The project's own command of a program task, which gives the expected output."""
        return self.folder / task

    @functools.cached_property
    def stubs(self):
        """{task: the stand-in for a task file that is missing or does not compile}: an object
        file, or a program for a program task (the build lists them, in a file stubs.txt)."""
        lines = (self.folder / "tests" / "grader" / "stubs.txt").read_text().splitlines()
        return {task: Path(path) for task, path in (line.split(" ", 1) for line in lines if line.strip())}

    @functools.cached_property
    def worker_recipe(self):
        """What a C++ task's worker is linked from (tests/grader/CMakeLists.txt, worker-link.json)."""
        return json.loads((self.submitted / "worker-link.json").read_text())


def catalog(build, task, cache={}):
    """The graded tests of a task's suite, with points and visibility: the judge lists them (it
    holds no submitted code). Listed once per build and grading."""
    key = (build.folder, task)
    if key not in cache:
        done = subprocess.run([str(build.judge(task)), "--list-graded"], stdout=subprocess.PIPE,
                              stderr=subprocess.PIPE, text=True, timeout=60)
        if done.returncode != 0:
            raise RuntimeError(f"listing the tests of {task} failed:\n{done.stderr}")
        cache[key] = [json.loads(line) for line in done.stdout.splitlines() if line.strip()]
    return cache[key]


def command_words(entry):
    """A compile command from compile_commands.json, without its source and output: the compiler
    and its flags."""
    words = shlex.split(entry["command"])
    kept, skip = [], False
    for word in words:
        if skip:
            skip = False
        elif word in {"-o", "-c"}:
            skip = True
        else:
            kept.append(word)
    return kept


def defines_before_course_headers(text):
    """True when a C++ task file defines or undefines a macro before it includes the course's
    headers (or includes none of them): then the precompiled headers, which come first, could
    change what the file means, and it is compiled without them."""
    for line in text.decode(errors="replace").splitlines():
        if re.match(r"\s*#\s*include\s*[<\"]billiard/", line):
            return False
        if re.match(r"\s*#\s*(define|undef)\b", line):
            return True
    return True


def file_digest(path):
    """The file's SHA-256, read a block at a time (hashlib.file_digest is Python 3.11's)."""
    digest = hashlib.sha256()
    with open(path, "rb") as file:
        while block := file.read(1 << 20):
            digest.update(block)
    return digest.hexdigest()


class Remembered:
    """Files made from others, kept in the build folder by a key of what they were made from, so
    that a task file or worker made before is not made again (the oldest go first). Where the
    build folder is not the grader's to write (an Autolab job's user, beside the image's build),
    nothing is remembered."""

    def __init__(self, folder):
        self.folder = folder
        try:
            folder.mkdir(parents=True, exist_ok=True)
        except OSError:
            pass

    def recall(self, key):
        """(content, extra) saved under `key`, or None."""
        entry = self.folder / f"{key}.json"
        try:
            extra = json.loads(entry.read_text())
            content = (self.folder / f"{key}.bin").read_bytes()
            os.utime(entry)
        except (OSError, ValueError):
            return None
        return content, extra

    def remember(self, key, content, extra):
        try:
            partial = self.folder / f"{key}.bin.{os.getpid()}.partial"  # gradings may share the folder
            partial.write_bytes(content)
            os.replace(partial, self.folder / f"{key}.bin")
            write_text(self.folder / f"{key}.json", json.dumps(extra))
            entries = sorted(self.folder.glob("*.json"), key=lambda path: path.stat().st_mtime)
            for old in entries[:-KEPT]:
                old.unlink(missing_ok=True)
                old.with_suffix(".bin").unlink(missing_ok=True)
        except OSError:
            pass


class BuildLock:
    """Held by every grading that uses a build folder: alone to build it, with the others to
    grade from it. Several gradings may share one (the class grader's workers on a machine), and
    a build must never rewrite a file that a grading reads: the gradings' compilers read the
    precompiled header through hard links, and one rewritten under a running compiler kills it
    with a bus error. Where the folder's parent is not the grader's to write (an Autolab job's
    user, beside the image's build), no one builds there and there is no lock."""

    def __init__(self, folder):
        try:
            self.file = open(folder.parent / f"{folder.name}.lock", "a")
        except OSError:
            self.file = None

    def to_build(self):
        """Waits until no other grading uses the folder."""
        if self.file:
            fcntl.flock(self.file, fcntl.LOCK_EX)

    def to_grade(self):
        if self.file:
            fcntl.flock(self.file, fcntl.LOCK_SH)

    def close(self):
        if self.file:
            self.file.close()


def write_text(path, text):
    partial = path.with_name(f"{path.name}.{os.getpid()}.partial")  # gradings may share the folder
    partial.write_text(text)
    os.replace(partial, path)


# --- What a task file may define ---------------------------------------------------------------

# Names a task file never defines: the program's entry, the C++ library's allocation functions
# (operator new and delete, mangled), and GoogleTest's.
ENTRY = {"main"}
ALLOCATION = re.compile(r"^_Z(nw|na|dl|da)[mjPvS]")
GOOGLE_TEST = re.compile(r"^_ZNK?7testing")
# Kinds of symbol (nm) that define something weakly: inline functions and templates, which every
# file that uses them defines and the linker merges.
WEAK = {"W", "V", "w", "v", "u"}


def object_symbols(data):
    """[(name, kind)] of the global and weak symbols an ELF object file (64-bit, little-endian:
    what the grader's compiler makes) defines, kind as nm's letters ("W", "V", "u" for the weak
    and unique ones, "T" for the others), and of those it uses without defining them ("U"); None
    when the bytes are not such a file. Read here, not by nm: the file is the submission's, and
    reading it takes no process."""
    import struct
    try:
        if data[:6] != b"\x7fELF\x02\x01":
            return None
        section_offset, = struct.unpack_from("<Q", data, 0x28)
        entry_size, count = struct.unpack_from("<HH", data, 0x3A)
        sections = [struct.unpack_from("<IIQQQQIIQQ", data, section_offset + k * entry_size) for k in range(count)]
        found = []
        for _, kind, _, _, offset, size, link, _, _, symbol_size in sections:
            if kind != 2 or symbol_size < 24:  # SHT_SYMTAB
                continue
            names_offset, names_size = sections[link][4], sections[link][5]
            for at in range(offset, offset + size - symbol_size + 1, symbol_size):
                name_at, info, _, section = struct.unpack_from("<IBBH", data, at)
                binding, symbol_type = info >> 4, info & 0xF
                if binding not in (1, 2, 10) or name_at == 0:  # global, weak, unique; named
                    continue
                end = data.index(b"\0", names_offset + name_at, names_offset + names_size)
                name = data[names_offset + name_at:end].decode(errors="replace")
                if section == 0:  # SHN_UNDEF: used, defined elsewhere
                    found.append((name, "U"))
                    continue
                letter = "u" if binding == 10 else ("V" if symbol_type == 1 else "W") if binding == 2 else "T"
                found.append((name, letter))
        return found
    except (struct.error, IndexError, ValueError):
        return None


def symbol_lines(text):
    """[(name, kind)] from `nm -P -g --defined-only` (names may hold spaces when demangled)."""
    symbols = []
    for line in text.splitlines():
        found = re.match(r"^(.*) ([A-Za-z]) [0-9a-fA-F]*( [0-9a-fA-F]*)?$", line.rstrip())
        if found:
            symbols.append((found.group(1), found.group(2)))
    return symbols


def defined_symbols(paths, dynamic=False):
    """The names defined (globally, strongly or weakly) in object files, archives or shared
    libraries; {name: kind}."""
    found = {}
    for path in paths:
        done = subprocess.run(["nm", "-P", "-g", "--defined-only", *(["-D"] if dynamic else []), str(path)],
                              stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True, timeout=120)
        for name, kind in symbol_lines(done.stdout):
            found.setdefault(name.split("@")[0], kind)
    return found


class Symbols:
    """The names a task file may not define: the C and C++ libraries' (from the shared libraries
    a worker is linked with), the grader's own (the worker's harness and the course's libraries),
    and the other tasks' reference code's; and each task's own functions (its stand-in's symbols),
    which are what it must define."""

    def __init__(self, build):
        recipe = build.worker_recipe
        c_libraries = [self.library(recipe["compiler"], name) for name in ["libc.so.6", "libm.so.6"]]
        cxx_libraries = [self.library(recipe["compiler"], name) for name in ["libstdc++.so.6", "libgcc_s.so.1"]]
        stubs = {task: path for task, path in build.stubs.items() if task not in PROGRAM_TASKS}
        files = [*c_libraries, *cxx_libraries, *recipe["harness"], *recipe["libraries"], *map(str, stubs.values()),
                 *[path for objects in recipe["tasks"].values() if isinstance(objects, list) for path in objects]]
        # Listed once per build folder, and again when any of these files changes.
        key = hashlib.sha256(json.dumps([[path, TaskFileCompiler.signature(path)] for path in files if path])
                             .encode()).hexdigest()
        saved = build.submitted / "symbols.json"
        try:
            listed = json.loads(saved.read_text())
            if listed["key"] != key or "functions" not in listed:  # (a listing of an older grader)
                raise ValueError
        except (OSError, ValueError, KeyError):
            listed = {"key": key,
                      "c": list(defined_symbols([path for path in c_libraries if path], dynamic=True)),
                      "cxx": list(defined_symbols([path for path in cxx_libraries if path], dynamic=True)),
                      "grader": list(defined_symbols([*recipe["harness"], *recipe["libraries"]])),
                      "reference": {task: list(defined_symbols(objects)) for task, objects in recipe["tasks"].items()
                                    if isinstance(objects, list)},
                      "own": {task: list(defined_symbols([path])) for task, path in stubs.items()},
                      # Each task's functions: what its stand-in defines strongly (not the inline
                      # functions and templates any file may also define or call).
                      "functions": {task: [name for name, kind in defined_symbols([path]).items() if kind not in WEAK]
                                    for task, path in stubs.items()}}
            try:
                write_text(saved, json.dumps(listed))
            except OSError:  # not the grader's to write (an Autolab job beside the image's build)
                pass
        self.c_library, self.cxx_library, self.grader = set(listed["c"]), set(listed["cxx"]), set(listed["grader"])
        self.reference = {task: set(names) for task, names in listed["reference"].items()}
        self.own = {task: set(names) for task, names in listed["own"].items()}
        self.functions = {task: set(names) for task, names in listed["functions"].items()}

    @staticmethod
    def library(compiler, name):
        done = subprocess.run([compiler, f"-print-file-name={name}"], stdout=subprocess.PIPE, text=True, timeout=60)
        path = done.stdout.strip()
        return path if os.path.isabs(path) and os.path.exists(path) else None

    def problems(self, task, symbols, demangle):
        """What is wrong with the names a task file defines (symbols: [(name, kind)] as nm lists
        them; demangle: names -> {name: as C++ writes it}): one line each, or [] when nothing is."""
        refused = []
        for name, kind in symbols:
            why = ""
            if kind == "U":  # a call: of another task's functions only where course.txt allows it
                other = next((t for t, names in self.functions.items() if t != task and name in names), None)
                if other and other not in USES.get(task, []):
                    why = (f"{{}}, a function of {task_name(other)}, which {TASK_FILE[task]} may not call: each task is "
                           f"graded on its own code, so write what {task} needs in {TASK_FILE[task]} itself")
                    refused.append((name, why))
                continue
            if name in self.own.get(task, ()):
                continue
            if name in ENTRY:
                why = "main(), the entry of a program: a task file holds the task's functions, and the grader provides main()"
            elif ALLOCATION.match(name):
                why = "{}, which belongs to the C++ library: a task file does not replace how memory is allocated"
            elif GOOGLE_TEST.match(name):
                why = "{}, a name of GoogleTest, which the grader's tests use"
            elif name in self.c_library:
                why = "{}, a function of the C library: a task file does not replace the C library's functions"
            elif kind in WEAK:
                continue  # an inline function or template, which the linker merges with the others
            elif name in self.cxx_library:
                why = "{}, which the C++ library defines"
            elif name in self.grader:
                why = "{}, which the grader's own code defines"
            else:
                other = next((t for t, defined in self.reference.items() if t != task and name in defined), None)
                if other:
                    why = (f"{{}}, which the reference code of {task_name(other)} defines too: give your helper "
                           "another name, or make it static or put it in an unnamed namespace")
            if why:
                refused.append((name, why))
        readable = demangle([name for name, _ in refused]) if refused else {}
        return [why.format(readable.get(name, name)) for name, why in refused]


def refused(task, problems):
    """The message for a task file whose symbols are refused."""
    lines = "\n".join(f"  - {problem}" for problem in problems[:10])
    more = f"\n  ... and {len(problems) - 10} more" if len(problems) > 10 else ""
    return (f"{TASK_FILE[task]} was not graded (0 points for this task): it defines or calls what a task file may "
            "not.\n"
            f"{lines}{more}\nA task file defines {TASK_FUNCTIONS[task]}, as lib/include/billiard/course.hpp declares "
            "it, and helpers of its own (best static, or in an unnamed namespace); nothing else.")


# --- Compiling and linking in the cells --------------------------------------------------------

class TaskFileCompiler:
    """Compiles submitted task files in their tasks' cells, each once, and links each C++ task's
    worker there (see the top of this file); remembers what it made in the build folder, by a key
    of everything it was made from, the protections of the cell included."""

    def __init__(self, build, cells):
        commands = {Path(entry["file"]).name: entry for entry in
                    json.loads((build.folder / "compile_commands.json").read_text())}
        for name in ["submitted_file.cpp", "submitted_file.c"]:
            if name not in commands:  # never compile a file unchecked
                raise RuntimeError(f"the grader's build has no compile command for {name}")
        self.build = build
        self.cells = cells
        self.commands = {".cpp": command_words(commands["submitted_file.cpp"]),
                         ".c": command_words(commands["submitted_file.c"])}
        self.originals = {}  # copy of a header folder -> the folder it copies
        self.words = {suffix: self.readable(words) for suffix, words in self.commands.items()}
        self.compiled_files = Remembered(build.submitted / "compiled")
        self.workers = Remembered(build.submitted / "workers")
        self.symbols = Symbols(build) if any(task not in PROGRAM_TASKS for task in TASKS) else None
        self.protection = cells.protections.describe()
        self.pieces = self.link_pieces()

    def readable(self, words):
        """The command with the project's folders and files (which may sit where a cell cannot
        read, such as under /root, or beside the reference solutions) replaced by copies in the
        grading's include folder."""
        copies = self.cells.include
        result = []
        for at, word in enumerate(words):
            option = "-I" if word.startswith("-I") else words[at - 1] if at else ""
            path = Path(word[2:] if option == "-I" else word)
            if option not in {"-I", "-isystem", "-include"} or not (path.is_relative_to(REPO) or
                                                                    path.is_relative_to(self.build.folder)):
                result.append(word)
                continue
            copy = copies / f"{len(list(copies.iterdir()))}"
            if option == "-include":  # a precompiled header: the header and its .gch beside it
                copy.mkdir()
                for source in path.parent.glob(path.name + "*"):
                    share(source, copy / source.name)
                result.append(str(copy / path.name))
                self.originals[str(copy)] = str(path.parent)
            else:
                shutil.copytree(path, copy)
                result.append(f"-I{copy}" if option == "-I" else str(copy))
                self.originals[str(copy)] = str(path)
        for item in [copies, *copies.rglob("*")]:
            if item.is_dir() or item.stat().st_nlink == 1:  # not the build's own files, shared by a link
                os.chmod(item, 0o755 if item.is_dir() else 0o644)
        return result

    def link_pieces(self):
        """The worker's pieces, put where the cells may read them: {"harness": [...], "libraries":
        [...], task: [...] (reference code), "stand-in-" + task: [its stand-in]}, each with its
        digest."""
        if self.symbols is None:
            return {}
        recipe = self.build.worker_recipe
        pieces = {}
        stand_ins = [(f"stand-in-{task}", [str(path)]) for task, path in self.build.stubs.items()
                     if task not in PROGRAM_TASKS]
        for group, paths in [("harness", recipe["harness"]), ("libraries", recipe["libraries"]),
                             *[(task, objects) for task, objects in recipe["tasks"].items() if isinstance(objects, list)],
                             *stand_ins]:
            folder = cell.own_folder(self.cells.objects / group, None, 0o755)
            pieces[group] = []
            for number, path in enumerate(paths):
                target = folder / f"{number}-{Path(path).name}"
                if not share(Path(path), target):  # a copy (a link is of a file anyone may read)
                    os.chmod(target, 0o644)
                pieces[group].append((target, file_digest(target)))
        return pieces

    def command(self, task, text, commands=None):
        """The compile command of a task file: as run, with the headers' copies (or as the build
        has it, with `commands=self.commands`, which is what a compiled file's key holds)."""
        words = (commands or self.words)[Path(TASK_FILE[task]).suffix]
        if task not in PROGRAM_TASKS and defines_before_course_headers(text):
            without = []
            for at, word in enumerate(words):
                if word == "-Winvalid-pch" or word == "-include" or (at and words[at - 1] == "-include"):
                    continue
                without.append(word)
            words = without
        return words

    def compiled(self, task):
        """Where a C++ task's compiled file is put for linking (a program task's program: bin/)."""
        return self.cells.objects / "submitted" / f"{task}.o"

    def put(self, task, content):
        """Puts a compiled task file (or a program task's program) where the workers take it."""
        if task in PROGRAM_TASKS:
            self.cells.put_program(content, "program", task)
            return
        target = self.compiled(task)
        cell.own_folder(target.parent, None, 0o755)
        target.write_bytes(content)
        os.chmod(target, 0o644)

    def put_stub(self, task):
        self.put(task, self.build.stubs[task].read_bytes())

    def compile(self, task, source, limit, remembered=True):
        """Compiles a task file in its cell (or takes it from the files compiled before, unless
        `remembered` is false) and checks what it defines; returns (problem message or "",
        seconds spent). The compiled file is put where its worker is linked from."""
        text = source.read_bytes()
        words = self.command(task, text)
        key = hashlib.sha256(json.dumps([TASK_FILE[task], self.command(task, text, self.commands), self.protection])
                             .encode() + b"\0" + text).hexdigest()
        if remembered:
            saved = self.compiled_files.recall(key)
            if saved and all(self.signature(path) == value for path, value in saved[1]["headers"].items()):
                return self.accept(task, saved[0]), 0.0
        work = self.cells.new_folder(task, "compile-")
        name = TASK_FILE[task]
        target = work / name
        target.write_bytes(text)
        if self.cells.uid(task) is not None:
            os.chown(target, self.cells.uid(task), self.cells.uid(task))
        program = task in PROGRAM_TASKS
        output_name = "program" if program else "compiled.o"
        compile_words = [*words, *([] if program else ["-c"]), name, "-o", output_name, "-MD", "-MF", "depends.d",
                         *(PROGRAM_LIBRARIES if program else [])]
        started = time.monotonic()
        try:
            ok, output, timed_out = run_limited(
                self.cells.command(task, compile_words, directory=work, reads=[self.cells.include], writes=[work],
                                   limits=self.build_limits(limit)), timeout=limit)
            seconds = time.monotonic() - started
            if timed_out:
                return (f"{name} does not compile: the compiler did not finish within {limit:.0f} s and was stopped. A "
                        "correct file compiles in a few seconds: does it include a file that never ends, or make the "
                        "compiler work without end?"), seconds
            compiled = read_regular_file(work / output_name, BUILT_FILE_CAP) if ok else None
            if compiled is None:
                return does_not_compile(task, source, compiler_messages(output.replace(str(work) + "/", ""))), seconds
            headers = self.headers(read_regular_file(work / "depends.d", BUILT_FILE_CAP) or b"")
            self.compiled_files.remember(key, compiled, {"headers": headers})
            return self.accept(task, compiled), seconds
        finally:
            shutil.rmtree(work, ignore_errors=True)

    def accept(self, task, compiled):
        """Puts a compiled file in place unless it defines what it may not; returns the problem."""
        if task not in PROGRAM_TASKS:
            symbols = object_symbols(compiled)
            if symbols is None:
                return f"{TASK_FILE[task]} compiles, but into something the grader cannot read: tell your instructor."
            problems = self.symbols.problems(task, symbols, lambda names: self.demangle(task, names))
            if problems:
                return refused(task, problems)
        self.put(task, compiled)
        return ""

    def demangle(self, task, names):
        """{name: as C++ writes it}, by c++filt in the task's cell (the names are the submission's)."""
        work = self.cells.new_folder(task, "names-")
        try:
            ok, output, _ = run_limited(self.cells.command(task, [shutil.which("c++filt") or "/usr/bin/c++filt", *names[:100]], directory=work,
                                                           writes=[work], limits=self.build_limits(30)), timeout=30)
            lines = output.splitlines()
            return dict(zip(names, lines)) if ok and len(lines) == len(names[:100]) else {}
        finally:
            shutil.rmtree(work, ignore_errors=True)

    def headers(self, depends):
        """{path: signature} of every header a compilation read, by the project's own paths."""
        try:
            listed = depends.decode(errors="replace").split(":", 1)[1].replace("\\\n", " ").split()
        except IndexError:
            return {}
        found = {}
        for path in listed:
            for copy, original in self.originals.items():
                if path.startswith(copy + "/"):
                    path = original + path[len(copy):]
                    break
            if os.path.isabs(path):
                found[path] = self.signature(path)
        return found

    @staticmethod
    def signature(path):
        """A file's size and time of change, or None if it is gone."""
        try:
            info = os.stat(path)
        except OSError:
            return None
        return [info.st_size, info.st_mtime_ns]

    def build_limits(self, seconds):
        return Limits(cpu_seconds=seconds, memory_bytes=SUBMISSION_BUILD_MEMORY, file_bytes=BUILT_FILE_CAP,
                      processes=BUILD_PROCESSES)

    def link(self, task, limit):
        """Links a C++ task's worker in its cell; returns (problem or "", seconds spent). With the
        reference code, a worker holds only that of the tasks course.txt lets this one use (and its
        suite calls: movie's, propagate): every other task is its stand-in, so no other task's
        reference code is in the worker's process to be reached, by a call or otherwise."""
        recipe = self.build.worker_recipe
        own = self.compiled(task)
        objects = [(own, file_digest(own))]
        for other in TASKS:
            if other == task or other in PROGRAM_TASKS:
                continue
            if recipe["tasks"][other] == "submitted":
                objects.append((self.compiled(other), file_digest(self.compiled(other))))
            elif other in USES[task]:
                objects += self.pieces[other]
            else:
                objects += self.pieces[f"stand-in-{other}"]
        pieces = [*self.pieces["harness"], *objects, *self.pieces["libraries"]]
        words = [recipe["compiler"], *recipe["flags"], *[str(path) for path, _ in pieces], "-o", "worker"]
        key = hashlib.sha256(json.dumps([words[:2], [digest for _, digest in pieces], self.protection]).encode()).hexdigest()
        saved = self.workers.recall(key)
        if saved:
            self.cells.put_program(saved[0], "worker", task)
            return "", 0.0
        work = self.cells.new_folder(task, "link-")
        started = time.monotonic()
        try:
            ok, output, timed_out = run_limited(
                self.cells.command(task, words, directory=work, reads=[self.cells.objects], writes=[work],
                                   limits=self.build_limits(limit)), timeout=limit)
            seconds = time.monotonic() - started
            if timed_out:
                return (f"{TASK_FILE[task]} compiles, but linking it did not finish within {limit:.0f} s. A correct "
                        "file links in about a second: does it define very large arrays?"), seconds
            worker = read_regular_file(work / "worker", BUILT_FILE_CAP) if ok else None
            if worker is None:
                messages = compiler_messages(output.replace(str(work) + "/", "").replace(str(self.cells.objects) + "/", ""))
                return (f"{TASK_FILE[task]} compiles, but does not link with the other tasks' code. Does it define "
                        f"{TASK_FUNCTIONS[task]} exactly as lib/include/billiard/course.hpp declares it? The linker "
                        "says:\n" + cap(messages, COMPILER_CAP)), seconds
            self.workers.remember(key, worker, {})
            self.cells.put_program(worker, "worker", task)
            return "", seconds
        finally:
            shutil.rmtree(work, ignore_errors=True)


def share(source, target):
    """A hard link of a file that anyone may read, where possible (the precompiled header is 100
    MB), else a copy; True for a link."""
    try:
        if os.stat(source).st_mode & stat.S_IROTH:
            os.link(source, target)
            return True
    except OSError:
        pass
    shutil.copyfile(source, target)
    return False


def does_not_compile(task, source, messages):
    """The message for a file the compiler rejects, with a hint when it is not text at all."""
    binary = b"\0" in source.read_bytes()
    return (f"{TASK_FILE[task]} does not compile" + (": it holds binary data, not source code. Did you submit the right file? "
                                              "The compiler says" if binary else "") + ":\n"
            + cap(messages, COMPILER_CAP // 4 if binary else COMPILER_CAP))


def compiler_messages(output):
    """The compiler's own lines from a build log (without ninja's progress and commands)."""
    keep = []
    for line in output.splitlines():
        if re.match(r"\[\d+/\d+\] ", line) or line.startswith(("ninja:", "FAILED:", ": && ")):
            continue
        if line.startswith(("/usr/bin/c++", "/usr/bin/g++", "c++ ", "g++ ", "/usr/bin/cc ", "/usr/bin/gcc ", "cc ", "gcc ")):
            continue
        keep.append(line.replace(str(REPO) + "/", ""))
    return "\n".join(keep).strip()


# --- The submission ----------------------------------------------------------------------------

def stage_submission(submission, grading, name="submission"):
    """Copies the task files of a submission into the grader's own folder, grading/<name>/, and
    returns it with {task: message} for the task files that cannot be graded (a folder, a link, a
    special or too large file). Only regular files are read, without following links, so that a
    submission cannot make the grader read files outside it."""
    staged = grading / name
    staged.mkdir(parents=True, exist_ok=True)
    problems = {}
    for task in TASKS:
        source, target = submission / f"{TASK_FILE[task]}", staged / f"{TASK_FILE[task]}"
        text, problem = read_task_file(source)
        if problem:
            problems[task] = (f"{TASK_FILE[task]} {problem}, so it was not graded (0 points for this task). Submit the file "
                              "itself.")
        if text is None:
            target.unlink(missing_ok=True)
        elif not (target.is_file() and target.read_bytes() == text):
            target.write_bytes(text)
    return staged, problems


def read_task_file(path):
    """(content, None) for a regular file of at most SUBMITTED_FILE_CAP bytes; else (None, why
    it cannot be graded, as in "<file> is a folder"; None when there is no such file). Links are
    not followed, and special files (a FIFO, a device, a socket) are not opened."""
    try:
        mode = os.lstat(path).st_mode
    except FileNotFoundError:
        return None, None
    except OSError:
        return None, "cannot be read"
    if not stat.S_ISREG(mode):
        return None, LINK if stat.S_ISLNK(mode) else FOLDER if stat.S_ISDIR(mode) else SPECIAL
    try:  # without following a link put in its place since, nor waiting on a FIFO
        descriptor = os.open(path, os.O_RDONLY | os.O_NOFOLLOW | os.O_NONBLOCK)
    except OSError:
        return None, "cannot be read"
    with os.fdopen(descriptor, "rb") as file:
        if not stat.S_ISREG(os.fstat(file.fileno()).st_mode):
            return None, SPECIAL
        text = file.read(SUBMITTED_FILE_CAP + 1)
    if len(text) > SUBMITTED_FILE_CAP:
        return None, TOO_LARGE
    return text, None


def build_suites(build, compiler, staged, problems, tasks, clocks, remembered=True, quiet=False):
    """Compiles the task files (those of `tasks`, or every task's where each worker links them all)
    and links each task's worker, within its task's budget; returns a TaskResult per task of
    `tasks`, with its tests to run or the problem that stops them."""
    problems = dict(problems)
    compile_seconds = {}
    for task in tasks if build.dependencies == "reference" else TASKS:
        source = staged / TASK_FILE[task]
        if task not in problems and not source.is_file():
            problems[task] = f"{TASK_FILE[task]} was not submitted."
        if task in problems:
            compiler.put_stub(task)
            continue
        if not quiet:
            print(f"grade: {task_name(task)}: compiling {TASK_FILE[task]}", flush=True)
        limit = clocks[task].build_limit()
        problem, compile_seconds[task] = compiler.compile(task, source, limit, remembered=remembered)
        clocks[task].spend(compile_seconds[task], building=True)
        if problem:
            problems[task] = problem
            compiler.put_stub(task)

    results = []
    for task in tasks:
        result = TaskResult(task, clock=clocks[task], compile_seconds=compile_seconds.get(task, 0.0))
        listed = catalog(build, task)
        result.maximum = sum(entry["points"] for entry in listed)
        results.append(result)
        if task in problems:
            result.problem = problems[task]
            continue
        if task not in PROGRAM_TASKS:  # a program task's worker runs the program itself
            limit = clocks[task].build_limit()
            result.problem, result.link_seconds = compiler.link(task, limit)
            clocks[task].spend(result.link_seconds, building=True)
            if result.problem:
                continue
        result.tests = [TestResult(task, entry["test"], entry["points"], entry["visibility"]) for entry in listed]
    return results


