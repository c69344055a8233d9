"""``anisotropy`` (surface level): the texture has a direction (the twin is isotropic); the
anisotropy index (l1 - l2)/(l1 + l2) of the 2D spectrum's direction tensor becomes a parameter.
Needs an area scan."""
from . import Effect, Param, register


def _apply(ctx, p, C, st):
    st = st.copy()
    st[ctx.stat_index("anisotropy_index")] = p["anisotropy_index"]
    return C, st


EFFECT = register(Effect(
    name="anisotropy", level="surface", requires=frozenset({"area"}),
    params=(Param("anisotropy_index", 0.0, 0.95, 0.1, "lin"),),
    apply_fn=_apply,
    description="directional texture (anisotropy index of the 2D spectrum)",
))
