"""billiard.sweep: many independent runs (a parameter grid times seeds) in parallel, on Dask.

One simulation is sequential; an ensemble (an equation of state over densities and seeds, a
curve averaged over many starts) is many independent runs. ``sweep`` sends each run to a Dask
worker process and gathers one record per run: the parameters, the seed, what the run returned
and how long it took, or why it failed. The engine holds Python's GIL while it runs, so the
workers are processes with one thread each.
"""

import ast
import inspect
import itertools
import logging
import math
import multiprocessing
import numbers
import os
import sys
import time
import traceback

# Columns that sweep itself writes in every record; a parameter or a result may not take them.
RESERVED_COLUMNS = ("seed", "run_time", "error", "traceback")
# The column of a result that is not a dict.
RESULT_COLUMN = "result"
# How long to wait for the scheduler at a given address before calling it unreachable.
CONNECT_TIMEOUT = "10s"
# Dask is needed only when sweep runs on workers; without it, this says what to install.
NO_DASK = ("billiard.sweep needs Dask: install Debian's python3-dask and python3-distributed "
           "(or pass workers=0 to run in this process)")
# The local cluster's housekeeping, relaxed: a run holds Python's lock through each engine
# call, so the workers' statistical profiler (every 10 ms) samples nothing of use, and it, the
# 20 ms tick and the memory monitor only wake up on cores the runs need. A client passed to
# sweep keeps its own settings.
LOCAL_CLUSTER_CONFIG = {
    # One run at a time on a worker of one thread, none waiting there, in a sweep of many runs (Dask
    # queues only large groups): a run that kills its worker (a crash in compiled code) then takes
    # few others down with it, and those go again alone.
    "distributed.scheduler.worker-saturation": 1.0,
    "distributed.worker.profile.enabled": False,
    "distributed.admin.tick.interval": "1s",
    "distributed.worker.memory.monitor-interval": "1s",
    "distributed.admin.system-monitor.interval": "5s",
}
# The progress line is rewritten at most this often (seconds), so that a notebook's output stays small.
PROGRESS_INTERVAL = 0.5


def sweep(run, grid, seeds=1, client=None, *, workers=None, quiet=False, as_frame=None):
    """Runs ``run(**parameters, seed=seed)`` for every point of ``grid`` and every seed, in
    parallel, and returns one record per run.

    run: a function that builds and runs a Simulation and returns a number, an array, or a dict
        of them (each key becomes a column). It must depend on its arguments only: then the
        numbers do not depend on where or in which order the runs ran. It travels to the workers
        with the tasks: a function (or lambda) of the calling script or notebook whole, one of a
        module by its name, so that module must be importable there.
    grid: the parameters. A dict {name: list of values} runs the Cartesian product of the lists
        (the first name varies slowest); a list of dicts runs each dict as one point (all with the
        same names). Names are passed to ``run`` as keyword arguments.
    seeds: a count n (seeds 0, 1, ..., n - 1) or a list of distinct non-negative integers. Each
        point runs once per seed, the seed passed to ``run`` as ``seed=``.
    client: None (default) starts a local Dask cluster of ``workers`` processes with one thread
        each, and closes it at the end: no set-up, no server. A scheduler's address such as
        "tcp://host:8786" or a ``dask.distributed.Client`` runs on that cluster instead (its workers
        must be able to import billiard and whatever ``run`` imports). An address where no
        scheduler answers within 10 s is a ValueError.
    workers: the number of local worker processes (default: the cores this process may use, at
        most one per run). 0 runs everything in this process, one run after the other, without
        Dask: for debugging, or where no processes can be started.
    quiet: False shows a progress line on stderr while the runs run.
    as_frame: None returns a pandas DataFrame when pandas is installed and a list of dicts
        otherwise; True or False asks for one of them.

    Returns the records in grid order (points in order, and the seeds of each point in order),
    whatever order they finished in. Each record has the parameters, "seed", the results (a dict's
    keys, or "result"), "run_time" (seconds of that run) and "error" and "traceback": None when
    the run returned, else the exception's type and message and its traceback as text, with the
    results None. A failed run never stops the others; a summary of the failures goes to stderr.

    Arguments are checked before anything starts: a wrong type is a TypeError and a wrong value a
    ValueError, each naming the argument.

    Call it from a script only under ``if __name__ == "__main__":``: the local worker processes
    import the script, and would otherwise start sweeps of their own (a call outside that guard
    is a RuntimeError).
    """
    points = _points(grid)
    seed_list = _seeds(seeds)
    _check_run(run, points[0], seed_list[0])
    _check_options(client, workers, quiet, as_frame)

    tasks = [(point, seed) for point in points for seed in seed_list]
    progress = _Progress(len(tasks), quiet)
    if client is None and workers == 0:
        outcomes = []
        for point, seed in tasks:
            outcomes.append(_run_one(run, point, seed))
            progress.update(1, outcomes[-1][2] is not None)
    else:
        outcomes = _run_on_dask(run, tasks, client, workers, progress)
    progress.finish()

    records = _records(tasks, outcomes)
    failed = [r for r in records if r["error"] is not None]
    if failed and not quiet:
        first = failed[0]
        shown = ", ".join(f"{name}={first[name]!r}" for name in points[0])
        print(f"sweep: {len(failed)} of {len(records)} runs failed (their records have the error); "
              f"the first: {shown}, seed={first['seed']}: {first['error']}", file=sys.stderr)
    return _table(records, as_frame)


