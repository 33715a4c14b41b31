"""Talus: implicit elasto-plasticity of geomaterials by semi-smooth Newton, from Python.

The native module calls the Talus library crates: the scene parser of ``talus run``, its
run loop, and the SSN solver of ``talus reduced``. Nothing is computed here; this module
shapes arrays and exceptions.
"""
from __future__ import annotations

import csv
import io
import json
import os
import sys
from typing import Any, Callable, Dict, List, Optional, Tuple, Union

import numpy as np

from . import _talus
from ._errors import (
    Collapsed,
    Interrupted,
    InvalidProblem,
    NotConverged,
    RunError,
    SceneError,
    SiconosError,
    TalusError,
)
from ._talus import Scene

__all__ = [
    "Scene",
    "Result",
    "run",
    "resume",
    "factor_of_safety",
    "FactorOfSafety",
    "read_siconos",
    "solve_reduced",
    "TalusError",
    "SceneError",
    "SiconosError",
    "InvalidProblem",
    "NotConverged",
    "RunError",
    "Collapsed",
    "Interrupted",
]


class Result:
    """What ``talus.run`` returns.

    ``history``: one float64 array per ``history.csv`` column, in the file's order, with
    the file's values (row 0 is the initial state). ``summary``: the content of
    ``summary.json``. ``state``: the final state's arrays (see ``talus.run``).
    ``kind``: ``"fem"`` or ``"mpm"``; ``dimension``: 2, or 3 for ``geometry = "3d"``.
    ``stages``: a staged scene's stages, in order, each
    a dict of ``summary.json``'s entry (``name``, ``first_step``, ``last_step``, ``time``,
    ``elements``, ``deactivated``, ``activated``, ``reaction``, ``factor_of_safety``);
    ``history["stage"]`` is each row's stage index. Empty for an unstaged scene."""

    def __init__(self, raw: Dict[str, Any]) -> None:
        self.kind: str = raw["kind"]
        self.dimension: int = int(raw.get("dimension", 2))
        self.history: Dict[str, np.ndarray] = dict(raw["history"])
        self.summary: Dict[str, Any] = json.loads(raw["summary_json"])
        self.state: Dict[str, np.ndarray] = dict(raw["state"])
        self.stages: List[Dict[str, Any]] = list(self.summary.get("stages", []))

    def to_pandas(self) -> Any:
        """The history as a pandas DataFrame (pandas must be installed)."""
        import pandas as pd

        return pd.DataFrame(self.history)

    def __repr__(self) -> str:
        steps = len(next(iter(self.history.values()))) - 1 if self.history else 0
        return f"<talus.Result {self.kind} {self.dimension}D, {steps} steps, status {self.summary.get('status')!r}>"


def _partial(raw: Dict[str, Any]) -> Dict[str, Any]:
    """What a failed run had written: history arrays and summary dict."""
    out: Dict[str, Any] = {}
    if "history" in raw:
        out["history"] = dict(raw["history"])
    if "summary_json" in raw:
        out["summary"] = json.loads(raw["summary_json"])
    return out


Progress = Dict[str, Any]


class _ProgressLine:
    """``progress=True``: on a terminal or in Jupyter, one line on stderr rewritten after
    every step; elsewhere (a log file, CI) a line at every tenth of the run."""

    def __init__(self) -> None:
        self.interactive = sys.stderr.isatty() or "ipykernel" in sys.modules
        self.shown = False
        self.tenth = -1

    def __call__(self, p: Progress) -> None:
        text = f"step {p['step']}/{p['steps']}  t = {p['time']:.6g} s  {p['message']}"
        if self.interactive:
            # "\x1b[K" clears what a longer line left.
            sys.stderr.write("\r" + text + "\x1b[K")
            self.shown = True
        else:
            tenth = 10 * p["step"] // max(p["steps"], 1)
            if tenth == self.tenth:
                return
            self.tenth = tenth
            sys.stderr.write(text + "\n")
        sys.stderr.flush()

    def close(self) -> None:
        if self.shown:
            sys.stderr.write("\n")
            sys.stderr.flush()


