"""A mistuning study on a Dask cluster (issue 44): mistuned patterns of a
wheel, each solved on a worker, their amplification factors in a table
(CSV) and their distribution as a figure (SVG), against the tuned wheel's
1 and Whitehead's bound (1 + √N)/2.

    pip install "dask[distributed]" pandas
    python mistuning_study.py [output folder] [--contact] [--patterns N]

By default the wheel is the paper's academic one on N = 6 sectors, linear
(the casing 1 m away: a linear study is where Whitehead's bound holds),
with 1 % blade stiffness scatter, 20 patterns; every pattern and its tuned
reference are solved at the same 240 frequencies across the first family
(0.1 to 0.3 s a pattern). With ``--contact`` it is the default case
itself (N = 24, the casing 1 mm away, R-HBM, N_h = 10), 100 patterns, at
90 frequencies up the first family's contact plateau (124 to 133 Hz): a
sweep up, each frequency from the last, a sheet's end passed along the
branch or by a jump to where Newton from the linear response lands.
"""

import argparse
import time
from pathlib import Path

import numpy as np
from distributed import Client, LocalCluster

import cyclorub

if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("output", nargs="?", default="mistuning_study")
    parser.add_argument("--contact", action="store_true",
                        help="the default case with its casing (N = 24)")
    parser.add_argument("--patterns", type=int, default=None,
                        help="how many patterns (20, or 100 with --contact)")
    arguments = parser.parse_args()
    output = Path(arguments.output)
    output.mkdir(parents=True, exist_ok=True)

    # %% The tuned wheel, and the frequencies every pattern is solved at.
    if arguments.contact:
        case = cyclorub.Case.default()
        frequencies = np.round(np.arange(124.0, 133.0, 0.1), 6)
        count = arguments.patterns or 100
    else:
        case = cyclorub.Case.default().replace({
            "model.sectors": 6,
            "harmonic_balance.harmonics": 1,
            "harmonic_balance.time_samples": 96,
            "casing.gap": 1.0,
        })
        frequencies = np.arange(204.0, 216.0, 0.05)
        count = arguments.patterns or 20
    sectors = case.get("model.sectors")

    # %% The patterns (seeds 1 to count, 1 % standard deviation) on a local
    # cluster of two worker processes; on a real cluster give the
    # scheduler's address to Client instead.
    with LocalCluster(n_workers=2, threads_per_worker=1, dashboard_address=None) as cluster, \
            Client(cluster) as client:
        clock = time.perf_counter()
        table = cyclorub.mistuning_study(case, count, standard_deviation=0.01, seed=1,
                                         executor=client.get_executor(),
                                         at_hz=frequencies, progress=True)
        elapsed = time.perf_counter() - clock

    # %% The table: one row per pattern (its seed as label).
    columns = ["label", "amplification_factor", "largest_sector_peak_m",
               "most_responding_sector", "tuned_peak_m", "unconverged_points", "solve_s"]
    print(table[columns].to_string(index=False))
    deviations = np.stack(table["deviations"].to_numpy())
    flat = table[columns].copy()
    for j in range(deviations.shape[1]):
        flat[f"deviation_sector_{j + 1}"] = deviations[:, j]
    flat.to_csv(output / "mistuning_study.csv", index=False)

    # %% The distribution of the amplification factors, over the patterns
    # solved at every frequency (a sweep left unconverged somewhere has
    # read its peak over the others only).
    unfinished = table[~table["finished"]]
    if len(unfinished):
        print(f"{len(unfinished)} patterns left out, not converged at every frequency: "
              + ", ".join(f"{label} ({n} points)" for label, n in
                          zip(unfinished["label"], unfinished["unconverged_points"])))
    table = table[table["finished"]]
    written = cyclorub.amplification_figure(table, output / "amplification_factors.svg")
    factors = table["amplification_factor"]
    print(f"{count} patterns in {elapsed:.1f} s; over the {len(table)} solved at every "
          f"frequency, amplification factor "
          f"{factors.min():.3f} to {factors.max():.3f} (mean {factors.mean():.3f}), "
          f"Whitehead's bound {cyclorub.whitehead_bound(sectors):.3f}")
    print("wrote", output / "mistuning_study.csv", *written)
