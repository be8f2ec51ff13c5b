"""Results: a solved branch as numpy arrays."""

import json
import os
import shutil

from . import _native


class Result:
    """A forced-response branch and everything the results files hold.

    Arrays are numpy, indexed ``[point, sector, ...]`` from 0; the ``dof``
    and ``sector`` arguments of :meth:`recover` are numbered from 1, like
    case files. Per point: ``frequency_hz``, ``unknowns``, ``iterations``,
    ``residual_norm``, ``converged``; per point and sector (observed dof):
    ``amplitude`` (largest displacement toward the casing, ``branch.csv``'s
    amplitude), ``max_abs``, ``velocity_max_abs``, ``observed`` (harmonic
    coordinates); contact: ``contact_fraction``, ``peak_force``,
    ``max_penetration`` ``[point, sector, contact dof]``,
    ``contact_force`` (coordinates), ``sectors_in_contact``; cyclic
    components ``forward`` and ``backward`` ``[point, harmonic, nodal
    diameter]``; ``stability`` (a dict, or ``None`` when not checked).

    The per-point recovery on every sector runs on the first access to
    one of those arrays (the solve itself computes only the branch).
    """

    __slots__ = ("_native",)

    # The class of ``Result.case`` (``cyclorub.Case``), set by the package
    # (``__init__.py``): ``_case`` imports this module (a case's run gives a
    # Result), so this module does not import ``_case`` back.
    _case_type = None

    _ARRAYS = (
        "frequency_hz", "unknowns", "amplitude", "max_abs", "velocity_max_abs",
        "observed", "iterations", "residual_norm", "converged",
        "sectors_in_contact", "contact_fraction", "peak_force",
        "max_penetration", "contact_force", "forward", "backward", "stability",
        "interrupted", "timings", "directory", "stop",
    )

    def __init__(self, native):
        self._native = native

    def __getattr__(self, name):
        if name in Result._ARRAYS:
            return getattr(self._native, name)
        raise AttributeError(name)

    def __dir__(self):
        return sorted(set(object.__dir__(self)) | set(Result._ARRAYS))

    def __len__(self):
        return len(self._native)

    @property
    def case(self):
        """The case as solved (frequency range filled in, basis set)."""
        return Result._case_type(self._native.case)

    @property
    def stop_reason(self):
        """Why the branch stopped, as ``run.json`` records it."""
        return json.loads(self._native.stop_json)

    @property
    def events(self):
        """Folds, branch points, kinks and the stop, by point."""
        return json.loads(self._native.events_json)

    @property
    def basis(self):
        """The basis solved on: kind, unknowns, sampled sectors, the signed
        nodal diameters per harmonic."""
        return json.loads(self._native.basis_json)

    @property
    def mistuning(self):
        """A mistuned wheel's record (``run.json``'s ``mistuning``), ``None``
        for a tuned wheel: ``deviations`` ``[sector]``, ``sector_peaks_m``
        and ``sector_peak_frequencies_hz`` ``[sector]``,
        ``most_responding_sector`` (from 1), ``tuned_peak_m`` (the tuned
        wheel's nonlinear peak, solved on the symmetry basis over the same
        range), ``tuned_reference`` and ``amplification_factor`` (largest
        sector peak over the tuned peak). For a solved result the first
        access solves the tuned reference branch."""
        text = self._native.mistuning_json
        return None if text is None else json.loads(text)

    @property
    def markers(self):
        """Where stability changes along the branch (empty when not checked)."""
        stability = self._native.stability
        return [] if stability is None else json.loads(stability["markers_json"])

    @property
    def branches(self):
        """The bifurcated branches recorded in a loaded results folder
        (``cyclorub branches`` or ``cyclorub run --branches``), in the order
        of ``branches/branches.json``: per branch point a dict of ``class``
        (σ), ``marker`` (its place in the stability markers, ``None``: found
        by ``--class``), ``marker_hz``, ``branch_point_hz`` (located; ``None``
        when not switched at, then ``not_switched`` says why),
        ``parent_point`` (the point of this branch after which the crossing
        lies), ``basis_unknowns`` and ``full_unknowns`` (the enlarged basis
        against the full wheel), ``file`` (its CSV) and ``sides`` (+v then
        −v): each a dict of ``direction`` (+1 or −1), ``frequency_hz``
        ``[S]`` (Hz), ``stable`` ``[S]`` (1 stable, 0 unstable, −1 not
        checked), ``sector_amplitude`` ``[S, sector]`` (m), ``stop`` (as
        ``run.json`` records it) and ``stop_reason`` (in words). Empty for a
        result solved here."""
        branches = self._native.branches
        for branch in branches:
            for side in branch["sides"]:
                side["stop"] = json.loads(side.pop("stop_json"))
        return branches

    def linear_response(self):
        """The linear response (no contact) of the observed dof over the
        branch's range: ``(frequency_hz [f], amplitude [f, sector])``."""
        return self._native.linear_response()

    def natural_frequencies(self):
        """``(nodal_diameters [d], frequencies_hz [d, mode])``."""
        return self._native.natural_frequencies()

    def recover(self, dof, sector=1, time_samples=None):
        """The motion of sector dof ``dof`` on ``sector`` (both from 1) at
        every point: a dict of ``coordinates`` ``[point, 2 N_h + 1]``,
        ``displacement`` and ``velocity`` ``[point, time_samples]`` and
        ``peak`` ``[point]`` (largest displacement over the period)."""
        return self._native.recover(int(dof), int(sector), time_samples)

    def save(self, directory, overwrite=False):
        """Writes the results folder ``cyclorub run`` writes (``branch.csv``,
        ``results.h5``, ``plots/``, ``run.json``, and
        ``observed_harmonics.csv`` when the case asks) into ``directory``; a
        loaded result copies its folder.
        A folder that holds another run is refused (``InputError`` naming
        ``output.directory``) unless ``overwrite``: then that run's files
        are removed first."""
        source = self._native.directory
        if source is not None:
            if os.path.abspath(source) != os.path.abspath(directory):
                shutil.copytree(source, directory, dirs_exist_ok=True)
            return directory
        self._native.save(os.fspath(directory), overwrite)
        return directory

    def table(self):
        """``branch.csv`` as a table: frequency, amplitude per sector,
        iterations, residual, converged (a pandas DataFrame when pandas is
        installed, else a dict of arrays)."""
        columns = {"frequency_hz": self.frequency_hz}
        amplitude = self.amplitude
        for j in range(amplitude.shape[1]):
            columns[f"amplitude_sector_{j + 1}"] = amplitude[:, j]
        columns["iterations"] = self.iterations
        columns["residual_norm"] = self.residual_norm
        columns["converged"] = self.converged
        try:
            import pandas
        except ImportError:
            return columns
        return pandas.DataFrame(columns)

    def __repr__(self):
        state = " (interrupted)" if self.interrupted else ""
        return (f"<cyclorub.Result: {len(self)} points, {self.basis.get('kind')} basis, "
                f"{self.stop}{state}>")


def load(directory, case_dir=None):
    """Reads a results folder written by ``cyclorub run`` or
    :meth:`Result.save`. ``case_dir``: where the case's relative paths
    start (for :meth:`Result.recover`, which rebuilds the problem)."""
    return Result(_native.load(os.fspath(directory),
                               None if case_dir is None else os.fspath(case_dir)))
