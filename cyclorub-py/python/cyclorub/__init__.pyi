# The package's types (see py.typed); _case.pyi and _result.pyi are
# generated from the key table by cyclorub-py/tools/stubs.py.
from ._case import Case as Case, keys as keys
from ._errors import CyclorubError as CyclorubError, InputError as InputError
from ._result import Result as Result, load as load
from ._study import (
    amplification_figure as amplification_figure,
    mistuning_patterns as mistuning_patterns,
    mistuning_study as mistuning_study,
    study as study,
    whitehead_bound as whitehead_bound,
)

__version__: str

__all__ = ["Case", "Result", "CyclorubError", "InputError", "keys", "load", "study",
           "mistuning_patterns", "mistuning_study", "amplification_figure", "whitehead_bound",
           "__version__"]
