"""The bifurcated branches of a results folder from Python (issue 42):
`cyclorub run --branches` on the N = 6 chain (class-3 branch points near
211.247 and 212.354 Hz, 42 of the full wheel's 126 unknowns), then one of
them again with stability; `cyclorub.load` gives each branch point's record
and its sides as arrays equal to its CSV and to run.json's entry."""

import csv
import json
import subprocess

import numpy as np

import cyclorub

SIX_SECTORS = "[model]\nsectors = 6\n[excitation]\nengine_order = 2\n"


def read_sides(path):
    """A branch CSV's sides: ``{direction: (frequency [S], stable [S],
    sector amplitudes [S, N])}``, stable as 1, 0, −1 (empty cell)."""
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    sides = {}
    for row in rows:
        side = sides.setdefault(float(row["side"]), ([], [], []))
        side[0].append(float(row["frequency_hz"]))
        side[1].append({"stable": 1, "unstable": 0, "": -1}[row["stable"]])
        side[2].append([float(row[k]) for k in row if k.startswith("sector_")])
    return {d: tuple(np.array(a) for a in side) for d, side in sides.items()}


def check_against_the_files(folder):
    """Every branch of ``cyclorub.load(folder)`` against its CSV (printed
    to ten decimals of a Hz, eleven digits of a metre) and run.json's
    entry (the same doubles). Returns the branches."""
    branches = cyclorub.load(folder).branches
    recorded = json.loads((folder / "run.json").read_text())["branches"]
    assert len(branches) == len(recorded) == 2
    for branch, entry in zip(branches, recorded):
        for key in ("class", "marker", "marker_hz", "parent_point", "branch_point_hz",
                    "basis_unknowns", "full_unknowns", "file"):
            assert branch[key] == entry[key], key
        assert branch["not_switched"] is None
        assert (branch["class"], branch["basis_unknowns"], branch["full_unknowns"]) == (3, 42, 126)
        from_csv = read_sides(folder / branch["file"])
        assert [s["direction"] for s in branch["sides"]] == [1.0, -1.0]
        for side, summary in zip(branch["sides"], entry["sides"]):
            hz, stable, amplitude = side["frequency_hz"], side["stable"], side["sector_amplitude"]
            points = summary["points"]
            assert hz.shape == stable.shape == (points,) and amplitude.shape == (points, 6)
            assert side["direction"] == summary["direction"]
            assert side["stop"] == summary["stop"]
            assert side["stop_reason"] == summary["stop_reason"]
            assert (hz[0], hz[-1]) == (summary["from_hz"], summary["to_hz"])
            peak = np.unravel_index(np.argmax(amplitude), amplitude.shape)
            assert amplitude[peak] == summary["peak_amplitude_m"]
            assert (peak[1] + 1, hz[peak[0]]) == (summary["peak_sector"], summary["peak_hz"])
            checked = bool(np.all(stable >= 0))
            assert summary["unstable_points"] == (int(np.sum(stable == 0)) if checked else None)
            csv_hz, csv_stable, csv_amplitude = from_csv[side["direction"]]
            np.testing.assert_allclose(hz, csv_hz, rtol=0, atol=1e-10)
            np.testing.assert_array_equal(stable, csv_stable)
            np.testing.assert_allclose(amplitude, csv_amplitude, rtol=1e-10, atol=0)
    return branches


def test_the_branches_of_a_folder_equal_its_csv_and_run_json(cli, tmp_path):
    case = tmp_path / "case.toml"
    case.write_text(SIX_SECTORS)
    results = tmp_path / "results"
    subprocess.run([cli, "run", str(case), "--output", str(results), "--branches"],
                   check=True, capture_output=True, cwd=tmp_path)
    first = check_against_the_files(results)
    hz = [b["branch_point_hz"] for b in first]
    np.testing.assert_allclose(hz, [211.2471, 212.3540], rtol=0, atol=1e-3)
    for branch in first:
        for side in branch["sides"]:
            assert len(side["frequency_hz"]) > 100 and side["stop"]["reason"] == "rejoined"
            assert np.all(side["stable"] == -1)
    # The first again, short and with stability: replaced (now last).
    subprocess.run([cli, "branches", str(results), "--marker", str(first[0]["marker"]),
                    "--max-points", "3", "--stability"],
                   check=True, capture_output=True, cwd=tmp_path)
    again = check_against_the_files(results)
    assert again[1]["branch_point_hz"] == first[0]["branch_point_hz"]
    for side in again[1]["sides"]:
        assert side["frequency_hz"].shape == (3,) and np.all(side["stable"] >= 0)
    # A branch solved here has none (switching is `cyclorub branches`).
    assert cyclorub.Case.default().run(
        stability=False, progress=False, at_hz=[200.0]).branches == []
