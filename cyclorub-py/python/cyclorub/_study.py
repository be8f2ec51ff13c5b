"""Parameter studies: many independent runs over any
``concurrent.futures.Executor``.

Each case travels to its worker as TOML text (with its folder for
relative paths), is solved there, and comes back as one row of plain
values and numpy arrays: nothing of the solver crosses a process
boundary, so any executor works (a local process pool, Dask's
``Client.get_executor()``, MPI pools). A case whose model is inline
(the academic model, ``Case.from_matrices``) needs nothing else on the
workers; one that reads Matrix Market files needs its ``case_dir`` on a
filesystem the workers see.

Mistuning studies (issue 44): :func:`mistuning_patterns` makes ``count``
mistuned copies of one case (one seed each), :func:`mistuning_study` runs
them, its rows carrying each pattern's amplification factor, and
:func:`amplification_figure` draws their distribution against the tuned
wheel's 1 and Whitehead's bound (the library's SVG figures).
"""

import contextlib
import ctypes
import multiprocessing
import os
import sys
from collections.abc import Mapping
from concurrent.futures import ProcessPoolExecutor, as_completed

from . import _native
from ._errors import CyclorubError, InputError


# glibc's mallopt parameters (malloc.h).
_M_TRIM_THRESHOLD = -1
_M_MMAP_THRESHOLD = -3
# glibc's mmap threshold when the environment fixes the thresholds.
_GLIBC_MMAP_THRESHOLD = 128 * 1024
# For a run: the thresholds glibc's own dynamic ones settle at on 64 bits.
_KEPT_MMAP_THRESHOLD = 32 * 1024 * 1024
_KEPT_TRIM_THRESHOLD = 64 * 1024 * 1024


def _glibc():
    """The process's own C library when it is glibc (``mallopt`` and
    ``malloc_trim`` typed), else ``None``."""
    if not sys.platform.startswith("linux"):
        return None
    try:
        libc = ctypes.CDLL(None)
        libc.mallopt.argtypes = (ctypes.c_int, ctypes.c_int)
        libc.mallopt.restype = ctypes.c_int
        libc.malloc_trim.argtypes = (ctypes.c_size_t,)
        libc.malloc_trim.restype = ctypes.c_int
    except (OSError, AttributeError):
        return None
    return libc


@contextlib.contextmanager
def _solver_scratch_kept():
    """Keeps the solver's scratch memory in the worker's heap during a run.

    Dask's workers start with ``MALLOC_TRIM_THRESHOLD_=65536`` (freed
    memory goes back to the system at once), which also fixes glibc's mmap
    threshold at 128 KiB: every matrix of a solve above that (a
    504-unknown Jacobian is 2 MB) is then mapped afresh and page-faulted at
    each Newton iteration. On the default case mistuned at 1 %, 90
    frequencies: 1.26 million page faults and 14.8 s, against 46 thousand
    and 11.6 s with glibc's defaults. Where the environment fixes the trim
    threshold (set when the worker started, as Dask sets it), the run has
    the thresholds glibc's dynamic ones settle at (32 MiB, 64 MiB), then
    the environment's values (the mmap threshold's, or glibc's 128 KiB)
    come back and the heap is trimmed. Elsewhere (no such variable, a value
    that is not an integer, or no glibc): nothing.
    """
    try:
        trim = int(os.environ["MALLOC_TRIM_THRESHOLD_"], 0)
        mmap = int(os.environ.get("MALLOC_MMAP_THRESHOLD_", str(_GLIBC_MMAP_THRESHOLD)), 0)
    except (KeyError, ValueError):
        yield
        return
    libc = _glibc()
    if libc is None or libc.mallopt(_M_MMAP_THRESHOLD, _KEPT_MMAP_THRESHOLD) != 1:
        yield
        return
    libc.mallopt(_M_TRIM_THRESHOLD, _KEPT_TRIM_THRESHOLD)
    try:
        yield
    finally:
        libc.mallopt(_M_MMAP_THRESHOLD, mmap)
        libc.mallopt(_M_TRIM_THRESHOLD, trim)
        libc.malloc_trim(0)


def _run_one(label, toml_text, case_dir, basis, at_hz, stability):
    """One run of a study, in a worker: the row of the table."""
    with _solver_scratch_kept():
        return _row(label, toml_text, case_dir, basis, at_hz, stability)


