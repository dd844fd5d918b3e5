"""Copies and near-copies in a class: each task's files compared pair by pair by Dolos, the copy
finder that Ghent University keeps for exactly this (npm's @dodona/dolos-lib, run by Node.js;
./build.sh installs it into build/copy-finder/, and copies/find_copies.mjs is what runs). Its
tokens are the nodes of each file's syntax tree, so renamed names, another layout, moved comments
and reordered functions do not hide a copy; it fingerprints runs of KGRAM tokens, keeping one
fingerprint in each WINDOW runs (winnowing; both Dolos's defaults). It flags pairs for an
instructor to look at; it never changes points.

What students share without copying counts for no pair, as MOSS discounts it: the task's stub,
which every student got (includes, signatures), and any passage found in more than SHARED_BY
of a task's different files, or SHARED_BY_SHARE of them in a large class (the one natural way
to write a small task). A file that is the untouched stub is not compared, nor one far larger
than any solution (over COMPARED_FILE_CAP bytes: a token flood) or one that does not build
(whatever text it holds), which a note names instead; identical files are found whatever they are.

A pair is flagged when at least SHARE_FLAGGED % of one file's own fingerprints are found in the
other, and at least FINGERPRINTS_FLAGGED in all: the dozen lines of a task as small as
init_velocities, which everyone writes alike, are too little to tell a copy by. Identical
files are flagged as a group, whatever their size.
"""

import html
import itertools
import json
import re
import resource
import shutil
import subprocess
from dataclasses import dataclass, field
from pathlib import Path

from course import TASK_FILE

HERE = Path(__file__).resolve().parent
FINDER_SCRIPT = HERE / "copies" / "find_copies.mjs"
FINDER_HOME = HERE.parents[1] / "build" / "copy-finder"  # npm's install (./build.sh grade --class)
OLDEST_NODE = 18                 # Dolos's oldest Node.js
LANGUAGE = {".cpp": "cpp", ".c": "c"}
KGRAM = 23                       # tokens per fingerprinted run (Dolos's default)
WINDOW = 17                      # one fingerprint kept per window of this many runs (Dolos's default)
SHARE_FLAGGED = 60               # % of one file's own fingerprints found in the other
FINGERPRINTS_FLAGGED = 30        # fingerprints matched, at least
SHARED_BY = 10                   # a passage in more of a task's different files is nobody's own (MOSS's)
SHARED_BY_SHARE = 0.1            # ... or in more than this share of them, in a large class
COMPARED_FILE_CAP = 64 << 10     # bytes: several times the largest reference solution
FINDER_SECONDS = 300             # CPU seconds for one task's comparison


@dataclass
class Pair:
    task: str
    first: str                 # a student's name
    second: str
    first_share: int = 100     # % of the first's own fingerprints found in the second's file
    second_share: int = 100
    fingerprints: int = 0      # fingerprints matched
    lines: tuple = (0, 0)      # lines of each file that the matched code spans
    identical: bool = False
    runs: list = field(default_factory=list)  # ((first's lines), (second's lines), fingerprints)

    @property
    def share(self):
        return max(self.first_share, self.second_share)


@dataclass
class Comparison:
    pairs: dict                # {task: [Pair]}
    notes: list                # one line each: what was not compared, and why


def node():
    return shutil.which("node") or shutil.which("nodejs")


