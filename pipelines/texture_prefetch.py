"""The ISO 13473-4 texture spectrum and the ISO 25178-2 texture figures of a levelled map,
started on a second core as soon as the map exists, while the spectrum, its fit and friction are
computed on the first.

:func:`roadscan.texture_spectrum.texture_spectrum` and
:func:`roadscan.iso25178.texture_parameters` (the autocorrelation's FFTs, the feature trees,
the material ratio) read the levelled map only and record no warning, so they can run beside
the rest of the chain; numpy releases the GIL in its FFTs and array loops. Their results are the
ones the chain would compute itself, handed over only for the very surface (and direction) they
were started on (identity, not equality). On a one-core machine nothing is started.
"""
from __future__ import annotations

import os
import threading

__all__ = ["TextureFigures", "MIN_POINTS"]

#: maps with fewer points are done on the calling thread: below about 0.5 Mpx the thread's
#: start and the sharing of the interpreter cost more CPU time than the overlap saves wall time
#: (512 x 512: 0.12 s CPU in one thread, 0.14-0.155 s with the second)
MIN_POINTS = 1 << 19


class TextureFigures:
    """``texture_spectrum(surface, direction)`` then ``texture_parameters(surface)`` computed on
    a background thread.

    Use :meth:`start` with the levelled map, then :meth:`spectrum` and :meth:`get` with the
    surface wanted: the background result when it is that very object, else a computation on the
    spot. An exception raised in the thread is raised again by :meth:`spectrum` or :meth:`get`.

    Parameters
    ----------
    direction : {"x", "y"} or None, optional
        Driving direction of the texture spectrum; None computes no spectrum in the background.
    """

    def __init__(self, direction=None):
        self._direction = direction
        self._surface = None
        self._thread = None
        self._result = None
        self._spectrum = None
        self._error = None
        self._spectrum_done = threading.Event()

    def start(self, surface):
        """Start computing the spectrum and figures of ``surface`` (a HeightMap of at least
        :data:`MIN_POINTS` points; anything else is ignored, as is every call on a one-core
        machine or after the first)."""
        from roadscan.heightmap import HeightMap

        if self._thread is not None or not isinstance(surface, HeightMap) or \
                surface.heights_m.size < MIN_POINTS or (os.cpu_count() or 1) < 2:
            return
        self._surface = surface
        self._thread = threading.Thread(target=self._run, name="roadscan-texture", daemon=True)
        self._thread.start()

    def _run(self):
        from roadscan.iso25178 import texture_parameters
        from roadscan.texture_spectrum import texture_spectrum

        try:
            try:
                if self._direction is not None:
                    self._spectrum = texture_spectrum(self._surface, direction=self._direction)
            finally:
                self._spectrum_done.set()
            self._result = texture_parameters(self._surface)
        except BaseException as err:        # handed to the caller of spectrum() / get()
            self._error = err

    def spectrum(self, surface, direction):
        """``texture_spectrum(surface, direction)`` (a TextureSpectrum)."""
        if self._thread is not None and surface is self._surface and \
                direction == self._direction:
            self._spectrum_done.wait()
            if self._spectrum is not None:
                return self._spectrum
            raise self._error
        from roadscan.texture_spectrum import texture_spectrum

        return texture_spectrum(surface, direction=direction)

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
