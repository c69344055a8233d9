"""Which length scales and frequencies carry the friction in each speed band.

Persson's mu(v) = 1/2 ∫ dq q^3 C(q) P(q) M(q) (docs: Theory), so per unit ln q the
contribution is ``dmu/dln q = 1/2 q^4 C(q) P(q) M(q)`` with
``M(q) = 4 / ((1 - nu^2) sigma0) ∫_0^{pi/2} dphi cos(phi) Im E(q v cos(phi), T0)``
(Im E > 0 for omega > 0; Gauss-Legendre in phi here, accurate enough for a map). P(q) comes
from the engine. For each band the map reports the wave-vector range holding the central
80 % of the integrand at the band's geometric-mean speed, its peak, the length scales 2 pi / q
and the excitation frequencies omega = q v over the band's speeds.

Cut-off sensitivity: ``dlnmu_dlnq1`` = d ln mu / d ln q1 at the band's centre speed, by a
one-sided difference with the spectrum cut at q1 / 1.25 (q1: the spectrum's highest wave
vector). A value near 0 means the measured band holds the friction; a large value (above
``CUTOFF_FLAG``, or the integrand peaking at the last wave vector) means mu is carried by the
spectrum's cut-off: it depends on where the spectrum is cut, not only on the measured texture
(``carried_by_cutoff``; the report says so).
"""

from __future__ import annotations

import numpy as np

__all__ = ["integrand", "band_map", "CUTOFF_FLAG"]

CUTOFF_FLAG = 0.3
CUT_STEP = 1.25


def integrand(result, psd, rubber, sigma0_Pa, T0_C=None, nu=0.5, n_phi=48):
    """dmu/dln q on the result's (nv, nq) grid [-] (see module docstring).

    Parameters
    ----------
    result : friction.FrictionResult
        An engine result: its speeds v [m/s], wave vectors q [1/m] and contact area P(q) are used.
    psd : spectrum
        The spectrum C(q) [m^4] the result was computed with.
    rubber : rubber model
        The rubber the result was computed with (its loss modulus Im E [Pa]).
    sigma0_Pa : float
        Nominal pressure [Pa].
    T0_C : float, optional
        Background temperature [C] of the modulus; None: passed as None to ``rubber.modulus``.
    nu : float, optional
        Poisson's ratio (default 0.5, incompressible), in (1 - nu^2) sigma0.
    n_phi : int, optional
        Gauss-Legendre nodes of the angular integral over [0, pi/2] (default 48).

    Returns
    -------
    ndarray, shape (nv, nq)
        dmu/dln q at each speed and wave vector [-]; its integral over ln q is mu (no S(q) factor).
    """
    q = result.q_per_m
    v = result.v_m_per_s
    x, w = np.polynomial.legendre.leggauss(n_phi)
    phi = (x + 1) * np.pi / 4
    wphi = w * np.pi / 4
    om = v[:, None, None] * q[None, :, None] * np.cos(phi)[None, None, :]
    ImE = np.imag(rubber.modulus(om, T0_C))
    M = 4.0 * np.sum(wphi * np.cos(phi) * ImE, axis=-1) / ((1 - nu * nu) * sigma0_Pa)
    return 0.5 * q[None, :] ** 4 * psd.C(q)[None, :] * result.P * M


def band_map(spec, bands, sigma0_Pa=0.2e6, T0_C=None, share=0.8):
    """One dict per speed band (v_min, v_max from :func:`gap.decade_bands`) with the q range
    carrying ``share`` of mu, the peak q, the length scales [m] and frequencies [rad/s].

    Also returns the curves (q, dmu/dln q per band) for the figure.

    Parameters
    ----------
    spec : SimSpec
        The model mapped: its spectrum, rubber, nu, tol and contact correction (isothermal; its
        flash, T0 shift and sigma0 scale are not applied).
    bands : list of tuple
        Speed bands (v_min, v_max, n) [m/s].
    sigma0_Pa : float, optional
        Nominal pressure [Pa].
    T0_C : float, optional
        Background temperature [C]; None: the rubber's ``T_ref_C``.
    share : float, optional
        Share of mu the q range carries.

    Returns
    -------
    rows : list of dict
        Per band: q_min/q_max/q_peak [1/m], lengths [m], omegas [rad/s], mu_at_centre,
        dlnmu_dlnq1 and carried_by_cutoff (d ln mu / d ln q1 > 0.3 or the peak at the last q).
    curves : tuple
        (q [1/m], dmu/dln q with shape (n_bands, nq), band-centre speeds [m/s]).
    """
    import friction

    v_c = np.array([np.sqrt(a * b) for a, b, *_ in bands])
    kw = dict(sigma0_Pa=sigma0_Pa, nu=spec.nu, T0_C=T0_C, tol=spec.tol, contact_gamma=spec.contact_gamma)
    res = friction.mu_isothermal(spec.psd, spec.rubber, v_c, **kw)
    T = spec.rubber.T_ref_C if T0_C is None else T0_C
    q1 = spec.psd.q1_per_m
    cut = friction.mu_isothermal(spec.psd.with_q1(q1 / CUT_STEP), spec.rubber, v_c, **kw)
    sens = np.log(np.asarray(res.mu) / np.asarray(cut.mu)) / np.log(CUT_STEP)
    f = integrand(res, spec.psd, spec.rubber, sigma0_Pa, T, nu=spec.nu)
    if spec.contact_gamma is not None:  # Persson's S(q) multiplies the integrand as in the engine
        from friction.contact import contact_S

        f = f * contact_S(res.P, spec.contact_gamma)
    lq = np.log(res.q_per_m)
    out = []
    for i, (a, b, *_) in enumerate(bands):
        fi = np.maximum(f[i], 0)
        cum = np.concatenate([[0], np.cumsum(0.5 * (fi[1:] + fi[:-1]) * np.diff(lq))])
        tot = cum[-1] if cum[-1] > 0 else 1.0
        lo_q = float(np.exp(np.interp((1 - share) / 2 * tot, cum, lq)))
        hi_q = float(np.exp(np.interp((1 + share) / 2 * tot, cum, lq)))
        ipk = int(np.argmax(fi))
        pk = float(res.q_per_m[ipk])
        out.append(
            dict(
                v_min_m_per_s=a,
                v_max_m_per_s=b,
                q_min_per_m=lo_q,
                q_max_per_m=hi_q,
                q_peak_per_m=pk,
                length_min_m=2 * np.pi / hi_q,
                length_max_m=2 * np.pi / lo_q,
                omega_min_rad_s=lo_q * a,
                omega_max_rad_s=hi_q * b,
                mu_at_centre=float(res.mu[i]),
                dlnmu_dlnq1=float(sens[i]),
                carried_by_cutoff=bool(sens[i] > CUTOFF_FLAG or ipk >= fi.size - 2),
            )
        )
    return out, (res.q_per_m, f, v_c)
