"""One parser for the friction flags (issue 23): every command that takes them gets the same
flags with the same defaults from :func:`pipelines.settings.friction.add_friction_options`, and
:func:`settings_from_args` turns the same flags into the same settings for each of them."""

import numpy as np
import pytest

from pipelines.cli.app import build_parser
from pipelines.settings.friction import FrictionSettings, settings_from_args
from roadscan.errors import InputError

# the positional arguments / required flags of each command, besides the friction flags
BASE = {
    "analyse": ["s.npy", "--out", "o"],
    "batch": ["s.npy", "--out", "o"],
    "compare": ["a.npy", "b.npy", "--out", "o"],
    "dry-vs-wet": ["s.npy", "--out", "o"],
    "friction": ["--self-affine", "H=0.8,h0=1e-4,q0=1e3,q1=1e5"],
    "diagnose": ["--measured", "m.csv", "--out", "o"],
}
FLAGS = [
    "--sigma0",
    "300kPa",
    "--temperature",
    "25",
    "--nu",
    "0.45",
    "--q0",
    "2e3",
    "--q1",
    "1e5",
    "--contact-gamma",
    "0.5",
    "--extrapolate",
    "hold",
]


def _parse(cmd, extra=()):
    return build_parser().parse_args([cmd, *BASE[cmd], *FLAGS, *extra])


def test_the_analyse_module_still_exports_the_settings():
    from pipelines.jobs.analyse.job import FrictionSettings as from_analyse

    assert from_analyse is FrictionSettings


@pytest.mark.parametrize("cmd", sorted(BASE))
def test_every_command_parses_the_same_flags_into_the_same_settings(cmd):
    s = settings_from_args(_parse(cmd))
    assert s.sigma0_Pa == pytest.approx(3e5)  # 300 kPa, parsed with its unit
    assert (s.T0_C, s.nu, s.q0_per_m, s.q1_per_m, s.contact_gamma, s.extrapolate) == (
        25.0,
        0.45,
        2e3,
        1e5,
        0.5,
        "hold",
    )
    assert s.rubber is None and s.enabled


@pytest.mark.parametrize("cmd", sorted(BASE))
def test_defaults_are_the_settings_defaults(cmd):
    args = build_parser().parse_args([cmd, *BASE[cmd]])
    s, d = settings_from_args(args), FrictionSettings()
    for field in (
        "sigma0_Pa",
        "T0_C",
        "flash",
        "q0_per_m",
        "q1_per_m",
        "nu",
        "contact_gamma",
        "extrapolate",
        "enabled",
        "rubber",
    ):
        assert getattr(s, field) == getattr(d, field), field
    assert s.v_m_per_s is None


@pytest.mark.parametrize("cmd", ["analyse", "batch", "compare", "dry-vs-wet", "friction"])
def test_speeds_and_flash_where_the_command_slides(cmd):
    s = settings_from_args(_parse(cmd, ["--velocities", "1e-3:1e1:5", "--flash"]))
    assert s.flash
    np.testing.assert_allclose(s.v_m_per_s, np.logspace(-3, 1, 5))


@pytest.mark.parametrize("cmd", sorted(BASE))
def test_a_bare_small_pressure_is_refused_everywhere(cmd):
    args = build_parser().parse_args([cmd, *BASE[cmd], "--sigma0", "0.3"])
    with pytest.raises(InputError, match=r"did you mean 0.3MPa"):
        settings_from_args(args)


def test_no_friction_only_where_friction_is_optional():
    p = build_parser()
    assert not settings_from_args(p.parse_args(["analyse", *BASE["analyse"], "--no-friction"])).enabled
    for cmd in ("friction", "diagnose"):
        with pytest.raises(SystemExit):
            p.parse_args([cmd, *BASE[cmd], "--no-friction"])
