"""Copies and near-copies in a class: each task's files compared pair by pair with Debian's
similarity tester (package similarity-tester: sim_c++ for C++, sim_c for C), which matches runs
of tokens and so sees through renamed variables, changed layout and comments, and reordered
functions. What every student shares (the lines of the task's stub: includes, signatures) is
left out before comparing, so that only each student's own code counts; a file that is the
untouched stub is not compared at all. It flags pairs for an instructor to look at; it never
changes points.

A pair is flagged when at least SHARE_FLAGGED % of one file's own code is found in the other,
in runs of at least RUN_TOKENS tokens that add up to MATCH_FLAGGED tokens or more (a few lines
any two solutions of a small task write alike are not a copy). Identical files are flagged as
a group.
"""

import difflib
import html
import itertools
import re
import resource
import subprocess
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

from course import TASK_FILE

SHARE_FLAGGED = 50    # % of one file's own code found in the other
MATCH_FLAGGED = 60    # tokens matched in all
RUN_TOKENS = 24       # the shortest run that counts (sim's default)
TESTER = {".cpp": "sim_c++", ".c": "sim_c"}
RUN_LINE = re.compile(r"^(?P<a>f\d+)\.\w+: line (?P<a0>\d+)-(?P<a1>\d+)\s*\|(?P<b>f\d+)\.\w+: line (?P<b0>\d+)-(?P<b1>\d+)"
                      r"\s*\[(?P<tokens>\d+)\]")
FILE_LINE = re.compile(r"^File (?P<file>f\d+)\.\w+: (?P<tokens>\d+) tokens")


@dataclass
class Pair:
    task: str
    first: str                 # a student's name
    second: str
    first_share: int = 100     # % of the first's own code found in the second's file
    second_share: int = 100
    tokens: int = 0            # tokens matched
    identical: bool = False
    runs: list = field(default_factory=list)  # ((first's lines), (second's lines), tokens)

    @property
    def share(self):
        return max(self.first_share, self.second_share)


def own_code(text, stub):
    """text with the lines it shares with the stub blanked (so line numbers stay), as sim reads."""
    lines, stub_lines = text.splitlines(), stub.splitlines()
    matcher = difflib.SequenceMatcher(None, [line.strip() for line in lines], [line.strip() for line in stub_lines],
                                      autojunk=False)
    kept = list(lines)
    for block in matcher.get_matching_blocks():
        for index in range(block.a, block.a + block.size):
            kept[index] = ""
    return "\n".join(kept) + "\n"


def limit_tester():
    """The tester reads students' text: it gets a bounded share of this machine."""
    resource.setrlimit(resource.RLIMIT_CPU, (60, 60))
    resource.setrlimit(resource.RLIMIT_AS, (2 << 30, 2 << 30))


