"""Cases: every input of a run, with attribute-style edits.

``case.contact.law = "dlft"`` sets the key ``contact.law`` of the case
file; the type is checked at once, the value by ``case.validate()`` and
before any run. Keys and tables are the case file's (see
docs/case-file.md, or ``cyclorub.keys()``); a key left absent reads ``None`` (its
automatic rule applies).
"""

import json
import os
import sys
import time
import warnings
from pathlib import Path

from . import _native
from ._errors import InputError
from ._result import Result

_KEYS = _native.keys()
_TABLES = sorted({table for table, *_ in _KEYS})


def keys():
    """Every key of a case file: a list of dicts with ``key`` (dotted),
    ``default``, ``unit``, ``allowed`` and ``doc``."""
    return [
        {"key": f"{table}.{name}", "default": default, "unit": unit,
         "allowed": allowed, "doc": doc}
        for table, name, default, unit, allowed, doc in _KEYS
    ]


def _plain(value):
    """A value as JSON data: numpy arrays and scalars, scipy.sparse
    matrices and paths converted."""
    if hasattr(value, "toarray"):  # scipy.sparse
        value = value.toarray()
    if hasattr(value, "tolist"):  # numpy arrays and scalars
        return value.tolist()
    if isinstance(value, os.PathLike):
        return os.fspath(value)
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    return value


def _rows(matrix, key):
    """A dense or scipy.sparse matrix as a list of rows of floats."""
    import numpy as np

    if hasattr(matrix, "toarray"):
        matrix = matrix.toarray()
    array = np.asarray(matrix, dtype=float)
    if array.ndim != 2:
        raise InputError(
            f"{key}: a matrix has 2 dimensions, this array has {array.ndim}",
            key, "usage")
    return array.tolist()


class _Section:
    """A table of a case (``case.contact``, ``case.model.damping``)."""

    __slots__ = ("_case", "_prefix")

    def __init__(self, case, prefix):
        object.__setattr__(self, "_case", case)
        object.__setattr__(self, "_prefix", prefix)

    def __getattr__(self, name):
        if name.startswith("__"):
            raise AttributeError(name)
        return self._case._get(f"{self._prefix}.{name}")

    def __setattr__(self, name, value):
        self._case._set(f"{self._prefix}.{name}", value)

    def __dir__(self):
        prefix = self._prefix + "."
        names = {t[len(prefix):] for t in _TABLES if t.startswith(prefix)}
        names |= {n for t, n, *_ in _KEYS if t == self._prefix}
        return sorted(names)

    def to_dict(self):
        """The table as a dict (absent keys left out)."""
        return json.loads(self._case._native.get_json(self._prefix))

    def __repr__(self):
        return f"[{self._prefix}] {self.to_dict()!r}"


class _Progress:
    """``progress=True``: one line on stderr, rewritten as points come."""

    def __init__(self):
        self.shown = False
        self.last = 0.0

    def __call__(self, points, frequency_hz, step):
        now = time.monotonic()
        if now - self.last < 0.2:
            return
        self.last = now
        self.shown = True
        sys.stderr.write(f"\rcyclorub: point {points} at {frequency_hz:.4f} Hz   ")
        sys.stderr.flush()

    def close(self):
        if self.shown:
            sys.stderr.write("\n")
            sys.stderr.flush()


