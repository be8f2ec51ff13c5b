from collections.abc import Mapping, Sequence
from concurrent.futures import Executor
from typing import Any

from ._case import Case

def study(
    cases: Sequence[Case] | Mapping[Any, Case],
    executor: Executor | None = ...,
    *,
    basis: str | None = ...,
    at_hz: Sequence[float] | None = ...,
    stability: bool = ...,
    max_workers: int | None = ...,
) -> Any: ...
