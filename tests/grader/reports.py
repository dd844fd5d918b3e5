"""What a grading reports: the results of each task and test, and the forms they are written in
for whoever reads them: the table printed at the end of a grading (the student's next step, or a
summary for whoever grades), Gradescope's results.json, JUnit's XML, and report.html with the
pictures of the failing cases. Hidden tests show only that they failed, never their name or
message, in every form a student may see; task_records keeps everything, for the instructor.
"""

import base64
import html
import os
import re
import xml.etree.ElementTree as ET
from dataclasses import MISSING, dataclass, field, fields

from course import TASK_FILE, TASK_FUNCTIONS, TASK_NUMBER, TASKS, is_optional, task_name
from progress import TaskProgress, next_step
from time_limits import used_up

HIDDEN_FEEDBACK = "This test is hidden: its details are not shown."
FEEDBACK_CAP = 8 * 1024  # characters of feedback kept per test
# Pictures of failing cases: the folder a test draws into (in its own folder, as the suites'
# BILLIARD_PICTURES) and the one they are kept in, in the results; the line of a message that
# names one.
PICTURES = "pictures"
PICTURE_LINE = re.compile(r"^Picture: .*(\n|$)", re.MULTILINE)


@dataclass
class TestResult:
    task: str
    name: str  # "Suite.Name"
    points: int
    visibility: str
    passed: bool = False
    feedback: str = ""
    seconds: float = 0.0      # wall time
    cpu_seconds: float = 0.0  # what the test's judge and its worker computed
    unfinished: bool = False  # stopped at its time limit
    not_run: bool = False     # its task's time budget was used up before it could start
    out_of_time: bool = False  # stopped or not run at the grading's deadline (a busy machine), not for its code
    picture: str = ""         # the picture of its failing case, relative to the results folder
    googletest: str = ""      # GoogleTest's own lines of its failures (judging.readable_first)

    @property
    def score(self):
        return self.points if self.passed else 0


@dataclass
class TaskResult:
    task: str
    tests: list = field(default_factory=list)
    maximum: int = 0
    problem: str = ""  # why the task could not be tested (a compile, link or symbol problem), if so
    clock: object = None  # its TaskClock: its time budget, and what used it
    compile_seconds: float = 0.0
    link_seconds: float = 0.0

    @property
    def score(self):
        return sum(test.score for test in self.tests)


def cap(text, limit):
    if len(text) <= limit:
        return text
    return text[:limit] + f"\n... (output cut after {limit} characters)"


def print_table(results, verbose, own_tasks=True):
    """The table of points per task, then what to do next: for a student grading their own tasks/,
    the next step; for whoever grades another folder (own_tasks false), a summary of it."""
    width = max(len(task) for task in TASKS) + 2
    print(f"\n{'task':<{width + 4}}points")
    for result in results:
        optional = "  (optional)" if is_optional(result.task) else ""
        print(f"{TASK_NUMBER[result.task]:>2}  {result.task:<{width}}{result.score:>3} / {result.maximum}{optional}")
        if result.problem:
            print(indent(result.problem, 6))
            continue
        failed = [test for test in result.tests if not test.passed and not test.not_run]
        not_run = [test for test in result.tests if test.not_run]
        if task_progress(result).missing == result.task:
            print(f"      not implemented yet: write it in tasks/{TASK_FILE[result.task]} (every test fails until then)"
                  if own_tasks else "      not implemented yet: the file is the untouched stub")
            continue
        for test in failed:
            name = "a hidden test" if test.visibility == "hidden" else test.name
            print(f"      failed: {name} ({plural(test.points, 'point')})")
            if verbose and test.feedback:
                feedback = shown_feedback(test)
                print(indent(feedback, 10))
        if not_run:
            print(f"      not run: {plural(len(not_run), 'test')} ({plural(sum(t.points for t in not_run), 'point')}): "
                  f"the task may take {result.clock.limits.budget:.0f} s in all here, and {used_up(result.clock)}. An "
                  f"endless loop in {TASK_FUNCTIONS[result.task]}?")
    counted = [result for result in results if not is_optional(result.task)]
    extra = [result for result in results if is_optional(result.task)]
    print(f"\n    {'total':<{width}}{sum(r.score for r in counted):>3} / {sum(r.maximum for r in counted)}")
    if extra:
        print(f"    {'optional':<{width}}{sum(r.score for r in extra):>3} / {sum(r.maximum for r in extra)}"
              f"  (extra credit: {', '.join(r.task for r in extra)}; not in the total)")
    if own_tasks:
        print("\n" + "\n".join(next_step([task_progress(result) for result in results])))
    else:
        print("\n" + "\n".join(grader_summary(results)))