def run(
    scene: Scene,
    out: Optional[Union[str, "os.PathLike[str]"]] = None,
    progress: Union[bool, Callable[[Progress], Optional[bool]]] = True,
    checkpoint_every: int = 0,
) -> Result:
    """Runs a FEM or MPM scene to its end, as ``talus run`` does, with the GIL released.

    ``out``: a folder for the CLI's files (history.csv, summary.json, VTU, PNG plots);
    without it nothing is kept. ``progress``: ``True`` reports on stderr (a line rewritten
    after each step on a terminal or in Jupyter, a line per tenth of the run elsewhere);
    ``False`` is silent; a callable is called after each step with a dict ``step``,
    ``steps``, ``time`` (s), ``newton_iterations``, ``substeps``, ``relative_residual`` and
    ``message``, and returning ``False`` stops the run (``Interrupted``). Ctrl-C stops it
    after the step in progress: the files are written (``summary.json`` status
    ``interrupted``), then ``KeyboardInterrupt`` is raised. ``checkpoint_every``: with
    ``out``, the full state every that many steps and at an interruption, for ``resume``
    (docs/scenes.md, 'Checkpoints and resume').

    The result's ``dimension`` is 2, or 3 for a scene with ``geometry = "3d"``. FEM
    ``state``: ``nodes`` (n_nodes, 2 or 3), ``cells`` (n_cells, int64, Gmsh node order:
    3 or 6 per triangle, 4 or 10 per tetrahedron), ``displacement`` (n_nodes, 2 or 3),
    ``stress`` (n_points, 4 or 6, Mandel σxx, σyy, σzz, √2 σxy in 2D; σxx, σyy, σzz,
    √2 σyz, √2 σxz, √2 σxy in 3D), ``plastic_strain`` (n_points,), ``gauss_element``
    (n_points,) the cell of each Gauss point. MPM ``state``: ``positions``, ``velocity``
    (n, 2), ``stress`` (n, 4), ``plastic_strain`` (n,).

    Raises ``SceneError`` for a scene the model builder rejects, ``NotConverged`` when a
    step does not converge after its halvings, ``Collapsed`` when the load passes the
    body's capacity, ``Interrupted`` when the callback stops the run (each with
    ``.report``: the partial ``history`` and ``summary``), ``RunError`` otherwise."""
    if _has(scene, "stability") and not _has(scene, "stage"):
        raise SceneError(
            "stability", None, "a factor-of-safety scene: call talus.factor_of_safety(scene)",
            None, scene.path,
        )
    path = None if out is None else os.fspath(out)
    return _stepped(progress, lambda callback: _talus.run(scene, path, callback, checkpoint_every))


def resume(
    out: Union[str, "os.PathLike[str]"],
    progress: Union[bool, Callable[[Progress], Optional[bool]]] = True,
) -> Result:
    """Continues the run whose checkpoint is in ``out`` (``talus run`` or ``talus.run`` with
    ``checkpoint_every``, killed or interrupted), as ``talus resume OUT`` does: the files
    are cut back to the checkpoint's step and the run goes on to its end; ``history`` and
    the final state are bit-identical to a run that was never stopped. A scene edited since
    the checkpoint, or a missing or corrupt checkpoint, raises ``RunError``. ``progress``:
    as in ``run``."""
    path = os.fspath(out)
    return _stepped(progress, lambda callback: _talus.resume(path, callback))


def _stepped(progress: Any, call: Callable[[Any], Dict[str, Any]]) -> Result:
    return Result(_with_progress(progress, call, _partial))


def _with_progress(
    progress: Any,
    call: Callable[[Any], Dict[str, Any]],
    shape: Callable[[Dict[str, Any]], Dict[str, Any]],
) -> Dict[str, Any]:
    """``call(callback)`` with the progress reporting asked for; a failed run's ``report``
    (the files it wrote, as text) is shaped by ``shape``."""
    line = _ProgressLine() if progress is True else None
    callback = line if line is not None else (progress if callable(progress) else None)
    try:
        return call(callback)
    except (NotConverged, RunError) as e:
        if isinstance(e.report, dict):
            e.report = shape(e.report)
        raise
    finally:
        if line is not None:
            line.close()


