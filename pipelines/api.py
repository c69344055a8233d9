"""The science chain as a Python API: ``pipelines.analyse(source, **options)`` analyses one scan
exactly as ``roadscan analyse`` does and returns an :class:`AnalysisResult`; :func:`analyse_scan`
is the same on a read scan with checked options; :func:`compare` is ``roadscan compare`` as one
call; :mod:`pipelines.chain` holds the steps.
"""
from __future__ import annotations

from .analyse import analyse, analyse_scan
from .analysis_result import AnalysisResult
from .compare import compare

__all__ = ["analyse", "analyse_scan", "AnalysisResult", "compare"]
