"""Writing output so that a failure never leaves a partial, stale or mixed file or folder behind.

- :func:`atomic_write_text` / :func:`atomic_write_bytes`: a temporary file in the same folder renamed into place;
  the file gets the user's normal permissions (0666 minus the umask), not tempfile's 0600.
- :func:`atomic_output_dir`: a folder's files are built in a run-unique staging sibling and moved into ``path``
  (other files of ``path`` are kept) only when the block succeeds.
- :func:`replace_output_dir`: a whole output folder built in a run-unique staging sibling and swapped in as a
  whole (Linux ``renameat2(RENAME_EXCHANGE)``: one atomic step; elsewhere two renames, so a reader may briefly
  find no folder but never one that mixes two runs), under an exclusive lock (:func:`output_lock`) so that two
  runs into the same folder cannot interleave. Only a folder that is new, empty or an earlier output of the tool
  (it holds one of :data:`OUTPUT_FILES`) is replaced; anything else is refused (InputError), never deleted.
- :func:`staged_output_dir`: a folder built in a staging sibling that grows (a wear run, step by step). Each
  :meth:`StagedOutput.publish` puts a snapshot of it in place of the visible sibling ``<name>.partial``
  (:func:`partial_dir`); :meth:`StagedOutput.finish` puts the ended run in place of ``path`` and removes the
  partial folder. So ``path`` keeps an earlier output until the new run ends (a ``kill -9`` cannot put anything
  back, hence nothing is taken away before the end), and the completed part of a killed run is in the partial
  folder. A snapshot is the staging folder's files hard-linked into a fresh sibling swapped in as a whole.
- Staging folders are named ``.<name>.staging-<pid>-<random>``; those whose process is gone (a killed run) are
  removed by the next run into the same folder (:func:`clean_stale_staging`), which also puts back an earlier
  output that a kill caught between the two renames of the non-atomic swap.
- A file or folder that cannot be written (disk full, permissions, read-only file system) raises
  :class:`OutputError` naming its path (``error: <path>: no space left on device``).
"""

from __future__ import annotations

import contextlib
import ctypes
import ctypes.util
import errno
import fcntl
import os
import shutil
import tempfile
from collections.abc import Iterator
from pathlib import Path

from wrlayer.errors import InputError, Terminated, check_terminated, record_kept, termination_deferred

#: Files by which an earlier output folder of the tool is recognised (such a folder may be replaced as a whole):
#: a run's record, or a rolling run's (``wrlayer rolling``).
OUTPUT_FILES = ("result.json", "rolling.json")
#: Files of an output folder that the tool writes (never carried over from an earlier run: a run that does not
#: write one of them, e.g. no frictional CSVs without a tangential problem, must not leave the old one beside its
#: result). Relative paths, matched with :meth:`pathlib.PurePath.match`; ``"name/"``: everything under the top
#: folder ``name``.
OWNED_PATTERNS = ("result.json", "*.png", "*.csv", "deformed_profiles/*")
#: Suffix of the sibling folder that holds a growing run's completed part until the run ends (:func:`partial_dir`).
PARTIAL_SUFFIX = ".partial"


class OutputError(InputError):
    """An output file or folder cannot be written (disk full, permissions, read-only file system): ``what`` is its
    path (exit code 2, like an unwritable ``--out``)."""


def output_error(err: OSError, path: str | os.PathLike) -> OutputError:
    """``err`` as an :class:`OutputError` naming ``path`` (or the file the OS named) and the reason in lower case:
    ``<path>: no space left on device``."""
    reason = err.strerror or str(err)
    return OutputError(str(err.filename or path), reason[:1].lower() + reason[1:])


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def _user_mode(path: str | os.PathLike, directory: bool = False) -> None:
    """Give ``path`` the permissions a normal ``open``/``mkdir`` would (0666/0777 minus the umask)."""
    os.chmod(path, (0o777 if directory else 0o666) & ~_umask())


def _write_atomic(path: Path, data: bytes) -> Path:
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    except OSError as err:
        raise output_error(err, path) from None
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
        _user_mode(tmp)
        os.replace(tmp, path)
    except BaseException as err:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)
        if isinstance(err, OSError):  # the temporary file's name would mislead: the path being written
            raise output_error(err, path) from None
        raise
    return path


def atomic_write_text(path: str | os.PathLike, text: str) -> Path:
    """Write ``text`` (UTF-8, "\\n" line ends) to ``path`` atomically (temporary file + rename). Returns the path."""
    return _write_atomic(Path(path), text.encode("utf-8"))


def atomic_write_bytes(path: str | os.PathLike, data: bytes) -> Path:
    """Write ``data`` to ``path`` atomically (temporary file + rename). Returns the path."""
    return _write_atomic(Path(path), bytes(data))


