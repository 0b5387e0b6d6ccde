"""Atomic file writing on the Python side, like the core's writers: the
data goes to a temporary sibling that is renamed into place, so a reader
never sees a partial file; when anything fails the temporary is removed,
the target is left as it was, and the error is a :class:`FileError`."""
from __future__ import annotations

import itertools
import os
from contextlib import contextmanager
from typing import Iterator

from .errors import FileError

_calls = itertools.count()


def file_error(path: str, e: BaseException) -> FileError:
    """A FileError for ``path``, worded like the core's (``i/o error: …``)."""
    message = e.strerror if isinstance(e, OSError) and e.strerror else str(e)
    err = FileError(f"i/o error: {path}: {message}")
    err.kind, err.path, err.message = "Io", str(path), message
    return err


@contextmanager
def temporary_for(path: str) -> Iterator[str]:
    """Yields a temporary path next to ``path``; the caller writes it.
    On leaving without an error it is renamed to ``path``; on any error it
    is removed (and an OSError becomes a FileError naming ``path``)."""
    path = os.fspath(path)
    parent, name = os.path.split(os.path.abspath(path))
    tmp = os.path.join(parent, f".{name}.tmp{os.getpid()}-{next(_calls)}")
    try:
        try:
            yield tmp
            os.replace(tmp, path)
        except BaseException:
            try:
                os.remove(tmp)
            except OSError:
                pass  # never created
            raise
    except OSError as e:
        if isinstance(e, FileError):
            raise
        raise file_error(path, e) from e


def write_text(path: str, text: str) -> None:
    """Writes ``text`` (UTF-8) to ``path`` atomically (see temporary_for)."""
    with temporary_for(path) as tmp:
        with open(tmp, "w", newline="", encoding="utf-8") as f:
            f.write(text)


def writable_dir(path: str, what: str) -> None:
    """Creates directory ``path`` if needed and checks that a file can be
    written in it (root ignores permission bits, so it is tried, not read);
    a SceneError keyed ``out`` naming ``what`` otherwise."""
    from .errors import _scene_error
    try:
        os.makedirs(path, exist_ok=True)
    except OSError as e:
        raise _scene_error("out", f"cannot create the {what} {path}: {e.strerror or e}", path) from e
    probe = os.path.join(path, f".write-test-{os.getpid()}")
    try:
        with open(probe, "w"):
            pass
        os.remove(probe)
    except OSError as e:
        raise _scene_error("out", f"the {what} {path} is not writable: {e.strerror or e}", path) from e
