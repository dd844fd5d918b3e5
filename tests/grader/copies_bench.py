#!/usr/bin/python3
"""How well the class grader's copy finder (similarity.py: Dolos) finds copies, side by side with
Debian 12's similarity tester (sim_c++ and sim_c, with the settings the class grader used before
Dolos), where that is installed.

    /usr/bin/python3 tests/grader/copies_bench.py [--class-size 300] [--seed 1]

First, each task's reference solution against copies of it hidden as a student would: every
local name renamed, the functions in another order, the comments replaced, all three at once,
and each mutant of the task so hidden (a copy with a bug of its own); and against solutions
written apart from it (tests/grader/tests/honest/), which must not be flagged. A pair is
compared alone, as in a small class. Then the time each finder takes for a class of
--class-size students in every task, files all different (the reference and its mutants,
hidden anew for each student).
"""

import argparse
import itertools
import random
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
REPO = HERE.parents[1]
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE / "tests"))
import similarity  # noqa: E402
from course import TASK_FILE, TASKS  # noqa: E402
from disguises import DISGUISES, hidden  # noqa: E402
from test_grader import mutant_source  # noqa: E402

class Sim:
    """Debian 12's similarity tester with the settings the class grader used before Dolos: the
    stub's lines blanked, runs of at least 24 tokens, flagged at 50 % of one file's own code and
    60 tokens in all."""
    name = "sim_c++/sim_c"
    TESTER = {".cpp": "sim_c++", ".c": "sim_c"}
    RUN_LINE = re.compile(r"^(?P<a>f\d+)\.\w+: line \d+-\d+\s*\|(?P<b>f\d+)\.\w+: line \d+-\d+\s*\[(?P<tokens>\d+)\]")
    FILE_LINE = re.compile(r"^File (?P<file>f\d+)\.\w+: (?P<tokens>\d+) tokens")

    @staticmethod
    def available():
        return all(shutil.which(tester) for tester in Sim.TESTER.values())

    @staticmethod
    def own_code(text, stub):
        import difflib
        lines, stub_lines = text.splitlines(), stub.splitlines()
        matcher = difflib.SequenceMatcher(None, [line.strip() for line in lines], [line.strip() for line in stub_lines],
                                          autojunk=False)
        for block in matcher.get_matching_blocks():
            for index in range(block.a, block.a + block.size):
                lines[index] = ""
        return "\n".join(lines) + "\n"

    @staticmethod
    def flagged(task, texts, stub):
        """{(a, b)} of the texts' indexes flagged."""
        suffix = Path(TASK_FILE[task]).suffix
        with tempfile.TemporaryDirectory(prefix="sim-") as folder:
            names = []
            for index, text in enumerate(texts):
                (Path(folder) / f"f{index}{suffix}").write_text(Sim.own_code(text, stub))
                names.append(f"f{index}{suffix}")
            done = subprocess.run([Sim.TESTER[suffix], "-e", "-s", "-n", "-r", "24", "-w", "200", *names], cwd=folder,
                                  stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, errors="replace", check=True)
        sizes, tokens = {}, {}
        for line in done.stdout.splitlines():
            if match := Sim.FILE_LINE.match(line):
                sizes[int(match["file"][1:])] = int(match["tokens"])
            elif (match := Sim.RUN_LINE.match(line)) and match["a"] != match["b"]:
                key = tuple(sorted((int(match["a"][1:]), int(match["b"][1:]))))
                tokens[key] = tokens.get(key, 0) + int(match["tokens"])
        return {key for key, count in tokens.items()
                if count >= 60 and max(100 * count / sizes[i] for i in key if sizes.get(i)) >= 50}


class Dolos:
    """The class grader's finder, similarity.py, as it flags."""
    name = "Dolos"

    @staticmethod
    def available():
        return similarity.finder_problem() is None

    @staticmethod
    def flagged(task, texts, stub):
        files = {str(index): text.encode() for index, text in enumerate(texts)}
        pairs, _ = similarity.compare_task(task, files, stub.encode())
        return {tuple(sorted((int(pair.first), int(pair.second)))) for pair in pairs}


def mutants_of(task):
    return sorted((REPO / "tests" / "mutants" / task).glob("*.mutant"))