class FactorOfSafety:
    """What ``talus.factor_of_safety`` returns.

    ``factor``: the middle of the final bracket (``None`` if none was reached within
    ``max_trials``); ``bracket``: ``(lo, hi)``, the largest factor found stable and the
    smallest found failing (``None`` where no trial said so); ``method`` and ``criterion``
    in words; ``trials``: the ``history.csv`` columns, one row per trial, row 0 the loading
    (``outcome`` an array of str, the other columns float64, NaN where the file is blank);
    ``summary``: the content of ``summary.json``."""

    def __init__(self, raw: Dict[str, Any]) -> None:
        self.summary: Dict[str, Any] = json.loads(raw["summary_json"])
        fos = self.summary["factor_of_safety"]
        self.factor: Optional[float] = fos["value"]
        self.bracket: Tuple[Optional[float], Optional[float]] = tuple(fos["bracket"])
        self.method: str = fos["method"]
        self.criterion: str = fos["criterion"]
        self.trials: Dict[str, np.ndarray] = _trials(raw["history_csv"])

    def __repr__(self) -> str:
        lo, hi = self.bracket
        return f"<talus.FactorOfSafety {self.method}: F = {self.factor} in [{lo}, {hi}], {len(self.trials['trial']) - 1} trials>"


def _trials(text: str) -> Dict[str, np.ndarray]:
    rows = list(csv.reader(io.StringIO(text)))
    header, rows = rows[0], rows[1:]
    columns: Dict[str, np.ndarray] = {}
    for j, name in enumerate(header):
        values = [r[j] for r in rows]
        if name == "outcome":
            columns[name] = np.array(values, dtype=str)
        else:
            columns[name] = np.array([float(v) if v else np.nan for v in values])
    return columns


def factor_of_safety(
    scene: Scene,
    method: Optional[str] = None,
    out: Optional[Union[str, "os.PathLike[str]"]] = None,
    progress: Union[bool, Callable[[Progress], Optional[bool]]] = True,
) -> FactorOfSafety:
    """The factor of safety of a FEM scene, as ``talus run`` computes it for a scene with
    ``[stability]`` (docs/stability.md): the loading to equilibrium, then trials that
    bisect on the factor until the bracket is within the tolerance.

    ``method``: ``"strength_reduction"`` (c and tan φ divided by F) or
    ``"gravity_increase"`` (gravity multiplied by F); it sets ``stability.method``, and a
    scene without ``[stability]`` gets that section with its defaults
    (``"strength_reduction"`` when ``method`` is ``None``). ``out``, ``progress``: as in
    ``run``, with one progress call per trial (``step`` counts trials, ``message`` gives
    the factor and its outcome).

    Raises ``SceneError``, ``NotConverged`` (the loading did not reach equilibrium),
    ``Interrupted`` or ``RunError``."""
    if method is not None or not _has(scene, "stability"):
        scene = scene.set("stability.method", method or "strength_reduction")
    path = None if out is None else os.fspath(out)
    raw = _with_progress(
        progress, lambda callback: _talus.factor_of_safety(scene, path, callback), _trial_report
    )
    return FactorOfSafety(raw)


def _trial_report(raw: Dict[str, Any]) -> Dict[str, Any]:
    """What a stopped factor of safety wrote: ``summary`` and ``trials``."""
    out: Dict[str, Any] = {}
    if "summary_json" in raw:
        out["summary"] = json.loads(raw["summary_json"])
    if "history_csv" in raw:
        out["trials"] = _trials(raw["history_csv"])
    return out


def _has(scene: Scene, field: str) -> bool:
    try:
        scene.get(field)
    except KeyError:
        return False
    return True


Cones = Dict[str, Any]


