"""The one chain from a scan to friction: every command that computes mu(v) from a height map
calls these steps (:mod:`pipelines.chain.steps`).

- :mod:`~pipelines.chain.surface`: level, fill, spectrum and roughness of one scan
- :mod:`~pipelines.chain.reliable`: the scales the measurement can be trusted on
- :mod:`~pipelines.chain.band`: the reliable band feeds the self-affine fit and the friction
- :mod:`~pipelines.chain.steps`: :func:`measure`, :func:`friction_psd`, :func:`friction_of`,
  :func:`scan_friction` (and the ``psd_band.json`` sidecar)
- :mod:`~pipelines.chain.provenance`: where mu comes from, and why a mu is implausible
"""

from __future__ import annotations

from pipelines.chain.steps import (
    FrictionOutcome,
    friction_of,
    friction_psd,
    judge_fine_end,
    measure,
    scan_friction,
)

__all__ = ["measure", "friction_psd", "friction_of", "scan_friction", "judge_fine_end", "FrictionOutcome"]
