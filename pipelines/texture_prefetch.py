"""The ISO 25178-2 texture figures of a levelled map, started on a second core as soon as the
map exists, while the spectrum, its fit and friction are computed on the first.

:func:`roadscan.iso25178.texture_parameters` (the autocorrelation's FFTs, the feature trees,
the material ratio) reads the levelled map only and records no warning, so it can run beside
the rest of the chain; numpy releases the GIL in its FFTs and array loops. Its result is the one
the chain would compute itself, handed over only for the very surface it was started on
(identity, not equality). On a one-core machine nothing is started.
"""
from __future__ import annotations

import os
import threading

__all__ = ["TextureFigures"]


class TextureFigures:
    """``texture_parameters(surface)`` computed on a background thread.

    Use :meth:`start` with the levelled map, then :meth:`get` with the surface the figures are
    wanted for: the background result when it is that very object, else a computation on the
    spot. An exception raised in the thread is raised again by :meth:`get`.
    """

    def __init__(self):
        self._surface = None
        self._thread = None
        self._result = None
        self._error = None

    def start(self, surface):
        """Start computing the figures of ``surface`` (a HeightMap; anything else is ignored,
        as is every call on a one-core machine or after the first)."""
        from roadscan.heightmap import HeightMap

        if self._thread is not None or not isinstance(surface, HeightMap) or \
                (os.cpu_count() or 1) < 2:
            return
        self._surface = surface
        self._thread = threading.Thread(target=self._run, name="roadscan-texture", daemon=True)
        self._thread.start()

    def _run(self):
        from roadscan.iso25178 import texture_parameters

        try:
            self._result = texture_parameters(self._surface)
        except BaseException as err:        # handed to the caller of get()
            self._error = err

    def get(self, surface):
        """(figures, notes) of ``surface`` as :func:`roadscan.iso25178.texture_parameters`
        gives them."""
        if self._thread is not None and surface is self._surface:
            self._thread.join()
            if self._error is not None:
                raise self._error
            return self._result
        from roadscan.iso25178 import texture_parameters

        return texture_parameters(surface)
