"""billiard.sweep: a parameter grid times seeds on Dask worker processes. The runs on a real
local cluster (two worker processes started here, nothing mocked) give exactly the numbers of
the same sweep run one after the other in this process; a run that fails, or kills its worker,
is reported in its own record while the others return; bad arguments are refused, naming the
argument, before any run starts. The DataFrame form is tested only where pandas is installed
(it is optional): without pandas those tests are skipped and say so."""

import logging
import os
import time
import subprocess
import sys

import dask
import numpy as np
import pytest
from distributed import Client, LocalCluster

import billiard
from billiard._sweep import LOCAL_CLUSTER_CONFIG

GRID = {"eta": [0.1, 0.4], "n": [30, 60]}
SEEDS = [0, 7, 11]


def gas_run(eta, n, seed):
    """A small periodic gas: its virial sum, time and final positions depend on every collision,
    so any difference between two runs of the same (eta, n, seed) shows."""
    side = np.sqrt(n * np.pi / eta)
    sim = billiard.Simulation(billiard.periodic_box(side, side))
    sim.add_random_discs(n, 1.0, kT=1.0, seed=seed)
    sim.advance(events=50 * n)
    return {"virial": sim.totals["virial"], "time": sim.time, "positions": sim.current_state["position"]}


def failing_run(eta, n, seed):
    if eta > 0.3 and seed == 7:
        raise ZeroDivisionError(f"no run at eta={eta}")
    return eta * n + seed


def crashing_run(x, seed):
    if x == 2:
        os._exit(3)  # the worker process dies, as in a crash of compiled code
    time.sleep(0.1)  # the other runs still wait on the worker when it dies
    return x + seed


def unused_run(x, seed):
    raise AssertionError("a run started although the arguments were wrong")


@pytest.fixture(scope="module")
def cluster():
    # The scheduler's setting of sweep's own local clusters, read when the scheduler starts; and a
    # worker's first death gives up on every run that was on it (Dask's default waits for three),
    # so that a crashing run takes its neighbours down every time, not by chance.
    saturation = "distributed.scheduler.worker-saturation"
    with dask.config.set({saturation: LOCAL_CLUSTER_CONFIG[saturation], "distributed.scheduler.allowed-failures": 0}):
        local = LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0",
                             silence_logs=logging.ERROR)
    with local:
        yield local


@pytest.fixture(scope="module")
def client(cluster):
    with Client(cluster) as connected:
        yield connected


def assert_same_numbers(first, second):
    assert len(first) == len(second)
    for a, b in zip(first, second):
        assert (a["eta"], a["n"], a["seed"]) == (b["eta"], b["n"], b["seed"])
        assert a["error"] is None and b["error"] is None, (a["error"], b["error"])
        assert a["virial"] == b["virial"] and a["time"] == b["time"]  # exact, not approximate
        np.testing.assert_array_equal(a["positions"], b["positions"])


@pytest.fixture(scope="module")
def serial():
    return billiard.sweep(gas_run, GRID, seeds=SEEDS, workers=0, quiet=True, as_frame=False)


def test_serial_records_in_grid_order(serial):
    assert [(r["eta"], r["n"], r["seed"]) for r in serial] == [
        (eta, n, seed) for eta in GRID["eta"] for n in GRID["n"] for seed in SEEDS]
    assert list(serial[0]) == ["eta", "n", "seed", "virial", "time", "positions", "run_time", "error", "traceback"]
    for record in serial:
        assert record["virial"] > 0 and record["run_time"] > 0 and record["traceback"] is None
    # different seeds are different runs
    assert len({r["virial"] for r in serial}) == len(serial)


def test_two_workers_give_the_serial_numbers(client, serial):
    parallel = billiard.sweep(gas_run, GRID, seeds=SEEDS, client=client, quiet=True, as_frame=False)
    assert_same_numbers(parallel, serial)
    assert len(client.scheduler_info()["workers"]) == 2


def test_scheduler_address_gives_the_serial_numbers(cluster, serial):
    parallel = billiard.sweep(gas_run, GRID, seeds=SEEDS, client=cluster.scheduler_address, quiet=True,
                              as_frame=False)
    assert_same_numbers(parallel, serial)


def test_default_local_cluster_gives_the_serial_numbers(serial):
    points = [{"eta": 0.4, "n": 60}, {"eta": 0.1, "n": 30}]
    parallel = billiard.sweep(gas_run, points, seeds=SEEDS[:2], workers=2, quiet=True, as_frame=False)
    expected = [r for point in points for r in serial if r["eta"] == point["eta"] and r["n"] == point["n"]
                and r["seed"] in SEEDS[:2]]
    assert_same_numbers(parallel, expected)


def worker_housekeeping():
    import dask
    return {key: dask.config.get(key) for key in billiard._sweep.LOCAL_CLUSTER_CONFIG}