def compare_task(task, files, stub):
    """[Pair] of a task's flagged pairs; files {student: bytes}, stub: the task's stub (bytes)."""
    suffix = Path(TASK_FILE[task]).suffix
    handed_in = {student: text for student, text in files.items() if text.strip() and text != stub}
    by_content = {}
    for student, text in sorted(handed_in.items()):
        by_content.setdefault(text, []).append(student)
    pairs = [Pair(task, a, b, identical=True) for names in by_content.values() for a, b in itertools.combinations(names, 2)]
    contents = list(by_content)
    if len(contents) < 2:
        return pairs
    stub_text = stub.decode(errors="replace")
    with tempfile.TemporaryDirectory(prefix="similarity-") as folder:
        paths = []
        for index, content in enumerate(contents):
            path = Path(folder) / f"f{index}{suffix}"
            path.write_text(own_code(content.decode(errors="replace"), stub_text))
            paths.append(path.name)
        done = subprocess.run([TESTER[suffix], "-e", "-s", "-n", "-r", str(RUN_TOKENS), "-w", "200", *paths],
                              cwd=folder, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, errors="replace",
                              timeout=600, preexec_fn=limit_tester)
    if done.returncode != 0:
        raise RuntimeError(f"{TESTER[suffix]} failed on {task}: {done.stderr.strip()[-500:]}")
    sizes, runs = {}, {}
    for line in done.stdout.splitlines():
        if match := FILE_LINE.match(line):
            sizes[int(match["file"][1:])] = int(match["tokens"])
        elif (match := RUN_LINE.match(line)) and match["a"] != match["b"]:
            a, b = int(match["a"][1:]), int(match["b"][1:])
            run = ((int(match["a0"]), int(match["a1"])), (int(match["b0"]), int(match["b1"])), int(match["tokens"]))
            if a > b:
                a, b, run = b, a, (run[1], run[0], run[2])
            runs.setdefault((a, b), []).append(run)
    for (a, b), found in runs.items():
        tokens = sum(run[2] for run in found)
        # (runs may overlap in one file, where it repeats itself: a share is at most all of it)
        shares = [min(100, round(100 * tokens / sizes[index])) if sizes.get(index) else 0 for index in (a, b)]
        if tokens < MATCH_FLAGGED or max(shares) < SHARE_FLAGGED:
            continue
        for first, second in itertools.product(by_content[contents[a]], by_content[contents[b]]):
            if first > second:
                pairs.append(Pair(task, second, first, shares[1], shares[0], tokens, False,
                                  sorted((run[1], run[0], run[2]) for run in found)))
            else:
                pairs.append(Pair(task, first, second, shares[0], shares[1], tokens, False, sorted(found)))
    return sorted(pairs, key=lambda pair: (not pair.identical, -pair.share, pair.first, pair.second))


def compare_class(files, stubs, tasks):
    """{task: [Pair]} for a class: files {student: {task: bytes}}, stubs {task: bytes}."""
    return {task: compare_task(task, {student: own[task] for student, own in files.items() if task in own},
                               stubs[task])
            for task in tasks}


def groups(pairs):
    """The identical files among pairs as groups of students ([[names]]), largest first."""
    joined = []
    for pair in pairs:
        if not pair.identical:
            continue
        group = next((group for group in joined if pair.first in group or pair.second in group), None)
        if group is None:
            joined.append({pair.first, pair.second})
        else:
            group |= {pair.first, pair.second}
    return sorted((sorted(group) for group in joined), key=lambda group: (-len(group), group))


def side_by_side(pair, first_text, second_text):
    """An HTML page showing a near-copy pair's matching runs side by side, lines numbered."""
    first_lines = first_text.decode(errors="replace").splitlines()
    second_lines = second_text.decode(errors="replace").splitlines()

    def excerpt(lines, span):
        start, end = span
        return "\n".join(f"{number:4d}  {html.escape(lines[number - 1]) if number <= len(lines) else ''}"
                         for number in range(start, end + 1))

    rows = "".join(f"<tr><td><pre>{excerpt(first_lines, a)}</pre></td><td><pre>{excerpt(second_lines, b)}</pre></td>"
                   f"<td>{tokens}</td></tr>" for a, b, tokens in pair.runs)
    title = f"{pair.task}: {pair.first} and {pair.second}"
    return f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>{html.escape(title)}</title>
<style>body {{ font-family: sans-serif; margin: 1em; }} table {{ border-collapse: collapse; width: 100%; }}
td, th {{ vertical-align: top; border-bottom: 1px solid #ccc; padding: 0.3em; text-align: left; }}
pre {{ margin: 0; white-space: pre-wrap; background: #fff8e1; font-size: 0.85em; }}</style></head><body>
<h1>{html.escape(title)}</h1>
<p>{pair.first_share} % of {html.escape(pair.first)}'s own code is found in {html.escape(pair.second)}'s file, and
{pair.second_share} % the other way ({pair.tokens} tokens in runs of at least {RUN_TOKENS}; names, layout and
comments may differ: the similarity tester compares tokens). The lines every student got in the stub are left
out. The matching parts, in {html.escape(pair.first)}'s order:</p>
<table><tr><th>{html.escape(pair.first)}</th><th>{html.escape(pair.second)}</th><th>tokens</th></tr>{rows}</table>
</body></html>
"""
