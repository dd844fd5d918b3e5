#!/usr/bin/python3
"""The course's catalogue: its tasks in order, each one's file, number and functions, and which
of them count, read from course.txt next to this file. Every part of the project that needs the
tasks takes them from here: the grader's scripts import this module, and CMake runs it.

    /usr/bin/python3 tests/grader/course.py --cmake

prints the catalogue as CMake set() commands (the top CMakeLists.txt includes them), or says
on stderr which line of course.txt is wrong, exit status 2.
"""

import re
import sys
from pathlib import Path

COURSE_FILE = Path(__file__).resolve().parent / "course.txt"
TASKS_FOLDER = Path(__file__).resolve().parents[2] / "tasks"
STATUSES = ("required", "optional", "off")
# Tasks 1-6 are the course's core: the `billiard` command, the Python module and the extension
# stages are built on them, so they stay required, unless the course is the C track alone (every
# task in C++ off, the program tasks such as particles on).
CORE_TASKS = 6


def is_program_task(name):
    """A task written in C as a whole program (tasks/<name>.c), graded by running it."""
    return (TASKS_FOLDER / f"{name}.c").is_file()


def read_course(path=COURSE_FILE):
    """[(number, name, status)] from course.txt, in course order; ValueError names a bad line."""
    return read_catalogue(path)[0]


def read_catalogue(path=COURSE_FILE):
    """([(number, name, status)], {name: [earlier tasks its file may call]}) from course.txt;
    ValueError names a bad line."""
    course, uses = [], {}
    for line_number, line in enumerate(path.read_text().splitlines(), start=1):
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        words = line.split()
        if len(words) not in (3, 5) or not words[0].isdigit() or words[2] not in STATUSES or \
                (len(words) == 5 and words[3] != "uses"):
            raise ValueError(f"{path.name} line {line_number}: '{line}' is not 'NUMBER NAME required|optional|off' "
                             "(and, for a task whose file calls earlier tasks' functions, 'uses TASK,TASK')")
        number, name, status = int(words[0]), words[1], words[2]
        if number != len(course) + 1:
            raise ValueError(f"{path.name} line {line_number}: task {number} should be task {len(course) + 1}")
        earlier = [task for _, task, _, _ in course]
        uses[name] = words[4].split(",") if len(words) == 5 else []
        for used in uses[name]:
            if used not in earlier or is_program_task(used):
                raise ValueError(f"{path.name} line {line_number}: {name} uses '{used}', which is not an earlier "
                                 "task written in C++")
        course.append((number, name, status, line_number))
    c_track_alone = all(status == "off" for _, name, status, _ in course if not is_program_task(name))
    for number, name, status, line_number in course:
        if number <= CORE_TASKS and status != "required" and not c_track_alone:
            raise ValueError(f"{path.name} line {line_number}: task {number} ({name}) is one of the six core tasks "
                             "and must stay required (unless every C++ task is off: the C track alone)")
    return [(number, name, status) for number, name, status, _ in course], uses


try:
    COURSE, DECLARED_USES = read_catalogue()
except ValueError as error:
    if __name__ != "__main__":
        raise
    print(f"tests/grader/{error}", file=sys.stderr)  # CMake shows it and stops
    sys.exit(2)
TASKS = [name for _, name, status in COURSE if status != "off"]           # built and graded
# Each task's file: <task>.cpp (functions linked with its graded suite), or <task>.c for a
# program task (a whole C program with main(), graded by running it; see tests/CMakeLists.txt).
PROGRAM_TASKS = [name for _, name, _ in COURSE if is_program_task(name)]
TASK_FILE = {name: f"{name}.c" if name in PROGRAM_TASKS else f"{name}.cpp" for _, name, _ in COURSE}
OPTIONAL = [name for _, name, status in COURSE if status == "optional"]   # extra credit
# The extension stages, built on the core in C++ (not the program tasks such as particles).
STAGES = [name for number, name, status in COURSE
          if number > CORE_TASKS and status != "off" and name not in PROGRAM_TASKS]
OFF = [name for _, name, status in COURSE if status == "off"]
TASK_NUMBER = {name: number for number, name, _ in COURSE}
# The earlier tasks whose functions a task's file may call (course.txt's "uses"): its worker is
# linked with their reference code, and with the stand-ins of every other task, whose functions
# say "not implemented yet" (tests/grader/building.py). A file that calls another task's
# functions is refused: the stages contain tasks 4 and 6, and no task is graded by another's
# reference code.
USES = {task: [used for used in DECLARED_USES[task] if used in TASKS] for task in TASKS}
# What a student writes in each task's file, for hints.
TASK_FUNCTIONS = {task: task for task in TASKS} | {
    "kinetic_energy": "kinetic_energy or correct_energy_drift",
    "gravity": "propagate_gravity or mean_energy",
    "walls": "propagate_walls",
    "sectors": "propagate_sectors",
} | {task: "main (the whole program)" for task in PROGRAM_TASKS}
# The course's error for a task that is not written yet (lib/src/course/not_implemented.cpp).
NOT_WRITTEN = re.compile(r"task (\d+) \(\w+\) is not implemented yet")
def is_optional(task):
    return task in OPTIONAL


def task_name(task):
    return f"task {TASK_NUMBER[task]} ({task})"


def task_with_number(number):
    return next((name for name, n in TASK_NUMBER.items() if n == number and name in TASKS), None)


def cmake():
    """The catalogue as CMake commands: BILLIARD_TASKS (every task that is not off, in course
    order), BILLIARD_TASK_NUMBER_<task>, BILLIARD_PROGRAM_TASKS (the C tasks graded as programs)
    and BILLIARD_STAGES (the extension stages in C++)."""
    lines = [f"set(BILLIARD_TASKS {';'.join(TASKS)})",
             f"set(BILLIARD_PROGRAM_TASKS {';'.join(task for task in TASKS if task in PROGRAM_TASKS)})",
             f"set(BILLIARD_STAGES {';'.join(STAGES)})"]
    lines += [f"set(BILLIARD_TASK_NUMBER_{task} {TASK_NUMBER[task]})" for task in TASKS]
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    if sys.argv[1:] != ["--cmake"]:
        print("usage: course.py --cmake", file=sys.stderr)
        sys.exit(2)
    sys.stdout.write(cmake())
