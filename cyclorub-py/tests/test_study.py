"""Studies: many runs over an executor equal the same runs one after the
other, on a local process pool and on a Dask LocalCluster."""

from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pandas as pd
import pytest

import cyclorub


def engine_order_cases():
    """A small study on the default case, each run short (N_h = 5,
    N_t = 2400, 0.1 s): engine orders 1 and 3, and h = 1 at half the force.
    (Other engine orders of this window run into the point cap.)"""
    base = cyclorub.Case.default().replace({"harmonic_balance.harmonics": 5,
                                            "harmonic_balance.time_samples": 2400,
                                            "continuation.max_points": 1000})
    return {"h=1": base,
            "h=3": base.replace({"excitation.engine_order": 3}),
            "h=1, 2 N": base.replace({"excitation.amplitude": 2.0})}


def serial(cases):
    return {label: case.run(stability=False, progress=False) for label, case in cases.items()}


def assert_equal_to_serial(table, expected):
    assert list(table["label"]) == list(expected)
    for _, row in table.iterrows():
        result = expected[row["label"]]
        assert row["error"] is None
        assert row["points"] == len(result)
        np.testing.assert_array_equal(row["frequency_hz"], result.frequency_hz)
        np.testing.assert_array_equal(row["amplitude"], result.amplitude)
        assert row["peak_amplitude_m"] == result.amplitude.max()


@pytest.fixture(scope="module")
def expected():
    return serial(engine_order_cases())


def test_the_default_executor_is_a_process_pool(expected):
    table = cyclorub.study(engine_order_cases(), max_workers=2)
    assert isinstance(table, pd.DataFrame)
    assert_equal_to_serial(table, expected)
    assert list(table["engine_order"]) == [1, 3, 1]
    assert table["finished"].all()


def test_a_thread_pool_and_a_list_of_cases(expected):
    cases = list(engine_order_cases().values())
    with ThreadPoolExecutor(2) as pool:
        table = cyclorub.study(cases, pool)
    assert list(table["label"]) == [0, 1, 2]
    for row, result in zip(table.itertuples(), expected.values()):
        np.testing.assert_array_equal(row.amplitude, result.amplitude)


def test_a_refused_case_is_a_row_with_its_error():
    bad = cyclorub.Case.default()
    bad.casing.gap = -1.0
    with ThreadPoolExecutor(1) as pool:
        table = cyclorub.study({"bad": bad}, pool)
    assert "casing.gap" in table.loc[0, "error"]


def test_without_pandas_the_rows_are_dicts(monkeypatch, expected):
    import builtins

    real_import = builtins.__import__

    def no_pandas(name, *args, **kwargs):
        if name == "pandas":
            raise ImportError("no pandas here")
        return real_import(name, *args, **kwargs)

    monkeypatch.setattr(builtins, "__import__", no_pandas)
    with ThreadPoolExecutor(1) as pool:
        rows = cyclorub.study({"h=1": engine_order_cases()["h=1"]}, pool)
    assert isinstance(rows, list) and rows[0]["label"] == "h=1"
    np.testing.assert_array_equal(rows[0]["amplitude"], expected["h=1"].amplitude)


def test_a_dask_local_cluster_with_two_workers(expected):
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        table = cyclorub.study(engine_order_cases(), client.get_executor())
        workers = client.run(lambda: __import__("os").getpid())
    assert len(workers) == 2
    assert_equal_to_serial(table, expected)


def test_workers_that_return_freed_memory_at_once_give_the_same_rows(expected, monkeypatch):
    """Dask's workers start with ``MALLOC_TRIM_THRESHOLD_=65536``; a study
    keeps the solver's scratch memory in the heap for each run there (see
    ``_solver_scratch_kept``) and gives the same curves bit for bit."""
    monkeypatch.setenv("MALLOC_TRIM_THRESHOLD_", "65536")
    table = cyclorub.study(engine_order_cases(), max_workers=2)
    assert_equal_to_serial(table, expected)


class FakeLibc:
    """Records the calls ``_solver_scratch_kept`` makes."""

    def __init__(self):
        self.calls = []

    def mallopt(self, parameter, value):
        self.calls.append(("mallopt", parameter, value))
        return 1

    def malloc_trim(self, pad):
        self.calls.append(("malloc_trim", pad))
        return 1


def test_scratch_kept_sets_the_thresholds_for_a_run_and_restores_the_environment_s(monkeypatch):
    """With the trim threshold in the environment: the mmap and trim
    thresholds raised before the run, the environment's (and glibc's
    128 KiB mmap threshold) back after it, then the heap trimmed; without
    the variable, or with a value that is not an integer, no call."""
    from cyclorub import _study

    fake = FakeLibc()
    monkeypatch.setattr(_study, "_glibc", lambda: fake)
    monkeypatch.delenv("MALLOC_MMAP_THRESHOLD_", raising=False)
    monkeypatch.setenv("MALLOC_TRIM_THRESHOLD_", "65536")
    with _study._solver_scratch_kept():
        assert fake.calls == [("mallopt", -3, 32 << 20), ("mallopt", -1, 64 << 20)]
    assert fake.calls[2:] == [("mallopt", -3, 128 << 10), ("mallopt", -1, 65536),
                              ("malloc_trim", 0)]
    for environ in [None, "a lot"]:
        fake.calls.clear()
        if environ is None:
            monkeypatch.delenv("MALLOC_TRIM_THRESHOLD_")
        else:
            monkeypatch.setenv("MALLOC_TRIM_THRESHOLD_", environ)
        with _study._solver_scratch_kept():
            pass
        assert fake.calls == []
