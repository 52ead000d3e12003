from os import PathLike
from typing import Any, Optional, Union

import numpy as np
import numpy.typing as npt

ArrayLike = npt.ArrayLike
Result = dict[str, np.ndarray]

LAW_KEYS: dict[str, tuple[str, ...]]
__version__: str

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
        radius: ArrayLike,
        density: ArrayLike,
        speed: ArrayLike,
        eccentricity: ArrayLike,
        stiffness: ArrayLike = ...,
        damping: ArrayLike = ...,
        young: ArrayLike = ...,
        poisson: ArrayLike = ...,
        dissipation: ArrayLike = ...,
        restitution: ArrayLike = ...,
        restitution_speed: ArrayLike = ...,
        radius2: Optional[ArrayLike] = ...,
        density2: Optional[ArrayLike] = ...,
        exact_fallback: bool = ...,
    ) -> dict[str, Any]: ...
    def pair(
        self,
        *,
        radius: float,
        density: float,
        stiffness: float = ...,
        damping: float = ...,
        young: float = ...,
        poisson: float = ...,
        dissipation: float = ...,
        radius2: Optional[float] = ...,
        density2: Optional[float] = ...,
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
    *,
    model: str,
    radius: ArrayLike,
    density: ArrayLike,
    speed: ArrayLike,
    eccentricity: ArrayLike,
    stiffness: ArrayLike = ...,
    damping: ArrayLike = ...,
    young: ArrayLike = ...,
    poisson: ArrayLike = ...,
    dissipation: ArrayLike = ...,
    restitution: ArrayLike = ...,
    restitution_speed: ArrayLike = ...,
    radius2: Optional[ArrayLike] = ...,
    density2: Optional[ArrayLike] = ...,
) -> dict[str, Any]: ...
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
    radius: ArrayLike,
    density: ArrayLike,
    stiffness: ArrayLike = ...,
    damping: ArrayLike = ...,
    young: ArrayLike = ...,
    poisson: ArrayLike = ...,
    dissipation: ArrayLike = ...,
    radius2: Optional[ArrayLike] = ...,
    density2: Optional[ArrayLike] = ...,
) -> Result: ...
def run(
    config: Union[str, PathLike[str], dict[str, Any], None] = ...,
    *,
    engine: str = ...,
    t_end: Optional[float] = ...,
    dt: Optional[float] = ...,
    threads: Optional[int] = ...,
    skin: Optional[float] = ...,
    mor: str = ...,
    checkpoint: Optional[Union[str, PathLike[str]]] = ...,
    resume: Optional[Union[str, PathLike[str]]] = ...,
    trajectory: Optional[Union[str, PathLike[str]]] = ...,
    log: Optional[Union[str, PathLike[str]]] = ...,
    frames: int = ...,
    progress: bool = ...,
    toml: Optional[str] = ...,
) -> dict[str, Any]: ...