def cases(rng):
    """[(task, kind, reference's text, other text, a copy?)]."""
    found = []
    for task in TASKS:
        reference = (REPO / "solutions" / TASK_FILE[task]).read_text()
        for kind, disguise in DISGUISES.items():
            found.append((task, kind, reference, disguise(reference, random.Random(rng.random())), True))
        for mutant in mutants_of(task):
            found.append((task, "a mutant, all three", reference, hidden(mutant_source(mutant), rng), True))
        honest = HERE / "tests" / "honest" / TASK_FILE[task]
        if honest.is_file():
            found.append((task, "written apart", reference, honest.read_text(), False))
    return found


def detection(finders, rng):
    print("Each pair alone: the reference solution and another file of its task, flagged?\n")
    results = {finder.name: {} for finder in finders}
    rows = cases(rng)
    for task, kind, reference, other, copy in rows:
        stub = (REPO / "tasks" / TASK_FILE[task]).read_text()
        for finder in finders:
            flagged = (0, 1) in finder.flagged(task, [reference, other], stub)
            results[finder.name].setdefault((kind, copy), []).append((task, flagged))
    kinds = sorted({(kind, copy) for _, kind, _, _, copy in rows}, key=lambda key: (not key[1], key[0]))
    print(f"{'kind of file':<28}" + "".join(f"{finder.name:>22}" for finder in finders))
    for kind, copy in kinds:
        label = f"{kind} ({'copies' if copy else 'not copies'})"
        cells = []
        for finder in finders:
            outcomes = results[finder.name][(kind, copy)]
            cells.append(f"{sum(flagged for _, flagged in outcomes)} of {len(outcomes)} flagged")
        print(f"{label:<28}" + "".join(f"{cell:>22}" for cell in cells))
    for finder in finders:
        missed = sorted({f"{task} ({kind})" for (kind, copy), outcomes in results[finder.name].items()
                         for task, flagged in outcomes if flagged != copy})
        print(f"{finder.name} misses or flags wrongly: {', '.join(missed) or 'nothing'}")
    print(f"(Dolos, as similarity.py runs it, flags no near-copy whose matched code is under "
          f"{similarity.FINGERPRINTS_FLAGGED} fingerprints: a task as small as init_velocities, whose copies and whose "
          "one natural way look alike, only by identical files)")


def class_time(finders, size, rng):
    print(f"\nA class of {size} students, every file different (the reference or a mutant, hidden anew). All of it is "
          "one solution hidden many ways, so Dolos, like MOSS, counts what more than a tenth of the files share as the "
          "class's own and flags nothing; sim, without such a discount, flags every pair:\n")
    print(f"{'task':<18}" + "".join(f"{finder.name + ' s':>18}{'flagged':>10}" for finder in finders))
    totals = {finder.name: 0.0 for finder in finders}
    for task in TASKS:
        sources = [(REPO / "solutions" / TASK_FILE[task]).read_text()] + [mutant_source(m) for m in mutants_of(task)]
        texts = [hidden(rng.choice(sources), rng) for _ in range(size)]
        stub = (REPO / "tasks" / TASK_FILE[task]).read_text()
        cells = ""
        for finder in finders:
            started = time.monotonic()
            flagged = finder.flagged(task, texts, stub)
            seconds = time.monotonic() - started
            totals[finder.name] += seconds
            cells += f"{seconds:>18.1f}{len(flagged):>10}"
        print(f"{task:<18}{cells}")
    print(f"{'all tasks':<18}" + "".join(f"{totals[finder.name]:>18.1f}{'':>10}" for finder in finders))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--class-size", type=int, default=300)
    parser.add_argument("--seed", type=int, default=1)
    arguments = parser.parse_args()
    finders = [finder for finder in (Dolos, Sim) if finder.available()]
    if Dolos not in finders:
        print(f"copies_bench: {similarity.finder_problem()}", file=sys.stderr)
        return 2
    if Sim not in finders:
        print("copies_bench: sim_c++ is not installed (Debian 12's similarity-tester): Dolos alone")
    detection(finders, random.Random(arguments.seed))
    class_time(finders, arguments.class_size, random.Random(arguments.seed))
    return 0


if __name__ == "__main__":
    sys.exit(main())
