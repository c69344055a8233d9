"""The result object of the friction engine."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["FrictionResult"]


@dataclass(frozen=True, eq=False)
class FrictionResult:
    """mu(v) and the contact quantities on the q grid.

    Attributes
    ----------
    v_m_per_s : ndarray, shape (nv,)
        Sliding speeds [m/s].
    mu : ndarray, shape (nv,)
        Kinetic friction coefficient (viscoelastic contribution, Persson's theory).
    q_per_m : ndarray, shape (nq,)
        Wave-vector nodes [1/m], uniform in ln q from q_min to q1.
    P : ndarray, shape (nv, nq)
        Relative contact area P(q) at each speed; ``P[:, -1]`` is A/A0.
    G : ndarray, shape (nv, nq)
        Persson's G(q).
    T_q_C : ndarray, shape (nv, nq), or None
        Flash temperature [C] at each length scale (None: isothermal).
    iterations : int
        Fixed-point iterations (0 for the isothermal model).
    residual : float
        Final max |T - Phi(T)| [K] (0 for the isothermal model).
    meta : dict
        The parameters and grid sizes used.
    """

    v_m_per_s: np.ndarray
    mu: np.ndarray
    q_per_m: np.ndarray
    P: np.ndarray
    G: np.ndarray
    T_q_C: np.ndarray | None = None
    iterations: int = 0
    residual: float = 0.0
    meta: dict = field(default_factory=dict)

    @property
    def q0_per_m(self) -> float:
        """The spectrum's q0 [1/m] (the first wave vector unless recorded in ``meta``)."""
        return self.meta.get("q0_per_m", float(self.q_per_m[0]))

    def _interp_q(self, arr, q):
        """Linear interpolation in ln q of ``arr`` (nv, nq) at wave vector(s) q; (nv,) or (nv, k)."""
        lq = np.log(self.q_per_m)
        qq = np.atleast_1d(np.asarray(q, dtype=float))
        if np.any(qq < self.q_per_m[0] * (1 - 1e-9)) or np.any(qq > self.q_per_m[-1] * (1 + 1e-9)):
            raise ValueError(
                f"wave vector outside the computed range [{self.q_per_m[0]:.4g}, {self.q_per_m[-1]:.4g}] 1/m"
            )
        x = np.clip(np.log(qq), lq[0], lq[-1])
        i = np.clip(np.searchsorted(lq, x) - 1, 0, lq.size - 2)
        t = (x - lq[i]) / (lq[i + 1] - lq[i])
        out = arr[:, i] * (1 - t) + arr[:, i + 1] * t
        return out[:, 0] if np.ndim(q) == 0 else out

    def temperature_at(self, zeta: ArrayLike) -> NDArray[np.float64]:
        """Flash temperature [C] at magnification ``zeta`` (q = zeta q0), shape (nv,) or (nv, k)."""
        if self.T_q_C is None:
            raise ValueError("isothermal result: no flash temperatures")
        return self._interp_q(self.T_q_C, np.asarray(zeta, dtype=float) * self.q0_per_m)

    def P_at(self, zeta: ArrayLike) -> NDArray[np.float64]:
        """Relative contact area at magnification ``zeta`` (q = zeta q0); P is interpolated
        linearly in ln G (G grows smoothly)."""
        with np.errstate(divide="ignore"):
            lG = self._interp_q(np.log(np.maximum(self.G, 1e-300)), np.asarray(zeta, float) * self.q0_per_m)
        from .contact import contact_P

        return contact_P(np.exp(lG))

    @property
    def peak(self) -> tuple[float, float]:
        """(mu_max, v at mu_max [m/s]): the largest mu on the speed grid, refined by a parabola
        through it and its neighbours in ln v (the grid value at the ends of the grid)."""
        i = int(np.argmax(self.mu))
        if 0 < i < self.mu.size - 1:
            x = np.log(self.v_m_per_s[i - 1 : i + 2])
            c = np.polyfit(x - x[1], self.mu[i - 1 : i + 2], 2)
            if c[0] < 0:
                xs = -c[1] / (2 * c[0])
                if abs(xs) <= max(abs(x[0] - x[1]), abs(x[2] - x[1])):
                    return float(np.polyval(c, xs)), float(np.exp(x[1] + xs))
        return float(self.mu[i]), float(self.v_m_per_s[i])

    def plot(self, ax: Any = None, label: str | None = None, **kwargs: Any) -> Any:
        """Plot mu(v) on a log speed axis; returns the axes."""
        if ax is None:
            import matplotlib.pyplot as plt

            _, ax = plt.subplots(figsize=(6, 4))
        ax.semilogx(self.v_m_per_s, self.mu, label=label, **kwargs)
        ax.set_xlabel("sliding speed v [m/s]")
        ax.set_ylabel("friction coefficient mu [-]")
        ax.grid(True, which="both", alpha=0.3)
        if label is not None:
            ax.legend()
        return ax