def grader_summary(results):
    """For whoever grades a submission: which tasks have full points, which lose points and where
    first (the first failing visible test), which are not written, which do not build."""
    full = [r.task for r in results if r.score == r.maximum and r.maximum > 0]
    lines = [f"Summary: full points in {len(full)} of {len(results)} tasks"
             + (f" ({', '.join(full)})" if full else "")]
    for result in results:
        if result.score == result.maximum and result.maximum > 0:
            continue
        if result.problem:  # its first line: not submitted, not compiled, not linked, refused
            first = result.problem.splitlines()[0].rstrip(":")
            why = first + (" (the whole message is above)" if "\n" in result.problem else "")
        elif task_progress(result).missing == result.task:
            why = "not written (the untouched stub)"
        else:
            failed = [t for t in result.tests if not t.passed]
            visible = [t for t in failed if t.visibility != "hidden"]
            first = f", first {visible[0].name}" if visible else ""
            why = f"{result.score} / {result.maximum}: {plural(len(failed), 'test')} fail{'s' if len(failed) == 1 else ''}{first}"
        lines.append(f"  {TASK_NUMBER[result.task]:>2} {result.task}: {why}")
    return lines


def task_progress(result):
    """A task's result as progress.py sees it, for the "Next:" lines."""
    progress = TaskProgress(result.task, problem=result.problem)
    for test in result.tests:
        progress.record(test.name, test.passed, test.feedback)
    return progress


def shown_feedback(test):
    """A test's feedback as the student sees it: of a hidden test, only whether it ran out of time."""
    if test.visibility != "hidden":
        return test.feedback
    if test.out_of_time:
        return (HIDDEN_FEEDBACK + " It was not run to its end: the grading machine was busy with other work and the "
                "grading's time there ran out. Submit again to have it graded.")
    if test.unfinished:
        return (HIDDEN_FEEDBACK + " It did not finish within its time limit: an endless loop in "
                f"{TASK_FUNCTIONS[test.task]}?")
    if test.not_run:
        return HIDDEN_FEEDBACK + f" It was not run: the time for {test.task}'s tests was used up (see the others)."
    return HIDDEN_FEEDBACK


def plural(count, word):
    return f"{count} {word}{'' if count == 1 else 's'}"


def indent(text, spaces):
    return "\n".join(" " * spaces + line if line else "" for line in text.splitlines())


def picture_html(test, folder):
    """A visible test's picture as an <img> with the SVG inside it (a data: address, so the page
    needs no other file and the picture cannot run anything), or "" if it has none."""
    if not test.picture or test.visibility == "hidden" or folder is None:
        return ""
    try:
        data = base64.b64encode((folder / test.picture).read_bytes()).decode()
    except OSError:
        return ""
    return (f'<img alt="the failing case of {html.escape(test.name)}, drawn" style="width: 100%; max-width: 800px; max-height: 95vh" '
            f'src="data:image/svg+xml;base64,{data}">')


