"""The ISO 13473-4 texture spectrum and the ISO 25178-2 texture figures of a levelled map,
started on a second core as soon as the map exists, while the spectrum, its fit and friction are
computed on the first.

:func:`roadscan.texture_spectrum.texture_spectrum` and
:func:`roadscan.iso25178.texture_parameters` (the autocorrelation's FFTs, the feature trees,
the material ratio) read the levelled map only and record no warning, so they can run beside
the rest of the chain; numpy releases the GIL in its FFTs and array loops. Their results are the
ones the chain would compute itself, handed over only for the very surface (and direction) they
were started on (identity, not equality). On a one-core machine nothing is started.

A map shorter than one 100 mm ISO 13473-1 segment along x gets no MPD but a short-baseline
mean segment depth (:func:`roadscan.texture_depth.short_segment_depth` of the scan as read, not
levelled); that too is computed on the second core: with the default settings as soon as the
scan is read (:func:`prepare_lattice_ahead`, beside the spectrum's lattice bookkeeping, while
the scan is checked), else on the texture thread when the source scan is known (given to
:meth:`TextureFigures.start`, or named by :func:`levelled_from` around the call of the
levelled-map hook, as :func:`pipelines.chain.surface.analyse_surface` does). It is handed
over only for that very scan object and equal ISO 13473-1 settings.
"""

from __future__ import annotations

import contextlib
import contextvars
import os
import threading
import weakref
from typing import Any

__all__ = ["TextureFigures", "MIN_POINTS", "levelled_from", "prepare_lattice_ahead"]

#: maps with fewer points are done on the calling thread: below about 0.5 Mpx the thread's
#: start and the sharing of the interpreter cost more CPU time than the overlap saves wall time
#: (512 x 512: 0.12 s CPU in one thread, 0.14-0.155 s with the second)
MIN_POINTS = 1 << 19

#: (levelled map, source scan, ISO 13473-1 settings) while the levelled-map hook runs
_SOURCE = contextvars.ContextVar("roadscan_levelled_source", default=None)


@contextlib.contextmanager
def levelled_from(levelled, source, mpd_settings=None):
    """Within the block, :meth:`TextureFigures.start` called with ``levelled`` (that very
    object) without a source takes ``source`` and ``mpd_settings`` as its source scan and
    ISO 13473-1 settings.

    Parameters
    ----------
    levelled : HeightMap
        The levelled map handed to the hook.
    source : HeightMap or Profile
        The scan it was levelled from (heights as read) [m].
    mpd_settings : dict, optional
        ISO 13473-1 settings of the analysis.
    """
    token = _SOURCE.set((levelled, source, mpd_settings))
    try:
        yield
    finally:
        _SOURCE.reset(token)


def _short_wanted(source, direction, mpd_settings):
    """True when the texture summary will ask for the short-baseline depth of ``source``: a
    map whose rows along x (the driving direction) are shorter than 100 mm and than the
    segment of ``mpd_settings`` (no MPD)."""
    from roadscan.heightmap import HeightMap

    if not isinstance(source, HeightMap) or direction == "y":
        return False
    length = source.nx * source.dx_m
    return length < 0.1 and length < (mpd_settings or {}).get("segment_m", 0.1) * (1 - 1e-9)


class _ReadAhead:
    """Work on a scan as read, done on a background thread while the scan is checked: the
    spectrum's lattice bookkeeping (:func:`roadscan.spectrum.prepare_lattice`, found cached by
    the spectrum and the anisotropy) and, for rows along x shorter than one segment, the
    short-baseline segment depth with the default ISO 13473-1 settings."""

    def __init__(self, scan):

        self.scan = weakref.ref(scan)
        self.short_wanted = _short_wanted(scan, "x", None)
        self.short = self.short_error = None
        self.done = threading.Event()
        self.thread = threading.Thread(target=self._run, args=(scan,), name="roadscan-ahead", daemon=True)

    def _run(self, scan):
        from roadscan.spectrum import prepare_lattice
        from roadscan.texture_depth import short_segment_depth

        try:
            try:
                prepare_lattice(scan.ny, scan.nx, scan.dx_m, scan.dy_m)
            except Exception:  # noqa: BLE001 - a cache warm-up: the spectrum computes its own
                pass
            if self.short_wanted:
                try:
                    self.short = short_segment_depth(scan)
                except BaseException as err:  # noqa: BLE001 - handed to the caller of short_depth()
                    self.short_error = err
        finally:
            self.done.set()

    def short_for(self, source, mpd_settings):
        """True when this holds (or is computing) the short depth of ``source`` (that very
        object) with ``mpd_settings`` (default settings only)."""
        return self.short_wanted and self.scan() is source and not (mpd_settings or {})

    def take_short(self):
        self.done.wait()
        if self.short_error is not None:
            raise self.short_error
        return self.short


