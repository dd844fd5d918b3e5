"""What an instructor reads of a graded class: gradebook.csv (a row of maxima, then a row per
student), tests.csv (a row per graded test), mistakes.csv (a row per mistake: the failures of a
task grouped by what they show), similarity.csv (copies and near-copies) and report.html, one page
with figures, the mistakes ranked, every student linked to their own report, and the copies.

A student's mistake in a task is read from their first failing test there, visible tests first
(what they read first): its lead hint (or first line); a file that does not build, a test that
ran out of time and the untouched stub are mistakes of their own. Every task with a failure
has at least one row. Percentages are of the students graded in that task, and say so.
"""

import collections
import csv
import html
import io
import os
import re
import shutil
import sys
from dataclasses import dataclass, field

import reports
import similarity
from course import NOT_WRITTEN, OPTIONAL, TASK_NUMBER, TASKS

MAXIMA_ROW = "Points Possible"  # the gradebook's row of each column's maximum (Canvas's name)
ID_COLUMNS = ["submission", "sid", "email", "repository"]  # grade_class.Student.ids, in the gradebook's order
TIMEOUT = "did not finish within its time limit: an endless loop, or far too slow"
NOT_WRITTEN_YET = "not written: the untouched stub"
GTEST_PLACE = re.compile(r"^(\S+:\d+: Failure|Failed)$")  # GoogleTest's lines before the message
GREEN, BROWN, RED, GREY = "#2e7d32", "#8d6e63", "#c62828", "#9e9e9e"  # the figures' colours


@dataclass
class Mistake:
    task: str
    words: str                 # the mistake, as its lead hint (or message, or build problem) says it
    test: str                  # the test it first shows in ("(builds)" for a build problem)
    visibility: str            # that test's: visible, after_due_date or hidden
    students: list = field(default_factory=list)   # [(name, folder)]
    points_lost: int = 0       # of the task's points, over these students
    example: str = ""          # one student's first message line, when the words are a general hint
    picture: str = ""          # one student's picture of it, relative to the results folder

    @property
    def not_written(self):
        return self.words == NOT_WRITTEN_YET


def lead_line(feedback):
    """The line of a failure message that says most: its hint, else its first line. A hint is the
    judge's own line: the student's text inside a message is indented (judging.student_text)."""
    hint = next((line.strip() for line in feedback.splitlines() if line.startswith("Hint:")), None)
    lines = [line.strip() for line in feedback.splitlines() if line.strip()]
    return short(hint or (lines[0] if lines else "(no message)"), 400)


def first_line(text):
    """A message's first line that says something (not GoogleTest's "file:line: Failure")."""
    return next((line.strip() for line in text.splitlines() if line.strip() and not GTEST_PLACE.match(line.strip())),
                "")


def mistake_of(record):
    """(words, test, visibility, example, the failing test's record or None) of a task record
    that lost points, or None if it has full points."""
    if record["problem"]:
        return first_line(record["problem"]).rstrip(":"), "(builds)", "visible", "", None
    failing = [test for test in record["tests"] if not test["passed"]]
    if not failing:
        return None
    if all(NOT_WRITTEN.search(test["feedback"]) for test in failing):
        return NOT_WRITTEN_YET, "", "visible", "", None
    order = {"visible": 0, "after_due_date": 1, "hidden": 2}
    first = min(failing, key=lambda test: order.get(test["visibility"], 1))  # min keeps the suite's order
    if first.get("unfinished") or first.get("not_run"):
        return TIMEOUT, first["name"], first["visibility"], "", first
    words = lead_line(first["feedback"])
    example = first_line(first["feedback"])
    return words, first["name"], first["visibility"], (example if example != words else ""), first