def gradescope_results(results, elapsed, folder=None):
    """Gradescope's results.json: the score and one entry per test. A visible test with a picture
    (in `folder`) is written as HTML, the message in <pre> and the picture under it: Gradescope's
    output_format "html" (its autograder specification, "Output String Formatting") renders
    sanitised HTML, and images embedded as base64 data are what its documentation's discussions
    show working; elsewhere the text stays text, without the picture's line (a path on the
    grading machine)."""
    tests = []
    for result in results:
        if result.problem:
            tests.append({"name": f"{result.task}: builds", "score": 0, "max_score": result.maximum,
                          "status": "failed", "visibility": "visible", "output": result.problem})
            continue
        for test in result.tests:
            hidden = test.visibility == "hidden"
            entry = {
                "name": f"{result.task}: " + ("hidden test" if hidden else test.name),
                "score": test.score, "max_score": test.points, "status": "passed" if test.passed else "failed",
                "visibility": test.visibility,
                "output": PICTURE_LINE.sub("", shown_feedback(test)).strip() or ("passed" if test.passed else ""),
            }
            picture = picture_html(test, folder)
            if picture:
                entry["output"] = f"<pre>{html.escape(entry['output'])}</pre>\n<p>{picture}</p>"
                entry["output_format"] = "html"
            tests.append(entry)
    return {
        "score": sum(result.score for result in results),
        "execution_time": round(elapsed, 1),
        "output": "Points per task: " + ", ".join(f"{r.task} {r.score}/{r.maximum}" + (" (optional)" if is_optional(r.task) else "")
                                            for r in results),
        "stdout_visibility": "hidden",
        "tests": tests,
    }


REPORT_STYLE = """
body { font-family: sans-serif; max-width: 60em; margin: 2em auto; color: #212121; }
table { border-collapse: collapse; } td, th { padding: 0.2em 0.8em; text-align: left; }
tr.lost td { color: #b71c1c; } pre { white-space: pre-wrap; background: #f5f5f5; padding: 0.6em; }
section.test { border-top: 1px solid #bdbdbd; margin-top: 1.5em; }
"""


def submission_report(results, folder, submission):
    """report.html: one page a browser opens from the file, with the points per task and each
    failing visible test's message above the picture of its failing case (of a hidden test, only
    that it failed)."""
    rows, sections = [], []
    for result in results:
        lost = result.score < result.maximum
        optional = " (optional)" if is_optional(result.task) else ""
        rows.append(f'<tr class="{"lost" if lost else "full"}"><td>{TASK_NUMBER[result.task]}</td>'
                    f"<td>{result.task}{optional}</td><td>{result.score} / {result.maximum}</td></tr>")
        if result.problem:
            sections.append(f'<section class="test"><h3>{task_name(result.task)} was not tested</h3>'
                            f"<pre>{html.escape(result.problem)}</pre></section>")
            continue
        for test in result.tests:
            if test.passed:
                continue
            if test.visibility == "hidden":
                sections.append(f'<section class="test"><h3>{task_name(result.task)}: a hidden test '
                                f"({plural(test.points, 'point')})</h3><p>{html.escape(shown_feedback(test))}</p></section>")
                continue
            picture = picture_html(test, folder)
            sections.append(f'<section class="test" id="{html.escape(test.name)}"><h3>{task_name(result.task)}: '
                            f"{html.escape(test.name)} ({plural(test.points, 'point')})</h3>"
                            f"<pre>{html.escape(PICTURE_LINE.sub('', test.feedback).strip())}</pre>"
                            + (f"<p>{picture}</p>" if picture else "") + "</section>")
    counted = [r for r in results if not is_optional(r.task)]
    total = f"{sum(r.score for r in counted)} / {sum(r.maximum for r in counted)}"
    return (f'<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8"><title>Grading of '
            f"{html.escape(submission)}: {total}</title><style>{REPORT_STYLE}</style></head><body>\n"
            f"<h1>Grading of {html.escape(submission)}: {total} points</h1>\n"
            "<table><tr><th></th><th>task</th><th>points</th></tr>\n" + "\n".join(rows) + "</table>\n"
            + ("<h2>What failed</h2>\n" + "\n".join(sections) if sections else "<p>Every test passed.</p>")
            + "\n</body></html>\n")