def _points(grid):
    """The grid as a list of dicts of parameters, in order; TypeError/ValueError naming `grid`."""
    if isinstance(grid, dict):
        if not grid:
            raise ValueError("grid: empty dict; give {name: [values, ...]} with at least one name")
        names = list(grid)
        _check_names(names, "grid")
        columns = []
        for name in names:
            values = grid[name]
            try:
                if isinstance(values, (str, bytes, dict)):
                    raise TypeError
                values = list(values)
            except TypeError:  # not iterable, or iterable by accident (a string, a 0-d array)
                raise TypeError(f"grid[{name!r}]: expected a list of values, got {type(values).__name__} "
                                f"{values!r}") from None
            if not values:
                raise ValueError(f"grid[{name!r}]: no values; give at least one")
            columns.append(values)
        return [dict(zip(names, combination)) for combination in itertools.product(*columns)]
    if isinstance(grid, (list, tuple)):
        if not grid:
            raise ValueError("grid: empty list; give at least one dict of parameters")
        names = None
        for k, point in enumerate(grid):
            if not isinstance(point, dict):
                raise TypeError(f"grid[{k}]: expected a dict of parameters, got {type(point).__name__}")
            if names is None:
                names = list(point)
                _check_names(names, f"grid[{k}]")
            elif set(point) != set(names):
                raise ValueError(f"grid[{k}]: names {sorted(point)} differ from grid[0]'s {sorted(names)}; "
                                 "every point needs the same names")
        return [{name: point[name] for name in names} for point in grid]
    raise TypeError(f"grid: expected a dict {{name: [values]}} or a list of dicts, got {type(grid).__name__}")


def _check_names(names, where):
    for name in names:
        if not isinstance(name, str) or not name.isidentifier():
            raise ValueError(f"{where}: parameter name {name!r} is not a Python identifier "
                             "(names are passed to run as keyword arguments)")
        if name in RESERVED_COLUMNS:
            raise ValueError(f"{where}: parameter name {name!r} is one of sweep's own columns "
                             f"{', '.join(RESERVED_COLUMNS)}; rename it")


def _seeds(seeds):
    """The seeds as a list of ints; TypeError/ValueError naming `seeds`."""
    if isinstance(seeds, numbers.Integral) and not isinstance(seeds, bool):
        if seeds < 1:
            raise ValueError(f"seeds: a count must be at least 1, got {seeds}")
        return list(range(int(seeds)))
    if isinstance(seeds, (str, bytes, dict)) or not hasattr(seeds, "__iter__"):
        raise TypeError(f"seeds: expected a count or a list of integers, got {type(seeds).__name__} {seeds!r}")
    seed_list = list(seeds)
    if not seed_list:
        raise ValueError("seeds: empty list; give a count or at least one seed")
    for seed in seed_list:
        if not isinstance(seed, numbers.Integral) or isinstance(seed, bool):
            raise TypeError(f"seeds: expected integers, got {type(seed).__name__} {seed!r}")
        if seed < 0:
            raise ValueError(f"seeds: must be >= 0, got {seed}")
    if len(set(seed_list)) != len(seed_list):
        repeated = next(s for s in seed_list if seed_list.count(s) > 1)
        raise ValueError(f"seeds: {repeated} appears more than once (it would repeat the same runs)")
    return [int(seed) for seed in seed_list]


