"""Writing files so that nothing a user has is lost or half-written."""
from __future__ import annotations

import os
import tempfile
from pathlib import Path


def atomic_write(path, write):
    """Call ``write(tmp)`` on a temporary file next to ``path``, then rename it over ``path``.

    Readers see the old file or the whole new one; on any failure (an exception, Ctrl-C)
    the temporary file is removed and the old file is untouched.
    """
    path = Path(os.fspath(path))
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent or ".")
    os.close(fd)
    try:
        write(tmp)
        os.replace(tmp, path)
    except BaseException:
        remove_quietly(tmp)
        raise
    return str(path)


def remove_quietly(path):
    """Remove a (temporary) file if it is there; a cleanup must not mask the real error."""
    try:
        os.unlink(path)
    except OSError:
        pass


def atomic_write_text(path, text: str):
    """Write ``text`` to ``path`` atomically (see :func:`atomic_write`)."""
    def write(tmp):
        with open(tmp, "w", encoding="utf-8") as fh:
            fh.write(text)
    return atomic_write(path, write)
