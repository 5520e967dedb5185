"""Writing files so that nothing a user has is lost or half-written.

* :func:`atomic_write` replaces one file: readers see the old file or the whole new one.
* :class:`ResultFolder` replaces a whole folder (the CSV tables and the picture of a
  solve): everything is written into a hidden sibling folder, which is then swapped in.

New files and folders get the modes the user's umask gives (0666/0777 masked), like
those of any other tool; a replaced folder keeps the permission bits of the old one.
"""
from __future__ import annotations

import ctypes
import errno
import hashlib
import os
import re
import secrets
import shutil
import stat
from pathlib import Path

from ..errors import InputError


def _new_file(path) -> int:
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
    os.close(_new_file(tmp))
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
        os.close(_new_file(probe))
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


# ------------------------------------------------------------------- whole folders
_STAGE = re.compile(r"^\.(?P<name>.+)\.lamodel-(?P<kind>new|old)-(?P<pid>\d+)-[0-9a-f]+$")
_EXCHANGE_UNSUPPORTED = {errno.EINVAL, errno.ENOSYS, errno.ENOTSUP, errno.EOPNOTSUPP, errno.EXDEV}
_renameat2 = []


def _exchange(a, b):
    """Swap two paths in one step (Linux renameat2 with RENAME_EXCHANGE)."""
    if not _renameat2:
        try:
            _renameat2.append(ctypes.CDLL(None, use_errno=True).renameat2)
        except (AttributeError, OSError):
            _renameat2.append(None)
    if _renameat2[0] is None:
        raise OSError(errno.ENOSYS, "renameat2 is not available")
    at_fdcwd, rename_exchange = -100, 2
    if _renameat2[0](at_fdcwd, os.fsencode(a), at_fdcwd, os.fsencode(b), rename_exchange) != 0:
        code = ctypes.get_errno()
        raise OSError(code, os.strerror(code), str(a), None, str(b))


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