def test_local_client_relaxes_housekeeping_in_its_workers_only():
    before = worker_housekeeping()
    with billiard.local_client(1) as client:
        seen = client.run(worker_housekeeping)
    assert list(seen.values()) == [billiard._sweep.LOCAL_CLUSTER_CONFIG], "the worker did not take the settings"
    assert worker_housekeeping() == before, "the calling process's Dask configuration changed"
    assert before["distributed.worker.profile.enabled"] is True  # Dask's default: the test can tell


def test_failed_run_is_reported_with_its_parameters(client, capsys):
    records = billiard.sweep(failing_run, GRID, seeds=SEEDS, client=client, as_frame=False)
    failed = [r for r in records if r["error"] is not None]
    assert [(r["eta"], r["n"], r["seed"]) for r in failed] == [(0.4, 30, 7), (0.4, 60, 7)]
    assert failed[0]["error"] == "ZeroDivisionError: no run at eta=0.4"
    assert "failing_run" in failed[0]["traceback"] and failed[0]["result"] is None
    for record in records:
        if record["error"] is None:
            assert record["result"] == record["eta"] * record["n"] + record["seed"]
    stderr = capsys.readouterr().err
    assert "sweep: 12/12 runs done, 2 failed" in stderr
    assert "2 of 12 runs failed" in stderr and "eta=0.4, n=30, seed=7" in stderr


def test_killed_worker_is_reported_and_the_others_return(client):
    # Dask gives up on every run that was on the worker when it died; those innocent runs must still
    # return (eight of them beside the crash, so that some share its worker).
    records = billiard.sweep(crashing_run, {"x": range(1, 10)}, seeds=1, client=client, quiet=True, as_frame=False)
    assert [r["result"] for r in records] == [1, None, *range(3, 10)]
    assert records[1]["error"].startswith("worker lost: KilledWorker")
    assert all(r["error"] is None for k, r in enumerate(records) if k != 1)


def test_lambda_with_closure_travels_to_the_workers(client):
    offset = 0.25
    records = billiard.sweep(lambda x, seed: x * 10 + seed + offset, [{"x": 1}, {"x": 2}], seeds=[3, 5],
                             client=client, quiet=True, as_frame=False)
    assert [r["result"] for r in records] == [13.25, 15.25, 23.25, 25.25]


def test_exit_in_a_run_is_reported_as_its_error():
    def leaving(x, seed):
        if x == 1:
            raise SystemExit(4)
        return x

    records = billiard.sweep(leaving, {"x": [0, 1, 2]}, workers=0, quiet=True, as_frame=False)
    assert [r["result"] for r in records] == [0, None, 2]
    assert records[1]["error"] == "SystemExit: 4"


def test_failed_run_in_this_process():
    records = billiard.sweep(failing_run, GRID, seeds=SEEDS, workers=0, quiet=True, as_frame=False)
    assert sum(r["error"] is not None for r in records) == 2


def test_quiet_prints_nothing(capsys):
    billiard.sweep(failing_run, {"eta": [0.1], "n": [1]}, seeds=2, workers=0, quiet=True)
    assert capsys.readouterr().err == ""


def test_result_key_that_clashes_is_an_error_of_that_run():
    def clash(eta, seed):
        return {"eta": 1.0} if seed else {"value": 2.0}

    records = billiard.sweep(clash, {"eta": [0.5]}, seeds=2, workers=0, quiet=True, as_frame=False)
    assert records[0]["value"] == 2.0 and records[0]["error"] is None
    assert "'eta'" in records[1]["error"] and records[1]["value"] is None and records[1]["eta"] == 0.5