def class_mistakes(students, graded):
    """[Mistake], most students first, then most points lost; the untouched stubs after the rest."""
    found = collections.OrderedDict()
    for student in students:
        for task in TASKS:
            record = graded.get(student.folder, {}).get(task)
            mistake = record and mistake_of(record)
            if not mistake:
                continue
            words, test, visibility, example, failing = mistake
            entry = found.setdefault((task, words), Mistake(task, words, test, visibility, example=example))
            entry.students.append((student.name, student.folder))
            entry.points_lost += record["maximum"] - sum(t["points"] for t in record["tests"] if t["passed"])
            pictures = ([failing] if failing else []) + [t for t in record["tests"] if not t["passed"]]
            drawn = next((t["picture"] for t in pictures if t.get("picture")), "")
            if drawn and not entry.picture:
                entry.picture = f"students/{student.folder}/{drawn}"
    # The untouched stubs last: they are worth knowing, but there is nothing in them to teach again.
    return sorted(found.values(), key=lambda m: (m.not_written, -len(m.students), -m.points_lost, TASK_NUMBER[m.task],
                                                 m.words))


def graded_in(graded):
    """{task: students graded in it}."""
    return collections.Counter(task for records in graded.values() for task in records)


# What makes a spreadsheet read a cell as a formula (OWASP's list for CSV injection): a text cell
# that starts so gets a leading apostrophe, which spreadsheets show as text and do not run.
FORMULA_START = ("=", "+", "-", "@", "\t", "\r")


def spreadsheet_safe(value):
    """A CSV cell: numbers as they are, text that a spreadsheet would run as a formula quoted."""
    if isinstance(value, str) and value.startswith(FORMULA_START):
        return "'" + value
    return value


def write_csv(path, header, rows):
    """Writes a CSV file whole or not at all; every text cell spreadsheet_safe (names, hints and
    paths come from students)."""
    partial = path.with_name(path.name + ".partial")
    with open(partial, "w", newline="") as out:
        writer = csv.writer(out)
        writer.writerow(header)
        writer.writerows([spreadsheet_safe(value) for value in row] for row in rows)
    os.replace(partial, path)


def points_of(record):
    return sum(test["points"] for test in record["tests"] if test["passed"])


def write_reports(folder, students, graded, copies=None, partial=None, notes=()):
    """gradebook.csv, tests.csv, mistakes.csv, similarity.csv and report.html in folder; graded:
    {student's folder: {task: record}}, copies: a similarity.Comparison keyed by the students'
    folders; partial: (students graded in every task, class size) when the grading was
    interrupted; notes: lines on what is left out and why (at the report's top). A student is
    their folder (unique), never their name (two may share one)."""
    counted = [task for task in TASKS if task not in OPTIONAL]
    maxima = {task: record["maximum"] for records in graded.values() for task, record in records.items()}

    # The identifiers the platform exported (Gradescope's submission, SID and e-mail; Autolab's
    # e-mail; the Classroom repository), so that the rows can be matched to the platform's.
    id_columns = [column for column in ID_COLUMNS if any(column in student.ids for student in students)]

    def row(student, points):
        return {"student": student.name if student else MAXIMA_ROW, "folder": student.folder if student else "",
                **{column: student.ids.get(column, "") if student else "" for column in id_columns},
                **{task: points.get(task, "") for task in TASKS},
                "total": sum(points.get(t, 0) for t in counted),
                "optional": sum(points.get(t, 0) for t in TASKS if t in OPTIONAL)}
    rows = [(student, row(student, {task: points_of(record) for task, record in graded[student.folder].items()}))
            for student in students if student.folder in graded]
    columns = ["student", "folder", *id_columns, *TASKS, "total", "optional"]
    # The maxima first, where spreadsheets and learning platforms (Canvas's "Points Possible") look.
    write_csv(folder / "gradebook.csv", columns,
              [[values[c] for c in columns] for values in [row(None, maxima)] + [r for _, r in rows]])

    tests = test_table(students, graded)
    write_csv(folder / "tests.csv", ["task", "test", "points", "visibility", "failed", "not_written", "students",
                                     "most_common_failure", "picture"],
              [[task, name, entry["points"], entry["visibility"], entry["failed"], entry["not_written"], len(graded),
                most_common(entry), entry["pictures"].get(most_common(entry), "")]
               for (task, name), entry in tests.items()])

    mistakes = class_mistakes(students, graded)
    counts = graded_in(graded)
    write_csv(folder / "mistakes.csv", ["task", "mistake", "first_failing_test", "visibility", "students", "of",
                                        "points_lost", "names", "example", "picture"],
              [[m.task, m.words, m.test, m.visibility, len(m.students), counts[m.task], m.points_lost,
                "; ".join(name for name, _ in m.students), m.example, m.picture] for m in mistakes])

    copies = copies or similarity.Comparison({}, [])
    pairs = copies.pairs
    views = similarity_pages(folder, students, pairs)
    names = {student.folder: student.name for student in students}
    write_csv(folder / "similarity.csv", ["task", "first", "second", "first_share", "second_share",
                                          "fingerprints_matched", "first_lines", "second_lines", "identical", "view",
                                          "first_folder", "second_folder"],
              [[p.task, names[p.first], names[p.second], p.first_share, p.second_share, p.fingerprints, *p.lines,
                "yes" if p.identical else "no", views.get(id(p), ""), p.first, p.second]
               for task in TASKS for p in pairs.get(task, [])])
    reports.write_atomically(folder / "report.html",
                             report_html(rows, maxima, counted, mistakes, counts, copies, views, partial, notes))


