"""Type stubs of vk_render."""

import os
from typing import Any, Mapping, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

from ._errors import DeviceError as DeviceError, Error as Error, SceneError as SceneError
from ._errors import SceneWarning as SceneWarning
from ._native import (
    CheckReport,
    Grid as Grid,
    Material,
    PathLike,
    Renderer as Renderer,
    Scene as Scene,
    SceneLike,
    devices as devices,
)

__version__: str

def default_renderer() -> Renderer: ...
def render(
    scene: SceneLike,
    *,
    set: Optional[Mapping[str, Any]] = None,
    width: Optional[int] = None,
    height: Optional[int] = None,
    samples: Optional[int] = None,
    view: Optional[str] = None,
    hdr: bool = False,
) -> npt.NDArray[Any]: ...
def brdf(material: Material, wi: npt.ArrayLike, wo: npt.ArrayLike, *, renderer: Optional[Renderer] = None) -> npt.NDArray[np.float32]: ...
def albedo(
    material: Material, theta_o_degrees: npt.ArrayLike, *, renderer: Optional[Renderer] = None
) -> Tuple[npt.NDArray[np.float64], float]: ...
def sample(
    material: Material, wo: Sequence[float], n: int, *, seed: int = 1, renderer: Optional[Renderer] = None
) -> Tuple[npt.NDArray[np.float32], npt.NDArray[np.float32]]: ...
def sampling_test(
    material: Material,
    *,
    theta_o: Optional[Sequence[float]] = None,
    phi_o: Optional[Sequence[float]] = None,
    samples: int = 1_000_000,
    seed: int = 1,
    level: float = 0.01,
    renderer: Optional[Renderer] = None,
) -> dict[str, Any]: ...
def reference(
    scene: SceneLike,
    *,
    set: Optional[Mapping[str, Any]] = None,
    width: Optional[int] = None,
    height: Optional[int] = None,
    samples: Optional[int] = None,
    hdr: bool = False,
) -> npt.NDArray[Any]: ...
def check(
    image: Union[npt.NDArray[np.uint8], PathLike],
    scene: Union[str, SceneLike],
    *,
    set: Optional[Mapping[str, Any]] = None,
    renderer: Optional[Renderer] = None,
) -> CheckReport: ...
def sweep(
    scene: SceneLike,
    grid: Mapping[str, Sequence[Any]],
    *,
    set: Optional[Mapping[str, Any]] = None,
    client: Any = None,
    out: Optional[PathLike] = None,
    name: str = "sweep",
    shard: Optional[Tuple[int, int]] = None,
    resume: bool = False,
    renderer: Optional[Renderer] = None,
    device: Union[int, str, None] = None,
    validate: bool = False,
    retries: int = 3,
) -> list[dict[str, Any]]: ...
