"""Type stubs of vk_render._native, the Rust half of vk_render."""

import os
from typing import Any, Mapping, Optional, Sequence, Tuple, TypedDict, Union

import numpy as np
import numpy.typing as npt

PathLike = Union[str, "os.PathLike[str]"]
SceneLike = Union["Scene", PathLike]
Material = Union[Mapping[str, Any], Tuple["Scene", str]]

__version__: str

class Scene:
    """A scene (SCENE_FORMAT version 1), validated as `vk-render render` validates it."""

    @staticmethod
    def load(path: PathLike) -> "Scene":
        """Reads and validates a scene file; SceneError names the file, key and value."""
    @staticmethod
    def from_toml(text: str, base_dir: PathLike = ...) -> "Scene":
        """A scene from TOML text; relative mesh and map paths are found in `base_dir`."""
    def with_set(self, set: Mapping[str, Any]) -> "Scene":
        """A new scene with values replaced exactly as `--set KEY=VALUE` replaces them."""
    def to_toml(self) -> str:
        """The scene as TOML text (comments not kept)."""
    @property
    def path(self) -> str: ...
    @property
    def width(self) -> int: ...
    @property
    def height(self) -> int: ...
    @property
    def samples(self) -> int: ...
    @property
    def view(self) -> str: ...
    @property
    def materials(self) -> list[str]: ...
    @property
    def objects(self) -> list[dict[str, Any]]: ...
    @property
    def lights(self) -> list[dict[str, Any]]: ...
    @property
    def has_environment(self) -> bool: ...
    @property
    def warnings(self) -> list[str]: ...

class CheckStatistics(TypedDict):
    rms: float
    mean: float
    p99: float
    over: float

class CheckMistake(TypedDict):
    name: str
    explanation: str
    should_be: str
    looks_like: str

class CheckWrongParameters(TypedDict):
    object: int
    material: str
    model: str
    fitted: dict[str, list[float]]
    scene: dict[str, list[float]]
    residual_levels: float
    scene_levels: float

class CheckReport(TypedDict):
    matches: bool
    verdict: str
    mistakes: list[CheckMistake]
    statistics: CheckStatistics
    regions: list[dict[str, Any]]
    tells_apart: Optional[str]
    tells_apart_levels: Optional[float]
    wrong_parameters: list[CheckWrongParameters]
    exact: npt.NDArray[np.uint8]

class Renderer:
    """A Vulkan device with vk-render's shaders, pipelines and meshes kept between calls."""

    def __init__(
        self, device: Union[int, str, None] = None, validate: bool = False, timeout: Optional[float] = None
    ) -> None: ...
    @property
    def device(self) -> str:
        """The name of the Vulkan device this renderer draws with."""
    @property
    def accuracy(self) -> Optional[dict[str, Any]]:
        """How exact the last image's environment light was (exact mode): samples, passes, p99_levels."""
    def render(
        self,
        scene: SceneLike,
        *,
        set: Optional[Mapping[str, Any]] = None,
        width: Optional[int] = None,
        height: Optional[int] = None,
        samples: Optional[int] = None,
        view: Optional[str] = None,
        hdr: bool = False,
    ) -> npt.NDArray[Any]:
        """(height, width, 3): uint8, the PNG's bytes of `vk-render render`; float32 with hdr=True, its EXR."""
    def brdf(self, material: Material, wi: npt.ArrayLike, wo: npt.ArrayLike) -> npt.NDArray[np.float32]:
        """f_r(wi, wo) by the shaders' brdf_eval on the GPU, (N, 3); unit directions (N, 3), normal +z."""
    def albedo(self, material: Material, theta_o_degrees: npt.ArrayLike) -> Tuple[npt.NDArray[np.float64], float]:
        """Directional albedo (N, 3) at each theta_o in degrees, and the largest error bound reached."""
    def sample(
        self, material: Material, wo: Sequence[float], n: int, *, seed: int = 1
    ) -> Tuple[npt.NDArray[np.float32], npt.NDArray[np.float32]]:
        """n draws of the material's own sampler seen from wo: directions (n, 3) and densities (n,)."""
    def sampling_test(
        self,
        material: Material,
        *,
        theta_o: Optional[Sequence[float]] = None,
        phi_o: Optional[Sequence[float]] = None,
        samples: int = 1_000_000,
        seed: int = 1,
        level: float = 0.01,
    ) -> dict[str, Any]:
        """`vk-render sampling`'s tests of the material's own sampler: passed, verdicts, views."""
    def check(
        self,
        image: Union[npt.NDArray[np.uint8], PathLike],
        scene: Union[str, SceneLike],
        *,
        set: Optional[Mapping[str, Any]] = None,
    ) -> CheckReport:
        """`vk-render check` of an image against a scene rendered at its size."""

class Grid:
    """The product of a few parameters' values, in `vk-render sweep`'s order (the first key slowest)."""

    def __init__(self, grid: Mapping[str, Sequence[Any]]) -> None: ...
    def __len__(self) -> int: ...
    def shard(self, k: int, n: int) -> list[int]:
        """The indices of shard k of n (1-based), as --shard K/N."""
    def combination(self, index: int, sheet: PathLike = ...) -> dict[str, Any]:
        """index, text, positions, label and tile (its file beside `sheet`)."""
    @property
    def keys(self) -> list[str]: ...

def reference(
    scene: SceneLike,
    *,
    set: Optional[Mapping[str, Any]] = None,
    width: Optional[int] = None,
    height: Optional[int] = None,
    samples: Optional[int] = None,
    hdr: bool = False,
) -> npt.NDArray[Any]: ...
def devices() -> list[dict[str, Any]]: ...
def write_png(image: npt.NDArray[np.uint8], path: PathLike) -> None: ...
def read_image(path: PathLike) -> npt.NDArray[Any]: ...
def brdf_mirror(
    material: Material, wi: npt.NDArray[np.float32], wo: npt.NDArray[np.float32]
) -> npt.NDArray[np.float32]: ...
