"""One BLAS/LAPACK thread for a stretch of many small dense solves.

numpy's ``linalg.solve`` of a stack of small systems calls LAPACK once per system; with
OpenBLAS's default of one thread per core, each call starts and joins the thread pool, which
costs far more than the work on systems of a few dozen unknowns (the biharmonic fill of the
shipped sample: 0.81 s with two threads, 0.09 s with one, on a loaded two-core machine).
:func:`single_threaded_blas` sets OpenBLAS to one thread for the duration of a ``with`` block
and restores the previous count after it (what ``threadpoolctl.threadpool_limits(1)`` does,
without that dependency). It reaches the OpenBLAS library bundled with numpy's wheels through
ctypes; with another BLAS (or none found) it does nothing. The thread count is global to the
process: BLAS calls made by other Python threads during the block run single-threaded too.

References
----------
OpenBLAS, ``openblas_set_num_threads`` / ``openblas_get_num_threads`` (OpenBLAS README,
"Setting the number of threads at runtime").
"""

from __future__ import annotations

import contextlib
import functools
import os
from collections.abc import Iterator

__all__ = ["single_threaded_blas"]

# exported names of the getter and setter, by build: numpy's scipy-openblas (64-bit integers,
# symbol suffix), its 32-bit-integer build, a plain OpenBLAS
_NAMES = (
    ("scipy_openblas_get_num_threads64_", "scipy_openblas_set_num_threads64_"),
    ("scipy_openblas_get_num_threads", "scipy_openblas_set_num_threads"),
    ("openblas_get_num_threads", "openblas_set_num_threads"),
)


@functools.lru_cache(maxsize=1)
def _openblas_functions():
    """(get, set) of the OpenBLAS bundled with numpy, or None."""
    import ctypes  # loaded only when the BLAS is searched for
    import glob

    import numpy

    site = os.path.dirname(os.path.dirname(os.path.abspath(numpy.__file__)))
    for folder in ("numpy.libs", os.path.join("numpy", ".dylibs")):
        for path in sorted(glob.glob(os.path.join(site, folder, "*openblas*"))):
            try:
                lib = ctypes.CDLL(path)
            except OSError:
                continue
            for get_name, set_name in _NAMES:
                get, set_ = getattr(lib, get_name, None), getattr(lib, set_name, None)
                if get is not None and set_ is not None:
                    get.restype, get.argtypes = ctypes.c_int, []
                    set_.restype, set_.argtypes = None, [ctypes.c_int]
                    return get, set_
    return None


@contextlib.contextmanager
def single_threaded_blas() -> Iterator[None]:
    """Context manager: OpenBLAS on one thread inside the block, its count restored after.

    Yields
    ------
    None

    Parameters
    ----------
    None

    Returns
    -------
    contextlib.AbstractContextManager
        Use with ``with``.
    """
    fns = _openblas_functions()
    if fns is None:
        yield
        return
    get, set_ = fns
    n = int(get())
    if n <= 1:
        yield
        return
    set_(1)
    try:
        yield
    finally:
        set_(n)
