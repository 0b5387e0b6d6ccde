"""The strandkit exception hierarchy, one class per variant of the core's
typed error (``strandkit_core::Error``). Every class derives from
:class:`StrandkitError` and from the built-in exception Python users already
catch (``ValueError`` for bad input, ``RuntimeError`` for solver failures,
``OSError`` for files). The variant's fields are attributes of the
exception (e.g. ``err.what``, ``err.value``, ``err.expected``;
``err.unknown``, ``err.constraints``; ``err.iterations``, ``err.residual``).

>>> import strandkit as sk
>>> try:
...     sk.World(dt=-1.0)
... except sk.InvalidInputError as e:
...     print(e.what, "|", e.value, "|", e.expected)
dt | -1 | finite and > 0
"""
from __future__ import annotations

__all__ = [
    "StrandkitError", "InvalidInputError", "InvalidHandleError", "SolverError", "SingularError",
    "ConvergenceError", "NonFiniteError", "DivergedError", "FileError", "WorldBusyError", "SceneError",
    "Interrupted",
]


class StrandkitError(Exception):
    """Base class of every error raised by strandkit."""

    #: The core's variant name ("InvalidInput", "Singular", …).
    kind: str = ""


class InvalidInputError(StrandkitError, ValueError):
    """A value out of its range, NaN/inf, or inconsistent with the rest of the
    input. Attributes: ``what`` (the argument), ``value`` (what was given),
    ``expected`` (what is accepted)."""

    what: str
    value: str
    expected: str


class InvalidHandleError(StrandkitError, ValueError):
    """A handle that names nothing in this world (removed, broken, or from
    another world). Attribute: ``what``."""


class SolverError(StrandkitError, RuntimeError):
    """The solver could not produce a valid new state; the world is unchanged."""


class SingularError(SolverError):
    """Singular system (under-constrained structure, contradictory
    constraints). Attributes: ``unknown`` (a dict naming the unknown, or
    None), ``constraints`` (list of constraint handles involved),
    ``detail``."""


class ConvergenceError(SolverError):
    """An iterative solve did not reach its tolerance. Attributes:
    ``iterations``, ``residual``, ``detail``."""


class NonFiniteError(SolverError):
    """A solve produced NaN/inf; nothing was committed. Attribute: ``rod``."""


class DivergedError(SolverError):
    """A step's energy or increment jumped beyond the allowed factor.
    Attributes: ``step``, ``rod``, ``factor``."""


class FileError(StrandkitError, OSError):
    """Reading or writing a file failed, or its content is not what strandkit
    writes (corrupt, foreign or old format). Attributes: ``path``, ``message``."""


class WorldBusyError(StrandkitError, RuntimeError):
    """The world (or QuasiDynamic driver) is being stepped in another thread
    right now (``step``, ``relax`` and frames run without the GIL): the call
    did nothing; retry once that step has returned. Not a core variant:
    raised by the bindings."""


class SceneError(InvalidInputError):
    """A scene file or a sweep grid that cannot run: an unknown version or
    key, a value out of range, a missing file, an output directory that is
    not writable. Raised before any work starts. Attributes: ``key`` (the
    dotted path of the offending entry, e.g. ``protocol[1].pull.velocity``),
    ``what``, ``value``, ``expected``."""

    key: str


class Interrupted(StrandkitError, KeyboardInterrupt):
    """A scene run or sweep stopped by Ctrl-C (or SIGTERM) between two steps:
    the outputs written so far are valid and a snapshot to resume from is on
    disk. Attributes: ``out`` (the output directory), ``time`` (simulated
    time reached), ``done`` (sweep points finished)."""


def _scene_error(key: str, problem: str, value=None, expected: str = "") -> SceneError:
    """A SceneError naming ``key``: ``invalid scene: <key>: <problem>``."""
    text = f"{key}: {problem}" if key else problem
    if expected:
        text += f" (expected {expected})"
    e = SceneError(f"invalid scene: {text}")
    e.kind, e.key, e.what, e.problem = "InvalidInput", key, key, problem
    e.value, e.expected = "" if value is None else repr(value), expected
    return e


def _invalid(what: str, value: str = "", expected: str = "") -> InvalidInputError:
    """An InvalidInputError raised on the Python side, worded like the
    core's (``invalid input: <what> must be <expected>, got <value>``)."""
    if value and expected:
        text = f"{what} must be {expected}, got {value}"
    elif expected:
        text = f"{what}: expected {expected}"
    elif value:
        text = f"{what}, got {value}"
    else:
        text = what
    e = InvalidInputError(f"invalid input: {text}")
    e.kind, e.what, e.value, e.expected = "InvalidInput", what, value, expected
    return e


#: core variant name → class (used by the native module).
BY_KIND = {
    "InvalidInput": InvalidInputError,
    "InvalidHandle": InvalidHandleError,
    "Singular": SingularError,
    "NotConverged": ConvergenceError,
    "NonFinite": NonFiniteError,
    "Diverged": DivergedError,
    "Io": FileError,
}