def _row(label, toml_text, case_dir, basis, at_hz, stability):
    """The row of one run."""
    import numpy as np

    from . import _native
    from ._case import Case

    row = {"label": label}
    try:
        case = Case(_native.Case.from_toml(toml_text, f"<study case {label}>", case_dir))
        d = case.to_dict()
        row.update({
            "sectors": d["model"]["sectors"],
            "excitation": d["excitation"]["kind"],
            "engine_order": d["excitation"]["engine_order"],
            "force_n": d["excitation"]["amplitude"],
            "law": d["contact"]["law"],
            "gap_m": d["casing"]["gap"],
        })
        result = case.run(basis=basis, at_hz=at_hz, progress=False, stability=stability)
        frequency = result.frequency_hz
        amplitude = result.amplitude
        peak = amplitude.max(axis=1) if amplitude.size else np.zeros(0)
        best = int(np.argmax(peak)) if peak.size else None
        stop = result.stop_reason
        timings = result.timings
        unconverged = int(np.size(result.converged) - np.count_nonzero(result.converged))
        row.update({
            "basis": result.basis.get("kind"),
            "unknowns": result.basis.get("unknowns"),
            "points": len(result),
            "stop": stop.get("reason") if isinstance(stop, dict) else stop,
            # As `cyclorub study`: the whole range, every point converged.
            "finished": (stop.get("reason") if isinstance(stop, dict) else stop)
            in ("end_reached", "all_frequencies_done") and unconverged == 0,
            "unconverged_points": unconverged,
            "peak_amplitude_m": float(peak[best]) if best is not None else float("nan"),
            "peak_frequency_hz": float(frequency[best]) if best is not None else float("nan"),
            "solve_s": timings["solve_s"],
            "frequency_hz": frequency,
            "amplitude": amplitude,
            "error": None,
        })
        mistuning = result.mistuning
        if mistuning is not None:
            row.update(_mistuning_columns(d.get("mistuning", {}), mistuning))
    except CyclorubError as error:
        row["error"] = error.message
    return row


def _mistuning_columns(table, record):
    """The columns of a mistuned run: its ``[mistuning]`` keys and its
    record (``Result.mistuning``)."""
    import numpy as np

    def number(value):
        return float("nan") if value is None else float(value)

    peaks = np.array([number(p) for p in record["sector_peaks_m"]])
    return {
        "seed": table.get("seed"),
        "standard_deviation": table.get("standard_deviation"),
        "amplification_factor": number(record.get("amplification_factor")),
        # A sector with no peak is null (NaN); none at all: NaN, quietly.
        "largest_sector_peak_m": (
            float(np.nanmax(peaks)) if np.isfinite(peaks).any() else float("nan")
        ),
        "most_responding_sector": record["most_responding_sector"],
        "tuned_peak_m": number(record.get("tuned_peak_m")),
        "sector_peaks_m": peaks,
        "deviations": np.array(record["deviations"], dtype=float),
    }


def study(cases, executor=None, *, basis=None, at_hz=None, stability=False,
          max_workers=None, progress=False):
    """Runs many cases, each on a worker of ``executor``.

    - ``cases``: a list of :class:`cyclorub.Case` (labelled 0, 1, …) or a
      dict ``{label: case}``.
    - ``executor``: any ``concurrent.futures.Executor``; ``None`` makes a
      local process pool of ``max_workers`` processes (spawned, not forked:
      a fork would copy the solver's thread pools mid-flight) and shuts it
      down after. For a Dask cluster:
      ``distributed.Client(cluster).get_executor()``.
    - ``basis``, ``at_hz``, ``stability``: as in :meth:`Case.run`
      (stability off by default: a study wants curves).

    Returns one row per case, in the order given: ``label``, the case's
    ``sectors``, ``excitation``, ``engine_order``, ``force_n``, ``law``,
    ``gap_m``; the run's ``basis``, ``unknowns``, ``points``, ``stop``,
    ``finished`` (its whole range, every point converged, as
    ``cyclorub study`` says), ``unconverged_points``,
    ``peak_amplitude_m``, ``peak_frequency_hz`` (largest over
    sectors), ``solve_s``, the arrays ``frequency_hz`` ``[point]`` and
    ``amplitude`` ``[point, sector]``, and ``error`` (the library's message
    when a case was refused, else ``None``). A mistuned case's row adds
    its ``seed``, ``standard_deviation``, ``amplification_factor``,
    ``largest_sector_peak_m``, ``most_responding_sector`` (from 1),
    ``tuned_peak_m``, ``sector_peaks_m`` ``[sector]`` and ``deviations``
    ``[sector]`` (see ``Result.mistuning``). A pandas DataFrame when pandas
    is installed, else a list of dicts.

    ``progress=True`` writes ``k/n runs done`` on stderr as runs end.

    Where a worker's environment fixes glibc's trim threshold (Dask's
    workers do), each run keeps the solver's scratch memory in the heap
    and gives it back after (``_solver_scratch_kept``).
    """
    items = list(cases.items()) if isinstance(cases, Mapping) else list(enumerate(cases))
    tasks = [
        (label, case.to_toml(), os.fspath(case.case_dir), basis,
         None if at_hz is None else [float(f) for f in at_hz], stability)
        for label, case in items
    ]
    own = executor is None
    if own:
        executor = ProcessPoolExecutor(
            max_workers=max_workers, mp_context=multiprocessing.get_context("spawn"))
    try:
        futures = [executor.submit(_run_one, *task) for task in tasks]
        if progress:
            for done, _ in enumerate(as_completed(futures), start=1):
                sys.stderr.write(f"\rcyclorub study: {done}/{len(futures)} runs done   ")
                sys.stderr.flush()
            sys.stderr.write("\n")
        rows = [future.result() for future in futures]
    finally:
        if own:
            executor.shutdown()
    try:
        import pandas
    except ImportError:
        return rows
    return pandas.DataFrame(rows)


