"""The science chain as a Python API: ``pipelines.analyse(source, **options)`` analyses one scan
exactly as ``roadscan analyse`` does and returns an :class:`AnalysisResult`; :func:`analyse_scan`
is the same on a read scan with checked options; :func:`compare` is ``roadscan compare`` as one
call, and so are :func:`dry_vs_wet`, :func:`rain_fill`, :func:`friction`, :func:`combine` and
:func:`diagnose` of their commands (keywords: the command's long flags with dashes as
underscores; each returns the dict of the command's main JSON); :mod:`pipelines.chain` holds
the steps.
"""
from __future__ import annotations

from .analyse import analyse, analyse_scan
from .analysis_result import AnalysisResult
from .combine import combine
from .compare import compare
from .diagnose.job import diagnose
from .dry_vs_wet import dry_vs_wet
from .friction_api import friction
from .rain_fill import rain_fill

__all__ = ["analyse", "analyse_scan", "AnalysisResult", "compare", "dry_vs_wet", "rain_fill", "friction",
           "combine", "diagnose"]