# Characters XML 1.0 does not allow (what a student's code prints may hold any byte).
NOT_IN_XML = re.compile("[^\x09\x0a\x0d\x20-\ud7ff\ue000-\ufffd\U00010000-\U0010ffff]")


def xml_text(text):
    return NOT_IN_XML.sub("\ufffd", text)


def junit_xml(results):
    suites = ET.Element("testsuites", name="billiard")
    for result in results:
        failures = sum(not test.passed for test in result.tests) + (1 if result.problem else 0)
        suite = ET.SubElement(suites, "testsuite", name=result.task, tests=str(max(len(result.tests), 1)),
                              failures=str(failures))
        ET.SubElement(suite, "properties").append(
            ET.Element("property", name="score", value=f"{result.score}/{result.maximum}"))
        if result.problem:
            case = ET.SubElement(suite, "testcase", classname=result.task, name="builds")
            ET.SubElement(case, "failure", message="not tested").text = xml_text(result.problem)
        for test in result.tests:
            hidden = test.visibility == "hidden"
            # A hidden test shows neither its name nor its suite's (which may name it too).
            case = ET.SubElement(suite, "testcase",
                                 classname=f"{result.task}.hidden" if hidden else f"{result.task}.{test.name.split('.')[0]}",
                                 name="hidden test" if hidden else test.name.split(".", 1)[1],
                                 time=f"{test.seconds:.3f}")
            if not test.passed:
                ET.SubElement(case, "failure", message=f"0 of {test.points} points").text = (
                    xml_text(shown_feedback(test)))
    ET.indent(suites)
    return ET.tostring(suites, encoding="unicode", xml_declaration=True) + "\n"


def googletest_log(results):
    """googletest.log: GoogleTest's own lines (each assertion's place and values) of every failing
    test that is not hidden, for whoever wants them beside the messages."""
    parts = [f"== {test.name} ({test.task})\n{test.googletest}\n" for result in results for test in result.tests
             if test.googletest and not test.passed and test.visibility != "hidden"]
    return "".join(parts) or "No failing test has lines of GoogleTest's own.\n"


def task_records(results):
    """Every task's result in full, hidden tests' names and messages included (for the
    instructor's class report, never for a student): a JSON-ready list, one entry per task."""
    return [{"task": result.task, "maximum": result.maximum, "problem": result.problem,
             "tests": [{key: value for key, value in vars(test).items() if key != "task"} for test in result.tests]}
            for result in results]


def record_problem(record):
    """Why a task record is not one that task_records writes (a file damaged, edited by hand or
    from another version of the grader), or None: the fields a result needs, each of its type,
    nothing else."""
    if not isinstance(record, dict):
        return "not a record"
    shape = {"task": str, "maximum": int, "problem": str, "tests": list}
    if set(record) != set(shape) or not all(isinstance(record[key], kind) for key, kind in shape.items()):
        return f"its fields are not {', '.join(shape)}"
    if record["task"] not in TASKS:
        return f"{record['task'][:40]!r} is not a task of this course"
    kinds = {item.name: (float, int) if item.type is float else item.type for item in fields(TestResult)
             if item.name != "task"}  # JSON writes 2.0 as 2.0, but a hand may write 2
    needed = {item.name for item in fields(TestResult) if item.default is MISSING} - {"task"}
    for number, test in enumerate(record["tests"], 1):
        if not isinstance(test, dict) or not needed <= set(test) <= set(kinds) or \
                not all(isinstance(value, kinds[key]) for key, value in test.items()):
            return f"its test {number} is not a test's result"
    return None


def results_from_records(records):
    """The TaskResults that task_records wrote (without their clocks)."""
    return [TaskResult(record["task"], [TestResult(record["task"], **test) for test in record["tests"]],
                       record["maximum"], record["problem"]) for record in records]


def write_atomically(path, text):
    path.parent.mkdir(parents=True, exist_ok=True)
    partial = path.with_name(path.name + ".partial")
    partial.write_text(text)
    os.replace(partial, path)
