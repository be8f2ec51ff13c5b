"""Runs: the branch equals the command line's, the arrays are those of
the results files, a saved folder loads back, Ctrl-C keeps the points."""

import csv
import json
import os
import signal
import subprocess
import threading
import time

import numpy as np
import pytest

import cyclorub
from conftest import small_case


def read_branch_csv(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    sectors = [k for k in rows[0] if k.startswith("amplitude_sector_")]
    frequency = np.array([float(r["frequency_hz"]) for r in rows])
    amplitude = np.array([[float(r[k]) for k in sectors] for r in rows])
    iterations = np.array([int(r["iterations"]) for r in rows])
    return frequency, amplitude, iterations


def test_the_default_branch_equals_the_command_lines(default_result, cli, tmp_path):
    output = tmp_path / "cli"
    subprocess.run([cli, "run", "--no-stability", "--output", str(output)],
                   check=True, capture_output=True, cwd=tmp_path)
    frequency, amplitude, iterations = read_branch_csv(output / "branch.csv")
    assert len(frequency) == len(default_result) > 100
    # branch.csv prints 13 significant digits.
    np.testing.assert_allclose(default_result.frequency_hz, frequency, rtol=1e-12, atol=0)
    np.testing.assert_allclose(default_result.amplitude, amplitude, rtol=1e-12, atol=0)
    np.testing.assert_array_equal(default_result.iterations, iterations)


def test_save_writes_the_folder_of_the_command_line(default_result, tmp_path):
    folder = tmp_path / "saved"
    default_result.save(folder)
    for name in ("branch.csv", "results.h5", "run.json", "plots"):
        assert (folder / name).exists(), name
    # The CSV of harmonics is written on demand ([output] harmonics_csv).
    assert not (folder / "observed_harmonics.csv").exists()
    frequency, amplitude, _ = read_branch_csv(folder / "branch.csv")
    np.testing.assert_allclose(default_result.frequency_hz, frequency, rtol=1e-12, atol=0)
    np.testing.assert_allclose(default_result.amplitude, amplitude, rtol=1e-12, atol=0)
    run = json.loads((folder / "run.json").read_text())
    assert run["stop"] == default_result.stop_reason
    assert run["basis"] == default_result.basis


def test_a_folder_holding_a_run_is_replaced_only_when_asked(default_result, tmp_path):
    folder = tmp_path / "saved"
    default_result.save(folder)
    with pytest.raises(cyclorub.InputError) as caught:
        default_result.save(folder)
    assert caught.value.key == "output.directory"
    # Issue 45 item 22: Python's switch, not the command's flags.
    assert "overwrite=True" in caught.value.message
    assert "--overwrite" not in caught.value.message
    default_result.save(folder, overwrite=True)
    assert (folder / "run.json").exists()


def test_a_saved_folder_loads_back_with_every_array(default_result, tmp_path):
    folder = tmp_path / "saved"
    default_result.save(folder)
    loaded = cyclorub.load(folder)
    assert len(loaded) == len(default_result)
    assert not loaded.interrupted
    # The stop in the library's words, as the solved result says it.
    assert loaded.stop == default_result.stop
    assert loaded.stop_reason == default_result.stop_reason
    for name in ("frequency_hz", "unknowns", "amplitude", "max_abs", "observed",
                 "contact_fraction", "peak_force", "forward",
                 "backward", "sectors_in_contact", "iterations", "converged"):
        np.testing.assert_array_equal(getattr(loaded, name), getattr(default_result, name),
                                      err_msg=name)
    # Not stored by default ([output] contact_harmonics): recovered from the
    # unknowns at the frequency read back.
    np.testing.assert_allclose(loaded.contact_force, default_result.contact_force,
                               rtol=1e-12, atol=1e-15)
    assert loaded.case.to_dict() == default_result.case.to_dict()
    assert loaded.basis == default_result.basis
    # recover rebuilds the problem from the case in results.h5.
    a = loaded.recover(dof=3, sector=5)
    b = default_result.recover(dof=3, sector=5)
    np.testing.assert_allclose(a["coordinates"], b["coordinates"], rtol=1e-12, atol=1e-20)
    copy = tmp_path / "copy"
    loaded.save(copy)
    assert (copy / "results.h5").exists()


def test_the_arrays_have_the_documented_shapes(default_result):
    r = default_result
    p, n, nh = len(r), 24, 10
    assert r.frequency_hz.shape == (p,)
    assert r.amplitude.shape == (p, n)
    assert r.observed.shape == (p, n, 2 * nh + 1)
    assert r.unknowns.shape == (p, r.basis["unknowns"])
    assert r.contact_fraction.shape == (p, n, 1)
    assert r.contact_force.shape == (p, n, 1, 2 * nh + 1)
    assert r.forward.shape == r.backward.shape == (p, nh + 1, n // 2 + 1)
    assert r.converged.all() and r.converged.dtype == bool
    assert r.stop_reason["reason"] == "end_reached"
    assert r.stability is None, "not asked"
    # A traveling wave: every sector has the same amplitude (up to the
    # sampling of the period, each sector's crest falling elsewhere).
    np.testing.assert_allclose(r.amplitude, r.amplitude[:, :1].repeat(n, axis=1), rtol=1e-6)
    # The traveling wave h = 1 is backward on harmonic 1, nodal diameter 1.
    peak = int(np.argmax(r.amplitude[:, 0]))
    assert r.backward[peak, 1, 1] > 100 * r.forward[peak, 1, 1]
    assert r.sectors_in_contact.max() == 24
    assert 0 < r.contact_fraction.max() < 1
    table = r.table()
    assert len(table["frequency_hz"]) == p


def test_recover_gives_the_observed_dof_and_the_others(default_result):
    r = default_result
    observed = r.recover(dof=1, sector=1)
    np.testing.assert_allclose(observed["coordinates"], r.observed[:, 0, :], rtol=1e-12, atol=0)
    np.testing.assert_allclose(observed["peak"], r.amplitude[:, 0], rtol=1e-9)
    assert observed["displacement"].shape == (len(r), 10000)
    fewer = r.recover(dof=4, sector=2, time_samples=64)
    assert fewer["displacement"].shape == (len(r), 64)
    assert np.all(np.abs(fewer["coordinates"]) < np.abs(observed["coordinates"]).max())


def test_the_linear_response_and_natural_frequencies(default_result):
    frequency, amplitude = default_result.linear_response()
    assert amplitude.shape == (len(frequency), 24)
    assert amplitude.max() > default_result.amplitude.max(), "the casing limits the response"
    diameters, natural = default_result.natural_frequencies()
    np.testing.assert_allclose(natural, cyclorub.Case.default().modes()[1])


def test_fixed_frequencies_and_another_basis():
    case = cyclorub.Case.default()
    at = [120.0, 125.0, 130.0]
    symmetry = case.run(at_hz=at, stability=False, progress=False)
    paper = case.run(at_hz=np.array(at), basis="nodal_diameter", stability=False, progress=False)
    np.testing.assert_allclose(symmetry.frequency_hz, at)
    assert paper.basis["kind"] == "nodal_diameter"
    assert paper.basis["unknowns"] > symmetry.basis["unknowns"]
    np.testing.assert_allclose(paper.amplitude, symmetry.amplitude, rtol=1e-8)


def test_the_stability_check_gives_arrays_per_point():
    case = cyclorub.Case.default()
    result = case.run(at_hz=[110.0, 127.0], stability=True, stability_harmonics=3,
                      progress=False)
    s = result.stability
    assert s is not None and s["harmonics"] == 3
    assert s["stable"].shape == (2,) and s["unstable_exponents"].shape == (2,)
    assert s["leading_re"].shape[:2] == (2, len(s["classes"]))
    assert isinstance(result.markers, list)


def test_progress_reaches_the_callback():
    seen = []
    small_case().run(stability=False, progress=lambda *p: seen.append(p))
    assert seen and seen[-1][0] > seen[0][0], "points counted up"


def interrupted_run(case, during_callback):
    """`case` run with Ctrl-C (SIGINT) at its 20th point or the first
    progress report past it: raised inside the progress callback, or sent
    by another thread so that it lands between two callbacks or in one."""
    def progress(points, frequency_hz, step):
        if points >= 20 and not progress.sent:
            progress.sent = True
            if during_callback:
                signal.raise_signal(signal.SIGINT)
            else:
                threading.Thread(
                    target=lambda: os.kill(os.getpid(), signal.SIGINT)).start()
    progress.sent = False
    # Python ignores SIGINT when it starts with it ignored (a background
    # job of a non-interactive shell): Ctrl-C's own handler, for the test.
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        return case.run(stability=False, progress=progress)
    finally:
        signal.signal(signal.SIGINT, previous)


@pytest.mark.parametrize("during_callback", [True, False])
def test_ctrl_c_returns_the_points_computed(recwarn, during_callback):
    case = small_case()
    full = case.run(stability=False, progress=False)
    partial = interrupted_run(case, during_callback)
    assert partial.interrupted
    assert 0 < len(partial) < len(full)
    assert partial.stop_reason["reason"] == "interrupted"
    n = len(partial)
    np.testing.assert_array_equal(partial.frequency_hz, full.frequency_hz[:n])
    assert any("interrupted" in str(w.message) for w in recwarn)


def test_the_python_call_costs_under_5_percent_of_the_solve():
    # The wall time of Case.run beyond the library's own set-up and solve
    # (the worker thread, the 50 ms polling, the wrappers): the best of
    # three, so that the load of a shared machine does not count.
    case = cyclorub.Case.default()
    ratios = []
    for _ in range(3):
        clock = time.perf_counter()
        result = case.run(stability=False, progress=False)
        wall = time.perf_counter() - clock
        inside = result.timings["setup_s"] + result.timings["solve_s"]
        ratios.append((wall - inside) / inside)
    assert min(ratios) < 0.05, ratios


def test_the_result_says_what_it_is(default_result):
    r = default_result
    assert len(r) == len(r.frequency_hz)
    assert "points" in repr(r) and "symmetry" in repr(r)
    kinds = {e.get("kind") for e in r.events if isinstance(e, dict)}
    assert r.events and kinds, r.events[:3]
    assert r.case.continuation.start_hz is not None, "the range resolved"
    assert r.markers == []
    assert r.directory is None and not r.interrupted
    assert r.timings["solve_s"] > 0
