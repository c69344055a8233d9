"""Persson's adhesive (interfacial) friction term and what water leaves of it.

In Persson's theory the shear stress tau_f acting in the area of real contact A(v) adds
``mu_adh = tau_f A(v) / (A0 sigma0)`` to the viscoelastic friction, with ``A(v)/A0 = P(q1)``
the engine's contact area at the finest scale and speed v (Persson, J. Phys.: Condens. Matter
18, 7789 (2006); Lorenz et al., J. Phys.: Condens. Matter 25, 095007 (2013),
doi:10.1088/0953-8984/25/9/095007). tau_f is a property of the rubber-road
pair (about 1-10 MPa for tread rubber on road stone in Lorenz et al. 2013); it has no default
here. Wet, only the contact that water does not separate keeps it: the real contact at the
contact pressure left after squeeze-out, outside the pools the rubber seals (where it touches
water, not road).
"""

from __future__ import annotations

import numpy as np

__all__ = ["adhesive_mu"]


def adhesive_mu(shear_stress_Pa, contact_area, sigma0_Pa, dry_fraction=1.0):
    """``mu_adh = tau_f (A/A0) f_dry / sigma0`` [-]; 0 when ``shear_stress_Pa`` is None.

    Parameters
    ----------
    shear_stress_Pa : float or None
        Frictional shear stress tau_f [Pa]; None leaves adhesion out (zeros).
    contact_area : array_like
        A/A0 at the finest scale, per speed (``FrictionResult.P[:, -1]``).
    sigma0_Pa : float
        Nominal pressure [Pa].
    dry_fraction : float or array_like, optional
        Fraction of that contact not separated by water (1 dry).

    Returns
    -------
    ndarray
        mu_adh per speed.

    References
    ----------
    B.N.J. Persson, J. Phys.: Condens. Matter 18, 7789 (2006), doi:10.1088/0953-8984/18/32/025.
    B. Lorenz, B.N.J. Persson et al., J. Phys.: Condens. Matter 25, 095007 (2013),
    doi:10.1088/0953-8984/25/9/095007.
    """
    A = np.asarray(contact_area, dtype=float)
    if shear_stress_Pa is None:
        return np.zeros(A.shape)
    return float(shear_stress_Pa) * A * np.asarray(dry_fraction, dtype=float) / float(sigma0_Pa)