# ------------------------------------------------------------------------------------------------ staging
def _pid_alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def _staging_dir(path: Path, kind: str = "staging") -> Path:
    """A new run-unique hidden sibling of ``path``: ``.<name>.<kind>-<pid>-<random>`` (user permissions).

    A SIGTERM while it is made is raised once the folder is removed again, so the caller either gets the folder
    (and removes it in its ``finally``) or no folder exists."""
    tmp = None
    try:
        with termination_deferred():
            path.parent.mkdir(parents=True, exist_ok=True)
            tmp = Path(tempfile.mkdtemp(prefix=f".{path.name}.{kind}-{os.getpid()}-", dir=path.parent))
            _user_mode(tmp, directory=True)
    except OSError as err:
        raise InputError(str(path), f"cannot create the output folder here ({err.strerror or err})") from None
    except Terminated:
        if tmp is not None:
            remove_tree(tmp)
        raise
    return tmp


def remove_tree(path: Path) -> None:
    """Remove the folder ``path`` (errors ignored) to the end, even if a SIGTERM arrives meanwhile (it is raised
    afterwards): a staging folder is gone or untouched, never half removed."""
    with termination_deferred():
        shutil.rmtree(path, ignore_errors=True)


def clean_stale_staging(path: str | os.PathLike) -> list[Path]:
    """Remove the staging/old folders beside ``path`` left by runs whose process no longer exists (killed runs);
    returns the removed folders. Folders of live runs are left alone."""
    path = Path(path)
    removed = []
    if not path.parent.is_dir():
        return removed
    if not path.exists():  # a kill between the two renames of a non-atomic swap: the earlier output comes back
        for item in path.parent.glob(f".{path.name}.old-*-*/{path.name}"):
            with contextlib.suppress(OSError):
                os.replace(item, path)
                break
    for kind in ("staging", "old"):
        for item in path.parent.glob(f".{path.name}.{kind}-*-*"):
            try:
                pid = int(item.name[len(f".{path.name}.{kind}-"):].split("-", 1)[0])
            except ValueError:
                continue
            if item.is_dir() and not _pid_alive(pid):
                shutil.rmtree(item, ignore_errors=True)
                removed.append(item)
    return removed


@contextlib.contextmanager
def atomic_output_dir(path: str | os.PathLike) -> Iterator[Path]:
    """Yield a run-unique staging folder; on success its files are moved into ``path`` (created if needed).

    Files already in ``path`` with other names are kept; files with the same names are replaced.
    On an exception nothing in ``path`` changes and the staging folder is removed.
    """
    path = Path(path)
    clean_stale_staging(path)
    tmp = _staging_dir(path)
    try:
        yield tmp
        check_terminated()  # a SIGTERM swallowed by a C callback: nothing is committed
        path.mkdir(parents=True, exist_ok=True)
        for item in sorted(tmp.rglob("*")):
            if item.is_file():
                dest = path / item.relative_to(tmp)
                dest.parent.mkdir(parents=True, exist_ok=True)
                os.replace(item, dest)
    finally:
        remove_tree(tmp)


# ------------------------------------------------------------------------------------------------ lock
@contextlib.contextmanager
def output_lock(path: str | os.PathLike, what: str | None = None) -> Iterator[Path]:
    """Hold an exclusive lock on the output ``path`` (a file ``.<name>.lock`` beside it) for the block.

    A second run into the same output while the first holds the lock is refused at once with an InputError
    naming ``what`` (default ``--out <path>``) and the holder's pid. The lock is released (and its file removed)
    when the block ends, also on an exception; a killed run's lock is released by the operating system.
    """
    path = Path(path)
    what = what or f"--out {path}"
    lock = path.parent / f".{path.name}.lock"
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
    except OSError as err:
        raise InputError(what, f"cannot create the output folder here ({err.strerror or err})") from None
    while True:
        fd = os.open(lock, os.O_RDWR | os.O_CREAT, 0o666)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError as err:
            os.close(fd)
            if err.errno not in (errno.EAGAIN, errno.EACCES, errno.EWOULDBLOCK):
                raise
            try:
                holder = lock.read_text().strip() or "?"
            except OSError:
                holder = "?"
            raise InputError(what, f"another run (pid {holder}) is writing into this output folder; wait for it "
                                   "to finish or choose another --out") from None
        try:  # the file may have been removed by the previous holder between open and lock: retry
            same = os.fstat(fd).st_ino == os.stat(lock).st_ino
        except FileNotFoundError:
            same = False
        if same:
            break
        os.close(fd)
    try:
        os.ftruncate(fd, 0)
        os.write(fd, str(os.getpid()).encode())
        yield lock
    finally:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(lock)
        os.close(fd)