def node_too_old():
    """The version of this system's Node.js when it is older than Dolos runs on (Ubuntu 22.04's
    12), else None."""
    if node() is None:
        return None
    done = subprocess.run([node(), "--version"], stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    found = re.match(r"v(\d+)\.", done.stdout)
    return None if found and int(found[1]) >= OLDEST_NODE else (done.stdout.strip() or "an unknown version")


def finder_problem():
    """None when the copy finder can run here, else one line saying why not and what to do."""
    if node() is None:
        return "Node.js is not installed (./build.sh grade --class installs it and the copy finder)"
    if node_too_old():
        return f"the copy finder (Dolos) needs Node.js {OLDEST_NODE} or newer, and this system has {node_too_old()}"
    if not (FINDER_HOME / "installed").is_file():
        return "the copy finder (Dolos, from npm) is not installed: ./build.sh grade --class installs it" + \
            install_failure()
    return None


def install_failure():
    """Why npm could not install the copy finder, as its log's first error says (", which
    failed: ..."), or ""."""
    try:
        lines = (FINDER_HOME / "npm.log").read_text(errors="replace").splitlines()
    except OSError:
        return ""
    # npm's first error lines name a code ("npm ERR! code E404"; "npm error" since npm 10); the
    # one after says what failed.
    errors = [found[1].strip() for line in lines if (found := re.match(r"npm (?:ERR!|error) (.*)", line))]
    said = next((line for line in errors if line and not re.match(r"(code|errno) ", line)), None)
    return f", which failed here: {said[:200]} ({FINDER_HOME / 'npm.log'})" if said else ""


def limit_finder():
    """The finder parses students' text: it gets a bounded share of this machine."""
    resource.setrlimit(resource.RLIMIT_CPU, (FINDER_SECONDS, FINDER_SECONDS))
    resource.setrlimit(resource.RLIMIT_AS, (4 << 30, 4 << 30))


def run_finder(language, template, texts, floor=SHARE_FLAGGED / 100):
    """Dolos's pairs of the texts [str] of which the share floor of one file's own fingerprints
    is found in the other, as find_copies.mjs writes them (files named by their index)."""
    shared_by = max(SHARED_BY, int(SHARED_BY_SHARE * len(texts)))
    request = {"language": language, "kgram": KGRAM, "window": WINDOW, "sharedBy": shared_by, "floor": floor,
               "template": template, "files": [{"name": str(index), "text": text} for index, text in enumerate(texts)]}
    script = FINDER_HOME / FINDER_SCRIPT.name  # beside its node_modules, where Node looks for them
    if not script.is_file() or script.read_bytes() != FINDER_SCRIPT.read_bytes():
        shutil.copyfile(FINDER_SCRIPT, script)
    done = subprocess.run([node(), str(script)], input=json.dumps(request), stdout=subprocess.PIPE,
                          stderr=subprocess.PIPE, text=True, errors="replace", timeout=2 * FINDER_SECONDS,
                          preexec_fn=limit_finder)
    if done.returncode != 0:
        raise RuntimeError(f"the copy finder failed: {done.stderr.strip()[-500:]}")
    return json.loads(done.stdout)["pairs"]


def one_to_one(fragments):
    """The matching parts to show of Dolos's fragments ([first rows], [second rows], fingerprints;
    rows from 0): the largest first, each line of either file in one part at most (Dolos also
    matches, say, each function's head with every other's), as ((first lines), (second lines),
    fingerprints) with lines from 1, in the first file's order."""
    taken, shown = (set(), set()), []
    for first, second, size in sorted(fragments, key=lambda fragment: -fragment[2]):
        lines = (set(range(first[0], first[1] + 1)), set(range(second[0], second[1] + 1)))
        if lines[0] & taken[0] or lines[1] & taken[1]:
            continue
        taken[0].update(lines[0])
        taken[1].update(lines[1])
        shown.append(((first[0] + 1, first[1] + 1), (second[0] + 1, second[1] + 1), size))
    return sorted(shown)


def spanned(runs, side):
    """How many lines of one side of a pair (0: first, 1: second) its runs span."""
    return sum(run[side][1] - run[side][0] + 1 for run in runs)


def by_content(files, stub):
    """{file's bytes: [students]} of the files handed in (not empty, not the untouched stub)."""
    found = {}
    for student, text in sorted(files.items()):
        if text.strip() and text != stub:
            found.setdefault(text, []).append(student)
    return found


def identical_pairs(task, contents):
    return [Pair(task, a, b, identical=True) for names in contents.values() for a, b in itertools.combinations(names, 2)]


def near_pair(task, first, second, raw):
    """The Pair of students first and second (first's file raw["first"]) from Dolos's raw pair."""
    shares = [min(100, round(100 * raw[f"{side}Covered"] / raw[f"{side}Own"])) if raw[f"{side}Own"] else 0
              for side in ("first", "second")]
    runs = one_to_one(raw["fragments"])
    lines = (spanned(runs, 0), spanned(runs, 1))
    pair = Pair(task, first, second, shares[0], shares[1], min(raw["firstCovered"], raw["secondCovered"]), lines,
                False, runs)
    if first < second:
        return pair
    return Pair(task, second, first, shares[1], shares[0], pair.fingerprints, lines[::-1], False,
                sorted((theirs, mine, size) for mine, theirs, size in runs))


def compare_task(task, files, stub, unbuilt=()):
    """([Pair], [note]) of a task's flagged pairs; files {student: bytes}, stub: the task's stub,
    unbuilt: the students whose file there does not build (only their identical copies are
    found)."""
    contents = by_content(files, stub)
    pairs = identical_pairs(task, contents)
    too_large = sorted(student for text, names in contents.items() if len(text) > COMPARED_FILE_CAP for student in names)
    not_built = sorted(student for text, names in contents.items() if len(text) <= COMPARED_FILE_CAP
                       for student in names if student in unbuilt)
    notes = [f"{task}: not compared, over {COMPARED_FILE_CAP >> 10} KiB (far larger than any solution): "
             f"{', '.join(too_large)}"] if too_large else []
    notes += [f"{task}: not compared, does not build (identical copies are still found): "
              f"{', '.join(not_built)}"] if not_built else []
    contents = {text: [name for name in names if name not in unbuilt] for text, names in contents.items()
                if len(text) <= COMPARED_FILE_CAP}
    contents = {text: names for text, names in contents.items() if names}
    texts = list(contents)
    if len(texts) >= 2:
        language = LANGUAGE[Path(TASK_FILE[task]).suffix]
        for raw in run_finder(language, stub.decode(errors="replace"), [text.decode(errors="replace") for text in texts]):
            shares = [raw[f"{side}Covered"] / raw[f"{side}Own"] if raw[f"{side}Own"] else 0 for side in ("first", "second")]
            if 100 * max(shares) < SHARE_FLAGGED or min(raw["firstCovered"], raw["secondCovered"]) < FINGERPRINTS_FLAGGED:
                continue
            mine, theirs = contents[texts[int(raw["first"])]], contents[texts[int(raw["second"])]]
            pairs += [near_pair(task, first, second, raw) for first, second in itertools.product(mine, theirs)]
    return sorted(pairs, key=lambda pair: (not pair.identical, -pair.share, pair.first, pair.second)), notes


def compare_class(files, stubs, tasks, unbuilt=None):
    """The copies in a class, a Comparison: files {student: {task: bytes}}, stubs {task: bytes},
    unbuilt {task: the students whose file there does not build}. Where the finder cannot run,
    or fails in a task, a note says so, and identical files are still found."""
    unbuilt = unbuilt or {}
    problem = finder_problem()
    pairs, notes = {}, [] if problem is None else [f"Near-copies were not looked for: {problem}."]
    for task in tasks:
        own = {student: mine[task] for student, mine in files.items() if task in mine}
        if problem is None:
            try:
                pairs[task], found = compare_task(task, own, stubs[task], unbuilt.get(task, set()))
                notes += found
                continue
            except (OSError, RuntimeError, ValueError, subprocess.TimeoutExpired) as error:
                notes.append(f"{task}: near-copies were not looked for: {last_line(error)}")
        pairs[task] = identical_pairs(task, by_content(own, stubs[task]))
    return Comparison(pairs, notes)


def last_line(error):
    lines = str(error).strip().splitlines()
    return lines[-1][:300] if lines else type(error).__name__


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
                   "</tr>" for a, b, _ in pair.runs)
    title = f"{pair.task}: {pair.first} and {pair.second}"
    return f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>{html.escape(title)}</title>
<style>body {{ font-family: sans-serif; margin: 1em; }} table {{ border-collapse: collapse; width: 100%; }}
td, th {{ vertical-align: top; border-bottom: 1px solid #ccc; padding: 0.3em; text-align: left; }}
pre {{ margin: 0; white-space: pre-wrap; background: #fff8e1; font-size: 0.85em; }}</style></head><body>
<h1>{html.escape(title)}</h1>
<p>{pair.first_share} % of {html.escape(pair.first)}'s own code is found in {html.escape(pair.second)}'s file, and
{pair.second_share} % the other way; the matched code spans {pair.lines[0]} of {html.escape(pair.first)}'s lines and
{pair.lines[1]} of {html.escape(pair.second)}'s. Names,
layout, comments and the order of functions may differ: the copy finder compares the files' syntax trees. What every
student got in the stub, and what many students' files share, is left out. The matching parts, in
{html.escape(pair.first)}'s order:</p>
<table><tr><th>{html.escape(pair.first)}</th><th>{html.escape(pair.second)}</th></tr>{rows}</table>
</body></html>
"""