class ResultFolder:
    """A folder replaced as a whole: written in full beside its place, then swapped in.

    ``ResultFolder(path, foreign).open()`` checks the place and creates the hidden sibling
    ``.<name>.lamodel-new-<pid>-<token>`` (so an unwritable place is found before any
    work); write every file into :attr:`path`, then :meth:`commit`. ``foreign(folder,
    names)`` lists the names in an existing folder that its owner did not write: a user's
    own files there (a log, notes) are carried into the new folder as hard links — the
    same files, also while another program still writes them — so none is ever lost; a
    folder holding a user's sub-folder or link is refused (InputError), never emptied.

    Guarantee (Linux, any local file system with ``renameat2(RENAME_EXCHANGE)``: ext4,
    xfs, btrfs, tmpfs): at every instant, also across ``kill -9`` or a power cut, the
    path holds the complete old folder or the complete new one. Where the exchange is
    not supported, the old folder is renamed aside and the new one renamed in: a reader
    may then find no folder for an instant, and a run killed in that instant leaves the
    old folder aside, which the next ``open()`` for the same path puts back. Hidden
    siblings of dead runs are removed by the next ``open()``. The folder is a new
    directory: a shell ``cd``'d into the old one keeps seeing the old files.
    """

    def __init__(self, path, foreign):
        self.shown = str(path)
        self.final = Path(os.path.realpath(os.fspath(path)))  # a symlinked folder is replaced where it is
        self.parent = self.final.parent
        name = self.final.name
        self._key = name if len(name) <= 100 else name[:80] + hashlib.sha1(os.fsencode(name)).hexdigest()[:12]
        self._foreign = foreign
        self.path = None
        self.committed = False

    def _sibling(self, kind: str) -> Path:
        return self.parent / f".{self._key}.lamodel-{kind}-{os.getpid()}-{secrets.token_hex(4)}"

    def _leftovers(self):
        """(kind, path) of the hidden siblings of dead runs for this folder, old ones first."""
        try:
            names = os.listdir(self.parent)
        except OSError:
            return []
        found = []
        for n in names:
            m = _STAGE.match(n)
            if m and m["name"] == self._key and int(m["pid"]) != os.getpid() and not _alive(int(m["pid"])):
                found.append((m["kind"], self.parent / n))
        return sorted(found, key=lambda kp: kp[0] != "old")

    def _clean(self):
        for kind, p in self._leftovers():
            if kind == "old" and not os.path.lexists(self.final):
                os.rename(p, self.final)  # killed between the two renames: the old folder goes back
            else:
                shutil.rmtree(p, ignore_errors=True)

    def foreign_names(self) -> list:
        if not self.final.is_dir():
            return []
        return sorted(self._foreign(self.final, os.listdir(self.final)))

    def _check(self):
        f = self.final
        if os.path.lexists(f) and not f.is_dir():
            raise InputError(f"{self.shown}: exists and is not a folder; expected a folder for the result files")
        cwd = Path.cwd().resolve()
        if f == f.parent or cwd == f or f in cwd.parents:
            raise InputError(f"{self.shown}: is the current folder or holds it; expected a folder of its own for "
                             "the results (the whole folder is replaced)")
        other = [n for n in self.foreign_names() if not self._plain_file(n)]
        if other:
            shown = ", ".join(other[:3]) + (f" and {len(other) - 3} more" if len(other) > 3 else "")
            raise InputError(f"{self.shown}: holds folders or links lamodel did not write ({shown}); expected a new "
                             "folder, or one holding only files (it is replaced as a whole; files are kept)")

    def _plain_file(self, name) -> bool:
        p = self.final / name
        return p.is_file() and not p.is_symlink()

    def open(self) -> "ResultFolder":
        """Check the place, clean up after killed runs, create the staging folder."""
        try:
            if self.parent.is_dir():
                self._clean()
            self._check()
            self.parent.mkdir(parents=True, exist_ok=True)
            self._clean()
            stage = self._sibling("new")
            os.mkdir(stage, 0o777)
            self.path = stage
            if self.final.is_dir():
                os.chmod(stage, stat.S_IMODE(os.stat(self.final).st_mode))
        except OSError as exc:
            raise InputError(f"{self.shown}: cannot create the result folder ({exc.strerror or exc}); "
                             "expected a writable place (its parent folder must be writable)") from None
        return self

    def commit(self) -> str:
        """Swap the staged folder in; the old one is removed. Returns the path."""
        foreign = self.foreign_names()
        other = [n for n in foreign if not self._plain_file(n)]
        if other:  # someone put a folder there during the run: keep both, lose nothing
            self.committed = True
            raise InputError(f"{self.shown}: a folder or link lamodel did not write appeared during the run "
                             f"({other[0]}); the new results are left in {self.path}")
        for name in foreign:  # the user's own files go along (same inodes)
            os.link(self.final / name, self.path / name)
        fsync_path(self.path)
        old = None
        if not os.path.lexists(self.final):
            os.rename(self.path, self.final)
        else:
            try:
                _exchange(self.path, self.final)
                old = self.path
            except OSError as exc:
                if exc.errno not in _EXCHANGE_UNSUPPORTED:
                    raise
                old = self._sibling("old")
                os.rename(self.final, old)
                os.rename(self.path, self.final)
        self.committed = True
        if old is not None:
            for name in self._foreign(old, os.listdir(old)):  # a file of the user's made in the last instant
                if not os.path.lexists(self.final / name):
                    os.rename(old / name, self.final / name)
            shutil.rmtree(old, ignore_errors=True)
        fsync_path(self.parent)
        return self.shown

    def discard(self):
        """Remove the staging folder unless it was committed (a failed or interrupted run)."""
        if self.path is not None and not self.committed:
            shutil.rmtree(self.path, ignore_errors=True)

    def __enter__(self):
        return self.open() if self.path is None else self

    def __exit__(self, *exc):
        self.discard()
        return False
