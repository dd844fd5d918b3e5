#!/usr/bin/python3
"""Runs one notebook headless, as the test suite does, and keeps its figures.

    /usr/bin/python3 tests/notebooks/run_notebooks.py notebooks/02_energy_drift.ipynb \
        --figures build/release/figures [--timeout 600]

Executes every cell with nbclient (Debian's python3-nbclient) in the Jupyter kernel
"python3" (Debian's ipykernel, i.e. /usr/bin/python3), with the notebook's own folder as the
working directory and MPLBACKEND=Agg (no display needed; the notebooks switch to the inline
backend themselves, so their figures still arrive as PNG outputs). The notebook file is never
rewritten: the committed notebooks stay without outputs.

Exit status 0 when every cell ran; 1 when a cell raised (an assertion of the notebook, or any
error): the failing cell's number, source and error are printed. With --skip-missing-tasks (the
student's build), 77 (a skip, for CTest) when a cell needs a course task that is not written yet:
then only that task's one-line "not implemented yet" message is printed. With --figures OUTDIR every
image/png output is written, in order, as OUTDIR/<notebook stem>/figure-<k>.png (k from 1),
next to the executed notebook OUTDIR/<stem>/<stem>.ipynb, so that each figure can be looked at.
The last line is a summary: cells, figures and seconds.

The module `billiard` must be importable by /usr/bin/python3: PYTHONPATH=<build>/python (what
CTest sets) or the .pth file of ./build.sh python.
"""

import argparse
import base64
import os
import re
import sys
import time
from pathlib import Path

import nbformat
from nbclient import NotebookClient
from nbclient.exceptions import CellExecutionError, CellTimeoutError, DeadKernelError

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "grader"))
from course import NOT_WRITTEN  # noqa: E402  (the course's "task N (...) is not implemented yet")

ANSI_ESCAPE = re.compile(r"\x1b\[[0-9;]*[A-Za-z]")
SKIPPED = 77  # exit status: the notebook waits for a task (CTest's SKIP_RETURN_CODE)


def failing_cell(notebook):
    """The (index, cell, error output) of the first cell whose outputs hold an error, or None."""
    for index, cell in enumerate(notebook.cells):
        for output in cell.get("outputs", []):
            if output.get("output_type") == "error":
                return index, cell, output
    return None


def missing_task(notebook):
    """The "task N (...) is not implemented yet ..." message when that is why a cell failed, else ""."""
    found = failing_cell(notebook)
    if found is None:
        return ""
    _, _, output = found
    message = str(output.get("evalue", ""))
    if output.get("ename") == "NotImplementedError" and NOT_WRITTEN.match(message):
        return message
    return ""


def report_failure(notebook, path, exception):
    """Prints which cell failed and why, as plain text."""
    found = failing_cell(notebook)
    print(f"FAILED: {path}", file=sys.stderr)
    if found is None:  # a timeout or a dead kernel leaves no error output
        print(f"{type(exception).__name__}: {exception}", file=sys.stderr)
        return
    index, cell, output = found
    print(f"--- cell {index + 1} of {len(notebook.cells)} (counting text cells) ---", file=sys.stderr)
    print(cell.source, file=sys.stderr)
    print("--- error ---", file=sys.stderr)
    traceback = ANSI_ESCAPE.sub("", "\n".join(output.get("traceback", [])))
    print(traceback or f"{output.get('ename')}: {output.get('evalue')}", file=sys.stderr)


def save_figures(notebook, folder):
    """Writes every image/png output as folder/figure-<k>.png (k = 1, 2, ...); returns the count."""
    folder.mkdir(parents=True, exist_ok=True)
    for old in folder.glob("figure-*.png"):
        old.unlink()
    count = 0
    for cell in notebook.cells:
        for output in cell.get("outputs", []):
            png = output.get("data", {}).get("image/png")
            if png:
                count += 1
                (folder / f"figure-{count}.png").write_bytes(base64.b64decode(png))
    return count


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("notebook", type=Path, help="the .ipynb file to run")
    parser.add_argument("--figures", type=Path, metavar="OUTDIR",
                        help="write the PNG figures (and the executed notebook) to OUTDIR/<notebook stem>/")
    parser.add_argument("--timeout", type=float, default=600, help="seconds allowed per cell (default 600)")
    parser.add_argument("--skip-missing-tasks", action="store_true",
                        help="exit 77 with one line when a cell fails because a course task is not written yet")
    args = parser.parse_args(argv)

    path = args.notebook.resolve()
    notebook = nbformat.read(path, as_version=4)
    code_cells = sum(cell.cell_type == "code" for cell in notebook.cells)
    # The kernel inherits this environment: no GUI backend, whatever the machine has.
    os.environ["MPLBACKEND"] = "Agg"
    os.environ.setdefault("PYDEVD_DISABLE_FILE_VALIDATION", "1")  # quiets ipykernel's debugger on Python 3.11
    client = NotebookClient(notebook, timeout=int(args.timeout), kernel_name="python3", allow_errors=False,
                            resources={"metadata": {"path": str(path.parent)}})
    start = time.monotonic()
    status = 0
    try:
        client.execute()
    except (CellExecutionError, CellTimeoutError, DeadKernelError) as exception:
        missing = missing_task(notebook) if args.skip_missing_tasks else ""
        if missing:
            print(f"{path.name}: skipped: {missing}")
            return SKIPPED
        report_failure(notebook, path, exception)
        status = 1
    seconds = time.monotonic() - start

    figures = 0
    if args.figures is not None:
        folder = args.figures / path.stem
        figures = save_figures(notebook, folder)
        nbformat.write(notebook, folder / path.name)
    print(f"{path.name}: {'ok' if status == 0 else 'FAILED'}, {code_cells} code cells, {figures} figures, "
          f"{seconds:.1f} s" + (f" (figures in {args.figures / path.stem})" if args.figures is not None else ""))
    return status


if __name__ == "__main__":
    sys.exit(main())
