"""The cost of calling the solver from Python on the default case: the
wall time of `Case.run` against the library's own set-up and solve times
(what `cyclorub run` reports), and the first access to the arrays (the
per-point recovery on every sector, the CLI's output stage).

    python bench/call_overhead.py [repeats]
"""

import statistics
import sys
import time

import cyclorub


def main(repeats=7):
    case = cyclorub.Case.default()
    case.run(stability=False, progress=False)  # warm up
    overheads, solves, recoveries = [], [], []
    for _ in range(repeats):
        clock = time.perf_counter()
        result = case.run(stability=False, progress=False)
        wall = time.perf_counter() - clock
        inside = result.timings["setup_s"] + result.timings["solve_s"]
        overheads.append(wall - inside)
        solves.append(inside)
        clock = time.perf_counter()
        result.amplitude
        recoveries.append(time.perf_counter() - clock)
    solve = statistics.median(solves)
    overhead = statistics.median(overheads)
    print(f"default case, {len(result)} points, {repeats} runs (medians):")
    print(f"  set-up + solve in the library  {solve * 1e3:8.2f} ms")
    print(f"  Case.run wall minus that       {overhead * 1e3:8.3f} ms  "
          f"({100 * overhead / solve:.2f} % of the solve)")
    print(f"  first array access (recovery)  {statistics.median(recoveries) * 1e3:8.2f} ms")
    return overhead / solve


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 7)