def read_siconos(path: Union[str, "os.PathLike[str]"]) -> Tuple[Any, np.ndarray, Cones]:
    """Reads a Siconos plasticity problem (the format of ``talus reduced``).

    Returns ``(W, q, cones)``: ``W`` a NumPy (n, n) array for a dense file or a
    ``scipy.sparse.coo_matrix`` with the file's triplets in the file's order (duplicates
    kept, summed by the solver) for a sparse one; ``q`` (n,); ``cones`` a dict with
    ``model`` ``"drucker_prager"`` and per-cone ``eta`` and ``theta``, or ``"von_mises"``
    and ``sigma_y``."""
    raw = _talus.read_siconos(os.fspath(path))
    n = raw["n"]
    if "dense" in raw:
        W: Any = raw["dense"]
    else:
        try:
            from scipy.sparse import coo_matrix
        except ImportError as e:
            raise ImportError(
                "this Siconos file stores W sparse: install scipy (pip install scipy)"
            ) from e
        W = coo_matrix((raw["values"], (raw["rows"], raw["cols"])), shape=(n, n))
    if raw["model"] == "drucker_prager":
        cones: Cones = {"model": "drucker_prager", "eta": raw["eta"], "theta": raw["theta"]}
    else:
        cones = {"model": "von_mises", "sigma_y": raw["sigma_y"]}
    return W, raw["q"], cones


def _f64(a: Any, name: str) -> np.ndarray:
    try:
        return np.ascontiguousarray(np.asarray(a, dtype=np.float64).ravel())
    except (TypeError, ValueError) as e:
        raise InvalidProblem(f"{name}: not an array of numbers: {e}") from e


def solve_reduced(
    W: Any,
    q: Any,
    cones: Cones,
    tol: float = _talus.REDUCED_TOLERANCE,
    rho_factor: float = _talus.REDUCED_RHO_FACTOR,
    global_rho: bool = False,
    max_iterations: int = _talus.REDUCED_MAX_ITERATIONS,
) -> Tuple[np.ndarray, Dict[str, Any]]:
    """Solves one reduced problem ``z = Wσ + q``, ``σᵢ = P_K(σᵢ − ρ y(zᵢ))`` per cone of
    dimension 3, with the solver and settings of ``talus reduced``.

    ``W``: a NumPy (n, n) array or any SciPy sparse matrix (its COO triplets are used,
    duplicates summed). ``cones``: as ``read_siconos`` returns it. ``tol``: stop when
    ‖F‖∞ ≤ tol·max(1, ‖σ‖∞). ``rho_factor``/``global_rho``: ρ = factor / max diag W, per
    cone unless global. Returns ``(σ, report)``; ``report`` has the keys of
    ``talus reduced --json`` (status, iterations, residual, relative_residual, …).

    Raises ``NotConverged`` (``.report``, ``.solution``) when the status is not
    ``converged`` (the CLI's exit codes 2 and 3), ``InvalidProblem`` for arrays or cones
    that do not fit."""
    q = _f64(q, "q")
    n = q.shape[0]
    dense = rows = cols = values = None
    if hasattr(W, "tocoo") and not isinstance(W, np.ndarray):
        coo = W.tocoo()
        if coo.shape != (n, n):
            raise InvalidProblem(f"W is {coo.shape[0]}×{coo.shape[1]}, q has length {n}")
        rows = np.ascontiguousarray(coo.row, dtype=np.int64)
        cols = np.ascontiguousarray(coo.col, dtype=np.int64)
        values = _f64(coo.data, "W")
    else:
        dense = np.ascontiguousarray(np.asarray(W, dtype=np.float64))
        if dense.shape != (n, n):
            raise InvalidProblem(f"W has shape {dense.shape}, q has length {n}")
    model = cones.get("model", "drucker_prager")
    eta = theta = sigma_y = None
    if model == "drucker_prager":
        eta = _f64(cones["eta"], "cones['eta']")
        theta = _f64(cones.get("theta", np.zeros_like(eta)), "cones['theta']")
    elif model == "von_mises":
        sigma_y = _f64(cones["sigma_y"], "cones['sigma_y']")
    else:
        raise InvalidProblem(f"cones['model'] = {model!r}: 'drucker_prager' or 'von_mises'")
    sigma, report, converged = _talus.solve_reduced(
        n, q, model, dense, rows, cols, values, eta, theta, sigma_y,
        float(tol), float(rho_factor), bool(global_rho), int(max_iterations),
    )
    if not converged:
        raise NotConverged(
            f"reduced solve: {report['status']} after {report['iterations']} iterations, "
            f"relative residual {report['relative_residual']:.3e} > tol {tol:.1e}",
            report,
            sigma,
        )
    return sigma, report