def test_table(students, graded):
    """{(task, test): {points, visibility, failed, not_written, messages, pictures}}; a task's
    build problems as its test "(builds)"."""
    tests = collections.OrderedDict()
    for student in students:
        for task, record in graded.get(student.folder, {}).items():
            if record["problem"]:
                entry = tests.setdefault((task, "(builds)"), new_entry(record["maximum"], "visible"))
                entry["failed"] += 1
                entry["messages"][lead_line(record["problem"])] += 1
            for test in record["tests"]:
                entry = tests.setdefault((task, test["name"]), new_entry(test["points"], test["visibility"]))
                if test["passed"]:
                    continue
                entry["failed"] += 1
                if NOT_WRITTEN.search(test["feedback"]):  # the untouched stub: nothing to re-teach
                    entry["not_written"] += 1
                else:
                    message = lead_line(test["feedback"])
                    entry["messages"][message] += 1
                    if test.get("picture"):
                        entry["pictures"].setdefault(message, f"students/{student.folder}/{test['picture']}")
    return tests


def new_entry(points, visibility):
    return {"points": points, "visibility": visibility, "failed": 0, "not_written": 0,
            "messages": collections.Counter(), "pictures": {}}


def most_common(entry):
    common = entry["messages"].most_common(1)
    return common[0][0] if common else ""


def similarity_pages(folder, students, pairs):
    """Writes a side-by-side page per near-copy pair under similarity/; {id(pair): its path}."""
    files = {student.folder: student.files for student in students}
    pages = folder / "similarity"
    shutil.rmtree(pages, ignore_errors=True)  # an earlier run's pages
    views = {}
    for task in TASKS:
        for number, pair in enumerate(pairs.get(task, []), start=1):
            if pair.identical or not pair.runs:
                continue
            path = pages / f"{task}-{number}.html"
            reports.write_atomically(path, similarity.side_by_side(pair, files[pair.first][task],
                                                                  files[pair.second][task]))
            views[id(pair)] = f"similarity/{path.name}"
    return views


# --- The page ---------------------------------------------------------------------------------------

def svg_figure(figure):
    import matplotlib.pyplot as plt
    out = io.StringIO()
    figure.savefig(out, format="svg", bbox_inches="tight")
    plt.close(figure)
    text = out.getvalue()
    return text[text.index("<svg"):]


def totals_figure(totals, total_max):
    """A dot per student at their total, stacked where totals are alike: reads for 10 students and
    for 300 (bins of one point, or of 0.5 % of the maximum where a course has more points)."""
    import matplotlib.pyplot as plt
    width = max(1, round(total_max / 200))
    stacks = collections.Counter()
    xs, ys = [], []
    for total in sorted(totals):
        spot = total // width * width
        stacks[spot] += 1
        xs.append(spot)
        ys.append(stacks[spot])
    figure, axes = plt.subplots(figsize=(7, 1.2 + 0.18 * max(stacks.values())))
    axes.scatter(xs, ys, s=60 if len(totals) <= 60 else 25, color=GREEN, zorder=3)
    axes.set_xlim(-0.02 * total_max - 1, total_max * 1.02 + 1)
    axes.set_ylim(0, max(stacks.values()) + 1)
    axes.set_xlabel(f"total points (required tasks, of {total_max}): a dot per student"
                    + (f", in steps of {width}" if width > 1 else ""))
    axes.set_yticks([])
    axes.grid(axis="x", color="#e0e0e0")
    axes.set_title(f"Totals of the {len(totals)} students")
    return svg_figure(figure)