@pytest.mark.parametrize("arguments, error, named", [
    (dict(run=42), TypeError, "run"),
    (dict(run=lambda eta: eta), TypeError, "run"),            # takes no seed
    (dict(run=lambda x, seed: x), TypeError, "run"),          # no parameter eta
    (dict(grid={}), ValueError, "grid"),
    (dict(grid=[]), ValueError, "grid"),
    (dict(grid={"eta": []}), ValueError, "grid['eta']"),
    (dict(grid={"eta": 0.5}), TypeError, "grid['eta']"),
    (dict(grid={"eta": "0.5"}), TypeError, "grid['eta']"),
    (dict(grid={"eta": np.array(0.5)}), TypeError, "grid['eta']"),
    (dict(grid={"seed": [1]}), ValueError, "grid"),
    (dict(grid={"not a name": [1]}), ValueError, "grid"),
    (dict(grid=[{"eta": 1}, {"n": 2}]), ValueError, "grid[1]"),
    (dict(grid=[0.5]), TypeError, "grid[0]"),
    (dict(grid=0.5), TypeError, "grid"),
    (dict(seeds=0), ValueError, "seeds"),
    (dict(seeds=-3), ValueError, "seeds"),
    (dict(seeds=[]), ValueError, "seeds"),
    (dict(seeds=[1, 1]), ValueError, "seeds"),
    (dict(seeds=[-1]), ValueError, "seeds"),
    (dict(seeds=[0.5]), TypeError, "seeds"),
    (dict(seeds=2.0), TypeError, "seeds"),
    (dict(seeds=True), TypeError, "seeds"),
    (dict(seeds="3"), TypeError, "seeds"),
    (dict(client=8786), TypeError, "client"),
    (dict(client="localhost"), ValueError, "client"),
    (dict(client="tcp://127.0.0.1:8786", workers=2), ValueError, "workers"),
    (dict(workers=-1), ValueError, "workers"),
    (dict(workers=1.5), TypeError, "workers"),
    (dict(quiet="no"), TypeError, "quiet"),
    (dict(as_frame="yes"), TypeError, "as_frame"),
])
def test_bad_arguments_are_refused_before_any_run(arguments, error, named):
    call = dict(run=unused_run, grid={"x": [1, 2]}, seeds=2)
    if "grid" in arguments and "run" not in arguments:
        call["run"] = lambda seed, **parameters: None
    if "run" in arguments:
        call["grid"] = {"eta": [0.5]}
    call.update(arguments)
    with pytest.raises(error, match=r"^" + named.replace("[", r"\[").replace("]", r"\]")):
        billiard.sweep(**call)


def test_cluster_object_is_refused_with_a_hint(cluster):
    with pytest.raises(TypeError, match="^client: .*LocalCluster; for a cluster object, pass its scheduler_address"):
        billiard.sweep(unused_run, {"x": [1]}, client=cluster)


def test_closed_client_is_refused(cluster):
    closed = Client(cluster)
    closed.close()
    with pytest.raises(ValueError, match="^client"):
        billiard.sweep(unused_run, {"x": [1]}, client=closed)


def test_dataframe_when_pandas_is_installed(serial):
    pandas = pytest.importorskip("pandas", reason="pandas is optional and not installed: the DataFrame form is untested")
    table = billiard.sweep(gas_run, GRID, seeds=SEEDS, workers=0, quiet=True)
    assert isinstance(table, pandas.DataFrame)
    assert list(table.columns) == list(serial[0])
    assert table["virial"].tolist() == [r["virial"] for r in serial]
    assert table.groupby("eta")["virial"].count().tolist() == [6, 6]


def test_records_without_pandas_asked_for():
    records = billiard.sweep(failing_run, {"eta": [0.1], "n": [2]}, seeds=1, workers=0, quiet=True, as_frame=False)
    assert records == [{"eta": 0.1, "n": 2, "seed": 0, "result": 0.2, "run_time": records[0]["run_time"],
                        "error": None, "traceback": None}]


def test_without_pandas_a_list_and_as_frame_true_is_refused(monkeypatch):
    monkeypatch.setitem(sys.modules, "pandas", None)  # import pandas fails, as where it is not installed
    records = billiard.sweep(failing_run, {"eta": [0.1], "n": [2]}, seeds=2, workers=0, quiet=True)
    assert isinstance(records, list) and [r["seed"] for r in records] == [0, 1]
    with pytest.raises(ValueError, match="^as_frame"):
        billiard.sweep(unused_run, {"x": [1]}, workers=0, as_frame=True)


def test_script_without_main_guard_is_refused_before_workers_start(tmp_path):
    # Its workers would import the script and start workers of their own, without end.
    script = tmp_path / "unguarded.py"
    script.write_text("import billiard\n\n\ndef run(x, seed):\n    return x\n\n\n"
                      "billiard.sweep(run, {'x': [1, 2]}, workers=2)\n")
    done = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=120)
    assert done.returncode == 1
    assert "RuntimeError: billiard: starting local worker processes from the top level of" in done.stderr
    assert 'put the call under `if __name__ == "__main__":`' in done.stderr


@pytest.mark.parametrize("way", ["stdin", "-c"])
def test_a_script_on_standard_input_or_the_command_line_runs_on_local_workers(way):
    # Local workers start by running the caller's script by its file name; "<stdin>" names none.
    script = ("import billiard\n\n\ndef run(x, seed):\n    return {'twice': 2 * x}\n\n\n"
              "print(sorted(r['twice'] for r in billiard.sweep(run, {'x': [1, 2, 3]}, workers=2, quiet=True)))\n")
    command = [sys.executable, "-"] if way == "stdin" else [sys.executable, "-c", script]
    done = subprocess.run(command, input=script if way == "stdin" else None, capture_output=True, text=True,
                          timeout=120)
    assert done.returncode == 0, done.stderr[-3000:]
    assert done.stdout.strip().splitlines()[-1] == "[2, 4, 6]"
