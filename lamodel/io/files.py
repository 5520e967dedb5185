"""Writing files so that nothing a user has is lost or half-written.

* :func:`atomic_write` replaces one file: readers see the old file or the whole new one.
* :func:`write_csv` writes a table that way.

A whole result folder is replaced the same way by
:class:`lamodel.output.folder.ResultFolder`.

New files get the modes the user's umask gives (0666 masked), like those of
any other tool.
"""
from __future__ import annotations

import os
import re
import secrets
from pathlib import Path

from ..errors import InputError


def new_file(path) -> int:
    """Create ``path`` exclusively, mode 0666 less the umask (mkstemp would give 0600)."""
    return os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_CLOEXEC", 0), 0o666)


def fsync_path(path):
    """Flush a file or a folder to disk (a rename is durable only after its data is)."""
    fd = os.open(path, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def atomic_write(path, write):
    """Call ``write(tmp)`` on a temporary file next to ``path``, then rename it over ``path``.

    Readers see the old file or the whole new one; on any failure (an exception, Ctrl-C)
    the temporary file is removed and the old file is untouched.
    """
    path = Path(os.fspath(path))
    tmp = (path.parent or Path(".")) / f".{path.name}.{secrets.token_hex(4)}.tmp"
    os.close(new_file(tmp))
    try:
        write(str(tmp))
        fsync_path(tmp)
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


def check_writable_folder(folder, what: str):
    """InputError unless a file can be created in ``folder`` (probed: permission bits do
    not tell about read-only file systems, or root)."""
    folder = Path(os.fspath(folder) or ".")
    if not folder.is_dir():
        raise InputError(f"{what}: the folder {folder} does not exist; expected an existing folder")
    probe = folder / f".lamodel-probe-{os.getpid()}-{secrets.token_hex(4)}"
    try:
        os.close(new_file(probe))
    except OSError as exc:
        raise InputError(f"{what}: cannot write in {folder} ({exc.strerror or exc}); expected a writable folder") from None
    remove_quietly(probe)


def read_text(path, what: str) -> str:
    """The text of a UTF-8 file (a byte-order mark is dropped); InputError naming the file
    and the first bad byte otherwise."""
    try:
        data = Path(path).read_bytes()
    except OSError as exc:
        raise InputError(f"{path}: cannot read the file ({exc.strerror or exc}); expected a readable {what}") from None
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        line = data[:exc.start].count(b"\n") + 1
        raise InputError(f"{path}: not UTF-8 text (byte 0x{data[exc.start]:02x} on line {line}); "
                         f"expected a UTF-8 {what}") from None


def safe_folder_name(name: str) -> str:
    """A single folder name made from a structure's name: no separators, no '..', no
    leading dot; what the JSON 'name' says can never point outside results/."""
    safe = re.sub(r"[^\w.\-]+", "_", str(name)).strip("._-")
    return safe[:100] or "structure"


def write_csv(df, path) -> str:
    """Write a table (a pandas DataFrame) as CSV atomically (a reader never sees a partial
    file); folders are created. Floats are written in their shortest round-trip form."""
    path = Path(os.fspath(path))
    path.parent.mkdir(parents=True, exist_ok=True)
    atomic_write(path, lambda tmp: df.to_csv(tmp, index=False))
    return str(path)