#: the last scans read ahead (:func:`prepare_lattice_ahead`), held weakly
_AHEAD: list[Any] = []
#: scans read ahead that are remembered (a command reads all its files before analysing them)
_AHEAD_KEPT = 8


def _ahead_for(source, mpd_settings):
    return next((a for a in list(_AHEAD) if a.short_for(source, mpd_settings)), None)


def prepare_lattice_ahead(scan):
    """Start the work on ``scan`` that needs the scan as read only, on a background thread:
    the spectrum's lattice bookkeeping (:func:`roadscan.spectrum.prepare_lattice`) and, for a
    map shorter than one 100 mm segment along x, its short-baseline segment depth with the
    default ISO 13473-1 settings (handed over by :meth:`TextureFigures.short_depth` for that
    very scan object only). Called as soon as a scan is read, it runs on the core left idle
    while the scan is checked. Only for a HeightMap of at least :data:`MIN_POINTS` points on a
    machine of two cores or more; returns the thread (or None)."""
    from roadscan.heightmap import HeightMap

    if not isinstance(scan, HeightMap) or scan.heights_m.size < MIN_POINTS or (os.cpu_count() or 1) < 2:
        return None
    try:
        ahead = _ReadAhead(scan)
    except TypeError:  # a scan type without weak references: nothing read ahead
        return None
    _AHEAD[:] = [a for a in _AHEAD[-(_AHEAD_KEPT - 1) :] if a.scan() is not None] + [ahead]
    ahead.thread.start()
    return ahead.thread


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
        self._source = None
        self._mpd_settings = None
        self._short = None
        self._short_error = None
        self._short_done = threading.Event()

    def start(self, surface, source=None, mpd_settings=None):
        """Start computing the spectrum and figures of ``surface`` (a HeightMap of at least
        :data:`MIN_POINTS` points; anything else is ignored, as is every call on a one-core
        machine or after the first), and the short-baseline segment depth of ``source`` (the
        scan ``surface`` was levelled from, by default the one named by :func:`levelled_from`)
        with ``mpd_settings`` when its rows are shorter than one segment."""
        from roadscan.heightmap import HeightMap

        if (
            self._thread is not None
            or not isinstance(surface, HeightMap)
            or surface.heights_m.size < MIN_POINTS
            or (os.cpu_count() or 1) < 2
        ):
            return
        named = _SOURCE.get()
        if source is None and named is not None and named[0] is surface:
            source, mpd_settings = named[1], named[2]
        if (
            source is not None
            and _short_wanted(source, self._direction, mpd_settings)
            and _ahead_for(source, mpd_settings) is None
        ):  # not read ahead already
            self._source, self._mpd_settings = source, dict(mpd_settings or {})
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
            if self._source is not None:
                self._run_short()
            self._result = texture_parameters(self._surface)
        except BaseException as err:  # noqa: BLE001 - handed to the caller of spectrum() / get()
            self._error = err
        finally:
            self._short_done.set()

    def _run_short(self):
        from roadscan.texture_depth import short_segment_depth

        try:
            self._short = short_segment_depth(self._source, **self._mpd_settings)
        except BaseException as err:  # noqa: BLE001 - handed to the caller of short_depth()
            self._short_error = err
        finally:
            self._short_done.set()

    def spectrum(self, surface, direction):
        """``texture_spectrum(surface, direction)`` (a TextureSpectrum)."""
        if self._thread is not None and surface is self._surface and direction == self._direction:
            self._spectrum_done.wait()
            if self._spectrum is not None:
                return self._spectrum
            raise self._error
        from roadscan.texture_spectrum import texture_spectrum

        return texture_spectrum(surface, direction=direction)

    def short_depth(self, source, mpd_settings=None):
        """``short_segment_depth(source, **mpd_settings)``: (depth [m] or None, baseline [m] or
        None, note) as :func:`roadscan.texture_depth.short_segment_depth` gives them."""
        ahead = _ahead_for(source, mpd_settings)
        if ahead is not None:
            return ahead.take_short()
        if (
            self._thread is not None
            and self._source is not None
            and source is self._source
            and dict(mpd_settings or {}) == self._mpd_settings
        ):
            self._short_done.wait()
            if self._short_error is not None:
                raise self._short_error
            if self._short is not None:
                return self._short
        from roadscan.texture_depth import short_segment_depth

        return short_segment_depth(source, **(mpd_settings or {}))

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