class Case:
    """A case: the TOML case file in memory, and the folder its relative
    paths (Matrix Market files) start from (``case.case_dir``).

    Make one with ``Case.default()``, ``Case.example(name)``,
    ``Case.from_toml(path_or_text)`` or ``Case.from_matrices(...)``; edit
    it by attribute (``case.excitation.engine_order = 3``) or with
    ``case.replace({"excitation.engine_order": 3})``. A case pickles as
    its TOML text (what a study sends to its workers).
    """

    __slots__ = ("_native",)

    def __init__(self, native=None):
        object.__setattr__(
            self, "_native", native if native is not None else _native.Case.default())

    # --- making one -------------------------------------------------------

    @classmethod
    def default(cls):
        """The paper's default case: academic model, N = 24, traveling wave
        h = 1 of 4 N, R-HBM, gap 1e-3 m, N_h = 10, N_t = 10000."""
        return cls(_native.Case.default())

    @classmethod
    def example(cls, name):
        """One of the paper's academic studies (``Case.examples()``)."""
        return cls(_native.Case.example(name))

    @staticmethod
    def examples():
        """The names of the paper's academic studies."""
        return list(_native.Case.example_names())

    @classmethod
    def from_toml(cls, path_or_text, case_dir=None):
        """A case from a TOML file (a path) or TOML text. Relative paths
        in it start from ``case_dir`` (default: the file's folder, or the
        working directory for text)."""
        is_path = isinstance(path_or_text, os.PathLike) or (
            isinstance(path_or_text, str)
            and "\n" not in path_or_text
            and "=" not in path_or_text
            and not path_or_text.lstrip().startswith("[")
            and path_or_text.strip() != "")
        if is_path:
            path = Path(path_or_text)
            try:
                text = path.read_text()
            except OSError as error:
                raise InputError(
                    f"cannot read the case file {path}: {error}", None, "case") from error
            origin = str(path)
            directory = case_dir if case_dir is not None else (path.parent or Path("."))
        else:
            text, origin = path_or_text, "<text>"
            directory = case_dir if case_dir is not None else "."
        return cls(_native.Case.from_toml(text, origin, os.fspath(directory)))

    @classmethod
    def from_matrices(cls, mass, stiffness, *, sectors, couplings=None,
                      left_boundary=None, right_boundary=None, damping=None,
                      symmetry_tolerance=None, base=None):
        """A case whose sector model is given by matrices (numpy arrays or
        scipy.sparse matrices), the rest taken from ``base`` (default: the
        default case: contact and excitation on dof 1, the observed dof 1).

        - ``mass``, ``stiffness``: the sector's matrices (symmetric).
        - ``sectors``: the number of sectors N.
        - ``couplings``: ``(mass_coupling, stiffness_coupling)`` blocks to
          the next sector of a block-circulant (lumped) sector; either may
          be ``None``.
        - ``left_boundary``, ``right_boundary``: the cyclic boundary dofs of
          a finite-element sector (numbered from 1), instead of couplings.
        - ``damping``: a dict of ``[model.damping]`` keys (e.g.
          ``{"kind": "rayleigh", "alpha": 1.0}``), or a damping matrix
          (``kind = "matrix"``); default: the base's (modal, 1e-3).

        The matrices are stored as dense rows in the case (``model.kind =
        "matrices"``), as a case file would hold them: the case stays one
        self-contained TOML text that pickles to any worker of a study, and
        the solver stores sector matrices densely anyway.
        """
        case = (base if base is not None else cls.default()).copy()
        model = {"kind": "matrices", "sectors": int(sectors),
                 "mass": _rows(mass, "model.mass"),
                 "stiffness": _rows(stiffness, "model.stiffness")}
        if couplings is not None:
            if isinstance(couplings, dict):
                mass_coupling = couplings.get("mass")
                stiffness_coupling = couplings.get("stiffness")
            else:
                mass_coupling, stiffness_coupling = couplings
            if mass_coupling is not None:
                model["mass_coupling"] = _rows(mass_coupling, "model.mass_coupling")
            if stiffness_coupling is not None:
                model["stiffness_coupling"] = _rows(
                    stiffness_coupling, "model.stiffness_coupling")
        if left_boundary is not None:
            model["left_boundary"] = [int(d) for d in left_boundary]
        if right_boundary is not None:
            model["right_boundary"] = [int(d) for d in right_boundary]
        if symmetry_tolerance is not None:
            model["symmetry_tolerance"] = float(symmetry_tolerance)
        if damping is None:
            model["damping"] = case.model.damping.to_dict()
        elif isinstance(damping, dict):
            model["damping"] = _plain(damping)
        else:
            model["damping"] = {"kind": "matrix",
                                "matrix": _rows(damping, "model.damping.matrix")}
        case._set("model", model)
        case.validate()
        return case

    # --- reading and editing ---------------------------------------------

    def _get(self, key):
        if key in _TABLES:
            return _Section(self, key)
        return json.loads(self._native.get_json(key))

    def _set(self, key, value):
        self._native.set_json(key, json.dumps(_plain(value)))

    def __getattr__(self, name):
        if name in _TABLES:
            return _Section(self, name)
        raise AttributeError(
            f"a case has no table {name!r}; its tables: "
            + ", ".join(t for t in _TABLES if "." not in t))

    def __setattr__(self, name, value):
        if name == "case_dir":
            self._native.case_dir = os.fspath(value)
        elif name in _TABLES:
            self._set(name, value)
        else:
            raise AttributeError(f"a case has no table {name!r}")

    def __dir__(self):
        return sorted(set(object.__dir__(self)) | {t for t in _TABLES if "." not in t})

    @property
    def case_dir(self):
        """The folder the case's relative paths start from."""
        return Path(self._native.case_dir)

    def set(self, key, value):
        """Sets dotted ``key`` (``"contact.law"``) to ``value`` (``None``:
        absent, its automatic rule applies)."""
        self._set(key, value)
        return self

    def get(self, key):
        """The value of dotted ``key`` (``None`` when absent)."""
        value = self._get(key)
        return value.to_dict() if isinstance(value, _Section) else value

    def replace(self, changes=None, **by_table):
        """A copy with ``changes`` (``{"excitation.engine_order": 3}``) made."""
        case = self.copy()
        for key, value in dict(changes or {}, **by_table).items():
            case._set(key, value)
        return case

    def copy(self):
        """An independent copy."""
        return Case(self._native.copy())

    def mistuned(self, standard_deviation=None, *, seed=None, deviations=None,
                 distribution=None, blade_dofs=None, blade_node_set=None):
        """A copy with its blades mistuned (``[mistuning]``, issue 44): the
        blade stiffness of sector ``j`` scaled by ``1 + δ_j``, the ``δ_j``
        given (``deviations``, one per sector) or drawn by the library
        from ``standard_deviation`` (e.g. 0.01 for 1 %), ``seed`` (the same
        seed, the same pattern) and ``distribution`` (``"normal"`` or
        ``"uniform"``); ``blade_dofs``: the blade's dofs (default: the
        academic blade, 1, 2, 3); ``blade_node_set``: on a finite-element
        sector, the node set of its blade (default ``"blade"``). Any
        ``[mistuning]`` of this case is replaced. The basis becomes ``"physical"``: a mistuned wheel is
        solved on the full wheel (no cyclic basis holds it)."""
        table = {"deviations": deviations, "standard_deviation": standard_deviation,
                 "seed": seed, "distribution": distribution, "blade_dofs": blade_dofs,
                 "blade_node_set": blade_node_set}
        case = self.copy()
        case._set("mistuning", {k: v for k, v in _plain(table).items() if v is not None})
        case._set("basis.kind", "physical")
        return case

    def mistuning_deviations(self):
        """The deviations ``δ_j`` of ``[mistuning]`` (given, or drawn as a
        run draws them) as a numpy array ``[sector]``; ``None`` for a tuned
        wheel."""
        import numpy as np

        deviations = self._native.mistuning_deviations()
        return None if deviations is None else np.asarray(deviations)

    def to_toml(self):
        """The case as TOML text (a case file ``cyclorub run`` reads)."""
        return self._native.to_toml()

    def to_dict(self):
        """The case as nested dicts (absent keys left out)."""
        return json.loads(self._native.to_json())

    def validate(self):
        """Checks every value; raises ``InputError`` naming the key. A
        model written in the case (``kind = "academic"`` or
        ``"matrices"``, as ``from_matrices`` makes) is built as a run
        builds it: matrices of unequal sizes, not symmetric, or a
        stiffness that does not hold the wheel are refused here. A model
        read from files (Matrix Market, finite element) is checked by the
        run, whose reduction may take long."""
        self._native.validate()
        return self

    def __eq__(self, other):
        return isinstance(other, Case) and self._native == other._native

    def __reduce__(self):
        return (_from_toml_text, (self.to_toml(), os.fspath(self.case_dir)))

    def __repr__(self):
        d = self.to_dict()
        e, m = d.get("excitation", {}), d.get("model", {})
        return (f"<cyclorub.Case: {m.get('kind')} model, N = {m.get('sectors')}, "
                f"{e.get('kind')} h = {e.get('engine_order')} of {e.get('amplitude')} N, "
                f"{d.get('contact', {}).get('law')} contact>")

    # --- computing ---------------------------------------------------------

    def plan(self):
        """What each basis keeps for this case's loads, before running:
        ``{basis: {"unknowns", "full_unknowns", "sampled_sectors",
        "reduction_percent", "nodal_diameters": [array per harmonic]}}``
        for ``symmetry``, ``paper``, ``nodal_diameter`` and ``full``
        (``{"error": ...}`` where a rule does not apply)."""
        return self._native.plan()

    def modes(self):
        """Natural frequencies of the model per nodal diameter:
        ``(nodal_diameters [d], frequencies_hz [d, mode])``."""
        return self._native.modes()

    def run(self, basis=None, at_hz=None, progress=True, stability=None,
            stability_harmonics=None):
        """Solves the forced response; returns a :class:`cyclorub.Result`.

        - ``basis``: ``"symmetry"``, ``"paper"``, ``"nodal_diameter"``,
          ``"full"`` or ``"physical"`` (default: the case's).
        - ``at_hz``: solve at exactly these frequencies (Hz) instead of
          following the branch by arc-length continuation.
        - ``progress``: ``True`` prints the current point on stderr;
          a callable gets ``(points, frequency_hz, step)``; ``False``: quiet.
        - ``stability``: check every point (Hill's method); default: the
          case's ``[stability] enabled``.

        The GIL is released while it runs. Ctrl-C (KeyboardInterrupt)
        stops the branch before its next point: the result holds every
        point found, ``result.interrupted`` is True, and a warning says so
        (no exception is raised).
        """
        callback = _Progress() if progress is True else (progress or None)
        try:
            native = self._native.run(
                basis=basis,
                at_hz=None if at_hz is None else [float(f) for f in _plain(at_hz)],
                stability=stability,
                stability_harmonics=stability_harmonics,
                progress=callback)
        finally:
            if isinstance(callback, _Progress):
                callback.close()
        result = Result(native)
        if result.interrupted:
            warnings.warn(
                f"cyclorub: interrupted; the result keeps the {len(result)} points found",
                RuntimeWarning, stacklevel=2)
        return result


def _from_toml_text(text, case_dir):
    return Case(_native.Case.from_toml(text, "<pickled case>", case_dir, False))