# ------------------------------------------------------------------------------------------------ replace
_RENAME_EXCHANGE = 2
_AT_FDCWD = -100


def _exchange(a: Path, b: Path) -> bool:
    """Atomically swap two paths (Linux renameat2 RENAME_EXCHANGE); False where the platform does not allow it."""
    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6", use_errno=True)
        fn = libc.renameat2
    except (OSError, AttributeError):
        return False
    fn.argtypes = [ctypes.c_int, ctypes.c_char_p, ctypes.c_int, ctypes.c_char_p, ctypes.c_uint]
    rc = fn(_AT_FDCWD, os.fsencode(a), _AT_FDCWD, os.fsencode(b), _RENAME_EXCHANGE)
    if rc == 0:
        return True
    err = ctypes.get_errno()
    if err in (errno.ENOSYS, errno.EINVAL, getattr(errno, "ENOTSUP", errno.EINVAL)):
        return False
    raise OSError(err, os.strerror(err), str(b))


def check_replaceable(path: str | os.PathLike, what: str | None = None) -> None:
    """InputError unless ``path`` is absent, an empty folder or an earlier output folder of the tool (holds one
    of :data:`OUTPUT_FILES`): the tool never deletes a folder it did not write."""
    path = Path(path)
    what = what or f"--out {path}"
    if not path.exists():
        return
    if not path.is_dir():
        raise InputError(what, "exists and is not a folder")
    if any((path / name).is_file() for name in OUTPUT_FILES) or not any(path.iterdir()):
        return
    raise InputError(what, "is a folder with other content (not an output folder of this tool): it would be "
                           "replaced as a whole; choose a new or empty folder")


def _owned(rel: Path, owned: tuple[str, ...]) -> bool:
    """``rel`` matches one of the ``owned`` patterns (``"name/"``: everything under the top folder ``name``)."""
    return any(rel.parts[0] == p[:-1] if p.endswith("/") else rel.match(p) for p in owned)


def _carry_over(old: Path, new: Path, owned: tuple[str, ...]) -> None:
    """Hard-link (or copy) into ``new`` the files of ``old`` that the tool does not own (a user's notes), unless
    ``new`` has a file of that name."""
    for item in old.rglob("*"):
        rel = item.relative_to(old)
        if not item.is_file() or _owned(rel, owned) or (new / rel).exists():
            continue
        (new / rel).parent.mkdir(parents=True, exist_ok=True)
        try:
            os.link(item, new / rel)
        except OSError:
            shutil.copy2(item, new / rel)


def _swap_in(new: Path, path: Path) -> None:
    """Put the folder ``new`` in place of ``path`` in one step; ``new`` then holds the previous ``path`` (or is
    gone), for the caller to remove."""
    if path.exists() and _exchange(new, path):
        return
    if path.exists():
        old = _staging_dir(path, "old")
        os.replace(path, old / path.name)
        os.replace(new, path)
        remove_tree(old)
    else:
        os.replace(new, path)


@contextlib.contextmanager
def replace_output_dir(path: str | os.PathLike, what: str | None = None,
                       owned: tuple[str, ...] = OWNED_PATTERNS) -> Iterator[Path]:
    """Build a whole output folder and put it in place of ``path`` as a whole, under :func:`output_lock`.

    Yields a run-unique staging folder. When the block succeeds, the files of the earlier output that the tool
    does not own (not matching ``owned``, e.g. a user's notes) are carried over, and the staging folder replaces
    ``path`` in one step: the tool's files in it all come from this run. On an exception ``path`` is unchanged
    and the staging folder is removed. Stale staging folders of killed runs are removed first. ``path`` must pass
    :func:`check_replaceable`.
    """
    path = Path(path)
    with output_lock(path, what):
        check_replaceable(path, what)
        clean_stale_staging(path)
        tmp = _staging_dir(path)
        try:
            yield tmp
            check_terminated()  # a SIGTERM swallowed by a C callback: the earlier output stays
            with termination_deferred():  # swapped in and said so, or neither
                if path.is_dir():
                    _carry_over(path, tmp, owned)
                _swap_in(tmp, path)
                record_kept(f"the complete output is in {path}")
        finally:
            remove_tree(tmp)


# ------------------------------------------------------------------------------------------------ publish
def _link_tree(src: Path, dest: Path) -> None:
    """Hard-link (or copy, across file systems) every file of ``src`` into ``dest``. The files of a staging
    folder are written atomically (a new file each time), so a snapshot never changes after it is taken."""
    for item in sorted(src.rglob("*")):
        if item.is_file() and not (item.name.startswith(".") and item.name.endswith(".tmp")):
            target = dest / item.relative_to(src)
            target.parent.mkdir(parents=True, exist_ok=True)
            try:
                os.link(item, target)
            except OSError:
                shutil.copy2(item, target)