def _check_run(run, point, seed):
    if not callable(run):
        raise TypeError(f"run: expected a function of the parameters and seed, got {type(run).__name__}")
    try:
        signature = inspect.signature(run)
    except (TypeError, ValueError):  # some built-in callables have none: they fail per run instead
        return
    try:
        signature.bind(**point, seed=seed)
    except TypeError as error:
        raise TypeError(f"run: cannot be called as run({', '.join(point)}, seed=...): {error}") from None


def _check_options(client, workers, quiet, as_frame):
    if client is not None:
        if isinstance(client, str):
            if "://" not in client and ":" not in client:
                raise ValueError(f"client: {client!r} is not a scheduler address; give one like \"tcp://host:8786\"")
        elif not (hasattr(client, "submit") and hasattr(client, "scheduler")):
            hint = "; for a cluster object, pass its scheduler_address" if hasattr(client, "scheduler_address") else ""
            raise TypeError(f"client: expected None, a scheduler address (\"tcp://host:8786\") or a "
                            f"dask.distributed.Client, got {type(client).__name__}{hint}")
        elif getattr(client, "status", "running") != "running":
            raise ValueError(f"client: the given Client is {client.status}, not running")
        if workers is not None:
            raise ValueError("workers: applies to the local cluster only; leave it out with a client")
    elif workers is not None:
        if not isinstance(workers, numbers.Integral) or isinstance(workers, bool):
            raise TypeError(f"workers: expected a number of processes, got {type(workers).__name__} {workers!r}")
        if workers < 0:
            raise ValueError(f"workers: must be >= 0 (0 runs in this process), got {workers}")
    if not isinstance(quiet, bool):
        raise TypeError(f"quiet: expected True or False, got {quiet!r}")
    if as_frame not in (None, True, False):
        raise TypeError(f"as_frame: expected None, True or False, got {as_frame!r}")
    if as_frame:
        try:
            import pandas  # noqa: F401
        except ImportError:
            raise ValueError("as_frame: True needs pandas, which is not installed; "
                             "use as_frame=False for a list of dicts") from None


def _refuse_unguarded_script():
    """RuntimeError when the call comes from a script's top level outside ``if __name__ ==
    "__main__":``: each worker process imports the script, and would start workers of its own."""
    main = sys.modules.get("__main__")
    path = getattr(main, "__file__", None)
    if not path or not str(path).endswith(".py"):
        return  # an interactive session or a notebook: nothing to import again
    frame = sys._getframe(1)
    while frame is not None and not (frame.f_code.co_name == "<module>" and frame.f_globals is vars(main)):
        frame = frame.f_back
    if frame is None:
        return
    try:
        with open(path, encoding="utf-8") as file:
            tree = ast.parse(file.read())
    except (OSError, SyntaxError, ValueError):
        return
    line = frame.f_lineno
    for node in tree.body:
        if isinstance(node, ast.If) and _is_main_test(node.test) and node.lineno <= line <= node.end_lineno:
            return
    raise RuntimeError(f"billiard: starting local worker processes from the top level of {path} (line {line}); "
                       "they import the script, so put the call under `if __name__ == \"__main__\":`")


def _forget_unreadable_main_file():
    """A script read on standard input (``python3 - < script.py``) has the file name "<stdin>",
    which a local worker process, started by multiprocessing's spawn, would run as the caller's
    script: it fails, and Dask starts it again without end. Without a file name the workers start
    as they do for ``python3 -c`` (the runs reach them by value, as cloudpickle sends functions of
    ``__main__``)."""
    main = sys.modules.get("__main__")
    path = getattr(main, "__file__", None)
    if isinstance(path, str) and path.startswith("<") and path.endswith(">"):
        del main.__file__


