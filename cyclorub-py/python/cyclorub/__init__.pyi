# The package's types (see py.typed); _case.pyi and _result.pyi are
# generated from the key table by cyclorub-py/tools/stubs.py.
from ._case import Case as Case, keys as keys
from ._errors import CyclorubError as CyclorubError, InputError as InputError
from ._result import Result as Result, load as load
from ._study import study as study

__version__: str

__all__ = ["Case", "Result", "CyclorubError", "InputError", "keys", "load", "study",
           "__version__"]
