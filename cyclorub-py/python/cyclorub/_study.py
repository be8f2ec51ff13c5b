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
"""

import multiprocessing
import os
from collections.abc import Mapping
from concurrent.futures import ProcessPoolExecutor

from ._errors import CyclorubError


def _run_one(label, toml_text, case_dir, basis, at_hz, stability):
    """One run of a study, in a worker: the row of the table."""
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
        row.update({
            "basis": result.basis.get("kind"),
            "unknowns": result.basis.get("unknowns"),
            "points": len(result),
            "stop": stop.get("reason") if isinstance(stop, dict) else stop,
            "finished": (stop.get("reason") if isinstance(stop, dict) else stop)
            in ("end_reached", "all_frequencies_done"),
            "peak_amplitude_m": float(peak[best]) if best is not None else float("nan"),
            "peak_frequency_hz": float(frequency[best]) if best is not None else float("nan"),
            "solve_s": timings["solve_s"],
            "frequency_hz": frequency,
            "amplitude": amplitude,
            "error": None,
        })
    except CyclorubError as error:
        row["error"] = error.message
    return row


def study(cases, executor=None, *, basis=None, at_hz=None, stability=False,
          max_workers=None):
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
    ``finished``, ``peak_amplitude_m``, ``peak_frequency_hz`` (largest over
    sectors), ``solve_s``, the arrays ``frequency_hz`` ``[point]`` and
    ``amplitude`` ``[point, sector]``, and ``error`` (the library's message
    when a case was refused, else ``None``). A pandas DataFrame when pandas
    is installed, else a list of dicts.
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
        rows = [future.result() for future in futures]
    finally:
        if own:
            executor.shutdown()
    try:
        import pandas
    except ImportError:
        return rows
    return pandas.DataFrame(rows)