def tasks_figure(rows, tasks, maxima, counts):
    """A bar per task: the class's mean share of its points."""
    import matplotlib.pyplot as plt
    figure, axes = plt.subplots(figsize=(7, 3))
    shares = [100 * sum(values[task] or 0 for _, values in rows) / (counts[task] * maxima[task])
              if maxima[task] else 0 for task in tasks]
    axes.bar([f"{TASK_NUMBER[t]} {t}" for t in tasks], shares, color=[BROWN if t in OPTIONAL else GREEN for t in tasks])
    axes.set_ylim(0, 100)
    axes.set_ylabel("% of the points, class mean")
    axes.set_title("Each task (brown: optional)")
    axes.tick_params(axis="x", labelrotation=45)
    return svg_figure(figure)


def mistakes_figure(shown, counts):
    """A bar per mistake: the share of the students graded in its task who make it."""
    import matplotlib.pyplot as plt
    figure, axes = plt.subplots(figsize=(7, 0.4 * len(shown) + 1.2))
    # A mistake's words may quote a student's text: a "$" must not start matplotlib's mathtext.
    labels = [f"{m.task}: {short(m.words.removeprefix('Hint: '), 60)}".replace("$", r"\$") for m in shown][::-1]
    axes.barh(labels, [100 * len(m.students) / counts[m.task] for m in shown][::-1],
              color=[GREY if m.not_written else RED for m in shown][::-1])
    axes.set_xlim(0, 100)
    axes.set_xlabel("% of the students graded in the task (grey: the stub untouched)")
    axes.set_title("The class's mistakes, most common first")
    return svg_figure(figure)


def figures_or_notes(drawings):
    """([svg], [note]): each drawing (name, function, arguments) drawn, or, where it fails (no
    matplotlib, a figure that cannot be drawn), a line saying which is missing and why."""
    try:
        import matplotlib
        matplotlib.use("Agg")
    except ImportError:
        return [], [f"No figures: matplotlib is not installed for {sys.executable} (python3-matplotlib)."]
    figures, notes = [], []
    for name, draw, arguments in drawings:
        try:
            figures.append(draw(*arguments))
        except Exception as error:  # one figure lost, never the page
            notes.append(f"The figure of {name} is missing: {type(error).__name__}: {str(error)[:200]}.")
    return figures, notes


def report_html(rows, maxima, counted, mistakes, counts, copies, views, partial=None, notes=()):
    """One self-contained page (figures inline as SVG, a few lines of script to sort the students'
    table): what the class got, what it got wrong, each student, the copies."""
    pairs = copies.pairs
    students = len(rows)
    total_max = sum(maxima.get(task, 0) for task in counted)
    tasks = [task for task in TASKS if task in maxima]
    drawings = []
    if rows:
        drawings.append(("the totals", totals_figure, ([values["total"] for _, values in rows], total_max)))
        drawings.append(("the tasks", tasks_figure, (rows, tasks, maxima, counts)))
    if mistakes:
        drawings.append(("the mistakes", mistakes_figure, (mistakes[:15], counts)))
    figures, missing = figures_or_notes(drawings)

    def seen(value):
        return {"visible": "seen before the due date", "after_due_date": "seen after the due date",
                "hidden": "hidden: never seen"}.get(value, value)

    def picture(mistake):
        return f'<a href="{html.escape(mistake.picture)}">picture</a>' if mistake.picture else ""

    mistake_rows = "".join(
        f"<tr><td>{html.escape(m.task)}</td><td>{html.escape(m.words.removeprefix('Hint: '))}"
        + (f'<br><small title="{html.escape(m.example)}">first failing test: {html.escape(m.test)}, {seen(m.visibility)}'
           "</small>" if m.test else "")
        + f"</td><td>{len(m.students)} of {counts[m.task]}</td><td>{m.points_lost}</td>"
        f"<td>{', '.join(student_link(name, folder) for name, folder in m.students)}</td><td>{picture(m)}</td></tr>"
        for m in mistakes)
    flags = collections.defaultdict(list)
    for task_pairs in pairs.values():
        for pair in task_pairs:
            for name in (pair.first, pair.second):
                flags[name].append(pair.task)
    student_rows = "".join(
        f"<tr><td>{student_link(student.name, student.folder)}</td>"
        + "".join(f"<td>{values[task]}</td>" for task in tasks)
        + f"<td>{values['total']}</td><td>{values['optional']}</td>"
        f"<td>{', '.join(str(TASK_NUMBER[t]) for t in TASKS if t in flags.get(student.folder, []))}</td></tr>"
        for student, values in rows)
    maxima_row = ("<tr class=\"maxima\"><td>maximum</td>" + "".join(f"<td>{maxima[task]}</td>" for task in tasks)
                  + f"<td>{total_max}</td><td>{sum(maxima[t] for t in tasks if t in OPTIONAL)}</td><td></td></tr>")
    mean = sum(values["total"] for _, values in rows) / students if students else 0
    return f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>billiard: the class's results</title>
