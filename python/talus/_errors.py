"""The exceptions of the talus package (raised by the native module too)."""
from __future__ import annotations

from typing import Any, Optional


class TalusError(Exception):
    """Base class of every error the talus package raises."""


class SceneError(TalusError, ValueError):
    """A scene that cannot be run: the field (a dotted TOML path such as
    ``material.friction_angle`` or ``boundary[3].velocity``), its value (``None`` when the
    field is missing), the reason, and the line of the scene text when it is known."""

    def __init__(
        self,
        field: str,
        value: Any,
        reason: str,
        line: Optional[int] = None,
        file: Optional[str] = None,
    ) -> None:
        self.field = field
        self.value = value
        self.reason = reason
        self.line = line
        self.file = file
        where = file or "scene"
        if line is not None:
            where = f"{where}:{line}"
        shown = "" if value is None else f" = {value!r}"
        super().__init__(f"{where}: {field}{shown}: {reason}")


class SiconosError(TalusError, ValueError):
    """A Siconos plasticity file that cannot be read (the message names the line)."""


class InvalidProblem(TalusError, ValueError):
    """A reduced problem whose arrays do not fit together or whose cones are invalid."""


class NotConverged(TalusError):
    """The semi-smooth Newton solve did not reach the tolerance.

    ``report`` is the solver's report (``solve_reduced``) or the run's partial result
    (``run``: ``history`` and ``summary``); ``solution`` is the last iterate σ of
    ``solve_reduced`` (``None`` for ``run``)."""

    def __init__(self, message: str, report: Any, solution: Any = None) -> None:
        super().__init__(message)
        self.report = report
        self.solution = solution


class RunError(TalusError):
    """A run that stopped for another reason than non-convergence (an output that cannot be
    written, a failed step); ``report`` holds what the run wrote before it stopped."""

    def __init__(self, message: str, report: Any = None) -> None:
        super().__init__(message)
        self.report = report


class Collapsed(RunError):
    """A load past the body's capacity: the run stopped at the step where the collapse
    criterion held (``summary["collapse"]`` has the step and time, ``docs/scenes.md``,
    'Collapse'); ``report`` holds the history and summary up to there."""


class Interrupted(RunError):
    """The progress callback returned ``False``: the run stopped after the step in
    progress and wrote its files (status ``interrupted``); ``report`` holds them. Ctrl-C
    raises ``KeyboardInterrupt`` the same way, once the files are written."""


# Shown as talus.SceneError etc. in tracebacks: the public names.
for _cls in (
    TalusError,
    SceneError,
    SiconosError,
    InvalidProblem,
    NotConverged,
    RunError,
    Collapsed,
    Interrupted,
):
    _cls.__module__ = "talus"
