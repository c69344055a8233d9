"""roadscan's jobs and the ``roadscan`` command, and the science chain as a Python API.

``pipelines.analyse(source, **options)`` analyses one scan exactly as ``roadscan analyse``
does (:func:`pipelines.api.analyse`; returns an :class:`pipelines.api.AnalysisResult`). The
building blocks of the chain are in :mod:`pipelines.chain` (:func:`~pipelines.chain.measure`,
:func:`~pipelines.chain.friction_psd`, :func:`~pipelines.chain.friction_of`,
:func:`~pipelines.chain.scan_friction`). Every other computing command is one function of
:mod:`pipelines.api` the same way: :func:`~pipelines.api.compare`,
:func:`~pipelines.api.dry_vs_wet`, :func:`~pipelines.api.rain_fill`,
:func:`~pipelines.api.friction`, :func:`~pipelines.api.combine` and
:func:`~pipelines.api.diagnose` (keywords: the command's long flags with dashes as
underscores, parsed by the command's own option definitions; each writes the command's files
and returns the dict of its main JSON). Names are imported on first use: ``import pipelines``
stays light.
"""
from __future__ import annotations

import importlib

__all__ = ["analyse", "AnalysisResult", "analyse_scan", "chain"]

_LAZY = {"AnalysisResult": ("pipelines.analysis_result", "AnalysisResult"),
         "analyse_scan": ("pipelines.analyse", "analyse_scan")}


def __getattr__(name):
    if name in ("analyse", "chain"):      # the module pipelines.analyse is callable
        return importlib.import_module(f"{__name__}.{name}")
    if name in _LAZY:
        mod, attr = _LAZY[name]
        return getattr(importlib.import_module(mod), attr)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