def mistuning_patterns(case, count, standard_deviation, seed=0, *, distribution=None):
    """``count`` mistuned copies of ``case`` (see :meth:`Case.mistuned`),
    as ``{seed: case}`` for the seeds ``seed``, ``seed + 1``, …: pattern
    ``k`` draws its deviations with standard deviation
    ``standard_deviation`` from seed ``seed + k`` (the same seeds, the same
    patterns, on every machine), from ``distribution`` (``"normal"`` or
    ``"uniform"``; default normal)."""
    if int(count) < 1:
        raise InputError(f"count = {count}: give at least one pattern", None, "usage")
    return {int(seed) + k: case.mistuned(standard_deviation, seed=int(seed) + k,
                                         distribution=distribution)
            for k in range(int(count))}


def mistuning_study(case, count, standard_deviation, seed=0, executor=None, *,
                    distribution=None, at_hz=None, max_workers=None, progress=False):
    """Runs :func:`mistuning_patterns` of ``case`` over ``executor`` (as
    :func:`study` does, on the physical full wheel): one row per pattern,
    labelled by its seed, with its ``amplification_factor`` and the other
    mistuning columns :func:`study` lists. ``at_hz``: solve every pattern
    (and its tuned reference) at these frequencies, so that all peaks are
    read on one frequency grid; without it each pattern's branch is
    followed by continuation."""
    patterns = mistuning_patterns(case, count, standard_deviation, seed,
                                  distribution=distribution)
    return study(patterns, executor, at_hz=at_hz, max_workers=max_workers,
                 progress=progress)


def whitehead_bound(sectors):
    """Whitehead's bound ``(1 + √N)/2`` on the amplification factor of a
    wheel of ``sectors`` sectors."""
    return _native.whitehead(int(sectors))


def amplification_figure(table, path, sectors=None, png=False):
    """Draws the distribution of a mistuning study's amplification factors
    into the SVG file ``path``: a histogram and the empirical cumulative
    distribution, with the tuned wheel's 1 and Whitehead's bound
    ``(1 + √N)/2`` marked; with ``png``, its PNG beside. ``table``: the
    study's table (DataFrame or list of rows; ``sectors`` is read from it)
    or a sequence of amplification factors (then give ``sectors``). Drawn
    by the library (plotters, as ``cyclorub run``'s figures): no plotting
    package needed. Returns the files written."""
    if hasattr(table, "to_dict"):  # a pandas DataFrame
        table = table.to_dict("records")
    rows = list(table)
    if rows and isinstance(rows[0], Mapping):
        factors = [r.get("amplification_factor") for r in rows]
        found = {r.get("sectors") for r in rows if r.get("sectors") is not None}
        if sectors is None and len(found) == 1:
            sectors = found.pop()
    else:
        factors = rows
    if sectors is None:
        raise InputError("sectors: give the number of sectors N (for Whitehead's bound)",
                         "sectors", "usage")
    factors = [float("nan") if f is None else float(f) for f in factors]
    return _native.amplification_figure(factors, int(sectors), os.fspath(path), bool(png))
