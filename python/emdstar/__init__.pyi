from os import PathLike
from typing import Any, Optional, Union

import numpy as np
import numpy.typing as npt

ArrayLike = npt.ArrayLike
Result = dict[str, np.ndarray]

LAW_KEYS: dict[str, tuple[str, ...]]

class Table:
    @classmethod
    def default(cls, model: str) -> "Table": ...
    @classmethod
    def load(cls, path: Union[str, PathLike[str]]) -> "Table": ...
    @property
    def model(self) -> str: ...
    @property
    def parameter_box(self) -> dict[str, tuple[float, float]]: ...
    @property
    def tolerance(self) -> float: ...
    @property
    def estimated_error(self) -> dict[str, float]: ...
    @property
    def rect(self) -> list[list[float]]: ...
    def lookup(
        self,
        *,
        exact_fallback: bool = ...,
        radius2: Optional[ArrayLike] = ...,
        density2: Optional[ArrayLike] = ...,
        **params: ArrayLike,
    ) -> Result: ...
    def pair(
        self, *, radius2: Optional[float] = ..., density2: Optional[float] = ..., **params: float
    ) -> "PairTable": ...

class PairTable:
    @property
    def patches(self) -> int: ...
    @property
    def nbytes(self) -> int: ...
    def lookup(
        self, *, speed: ArrayLike, eccentricity: ArrayLike, exact_fallback: bool = ...
    ) -> Result: ...

def mor(
    *, model: str, radius2: Optional[ArrayLike] = ..., density2: Optional[ArrayLike] = ..., **params: ArrayLike
) -> Result: ...
def mor_scaled(*, model: str, l_tilde: ArrayLike, c_phi: ArrayLike, c_dis: ArrayLike) -> Result: ...
def collide(
    *,
    x1: ArrayLike,
    v1: ArrayLike,
    x2: ArrayLike,
    v2: ArrayLike,
    model: str,
    table: Optional[Table] = ...,
    exact_fallback: bool = ...,
    radius2: Optional[ArrayLike] = ...,
    density2: Optional[ArrayLike] = ...,
    **params: Any,
) -> Result: ...
def run(
    path: Optional[Union[str, PathLike[str]]] = ...,
    *,
    toml: Optional[str] = ...,
    engine: str = ...,
    t_end: Optional[float] = ...,
    frames: int = ...,
    mor: str = ...,
) -> dict[str, Any]: ...