def _is_main_test(test):
    if not (isinstance(test, ast.Compare) and len(test.ops) == 1 and isinstance(test.ops[0], ast.Eq)):
        return False
    sides = [test.left, test.comparators[0]]
    return (any(isinstance(side, ast.Name) and side.id == "__name__" for side in sides)
            and any(isinstance(side, ast.Constant) and side.value == "__main__" for side in sides))


def _refuse_inside_worker_start():
    # A worker process starts by importing the caller's script (multiprocessing's spawn marks the
    # process as "inheriting" meanwhile); a sweep at the script's top level would start there
    # again, and again in its workers.
    if getattr(multiprocessing.current_process(), "_inheriting", False):
        raise RuntimeError("billiard: local workers started while a worker process imports the script; "
                           "start them under `if __name__ == \"__main__\":` in scripts")


def _run_one(run, point, seed):
    """One run, in whichever process: (results, seconds, error, traceback text)."""
    clock = time.perf_counter()
    try:
        results = run(**point, seed=seed)
    except (Exception, SystemExit) as error:  # reported in the record: one failed run never stops the others
        seconds = time.perf_counter() - clock
        frames = traceback.extract_tb(error.__traceback__)[1:]  # leave out this function's frame
        text = "".join(traceback.format_list(frames)) + "".join(traceback.format_exception_only(error))
        return None, seconds, _one_line(error), text
    return results, time.perf_counter() - clock, None, None


def _one_line(error):
    message = str(error).strip().splitlines()
    return f"{type(error).__name__}: {message[0]}" if message else type(error).__name__


def _run_on_dask(run, tasks, client, workers, progress):
    try:
        from distributed import Client, as_completed
    except ImportError:
        raise ImportError(NO_DASK) from None
    own_client = None
    try:
        if client is None:
            client = own_client = local_client(min(workers or _usable_cores(), len(tasks)))
        elif isinstance(client, str):
            address = client
            try:
                client = own_client = Client(address, timeout=CONNECT_TIMEOUT)
            except (OSError, TimeoutError, ValueError) as error:
                raise ValueError(f"client: no Dask scheduler answers at {address!r} ({error}); start one with "
                                 "`dask scheduler` and workers with `dask worker ADDRESS`") from None
        futures = [client.submit(_run_one, run, point, seed, pure=False) for point, seed in tasks]
        try:
            outcomes = _gather(futures, as_completed, progress, count_lost=False)
            # A run whose worker died beside a run that crashed it is lost with it (Dask gives up on
            # every run that was on a worker as often as it died); each lost run goes again alone,
            # so that only a run that kills its worker on its own is reported as lost.
            for k, outcome in enumerate(outcomes):
                if outcome is LOST:
                    futures[k:k + 1] = [client.submit(_run_one, run, *tasks[k], pure=False)]
                    outcomes[k] = _gather(futures[k:k + 1], as_completed, progress, count_lost=True)[0]
            return outcomes
        except BaseException:  # an interrupt: the runs not done yet must not go on on a shared cluster
            client.cancel(futures)
            raise
    finally:
        if own_client is not None:
            own_client.close()  # and the local cluster it started


LOST = object()  # a run whose worker died, not yet run again alone


def _gather(futures, as_completed, progress, count_lost):
    """The outcome of each future, in the futures' order, as they finish; a run whose worker died
    (a crash in the run, memory) more often than Dask retries is LOST unless count_lost."""
    index = {future.key: k for k, future in enumerate(futures)}
    outcomes = [None] * len(futures)
    for future in as_completed(futures):
        k = index[future.key]
        if future.status == "finished":
            outcomes[k] = future.result()
        else:
            error = future.exception()
            killed = type(error).__name__ == "KilledWorker"
            if killed and not count_lost:
                outcomes[k] = LOST
                future.release()
                continue
            lost = "worker lost: " if killed else ""
            outcomes[k] = (None, math.nan, lost + _one_line(error), "".join(traceback.format_exception_only(error)))
        future.release()
        progress.update(1, outcomes[k][2] is not None)
    return outcomes


