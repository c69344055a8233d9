"""roadscan's jobs as a Python API, and the ``roadscan`` command.

Every job of the command line is one function here, with keyword-only options in SI units:
:func:`analyse` (one scan to its spectrum, fit, texture figures and mu(v); returns an
:class:`AnalysisResult`), :func:`compare`, :func:`dry_vs_wet`, :func:`rain_fill`,
:func:`friction`, :func:`combine`, :func:`diagnose` and :func:`batch`. The building blocks of
the chain are in :mod:`pipelines.chain`. Names are imported on first use, so ``import
pipelines`` stays light (``roadscan --help`` needs none of numpy's weight).

Layout: ``chain/`` (the science chain, one module per step), ``settings/`` (the option groups
the command line and the API both build), ``checks/`` (input trust, run warnings), ``jobs/``
(one module or folder per job), ``output/`` (reports, figures, files), ``cli/`` (the
command), ``campaign/`` (batch on Dask), ``diagnosis/`` (the sim-to-real gap diagnosis).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import lazy_loader

from roadscan.errors import RoadscanWarning

__all__ = [
    "analyse",
    "analyse_scan",
    "AnalysisResult",
    "compare",
    "dry_vs_wet",
    "rain_fill",
    "friction",
    "combine",
    "diagnose",
    "batch",
    "chain",
    "RoadscanWarning",
]

#: public name -> the submodule that defines it, imported on first use (``lazy_loader``, the
#: mechanism scikit-image uses, as in ``roadscan`` and ``friction``)
_HOMES = {
    "jobs.analyse.call": ["analyse"],
    "jobs.analyse.job": ["analyse_scan"],
    "jobs.analyse.result": ["AnalysisResult"],
    "jobs.compare": ["compare"],
    "jobs.dry_vs_wet": ["dry_vs_wet"],
    "jobs.rain_fill": ["rain_fill"],
    "jobs.friction_call": ["friction"],
    "jobs.combine.job": ["combine"],
    "diagnosis.job": ["diagnose"],
    "campaign.api": ["batch"],
}
__getattr__, _, _ = lazy_loader.attach(__name__, submodules=["chain"], submod_attrs=_HOMES)

if TYPE_CHECKING:  # pragma: no cover - for type checkers and editors only
    from pipelines import chain
    from pipelines.campaign.api import batch
    from pipelines.diagnosis.job import diagnose
    from pipelines.jobs.analyse.call import analyse
    from pipelines.jobs.analyse.job import analyse_scan
    from pipelines.jobs.analyse.result import AnalysisResult
    from pipelines.jobs.combine.job import combine
    from pipelines.jobs.compare import compare
    from pipelines.jobs.dry_vs_wet import dry_vs_wet
    from pipelines.jobs.friction_call import friction
    from pipelines.jobs.rain_fill import rain_fill


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
