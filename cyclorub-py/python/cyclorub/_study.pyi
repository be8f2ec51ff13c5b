from collections.abc import Mapping, Sequence
from concurrent.futures import Executor
from os import PathLike
from pathlib import Path
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from ._case import Case

def study(
    cases: Sequence[Case] | Mapping[Any, Case],
    executor: Executor | None = ...,
    *,
    basis: str | None = ...,
    at_hz: Sequence[float] | NDArray[np.float64] | None = ...,
    stability: bool = ...,
    max_workers: int | None = ...,
    progress: bool = ...,
) -> Any: ...
def mistuning_patterns(
    case: Case,
    count: int,
    standard_deviation: float,
    seed: int = ...,
    *,
    distribution: Literal["normal", "uniform"] | None = ...,
) -> dict[int, Case]: ...
def mistuning_study(
    case: Case,
    count: int,
    standard_deviation: float,
    seed: int = ...,
    executor: Executor | None = ...,
    *,
    distribution: Literal["normal", "uniform"] | None = ...,
    at_hz: Sequence[float] | NDArray[np.float64] | None = ...,
    max_workers: int | None = ...,
    progress: bool = ...,
) -> Any: ...
def whitehead_bound(sectors: int) -> float: ...
def amplification_figure(
    table: Any,
    path: str | PathLike[str],
    sectors: int | None = ...,
    png: bool = ...,
) -> list[Path]: ...
