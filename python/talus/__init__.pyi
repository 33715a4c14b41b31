"""Talus: implicit elasto-plasticity of geomaterials by semi-smooth Newton, from Python."""
import os
from typing import Any, Dict, Literal, Optional, Tuple, Union

import numpy as np
import numpy.typing as npt

from ._errors import (
    InvalidProblem as InvalidProblem,
    NotConverged as NotConverged,
    RunError as RunError,
    SceneError as SceneError,
    SiconosError as SiconosError,
    TalusError as TalusError,
)

_Path = Union[str, "os.PathLike[str]"]
Cones = Dict[str, Any]

class Scene:
    """A validated scene: FEM (``[mesh]``) or MPM (``[grid]``), checked by the parser and
    model builder of ``talus run``. Scenes are immutable: ``set`` returns a new one."""

    @staticmethod
    def load(path: _Path) -> Scene:
        """Reads and checks a scene file; relative paths in it are relative to its folder."""
    @staticmethod
    def from_toml(text: str, path: Optional[_Path] = None) -> Scene:
        """Checks a scene given as TOML text (relative paths: relative to ``path``'s
        folder, else to the working directory)."""
    @staticmethod
    def from_dict(d: Dict[str, Any], path: Optional[_Path] = None) -> Scene:
        """Checks a scene given as the nested dicts and lists of its TOML document."""
    def to_dict(self) -> Dict[str, Any]:
        """The TOML document as nested dicts and lists."""
    def to_toml(self) -> str:
        """The scene's TOML text."""
    def get(self, field: str) -> Any:
        """The value at a dotted TOML path (``KeyError`` when absent)."""
    def set(self, field: str, value: Any) -> Scene:
        """A new scene with ``field`` (dotted TOML path: ``material.friction_angle``,
        ``boundary[3].velocity``) set to ``value``, checked as ``talus run`` checks a file.
        Raises ``SceneError`` naming the field, the value and the reason."""
    @property
    def kind(self) -> Literal["fem", "mpm"]:
        """``"fem"`` or ``"mpm"``."""
    @property
    def path(self) -> Optional[str]:
        """The file the scene was read from, or ``None``."""

class Result:
    """What ``run`` returns."""

    kind: Literal["fem", "mpm"]
    history: Dict[str, npt.NDArray[np.float64]]
    """One float64 array per ``history.csv`` column (row 0: the initial state)."""
    summary: Dict[str, Any]
    """The content of ``summary.json``."""
    state: Dict[str, np.ndarray]
    """The final state's arrays (see ``run``)."""
    def to_pandas(self) -> Any:
        """The history as a pandas DataFrame (needs pandas)."""

def run(scene: Scene, out: Optional[_Path] = None, progress: bool = False) -> Result:
    """Runs a FEM or MPM scene to its end as ``talus run`` does, the GIL released.
    Files are written to ``out`` when given. Raises ``SceneError``, ``NotConverged``
    (``.report``: partial ``history`` and ``summary``) or ``RunError``."""

def read_siconos(path: _Path) -> Tuple[Any, npt.NDArray[np.float64], Cones]:
    """``(W, q, cones)`` of a Siconos plasticity file: ``W`` a NumPy (n, n) array or a
    ``scipy.sparse.coo_matrix`` with the file's triplets; ``cones`` ``{"model":
    "drucker_prager", "eta", "theta"}`` or ``{"model": "von_mises", "sigma_y"}``."""

def solve_reduced(
    W: Any,
    q: npt.ArrayLike,
    cones: Cones,
    tol: float = 1e-12,
    rho_factor: float = 10.0,
    global_rho: bool = False,
    max_iterations: int = 100,
) -> Tuple[npt.NDArray[np.float64], Dict[str, Any]]:
    """Solves ``z = Wσ + q``, ``σᵢ = P_K(σᵢ − ρ y(zᵢ))`` with the solver of
    ``talus reduced``; returns ``(σ, report)``. Raises ``NotConverged`` (``.report``,
    ``.solution``) unless the status is ``converged``."""
