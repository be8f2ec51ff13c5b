"""The exceptions the solver raises."""


class CyclorubError(Exception):
    """An error of the cyclorub library.

    Attributes:
        message: the library's whole message (what is wrong, what is allowed).
        key: the case-file key it names (``"casing.gap"``,
            ``"model.stiffness"``), or ``None`` when it names none.
        kind: the layer it comes from: ``"case"``, ``"model"``,
            ``"harmonic_balance"``, ``"results"``, ``"run"`` or ``"usage"``
            (an argument of the Python API).
    """

    def __init__(self, message, key=None, kind="run"):
        super().__init__(message)
        self.message = message
        self.key = key
        self.kind = kind

    def __reduce__(self):
        # Raised in a worker process of a study: it must pickle back.
        return (type(self), (self.message, self.key, self.kind))


class InputError(CyclorubError, ValueError):
    """An error in what was given (a case value, a matrix, an argument),
    as opposed to a failure while computing or writing."""
