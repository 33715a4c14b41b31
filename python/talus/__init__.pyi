"""Talus: implicit elasto-plasticity of geomaterials by semi-smooth Newton, from Python."""
import os
from typing import Any, Callable, Dict, List, Literal, Optional, Tuple, Union

import numpy as np
import numpy.typing as npt

from ._errors import (
    Collapsed as Collapsed,
    Interrupted as Interrupted,
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
    dimension: int
    """2, or 3 for a scene with ``geometry = "3d"``."""
    history: Dict[str, npt.NDArray[np.float64]]
    """One float64 array per ``history.csv`` column (row 0: the initial state)."""
    summary: Dict[str, Any]
    """The content of ``summary.json``."""
    state: Dict[str, np.ndarray]
    """The final state's arrays (see ``run``)."""
    stages: List[Dict[str, Any]]
    """A staged scene's ``summary.json`` stage entries, in order (empty otherwise)."""
    def to_pandas(self) -> Any:
        """The history as a pandas DataFrame (needs pandas)."""

Progress = Dict[str, Any]
"""After each step: ``step``, ``steps``, ``time`` (s), ``newton_iterations``, ``substeps``,
``relative_residual``, ``message``."""

def run(
    scene: Scene,
    out: Optional[_Path] = None,
    progress: Union[bool, Callable[[Progress], Optional[bool]]] = True,
    checkpoint_every: int = 0,
) -> Result:
    """Runs a FEM or MPM scene to its end as ``talus run`` does, the GIL released.
    Files are written to ``out`` when given. ``progress``: a line on stderr (``True``),
    nothing (``False``), or a callable told of each step (``False`` stops the run). Ctrl-C
    stops after the step in progress, writes the files and raises ``KeyboardInterrupt``.
    ``checkpoint_every`` (needs ``out``): the full state every that many steps, for
    ``resume``. Raises ``SceneError``, ``NotConverged``, ``Collapsed``, ``Interrupted``
    (``.report``: partial ``history`` and ``summary``) or ``RunError``."""

def resume(
    out: _Path,
    progress: Union[bool, Callable[[Progress], Optional[bool]]] = True,
) -> Result:
    """Continues the checkpointed run in ``out`` to its end, bit-identical to a run never
    stopped. Raises ``RunError`` for an edited scene or a missing or corrupt checkpoint."""

class FactorOfSafety:
    """What ``factor_of_safety`` returns."""

    factor: Optional[float]
    """The middle of the final bracket; ``None`` when none was reached."""
    bracket: Tuple[Optional[float], Optional[float]]
    """The largest factor found stable, the smallest found failing."""
    method: str
    criterion: str
    trials: Dict[str, np.ndarray]
    """``history.csv``'s columns, one row per trial (row 0: the loading)."""
    summary: Dict[str, Any]

def factor_of_safety(
    scene: Scene,
    method: Optional[Literal["strength_reduction", "gravity_increase"]] = None,
    out: Optional[_Path] = None,
    progress: Union[bool, Callable[[Progress], Optional[bool]]] = True,
) -> FactorOfSafety:
    """The factor of safety of a FEM scene (docs/stability.md); ``method`` sets
    ``stability.method`` (a scene without ``[stability]`` gets it, default
    ``"strength_reduction"``). One progress call per trial. Raises ``SceneError``,
    ``NotConverged``, ``Interrupted`` or ``RunError``."""

def read_siconos(path: _Path) -> Tuple[Any, npt.NDArray[np.float64], Cones]:
    """``(W, q, cones)`` of a Siconos plasticity file: ``W`` a NumPy (n, n) array or a
    ``scipy.sparse.coo_matrix`` with the file's triplets; ``cones`` ``{"model":
    "drucker_prager", "eta", "theta"}`` or ``{"model": "von_mises", "sigma_y"}``."""

def solve_reduced(
    W: Any,
    q: npt.ArrayLike,
    cones: Cones,
    tol: float = ...,
    rho_factor: float = ...,
    global_rho: bool = False,
    max_iterations: int = ...,
) -> Tuple[npt.NDArray[np.float64], Dict[str, Any]]:
    """Solves ``z = Wσ + q``, ``σᵢ = P_K(σᵢ − ρ y(zᵢ))`` with the solver of
    ``talus reduced``; returns ``(σ, report)``. Raises ``NotConverged`` (``.report``,
    ``.solution``) unless the status is ``converged``."""
