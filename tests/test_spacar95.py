"""SPACAR95 (Delft) input files: read with their manual's meaning, or refused naming
SPACAR95 (A.L. Schwab, J.P. Meijaard, *Manual SPACAR95*, TU Delft, November 2000)."""

import dataclasses

import pytest

from flexmbd.analysis.runs import analyse, default_mode
from flexmbd.errors import InputFileError
from flexmbd.io.dat import dat_from_text

#: the manual's example (its section 5.7): a slider-crank with an elastic connecting rod
#: of two planar beams, the crank turned at 1.5 rad/s
MANUAL_EXAMPLE = """\
* the SPACAR95 manual's example, section 5.7
PLBEAM 1 1 2 3 4
PLBEAM 2 3 5 6 7
PLBEAM 3 6 7 8 9
FIX 1
FIX 8 2
X 3 0.15 0.
X 6 0.30 0.
X 8 0.45 0.
INPUTX 2 1
DYNE 2 2
DYNE 2 3
DYNE 3 2
DYNE 3 3
TIMESTEP 100 5.0
MASS 8 0.033375
EMASS 1 0.2225
EMASS 2 0.2225
EMASS 3 0.2225
ESTIFF 2 0. 0.0012723
ESTIFF 3 0. 0.0012723
INPUTX 2 1
XD 2 1 1.5
END
"""

#: the state the manual prints after 5 s (4 digits)
PRINTED_POSITIONS = {"x2.1": 7.500, "x3.1": 5.199e-02, "x3.2": 1.407e-01, "x4.1": 7.500,
                     "x5.1": -4.443e-01, "x6.1": 1.863e-01, "x6.2": 7.383e-02,
                     "x7.1": -4.903e-01, "x8.1": 3.168e-01, "x9.1": -5.279e-01}
PRINTED_DEFORMATIONS = {"e2.2": 2.673e-03, "e2.3": 4.227e-03, "e3.2": 3.644e-03,
                        "e3.3": 1.996e-03}


def test_the_manuals_example_reaches_its_printed_state():
    """Read with SPACAR95's meaning (``TIMESTEP n Tp``, ``MASS``, ``EMASS``, the crank's
    rate ``XD`` as its law), the run ends at 5 s in 100 intervals with the printed
    positions to their four digits (a unit of the last) and the rod's bending
    deformations to 3e-3. (The printed rates ``ED`` are not compared: the rod's
    vibration phase after 5 s moves them by tens of percent between integrator
    tolerances 1e-3 and 1e-9, and SPACAR95 integrated with 1e-3.)"""
    model, settings = dat_from_text(MANUAL_EXAMPLE, "manual.dat")
    assert (settings.t_end, settings.steps) == (5.0, 100)
    assert settings.notes[0].startswith("read as a SPACAR95 (Delft) file")
    settings = dataclasses.replace(settings, rtol=1e-9, atol=1e-12)
    result = analyse(model, settings, default_mode(model), settings.output_times(),
                     progress=False)
    for label, printed in PRINTED_POSITIONS.items():
        # within a unit of the last printed digit (the crank tip's 0.15 cos 7.5 =
        # 0.0519953 is printed 5.199E-02)
        assert result[label][-1] == pytest.approx(printed, abs=10.0 ** (
            _exponent(printed) - 3)), label
    for label, printed in PRINTED_DEFORMATIONS.items():
        assert result[label][-1] == pytest.approx(printed, rel=3e-3), label


def _exponent(value: float) -> int:
    return int(f"{value:e}".split("e")[1])


@pytest.mark.parametrize("text, words", [
    (MANUAL_EXAMPLE.replace("DYNE 3 3", "DYNE 3 3\nPLBELT 4 8 9 10 11 0.1 0.1"),
     r"manual\.dat:\d+: SPACAR95 \(Delft\) keyword PLBELT has no counterpart in flexmbd"),
    (MANUAL_EXAMPLE.replace("XD 2 1 1.5", "XD 2 1 1.5\nGRAVITY 0 -9.81"),
     r"mixes SPACAR95 \(Delft\) keyword MASS \(line 16\) and UT SPACAR keyword GRAVITY"),
    ("PLBEAM 1 1 2 3 4\nX 3 1 0\nFIX 1\nTIMESTEP 100 5.0\nEND\nEND\n",
     r"manual\.dat:4: TIMESTEP before the first END: a SPACAR95 .*TIMESTEP n Tp.*UT SPACAR "
     r"file writes TIMESTEP T n"),
    (MANUAL_EXAMPLE + "TIMESTEP 10 1.0\nEND\n",
     r"SPACAR95: input after the END on line 24 continues the analysis"),
    (MANUAL_EXAMPLE.replace("XD 2 1 1.5", "XD 2 1 1.5\nTIME 2.0"),
     r"SPACAR95: TIME sets a start time other than 0"),
    (MANUAL_EXAMPLE.replace("XD 2 1 1.5", "XD 2 1 1.5\nXD 3 1 0.2"),
     r"SPACAR95: an initial value of x3\.1, which is neither an input nor a dynamic"),
])
def test_spacar95_input_without_a_counterpart_is_refused_naming_spacar95(text, words):
    with pytest.raises(InputFileError, match=words):
        dat_from_text(text, "manual.dat")


def test_spacar95_settings_are_noted_and_a_dynamic_rate_starts_the_motion():
    text = MANUAL_EXAMPLE.replace("XD 2 1 1.5", "XD 2 1 1.5\nED 2 2 0.01\nHMAX 0.01\n"
                                                "EPSKIN 1e-5")
    _, settings = dat_from_text(text, "manual.dat")
    assert settings.initial["e2.2"] == (0.0, 0.01)
    assert any(note.startswith("SPACAR95's HMAX on line 25: read and not used")
               for note in settings.notes)
