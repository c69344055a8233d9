"""One file written then renamed: :func:`atomic_path` and the writers built on it.

The data go to a hidden temporary file beside the target (mode ``0o666 & ~umask``, not
``mkstemp``'s 0600), renamed onto it only when complete; a write goes *through* a symbolic
link, names the final file in "No space left on device" and other write errors, and refuses
to replace a file the running command has read (:mod:`roadscan.io.overwrite_guard`).
:mod:`roadscan.io.atomic` re-exports every public name here, beside the whole output folders
and file sets it writes on the same principle.
"""

from __future__ import annotations

import contextlib
import os
import tempfile
from pathlib import Path

from ..errors import InputError
from .folder_swap import TMP_TAG
from .overwrite_guard import check_not_read

__all__ = [
    "atomic_path",
    "atomic_write_text",
    "atomic_write_bytes",
    "atomic_save_npy",
    "file_mode",
    "through_link",
    "final_name",
]


def through_link(path):
    """The path a write to ``path`` should replace: where a symbolic link points (followed to
    the end, a dangling link's target included), else ``path`` itself. A link loop is refused
    (:class:`InputError`): writing "through" it has no meaning.

    Parameters
    ----------
    path : str or Path
        The output path.

    Returns
    -------
    Path
        The path that will be replaced.
    """
    path = Path(path)
    if not os.path.islink(path):
        return path
    try:
        return Path(path.resolve(strict=False))
    except (RuntimeError, OSError):  # Python 3.11: RuntimeError on a loop
        raise InputError(path, "is a symbolic link loop; name another output") from None


def final_name(path):
    """Where a file being written inside a temporary output folder ends up
    (``.out.roadscan-tmp-ab12/psd.csv`` -> ``out/psd.csv``), for messages.

    Parameters
    ----------
    path : str or Path
        A path inside a temporary output folder.

    Returns
    -------
    Path
        Its final name.
    """
    parts = list(Path(path).parts)
    for i, part in enumerate(parts):
        if part.startswith(".") and TMP_TAG in part:
            parts[i] = part[1:].split(TMP_TAG, 1)[0]
    return Path(*parts) if parts else Path(path)


def _in_tmp_folder(path):
    return any(part.startswith(".") and TMP_TAG in part for part in Path(path).parent.parts)


def _named(exc, path):
    """``exc`` as an OSError naming ``path`` when it names no file (a full disk, a quota, an
    I/O error raised by ``write``): "No space left on device" then says where."""
    if getattr(exc, "filename", None) or not isinstance(exc, OSError) or exc.errno is None:
        return exc
    named = OSError(exc.errno, exc.strerror or str(exc), str(path))
    named.__cause__ = exc
    return named


def file_mode():
    """Permission bits of a newly created file under the current umask (``0o666 & ~umask``).

    Parameters
    ----------
    None

    Returns
    -------
    int
        Permission bits.
    """
    mask = os.umask(0)
    os.umask(mask)
    return 0o666 & ~mask


def _dir_mode():
    mask = os.umask(0)
    os.umask(mask)
    return 0o777 & ~mask


@contextlib.contextmanager
def atomic_path(path, suffix=None):
    """Yield a temporary path beside ``path``; rename it onto ``path`` on success.

    The temporary file keeps the final suffix (writers that pick a format from the
    extension still work) and gets mode ``0o666 & ~umask``. On an exception it is removed.

    Parameters
    ----------
    path : str or Path
        The final file.
    suffix : str, optional
        Suffix of the temporary file (default: that of ``path``).

    Yields
    ------
    Path
        The temporary path to write.

    Returns
    -------
    contextlib.AbstractContextManager
        Use with ``with``; the block receives the temporary path.
    """
    shown = Path(path)
    path = through_link(shown)
    if path.is_dir():
        raise InputError(shown, "is a directory, cannot write a file there")
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        # the stem cut to 100 characters: a legal 255-character name keeps a legal temporary one
        fd, tmp = tempfile.mkstemp(
            prefix=f".{path.stem[:100]}.", suffix=suffix or path.suffix, dir=path.parent
        )
    except OSError as exc:  # the name the user gave, not the hidden temporary one
        raise OSError(exc.errno, exc.strerror or str(exc), str(final_name(shown))) from None
    try:
        os.fchmod(fd, file_mode())
    finally:
        os.close(fd)
    try:
        yield Path(tmp)
        if not _in_tmp_folder(path):
            check_not_read([path], option=None, exclude=tmp)
        os.replace(tmp, path)
    except BaseException as exc:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)
        if isinstance(exc, OSError) and not isinstance(exc, InputError):
            raise _named(exc, final_name(shown)) from None
        raise


def atomic_write_text(path, text, encoding="utf-8"):
    """Write ``text`` to ``path`` through a temporary file renamed into place.

    Parameters
    ----------
    path : str or Path
        Output file.
    text : str
        Its content.
    encoding : str, optional
        Text encoding.

    Returns
    -------
    None
    """
    with atomic_path(path) as tmp:
        tmp.write_text(text, encoding=encoding)


def atomic_write_bytes(path, data):
    """Write ``data`` to ``path`` through a temporary file renamed into place.

    Parameters
    ----------
    path : str or Path
        Output file.
    data : bytes
        Its content.

    Returns
    -------
    None
    """
    with atomic_path(path) as tmp:
        tmp.write_bytes(data)


def atomic_save_npy(path, array):
    """``numpy.save`` through a temporary file (float64 heights in metres, NaN kept).

    Parameters
    ----------
    path : str or Path
        Output ``.npy`` file.
    array : ndarray
        The array.

    Returns
    -------
    None
    """
    import numpy as np

    with atomic_path(path) as tmp:
        with open(tmp, "wb") as fh:
            np.save(fh, np.asarray(array, dtype=np.float64))