<style>body {{ font-family: sans-serif; max-width: 80em; margin: 2em auto; color: #212121; }}
table {{ border-collapse: collapse; }} td, th {{ padding: 0.2em 0.6em; text-align: left; vertical-align: top;
border-bottom: 1px solid #ddd; }} th.sortable {{ cursor: pointer; text-decoration: underline dotted; }}
tr.maxima td {{ font-style: italic; color: #616161; }} svg {{ max-width: 100%; height: auto; }}
small {{ color: #616161; }} p.missing {{ color: #b71c1c; }} table.mistakes td:nth-child(2) {{ min-width: 28em; }}</style>
</head><body>
<h1>The class's results</h1>
{f'<p><strong>Partial: the grading was interrupted with {partial[0]} of {partial[1]} students graded in every task; run the same command again to grade the rest.</strong></p>' if partial else ''}
<p>{students} students graded; mean total {mean:.1f} of {total_max} points in the required tasks.
Files beside this page: <code>gradebook.csv</code> (a row per student, the maxima first), <code>mistakes.csv</code>,
<code>tests.csv</code> (a row per test) and <code>similarity.csv</code>.</p>
{''.join(f'<p class="missing">{html.escape(note)}</p>' for note in notes)}
{''.join(f'<figure>{svg}</figure>' for svg in figures)}{''.join(f'<p class="missing">{html.escape(note)}</p>' for note in missing)}
<h2 id="mistakes">What the class got wrong</h2>
<p>Each student's failures in a task, grouped by the mistake they show: the lead hint (or first line) of their first
failing test there, visible tests first (under it: that test, and when a student sees it on Gradescope); a file that
does not build, a test out of time and the untouched stub are mistakes of their own. Most students first, the untouched stubs last.
<em>Students</em>: how many of those graded in the task show it; <em>points lost</em>: what they lost in the task,
added up; the picture: one student's failing case, drawn.</p>
<table class="mistakes"><tr><th>task</th><th>mistake</th><th>students</th><th>points lost</th><th>who</th><th></th></tr>
{mistake_rows}</table>
<h2 id="students">Students</h2>
<p>Points per task and in all; click a column's name to sort by it, a student's name for their own report (each
failing test's message and picture, as they may see it). <em>Similar in</em>: the numbers of the tasks where their file is a
copy or near-copy of another's (below).</p>
<table id="students-table"><thead><tr><th class="sortable">student</th>{''.join(f'<th class="sortable">{TASK_NUMBER[t]} {html.escape(t)}</th>' for t in tasks)}
<th class="sortable">total</th><th class="sortable">optional</th><th class="sortable">similar in</th></tr>{maxima_row}</thead>
<tbody>{student_rows}</tbody></table>
{similarity_section(copies, views, {student.folder: student_link(student.name, student.folder) for student, _ in rows})}
<script>
// Sorts the students' table by the column clicked (numbers as numbers; again: the other way).
document.querySelectorAll("#students-table th.sortable").forEach((header, column) => {{
  header.addEventListener("click", () => {{
    const body = document.querySelector("#students-table tbody");
    const value = row => row.children[column].textContent.trim();
    const down = header.dataset.down !== "true";
    header.dataset.down = down;
    const rows = Array.from(body.rows).sort((a, b) => {{
      const [x, y] = [value(a), value(b)];
      const order = (x !== "" && y !== "" && !isNaN(x) && !isNaN(y)) ? x - y : x.localeCompare(y);
      return down ? -order : order;
    }});
    rows.forEach(row => body.appendChild(row));
  }});
}});
</script>
</body></html>
"""


def student_link(name, folder):
    """A student's name, linked to their own report."""
    return f'<a href="students/{html.escape(folder)}/report.html">{html.escape(name)}</a>'


def similarity_section(copies, views, links):
    """The copies: identical files by group, then the near-copies with their shares and views,
    and a line for each thing the finder left out."""
    pairs = copies.pairs
    def name(student):
        return links.get(student, html.escape(student))
    groups = "".join(f"<tr><td>{html.escape(task)}</td><td>{len(group)}</td><td>{', '.join(name(s) for s in group)}</td></tr>"
                     for task in TASKS for group in similarity.groups(pairs.get(task, [])))
    # A near-copy once per pair of different files: the students who hand in the same file as
    # one of the pair are named with it.
    same = {}  # (task, student) -> the students with their file, first named
    for task in TASKS:
        for group in similarity.groups(pairs.get(task, [])):
            for student in group:
                same[(task, student)] = group

    def side(task, student):
        group = same.get((task, student), [student])
        return name(group[0]) + (f" <small>and {len(group) - 1} more with the same file</small>" if len(group) > 1 else "")
    shown, near = set(), ""
    for task in TASKS:
        for p in pairs.get(task, []):
            key = (task, *sorted([same.get((task, p.first), [p.first])[0], same.get((task, p.second), [p.second])[0]]))
            if p.identical or key in shown:
                continue
            shown.add(key)
            view = f'<a href="{views[id(p)]}">side by side</a>' if id(p) in views else ""
            near += (f"<tr><td>{html.escape(task)}</td><td>{side(task, p.first)}</td><td>{side(task, p.second)}</td>"
                     f"<td>{p.first_share} %</td><td>{p.second_share} %</td><td>{p.lines[0]} / {p.lines[1]}</td>"
                     f"<td>{view}</td></tr>")
    notes = "".join(f'<p class="missing">{html.escape(note)}</p>' for note in copies.notes)
    return f"""<h2 id="similarity">Copies and near-copies</h2>
<p>Each task's files compared pair by pair by Dolos, a copy finder made for students' code, which compares the files'
syntax trees: renamed variables, another layout, other comments and functions in another order do not hide a copy.
What the students share without copying is left out: the stub, which every student got, and any passage found in
more than {similarity.SHARED_BY} of a task's different files (or {100 * similarity.SHARED_BY_SHARE:.0f} % of them in
a large class: the one natural way to write a small task), and a file that is the untouched stub is not compared. A
pair is listed when at least {similarity.SHARE_FLAGGED} % of one file's own code is found in the other
({similarity.FINGERPRINTS_FLAGGED} fingerprints or more: a task of a dozen lines that everyone writes alike is too small
to tell). This flags; it changes no points.</p>
{notes}
<h3>Identical files</h3>
{f'<table><tr><th>task</th><th>students</th><th>who handed in the same file</th></tr>{groups}</table>' if groups else '<p>None.</p>'}
<h3>Near-copies</h3>
<p><em>first share</em>: how much of the first student's own code is found in the second's file; <em>second
share</em>: the other way; <em>lines</em>: how many lines of each file the matched code spans.</p>
{f'<table><tr><th>task</th><th>first</th><th>second</th><th>first share</th><th>second share</th><th>lines</th><th></th></tr>{near}</table>' if near else '<p>None.</p>'}
"""


def short(text, limit):
    return text if len(text) <= limit else text[:limit - 1].rstrip() + "…"
