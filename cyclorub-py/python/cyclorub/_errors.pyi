from typing import Literal

_Kind = Literal["case", "model", "harmonic_balance", "results", "run", "usage"]

class CyclorubError(Exception):
    message: str
    key: str | None
    kind: _Kind
    def __init__(self, message: str, key: str | None = ..., kind: _Kind = ...) -> None: ...

class InputError(CyclorubError, ValueError): ...
