"""``relaxation_spectrum``: the rubber has a spread of relaxation times, not one (the thesis's
main recommendation). A width of 0.01 decade is the rubber itself (no effect).

Each Prony term (the standard linear solid is a one-term Prony series, docs: Theory) of
strength E_i and relaxation time tau_i is replaced by ``n_terms`` terms with log10 tau normally
distributed around log10 tau_i with standard deviation ``width_decades`` (a log-normal
relaxation spectrum), strengths summing to E_i. The rubbery and glassy limits E(0), E(inf),
the reference temperature and the temperature shift are kept, so only the shape of the loss
peak changes (broader and lower). The centre is not a parameter: a shift of every relaxation
time is exactly a temperature offset (WLF), a separate effect, and a spread whose centre also
moved is the pair relaxation_spectrum+temperature_offset. (Keeping the two apart keeps the
effects identifiable: with a free centre this effect would contain every temperature offset.)
"""

import numpy as np

from pipelines.diagnosis.effects import Effect, Param, register

N_TERMS = 25
SPAN_SIGMAS = 3.0


def lognormal_prony(rubber, width_decades, n_terms=N_TERMS):
    """A :class:`friction.Prony` with each term of ``rubber`` spread log-normally in tau."""
    from friction.rubber import Prony

    base = rubber.as_prony() if hasattr(rubber, "as_prony") else rubber
    z = np.linspace(-SPAN_SIGMAS, SPAN_SIGMAS, n_terms)
    w = np.exp(-0.5 * z**2)
    w /= w.sum()
    E = np.concatenate([Ei * w for Ei in base.E_i_Pa])
    tau = np.concatenate([ti * 10.0 ** (width_decades * z) for ti in base.tau_i_s])
    return Prony(base.E_inf_Pa, E, tau, base.T_ref_C, base.shift, base.thermal)


def _prepare(ctx):
    r = ctx.base.rubber
    if not (hasattr(r, "as_prony") or hasattr(r, "tau_i_s")):
        return f"the rubber is a {type(r).__name__} (measured curve), not a relaxation-time model"
    return None


EFFECT = register(
    Effect(
        name="relaxation_spectrum",
        level="friction",
        params=(Param("width_decades", 0.01, 4.0, 1.0, "log"),),
        modify=lambda spec, p, ctx: spec.with_(rubber=lognormal_prony(spec.rubber, p["width_decades"])),
        prepare=_prepare,
        null=lambda ctx: {"width_decades": 0.01},
        description="log-normal spread of relaxation times around the rubber's own",
    )
)