def local_client(workers=None):
    """A dask.distributed Client on a new local cluster of `workers` processes (default: the cores
    this process may use) with one thread each, the cluster sweep starts by default. Several
    sweeps with ``client=`` this share one start of the workers (seconds: each imports Python,
    Dask and numpy); close it, or use it in a ``with`` block, to stop the workers."""
    if workers is not None and (not isinstance(workers, numbers.Integral) or isinstance(workers, bool)):
        raise TypeError(f"workers: expected a number of processes, got {type(workers).__name__} {workers!r}")
    if workers is not None and workers < 1:
        raise ValueError(f"workers: must be >= 1, got {workers}")
    _refuse_inside_worker_start()
    _refuse_unguarded_script()
    _forget_unreadable_main_file()
    try:
        import dask
        from distributed import Client
    except ImportError:
        raise ImportError(NO_DASK) from None
    # A Client given no address starts its own LocalCluster and closes it with itself; the
    # scheduler and the worker processes take the configuration in force when they start.
    with dask.config.set(LOCAL_CLUSTER_CONFIG):
        return Client(n_workers=workers or _usable_cores(), threads_per_worker=1, processes=True,
                      dashboard_address=":0", silence_logs=logging.ERROR)  # any free port: never a clash


def _usable_cores():
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:
        return os.cpu_count() or 1


def _records(tasks, outcomes):
    """One dict per run with the same keys in every record (None where a run had no such result)."""
    taken = set(tasks[0][0]) | set(RESERVED_COLUMNS)
    result_names = []
    for results, _, error, _ in outcomes:
        if error is None:
            names = list(results) if isinstance(results, dict) else [RESULT_COLUMN]
            result_names += [name for name in names
                             if isinstance(name, str) and name not in taken and name not in result_names]
    records = []
    for (point, seed), (results, seconds, error, trace) in zip(tasks, outcomes):
        record = dict(point)
        record["seed"] = seed
        if error is None and not isinstance(results, dict):
            results = {RESULT_COLUMN: results}
        if error is None:
            clash = [name for name in results if not isinstance(name, str) or name in taken]
            if clash:
                error = (f"ValueError: run returned the key {clash[0]!r}, which is not a string or is a "
                         "parameter's or sweep's own column; rename it")
                results, trace = None, None
        for name in result_names:
            record[name] = results.get(name) if error is None else None
        record["run_time"] = seconds
        record["error"] = error
        record["traceback"] = trace
        records.append(record)
    return records


def _table(records, as_frame):
    if as_frame is False:
        return records
    try:
        import pandas
    except ImportError:
        return records  # as_frame=True was checked before the runs
    return pandas.DataFrame.from_records(records, columns=list(records[0]))


class _Progress:
    """A one-line progress report on stderr, rewritten in place: runs done, failures, time."""

    def __init__(self, total, quiet):
        self.total, self.quiet = total, quiet
        # Rewriting a line works in a terminal and in Jupyter; elsewhere (a log file) only the
        # final line is written.
        self.live = "ipykernel" in sys.modules or (hasattr(sys.stderr, "isatty") and sys.stderr.isatty())
        self.done = self.failed = 0
        self.start = self.shown = time.perf_counter()
        self.width = 0

    def update(self, done, failed):
        self.done += done
        self.failed += int(failed)
        now = time.perf_counter()
        if self.live and now - self.shown >= PROGRESS_INTERVAL and self.done < self.total:
            self.shown = now
            self._show("\r")

    def finish(self):
        self._show("\r")
        if not self.quiet:
            sys.stderr.write("\n")
            sys.stderr.flush()

    def _show(self, start):
        if self.quiet:
            return
        failed = f", {self.failed} failed" if self.failed else ""
        line = (f"sweep: {self.done}/{self.total} runs done{failed}, "
                f"{time.perf_counter() - self.start:.1f} s")
        sys.stderr.write(start + line.ljust(self.width))
        sys.stderr.flush()
        self.width = len(line)
