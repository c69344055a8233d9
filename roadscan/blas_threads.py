"""One BLAS/LAPACK thread for a stretch of many small dense solves.

numpy's ``linalg.solve`` of a stack of small systems calls LAPACK once per system; with
OpenBLAS's default of one thread per core, each call starts and joins the thread pool, which
costs far more than the work on systems of a few dozen unknowns (the biharmonic fill of the
shipped sample: 0.81 s with two threads, 0.09 s with one, on a loaded two-core machine).
:func:`single_threaded_blas` limits every BLAS library loaded in the process (OpenBLAS, MKL,
BLIS) to one thread for the duration of a ``with`` block and restores the previous counts
after it, through ``threadpoolctl`` (imported when first used: 10-20 ms). The thread count is
global to the process: BLAS calls made by other Python threads during the block run
single-threaded too.

References
----------
threadpoolctl, ``threadpool_limits`` (https://github.com/joblib/threadpoolctl, BSD-3-Clause).
"""

from __future__ import annotations

import contextlib
from collections.abc import Iterator

__all__ = ["single_threaded_blas"]


@contextlib.contextmanager
def single_threaded_blas() -> Iterator[None]:
    """Context manager: the BLAS libraries on one thread inside the block, their counts
    restored after (``threadpoolctl.threadpool_limits(1, user_api="blas")``).

    Yields
    ------
    None

    Returns
    -------
    contextlib.AbstractContextManager
        Use with ``with``.
    """
    from threadpoolctl import threadpool_limits

    with threadpool_limits(limits=1, user_api="blas"):
        yield
