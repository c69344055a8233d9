"""The two ways :func:`friction.mu_flash` refuses to answer, re-exported by
:mod:`friction.flash`: a band too short for its macro-asperities, and a flash temperature
that was not found.
"""

from __future__ import annotations

__all__ = ["FlashBandError", "FlashConvergenceError"]


class FlashConvergenceError(RuntimeError):
    """The self-consistent flash temperature was not found (the message is one line, naming the
    speeds and the residual).

    Parameters
    ----------
    message : str
        One line: the speeds that did not converge and the residual [K].
    """


class FlashBandError(ValueError):
    """The macro-asperity wave vector q_m = zeta_m q0 lies outside the spectrum's band
    [q_min, q1]: a band shorter than zeta_m in q has no macro-asperities to heat.

    Attributes
    ----------
    q_m_per_m, q1_per_m : float
        q_m and the band's end [1/m].
    zeta_m : float
        The magnification used.
    """

    def __init__(self, q_m_per_m, q1_per_m, zeta_m):
        super().__init__(
            f"q_m = zeta_m q0 = {q_m_per_m:.3g} 1/m (zeta_m = {zeta_m:g}) must lie inside the "
            f"spectrum's band, which ends at q1 = {q1_per_m:.3g} 1/m"
        )
        self.q_m_per_m, self.q1_per_m, self.zeta_m = float(q_m_per_m), float(q1_per_m), float(zeta_m)
