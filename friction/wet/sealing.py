"""Where the contact seals the water in: the percolation magnification of Persson's contact.

Persson, Tartaglino, Albohr and Tosatti (Phys. Rev. B 71, 035428 (2005)): at low speed the
rubber closes the road's water-filled "pools" at the magnification zeta_c where the
non-contact area stops percolating, i.e. where the contact area P(zeta) = A(zeta)/A0 the
engine computes has fallen to the percolation fraction (A/A0 ~ 0.42, Dapp et al., PRL 108,
244301 (2012)). The water sealed in those pools cannot leave; it smooths the road the rubber
feels at every shorter scale. Which regions are pools is a property of the map, not of the
spectrum: :func:`roadscan.sealing.seal_pools` fills them on a height map given the wave vector
``q_c = zeta_c q0`` and the contact fraction returned here, and the wet friction integrates
the sealed map's spectrum (:func:`friction.wet.model.wet_friction`).
"""

from __future__ import annotations

import numpy as np

from .water import PERCOLATION_CONTACT_FRACTION

__all__ = ["sealing_wave_vector"]


def sealing_wave_vector(q_per_m, P, contact_fraction=PERCOLATION_CONTACT_FRACTION):
    """The wave vector q_c [1/m] where the contact area P(q) first falls to ``contact_fraction``.

    P(q) falls from 1 at the lowest wave vector; q_c is interpolated linearly in (ln q, P).
    When P stays above the fraction over the whole band the contact does not percolate at any
    scale and every non-contact region is a closed pool: q_c is the band's upper end.

    Parameters
    ----------
    q_per_m : array_like, shape (nq,)
        Wave vectors of the engine's grid [1/m] (``FrictionResult.q_per_m``).
    P : array_like, shape (nq,)
        Contact area at one speed (``FrictionResult.P[i]``), the slow speed at which the
        block lands.
    contact_fraction : float, optional
        A/A0 at which the non-contact area percolates (0.42).

    Returns
    -------
    float
        q_c [1/m].

    References
    ----------
    B.N.J. Persson, U. Tartaglino, O. Albohr, E. Tosatti, "Rubber friction on wet and dry road
    surfaces: the sealing effect", Phys. Rev. B 71, 035428 (2005),
    doi:10.1103/PhysRevB.71.035428.
    W.B. Dapp, A. Luecke, B.N.J. Persson, M.H. Mueser, Phys. Rev. Lett. 108, 244301 (2012),
    doi:10.1103/PhysRevLett.108.244301.
    """
    q = np.asarray(q_per_m, dtype=float)
    P = np.asarray(P, dtype=float)
    below = np.nonzero(P <= contact_fraction)[0]
    if below.size == 0:
        return float(q[-1])
    i = int(below[0])
    if i == 0:
        return float(q[0])
    t = (P[i - 1] - contact_fraction) / (P[i - 1] - P[i])
    return float(np.exp(np.log(q[i - 1]) + t * (np.log(q[i]) - np.log(q[i - 1]))))