def partial_dir(path: str | os.PathLike) -> Path:
    """The visible sibling ``<name>.partial`` of the output folder ``path`` that receives a growing run's
    published snapshots until the run ends (:class:`StagedOutput`)."""
    path = Path(path)
    return path.with_name(path.name + PARTIAL_SUFFIX)


class StagedOutput:
    """A staging folder ``dir`` (build the output in it): :meth:`publish` puts a snapshot of it in place of
    ``partial`` while the run goes, :meth:`finish` puts the ended run in place of ``path``.

    ``published``: the snapshots published so far; ``where``: the folder the last one went to (None: none yet)."""

    def __init__(self, path: Path, staging: Path, owned: tuple[str, ...]):
        self.path, self.dir, self.owned = path, staging, owned
        self.partial = partial_dir(path)
        self.published = 0
        self.where: Path | None = None

    def _put(self, target: Path, kept: str) -> None:
        """A snapshot of the staging folder in place of ``target`` as a whole (files of the previous ``target``
        that the tool does not own are carried over), then ``kept`` recorded for the SIGTERM line. A SIGTERM
        meanwhile is raised once both are done (or the snapshot is removed): the line never misstates the folder.
        A kill at any moment leaves ``target`` unchanged or the complete snapshot; a snapshot left by a kill is
        removed by the next run (:func:`clean_stale_staging`)."""
        with termination_deferred():
            snap = _staging_dir(target)
            try:
                _link_tree(self.dir, snap)
                if target.is_dir():
                    _carry_over(target, snap, self.owned)
                _swap_in(snap, target)
            except OSError as err:
                raise output_error(err, target) from None
            finally:
                remove_tree(snap)  # the previous output, or a snapshot not swapped in
            self.published += 1
            self.where = target
            record_kept(kept)

    def partial_kept(self, completed: str) -> str:
        """What the SIGTERM line says once ``completed`` (e.g. "2 completed step(s)") is published in :attr:`partial`:
        there, and whether ``path`` keeps an earlier output of the tool."""
        earlier = any((self.path / name).is_file() for name in OUTPUT_FILES)
        return (f"{completed} kept in {self.partial}; {self.path} "
                + ("keeps the earlier output" if earlier else "was not written"))

    def publish(self, kept: str = "") -> None:
        """Publish the staging folder's current state into :attr:`partial` (``path`` is not touched); ``kept``:
        what the SIGTERM line then says (default: the folder's name)."""
        self._put(self.partial, kept or f"the output published last is in {self.partial}")

    def finish(self, kept: str = "") -> None:
        """Put the ended run in place of ``path`` and remove :attr:`partial`; ``kept`` as for :meth:`publish`."""
        with termination_deferred():
            self._put(self.path, kept or f"the complete output is in {self.path}")
            if self.partial.exists():  # renamed first: a kill -9 meanwhile leaves a stale sibling, not half a folder
                gone = self.partial.with_name(f".{self.partial.name}.old-{os.getpid()}-{os.urandom(4).hex()}")
                os.replace(self.partial, gone)
                remove_tree(gone)


@contextlib.contextmanager
def staged_output_dir(path: str | os.PathLike, what: str | None = None,
                      owned: tuple[str, ...] = OWNED_PATTERNS) -> Iterator[StagedOutput]:
    """Build an output folder beside ``path``, publish its growing state into ``<path>.partial`` as often as the
    block asks and put it in place of ``path`` at the end (:class:`StagedOutput`), under :func:`output_lock` of
    ``path``. ``path`` is untouched until :meth:`StagedOutput.finish`; the staging folder is removed when the block
    ends, also on an exception or SIGTERM (what was published stays). ``path`` and the partial folder must pass
    :func:`check_replaceable`; stale staging folders of killed runs beside both are removed first."""
    path = Path(path)
    what = what or f"--out {path}"
    with output_lock(path, what):
        partial = partial_dir(path)
        check_replaceable(path, what)
        check_replaceable(partial, f"{what} (its partial-output folder {partial})")
        clean_stale_staging(path)
        clean_stale_staging(partial)
        tmp = _staging_dir(path)
        try:
            yield StagedOutput(path, tmp, owned)
        finally:
            remove_tree(tmp)


__all__ = ["OUTPUT_FILES", "OWNED_PATTERNS", "OutputError", "PARTIAL_SUFFIX", "StagedOutput", "atomic_output_dir",
           "atomic_write_bytes", "atomic_write_text", "check_replaceable", "clean_stale_staging", "output_error",
           "output_lock", "partial_dir", "remove_tree", "replace_output_dir", "staged_output_dir"]
