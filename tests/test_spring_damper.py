"""The spring-damper (PLSPRING): a mass on a pre-loaded spring-damper against the closed
form of the damped oscillator, built in Python and read from a SPACAR file."""

import math

import numpy as np
import pytest

import flexmbd as fm
from flexmbd.cli import main as cli
from flexmbd.io.dat import dat_text

K, C, PRELOAD, MASS = 400.0, 1.5, 2.0, 0.25  # N/m, N s/m, N, kg
U0 = 0.01  # initial stretch [m]

SPRING_FILE = f"""\
PLSPRING 1 1 2
X 1 0 0
X 2 1 0
FIX 1
FIX 2 2
DYNX 2 1
END
HALT
ESTIFF 1 {K}
EDAMP 1 {C}
ESIG 1 {PRELOAD}
XM 2 {MASS}
STARTDX 2 1 {1 + U0} 0
TIMESTEP 0.5 100
ERROR 1e-12 1e-10
END
END
"""


def oscillator(t):
    """``u(t)`` of ``m u'' + c u' + k u + sigma0 = 0`` from ``u(0) = U0``, ``u'(0) = 0``."""
    omega = math.sqrt(K / MASS)
    zeta = C / (2 * math.sqrt(K * MASS))
    damped = omega * math.sqrt(1 - zeta**2)
    rest = -PRELOAD / K
    return rest + (U0 - rest) * np.exp(-zeta * omega * t) * (
        np.cos(damped * t) + zeta * omega / damped * np.sin(damped * t))


def spring_model() -> fm.Model:
    b = fm.ModelBuilder("mass on a spring-damper")
    b.add_node(1, 0.0, 0.0).add_node(2, 1.0, 0.0)
    b.add_element(1, fm.SpringDamper, (1, 2))
    b.fix(1).fix(2, "y").dynamic_coordinate(2, "x")
    b.set_stiffness(1, spring=K).set_damping(1, spring=C).set_prestress(1, 1, PRELOAD)
    b.add_point_mass(2, MASS)
    return b.build()


@pytest.mark.parametrize("method", ["DOP853", "GeneralizedAlpha"])
def test_a_mass_on_a_spring_damper_oscillates_as_the_closed_form(method):
    model = spring_model()
    assert model.q_labels == ("x2.1",)  # the elongation is released: not a constraint
    times = np.linspace(0.0, 0.5, 101)
    options = {"rtol": 1e-10, "atol": 1e-12} if method == "DOP853" else {"step": 1e-5}
    result = fm.simulate(model, times, initial={"x2.1": (1 + U0, 0.0)}, method=method,
                         with_reactions=True, **options)
    u = result["x2.1"] - 1.0
    tolerance = 1e-9 if method == "DOP853" else 1e-7  # second order at 1e-5 s steps
    np.testing.assert_allclose(u, oscillator(times), atol=tolerance * U0 / 1e-2)
    np.testing.assert_allclose(result["e1.1"], u, atol=1e-14)
    # the force along the spring, and the support holding its other end
    force = K * result["e1.1"] + C * result["ed1.1"] + PRELOAD
    np.testing.assert_allclose(result["sig1.1"], force, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(result["f1.1"], -force, rtol=1e-9, atol=1e-9)
    # it really oscillates about the pre-loaded rest, and the damping takes the amplitude
    # to exp(-zeta omega t) = exp(-1.5) of the start in 0.5 s
    swing = np.abs(u + PRELOAD / K)
    assert np.ptp(u) > U0 and swing[-20:].max() < 0.3 * swing[0]


def test_the_spring_file_runs_through_flexmbd_run(tmp_path, capsys):
    path = tmp_path / "spring.dat"
    path.write_text(SPRING_FILE)
    model, settings = fm.read_dat(path)
    assert model.elements[1].type is fm.SpringDamper
    assert settings.initial == {"x2.1": (1 + U0, 0.0)}
    out = tmp_path / "spring.csv"
    assert cli(["run", str(path), "--out", str(out), "--method", "DOP853"]) == 0
    data = np.genfromtxt(out, delimiter=",", names=True)
    np.testing.assert_allclose(data["x21"] - 1.0, oscillator(data["t"]), atol=1e-8)
    written = fm.write_dat(model, tmp_path / "again.dat", settings)
    assert dat_text(*fm.read_dat(written)).split("\n", 1)[1] == \
        dat_text(model, settings).split("\n", 1)[1]  # all but the name in the first line
