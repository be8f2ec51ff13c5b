"""Mistuning studies (issue 44 item 5): patterns drawn from seeds, rows
equal to single runs of the same patterns, the pattern of zero deviations
at amplification factor 1, a process pool and a Dask LocalCluster, the
distribution figure; a mistuned result saved and loaded back through the
library's reader (issue 41 item 4)."""

import multiprocessing
from concurrent.futures import ProcessPoolExecutor

import numpy as np
import pytest

import cyclorub

# One frequency grid for every pattern and its tuned reference: the first
# family of the 6-sector wheel (208.7 to 212.1 Hz tuned) and around it.
FREQUENCIES = np.arange(204.0, 216.0, 0.05)


def small_wheel():
    """The default case on 6 sectors, linear (the casing 1 m away), one
    harmonic (96 instants, a multiple of N): about 0.1 s a run."""
    return cyclorub.Case.default().replace({
        "model.sectors": 6, "harmonic_balance.harmonics": 1,
        "harmonic_balance.time_samples": 96, "casing.gap": 1.0})


def single(case):
    return case.run(at_hz=FREQUENCIES, progress=False, stability=False)


@pytest.fixture(scope="module")
def pool_table():
    with ProcessPoolExecutor(2, mp_context=multiprocessing.get_context("spawn")) as pool:
        return cyclorub.mistuning_study(small_wheel(), 3, 0.01, seed=1, executor=pool,
                                        at_hz=FREQUENCIES)


def test_patterns_are_reproducible_from_the_seed_and_differ_between_seeds():
    a = cyclorub.mistuning_patterns(small_wheel(), 3, 0.01, seed=7)
    b = cyclorub.mistuning_patterns(small_wheel(), 3, 0.01, seed=7)
    assert list(a) == [7, 8, 9]
    drawn = {seed: case.mistuning_deviations() for seed, case in a.items()}
    for seed, case in b.items():
        np.testing.assert_array_equal(case.mistuning_deviations(), drawn[seed])
        assert case.basis.kind == "physical"
        assert case.mistuning.seed == seed and case.mistuning.standard_deviation == 0.01
    assert not np.array_equal(drawn[7], drawn[8]) and not np.array_equal(drawn[8], drawn[9])
    assert drawn[7].shape == (6,) and 0 < np.abs(drawn[7]).max() < 0.05
    np.testing.assert_array_equal(small_wheel().mistuned(0.01, seed=7).mistuning_deviations(),
                                  drawn[7])
    assert small_wheel().mistuning_deviations() is None
    # The standard deviation of many drawn deviations is the one asked for.
    many = small_wheel().replace({"model.sectors": 4000}).mistuned(0.01, seed=3)
    assert abs(np.std(many.mistuning_deviations()) - 0.01) < 5e-4


def test_the_rows_equal_single_runs_of_the_same_patterns(pool_table):
    assert list(pool_table["label"]) == [1, 2, 3]
    assert pool_table["error"].isna().all()
    tuned = single(small_wheel())
    for _, row in pool_table.iterrows():
        case = small_wheel().mistuned(0.01, seed=row["label"])
        result = single(case)
        record = result.mistuning
        assert abs(row["amplification_factor"] - record["amplification_factor"]) <= \
            1e-12 * record["amplification_factor"]
        np.testing.assert_array_equal(row["deviations"], case.mistuning_deviations())
        np.testing.assert_array_equal(row["deviations"], record["deviations"])
        np.testing.assert_allclose(row["sector_peaks_m"], record["sector_peaks_m"],
                                   rtol=1e-12, atol=0)
        assert row["most_responding_sector"] == record["most_responding_sector"]
        assert row["seed"] == row["label"] and row["standard_deviation"] == 0.01
        # Independently: the largest sector peak is the branch's largest
        # amplitude, the tuned peak the tuned wheel's (symmetry basis) on
        # the same grid, and their ratio the amplification factor.
        assert abs(row["largest_sector_peak_m"] - result.amplitude.max()) <= \
            1e-12 * result.amplitude.max()
        assert abs(row["tuned_peak_m"] - tuned.amplitude.max()) <= 1e-12 * tuned.amplitude.max()
        assert abs(row["amplification_factor"]
                   - result.amplitude.max() / tuned.amplitude.max()) <= 1e-12
        assert row["most_responding_sector"] == int(np.argmax(result.amplitude.max(axis=0))) + 1
        # A linear wheel stays under Whitehead's bound.
        assert 1.0 < row["amplification_factor"] < cyclorub.whitehead_bound(6)


def test_zero_deviations_give_an_amplification_factor_of_one():
    result = single(small_wheel().mistuned(deviations=[0.0] * 6))
    factor = result.mistuning["amplification_factor"]
    assert abs(factor - 1.0) < 1e-10, factor


def test_a_dask_local_cluster_gives_the_same_rows(pool_table):
    distributed = pytest.importorskip("distributed", reason="dask's distributed is not installed")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        table = cyclorub.mistuning_study(small_wheel(), 3, 0.01, seed=1,
                                         executor=client.get_executor(), at_hz=FREQUENCIES)
    np.testing.assert_array_equal(table["amplification_factor"],
                                  pool_table["amplification_factor"])


def test_the_distribution_figure_marks_the_tuned_value_and_whiteheads_bound(
        pool_table, tmp_path):
    assert cyclorub.whitehead_bound(24) == pytest.approx((1 + 24 ** 0.5) / 2, rel=1e-15)
    written = cyclorub.amplification_figure(pool_table, tmp_path / "plots" / "af.svg")
    assert [p.name for p in written] == ["af.svg"]
    svg = (tmp_path / "plots" / "af.svg").read_text()
    assert "Whitehead" in svg and "= 1.725" in svg and "tuned wheel: 1" in svg
    assert "of 3 patterns (N = 6)" in svg
    # A list of factors needs the number of sectors.
    with pytest.raises(cyclorub.InputError, match="sectors"):
        cyclorub.amplification_figure([1.1, 1.2], tmp_path / "b.svg")
    cyclorub.amplification_figure([1.1, 1.2], tmp_path / "b.svg", sectors=6)
    with pytest.raises(cyclorub.InputError, match="no finite amplification factor"):
        cyclorub.amplification_figure([float("nan")], tmp_path / "c.svg", sectors=6)


def test_a_saved_mistuned_result_loads_back_with_its_record(tmp_path):
    result = single(small_wheel().mistuned(0.01, seed=2))
    result.save(tmp_path / "saved")
    loaded = cyclorub.load(tmp_path / "saved")
    assert loaded.mistuning == result.mistuning
    assert loaded.stop == result.stop and loaded.timings["solve_s"] >= 0
    np.testing.assert_array_equal(loaded.amplitude, result.amplitude)
    assert loaded.case.mistuning.seed == 2
    # A tuned result has no mistuning record, solved or loaded.
    assert single(small_wheel()).mistuning is None
