"""The result folder of a solve, in one place: its names (lamodel's files, and the user's
that it must never delete), the places of its picture, report and animation, checked
before any work, and :class:`ResultFolder`, which replaces it as a whole.

No pandas here: a result folder is checked before solving, while pandas loads.
"""
from __future__ import annotations

import csv
import ctypes
import errno
import hashlib
import os
import re
import secrets
import shutil
import stat
from pathlib import Path

from ..errors import InputError, OutputError
from ..io.files import check_writable_folder, fsync_path
from ..signals import staged, unstaged

#: The four tables of a result folder (:mod:`lamodel.output.results`), by name.
TABLE_FILES = {"summary": "summary.csv", "blocks": "blocks.csv", "contacts": "contacts.csv", "runs": "runs.csv"}

#: The files of a result folder. The picture, the HTML report, the animation and the 3D
#: browser view, when written into it, are named in summary.csv's columns ``picture``,
#: ``report``, ``animation`` and ``view`` (by the command line); ``mechanism.*`` is the picture's default name.
RESULT_FILES = tuple(TABLE_FILES.values())
#: What ``lamodel solve`` writes beside them for --method all, load cases, rolling loads.
COMPANION_FILES = ("methods.csv", "cases.csv", "rolling.csv", "rolling.png")
PICTURE_STEM = "mechanism"
_PICTURE_EXTENSIONS = {"png", "svg", "svgz", "pdf", "eps", "ps", "jpg", "jpeg", "tif", "tiff", "webp", "pgf",
                       "raw", "rgba", "gif", "avif"}  # matplotlib's formats
_RECORDED = {"picture": _PICTURE_EXTENSIONS, "report": {"html", "htm"}, "animation": {"gif"}, "view": {"html", "htm"}}
_LEFTOVER = re.compile(r"^\.(?P<name>.+)\.[^.]+\.(tmp|bak)$")  # temporary files of older lamodel versions


def recorded_files(folder: Path) -> set:
    """The files beside the tables that the folder's summary.csv names as written there."""
    try:
        with open(folder / "summary.csv", newline="", encoding="utf-8") as fh:
            row = next(csv.DictReader(fh), None) or {}
    except (OSError, UnicodeDecodeError, csv.Error):
        return set()
    names = set()
    for column, extensions in _RECORDED.items():
        name = str(row.get(column) or "")
        if name == Path(name).name and not name.startswith(".") and name.rsplit(".", 1)[-1].lower() in extensions:
            names.add(name)
    return names


def foreign_files(folder, names) -> list:
    """The names in a result folder that lamodel did not write (they make it refuse to
    replace the folder: a user's own files are never deleted)."""
    folder = Path(folder)
    ours = {*RESULT_FILES, *COMPANION_FILES, *recorded_files(folder)}

    def owned(name):
        if name in ours or (name.startswith(PICTURE_STEM + ".")
                            and name[len(PICTURE_STEM) + 1:].lower() in _PICTURE_EXTENSIONS):
            return os.path.isfile(folder / name) or os.path.islink(folder / name)
        m = _LEFTOVER.match(name)
        return bool(m) and owned(m["name"])
    return [n for n in names if not owned(n)]


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
            staged(stage)  # named before it exists: removed by a run a stop signal ends, at any instant
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
        unstaged(self.path)
        if old is not None:
            for name in self._foreign(old, os.listdir(old)):  # a file of the user's made in the last instant
                if not os.path.lexists(self.final / name):
                    os.rename(old / name, self.final / name)
            shutil.rmtree(old, ignore_errors=True)
        fsync_path(self.parent)
        return self.shown

    def publish(self) -> str:
        """:meth:`commit`, a failure to write being an OutputError (one line)."""
        try:
            return self.commit()
        except OSError as exc:
            raise OutputError(exc.errno, f"cannot write the results to {self.shown}: {exc.strerror or exc}") from None

    def discard(self):
        """Remove the staging folder unless it was committed (a failed or interrupted run)."""
        if self.path is not None and not self.committed:
            shutil.rmtree(self.path, ignore_errors=True)
            unstaged(self.path)

    def __enter__(self):
        return self.open() if self.path is None else self

    def __exit__(self, *exc):
        self.discard()
        return False


# ------------------------------------------------------------------- places of the extras
def picture_place(plot, out) -> Path:
    """Where the picture goes, checked before solving: a known format, a writable place.
    ``plot`` None: ``<out>/mechanism.png``. Beside the tables it is part of the result
    folder (the path returned is then in the folder's final place); elsewhere its folder
    must exist."""
    path = Path(plot) if plot else Path(out) / f"{PICTURE_STEM}.png"
    ext = path.suffix.lower().lstrip(".")
    supported = ("png",)
    if ext != "png":  # any other format: ask matplotlib (0.6 s to load; png needs no asking)
        from matplotlib.backend_bases import FigureCanvasBase
        supported = FigureCanvasBase.get_supported_filetypes()
    if ext not in supported:
        raise InputError(f"{path}: unknown picture format '{path.suffix}'; expected one of "
                         f"{', '.join('.' + e for e in sorted(supported))}")
    if in_folder(path, out):
        return Path(os.path.realpath(out)) / path.name
    if os.path.isdir(path):
        raise InputError(f"{path}: is a folder; expected a picture file name")
    check_writable_folder(path.parent, f"picture {path}")
    return path


def check_output_file(what: str, path, suffixes, out):
    """A file written besides the tables (the report, the animation): one of ``suffixes``,
    not a folder, and in a writable folder (or in the result folder ``out``, which then
    holds it). ``what`` names it in errors."""
    p = Path(path)
    if p.suffix.lower() not in suffixes:
        raise InputError(f"{path}: {what} writes a {suffixes[0]} file; expected a file name ending in {suffixes[0]}")
    if p.is_dir():
        raise InputError(f"{path}: is a folder; expected a file name for {what}")
    if not in_folder(p, out):
        check_writable_folder(p.parent, f"{what} {path}")


def in_folder(path, folder) -> bool:
    """True when ``path`` names a file directly in ``folder`` (links resolved)."""
    return path is not None and os.path.realpath(Path(path).parent) == os.path.realpath(folder)
