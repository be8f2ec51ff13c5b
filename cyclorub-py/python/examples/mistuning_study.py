"""A mistuning study on a Dask cluster (issue 44): 20 mistuned patterns of
a small wheel, each solved on a worker, their amplification factors in a
table (CSV) and their distribution as a figure (SVG), against the tuned
wheel's 1 and Whitehead's bound (1 + √N)/2.

    pip install "dask[distributed]" pandas
    python mistuning_study.py [output folder]

The wheel is the paper's academic one on N = 6 sectors, linear (the
casing 1 m away: a linear study is where Whitehead's bound holds), with
1 % blade stiffness scatter; every pattern and its tuned reference are
solved at the same 240 frequencies across the first family (0.1 to 0.3 s
a pattern). For a study with contact, bring the casing back
(`casing.gap = 1e-3`) and give the harmonics contact needs
(`harmonic_balance.harmonics = 5` or more): each pattern then takes
seconds to minutes (docs/design.md §12 says where the time goes).
"""

import sys
import time
from pathlib import Path

import numpy as np
from distributed import Client, LocalCluster

import cyclorub

if __name__ == "__main__":
    output = Path(sys.argv[1] if len(sys.argv) > 1 else "mistuning_study")
    output.mkdir(parents=True, exist_ok=True)

    # %% The tuned wheel, and the frequencies every pattern is solved at.
    case = cyclorub.Case.default().replace({
        "model.sectors": 6,
        "harmonic_balance.harmonics": 1,
        "harmonic_balance.time_samples": 96,
        "casing.gap": 1.0,
    })
    frequencies = np.arange(204.0, 216.0, 0.05)

    # %% 20 patterns (seeds 1 to 20, 1 % standard deviation) on a local
    # cluster of two worker processes; on a real cluster give the
    # scheduler's address to Client instead.
    with LocalCluster(n_workers=2, threads_per_worker=1, dashboard_address=None) as cluster, \
            Client(cluster) as client:
        clock = time.perf_counter()
        table = cyclorub.mistuning_study(case, 20, standard_deviation=0.01, seed=1,
                                         executor=client.get_executor(),
                                         at_hz=frequencies, progress=True)
        elapsed = time.perf_counter() - clock

    # %% The table: one row per pattern (its seed as label).
    columns = ["label", "amplification_factor", "largest_sector_peak_m",
               "most_responding_sector", "tuned_peak_m", "solve_s"]
    print(table[columns].to_string(index=False))
    deviations = np.stack(table["deviations"].to_numpy())
    flat = table[columns].copy()
    for j in range(deviations.shape[1]):
        flat[f"deviation_sector_{j + 1}"] = deviations[:, j]
    flat.to_csv(output / "mistuning_study.csv", index=False)

    # %% The distribution of the amplification factors.
    written = cyclorub.amplification_figure(table, output / "amplification_factors.svg")
    factors = table["amplification_factor"]
    print(f"{len(table)} patterns in {elapsed:.1f} s: amplification factor "
          f"{factors.min():.3f} to {factors.max():.3f} (mean {factors.mean():.3f}), "
          f"Whitehead's bound {cyclorub.whitehead_bound(6):.3f}")
    print("wrote", output / "mistuning_study.csv", *written)
