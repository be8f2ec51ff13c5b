"""The GIL is released while the solver runs: Python threads go on, and
two solves on two threads take clearly less than twice one."""

import json
import os
import subprocess
import sys
import textwrap
import threading
import time

import cyclorub
from conftest import small_case


def test_python_threads_run_while_a_case_solves():
    case = small_case()
    done = threading.Event()
    counted = []

    def count():
        n = 0
        while not done.is_set():
            n += 1
        counted.append(n)

    worker = threading.Thread(target=count)
    clock = time.perf_counter()
    worker.start()
    try:
        case.run(stability=False, progress=False)
    finally:
        done.set()
        worker.join()
    elapsed = time.perf_counter() - clock
    # Holding the GIL, the solve would leave the counter a few switch
    # intervals (5 ms each) of the run; released, it counts all along:
    # at least a million a second on any machine that runs the suite.
    assert counted[0] > 2e5 * elapsed, (counted, elapsed)


# Measured in a fresh interpreter with one rayon thread, so that each
# solve uses one core and two solves can use two. On a shared machine the
# load comes and goes: rounds of (one solve, two concurrent solves), and
# the best of each.
SCRIPT = textwrap.dedent("""
    import json, sys, threading, time
    sys.path.insert(0, {tests!r})
    from conftest import small_case
    case = small_case()
    def one():
        case.run(stability=False, progress=False)
    one()  # warm up
    singles, pairs = [], []
    for _ in range(3):
        clock = time.perf_counter(); one(); singles.append(time.perf_counter() - clock)
        threads = [threading.Thread(target=one) for _ in range(2)]
        clock = time.perf_counter()
        for t in threads: t.start()
        for t in threads: t.join()
        pairs.append(time.perf_counter() - clock)
    print(json.dumps({{"one": min(singles), "two_concurrent": min(pairs)}}))
""")


def test_two_cases_on_two_threads_take_less_than_twice_one():
    tests = os.path.dirname(os.path.abspath(__file__))
    env = dict(os.environ, RAYON_NUM_THREADS="1")
    ratios = []
    for _ in range(3):  # the load of a shared machine comes and goes
        out = subprocess.run([sys.executable, "-c", SCRIPT.format(tests=tests)],
                             env=env, check=True, capture_output=True, text=True)
        times = json.loads(out.stdout.strip().splitlines()[-1])
        ratios.append(times["two_concurrent"] / times["one"])
        print(f"one solve {times['one']:.3f} s, two on two threads "
              f"{times['two_concurrent']:.3f} s: {ratios[-1]:.2f}x")
        if ratios[-1] < 1.6:
            break
    # Serialized by the GIL it would be 2x; released, about 1x on 2 cores.
    assert min(ratios) < 1.6, f"two concurrent solves took {ratios} x one (GIL held?)"
