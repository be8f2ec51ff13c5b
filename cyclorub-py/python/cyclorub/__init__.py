"""cyclorub: nonlinear forced responses of bladed disks rubbing on their
casing, by the harmonic balance method with exact cyclic-symmetry
reductions, from Python.

    import cyclorub
    case = cyclorub.Case.default()            # the paper's default case
    case.contact.law = "dlft"                 # any case-file key, by attribute
    result = case.run(stability=False)        # GIL released; Ctrl-C keeps the points
    result.frequency_hz, result.amplitude     # numpy arrays [point], [point, sector]
    result.save("results")                    # the folder `cyclorub run` writes
    table = cyclorub.study([case.replace({"excitation.engine_order": h}) for h in (1, 2, 3)])
    table = cyclorub.mistuning_study(case, 20, standard_deviation=0.01)   # issue 44
    cyclorub.amplification_figure(table, "amplification.svg")
"""

from ._native import __version__
from ._errors import CyclorubError, InputError
from ._case import Case, keys
from ._result import Result, load
from ._study import (amplification_figure, mistuning_patterns, mistuning_study, study,
                     whitehead_bound)

# A result hands back its case as a Case (see Result._case_type).
Result._case_type = Case

__all__ = ["Case", "Result", "CyclorubError", "InputError", "keys", "load", "study",
           "mistuning_patterns", "mistuning_study", "amplification_figure", "whitehead_bound",
           "__version__"]
