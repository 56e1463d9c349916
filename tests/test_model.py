"""Model building and validation: every problem is reported, by name."""

import math
import warnings

import numpy as np
import pytest

import flexmbd as fm
from flexmbd.model import CoordinateClass, DeformationClass

from .models import slider_crank


def sliding_truss() -> fm.ModelBuilder:
    b = fm.ModelBuilder("bar")
    b.add_node(1, -math.sqrt(3), 0.0).add_node(2, 0.0, 1.0)
    b.add_truss(1, 1, 2)
    return b


def problems_of(builder: fm.ModelBuilder) -> list[str]:
    with pytest.raises(fm.ModelError) as info:
        builder.build()
    return info.value.problems


def test_slider_crank_numbering_and_classes():
    model = slider_crank()
    assert model.coordinate_labels == ("x1.1", "x1.2", "x2.1", "x3.1", "x3.2", "x4.1",
                                       "x5.1", "x5.2")
    assert model.deformation_labels == ("e1.1", "e1.2", "e2.1", "e2.2")
    assert [model.coordinate_labels[i] for i in model.dependent] == ["x3.1", "x3.2", "x4.1",
                                                                    "x5.1"]
    assert [model.coordinate_labels[i] for i in model.fixed] == ["x1.1", "x1.2", "x5.2"]
    assert model.q_labels == ("x2.1",)
    assert model.q_is_input.tolist() == [True]
    assert model.n_dof == 1
    assert model.coordinate_index((5, "x")) == model.coordinate_index("x5.1") == 6
    assert model.describe_deformation(3) == "e2.2 (rigid beam 2, normal offset)"


def test_model_is_immutable():
    model = slider_crank()
    with pytest.raises(ValueError):
        model.x0[0] = 1.0
    with pytest.raises(AttributeError):
        model.name = "other"  # type: ignore[misc]
    with pytest.raises(TypeError):
        model.nodes[9] = None  # type: ignore[index]


def test_reference_length_and_angle():
    model = slider_crank()
    np.testing.assert_allclose([model.elements[n].reference for n in (1, 2)],
                               [[1.0, 0.0], [math.sqrt(3), 0.0]])
    tilted = sliding_truss().fix(1, "y").fix(2, "x").input_coordinate(1, "x").build()
    np.testing.assert_allclose(tilted.elements[1].reference, [2.0])  # a truss uses l0 only


def test_all_structural_problems_are_reported_at_once():
    b = fm.ModelBuilder()
    b.add_node(1, 0.0, 0.0).add_node(2, 0.0, 0.0).add_node(2, 1.0, 0.0)
    b.add_truss(1, 1, 2)
    b.add_truss(1, 1, 3)  # duplicate number, node 3 has no position
    b.add_beam(2, 1, 4, 5, 1)  # node 1 used as translational and rotational
    b.fix(9)
    problems = problems_of(b)
    text = "\n".join(problems)
    assert "node 2 is given a position twice" in text
    assert "element number 1 is used twice" in text
    assert "node 3 (used by truss 1) has no position" in text
    assert "node 1 is used as translational by" in text and "rotational by beam 2" in text
    assert len(problems) >= 4


def test_unknown_node_zero_length_and_double_class():
    b = fm.ModelBuilder()
    b.add_node(1, 0.0, 0.0).add_node(2, 0.0, 0.0)
    b.add_truss(1, 1, 2)
    b.fix(1).fix(7, "x").input_coordinate(1, "x").fix(2, "z").release(3, 1)
    text = "\n".join(problems_of(b))
    assert "truss 1 has zero length: its nodes 1 and 2 coincide" in text
    assert "fix: node 7 is not in the model" in text
    assert "x1.1 is put in two classes: fixed and an input" in text
    assert "direction 'z' does not exist" in text
    assert "release: element 3 is not in the model" in text


def test_deformation_classes_and_bad_index():
    b = sliding_truss()
    b.fix(1, "y").fix(2, "x").input_coordinate(1, "x")
    b.release(1, 2)
    assert "deformation 2 does not exist; a truss has deformations 1 to 1" in problems_of(b)[0]
    b = sliding_truss().fix(1, "y").fix(2, "x").input_coordinate(1, "x")
    b.release(1).dynamic_deformation(1, 1)
    assert "e1.1 is put in two classes: released and dynamic" in problems_of(b)[0]


def test_under_determined_names_the_free_coordinates():
    b = sliding_truss().fix(1, "y").fix(2, "x")  # x_p neither fixed nor input
    (problem,) = problems_of(b)
    assert "1 equation(s) too few" in problem
    assert "1 constraint equations" in problem and "2 dependent coordinates" in problem
    assert "x1.1 (node 1, x)" in problem and "x2.2 (node 2, y)" in problem


def test_over_determined_names_the_redundant_equations():
    b = sliding_truss().fix(1).fix(2, "x").input_coordinate(2, "y")
    (problem,) = problems_of(b)
    assert "1 equation(s) too many" in problem
    assert "e1.1 (truss 1, elongation)" in problem


def test_singular_start_is_reported_with_svd_names():
    """Truss along x with its end free only along x cannot fix y: D_c singular."""
    b = fm.ModelBuilder()
    b.add_node(1, 0.0, 0.0).add_node(2, 2.0, 0.0)
    b.add_truss(1, 1, 2)
    b.fix(1).fix(2, "x")  # dependent y_q, but d e1 / d y_q = 0 when the bar lies flat
    (problem,) = problems_of(b)
    assert problem.startswith("D_c is singular in the initial configuration")
    assert "x2.2 (node 2, y) can move" in problem
    assert "e1.1 (truss 1, elongation)" in problem


def test_slider_crank_driven_at_the_slider_is_singular_when_stretched():
    b = fm.ModelBuilder()
    b.add_node(1, 0.0, 0.0).add_node(3, 1.0, 0.0).add_node(5, 3.0, 0.0)
    b.add_rigid_beam(1, 1, 2, 3).add_rigid_beam(2, 3, 4, 5)
    b.fix(1).fix(5, "y").input_coordinate(5, "x")
    (problem,) = problems_of(b)
    assert "D_c is singular" in problem and "x2.1 (node 2, phi)" in problem


def test_laws_and_classification_requests():
    b = sliding_truss().fix(1, "y").fix(2, "x")
    b.input_coordinate(1, "x", "y", law=fm.Polynomial(0.0))
    assert "a law needs exactly one direction" in problems_of(b)[0]
    model = (sliding_truss().fix(1, "y").fix(2, "x")
             .input_coordinate(1, 1, law=fm.Polynomial(-2.0, 4.0)).build())
    assert model.coordinate_class[model.coordinate_index("x1.1")] == CoordinateClass.INPUT
    assert model.deformation_class[0] == DeformationClass.RIGID
    assert set(model.input_laws) == {"x1.1"}


def test_model_error_message_lists_every_problem():
    error = fm.ModelError(["first", "second"])
    assert "2 problems" in str(error) and "- first" in str(error) and "- second" in str(error)
    assert str(fm.ModelError("only")) == "invalid model: only"


def test_index_sets_are_part_of_the_immutable_model():
    model = slider_crank()
    with pytest.raises(ValueError):
        model.dependent[0] = 0
    with pytest.raises(AttributeError):
        model.fixed = np.array([0])  # type: ignore[misc]
    assert not hasattr(model, "assembly") and not hasattr(model, "settings")


def test_properties_are_checked_against_the_element_type():
    b = sliding_truss().fix(1, "y").fix(2, "x").input_coordinate(1, "x")
    b.set_stiffness(1, bending=3.0).set_damping(1, hinge=0.1).set_stiffness(1, axial=-1.0)
    b.set_mass(1, 2.0, "heavy")
    text = "\n".join(problems_of(b))
    assert "a truss has no bending stiffness; it takes axial (EA [N])" in text
    assert "a truss has no hinge damping; it takes axial (c_A [N s])" in text
    assert "axial -1.0 is negative" in text
    assert "formulation 'heavy' is not 'consistent' or 'lumped'" in text


def test_a_spring_damper_is_released_and_massless():
    b = sliding_truss().fix(1).fix(2, "x").add_node(3, 0.0, 3.0).fix(3)
    b.add_element(2, fm.SpringDamper, (2, 3))
    b.set_stiffness(2, spring=1e3).set_damping(2, spring=2.0)
    b.set_prestress(2, 1, 5.0)
    model = b.build()  # truss 1 holds node 2 on a circle; its x is fixed: y dependent
    assert model.deformation_class[model.deformation_index("e2.1")] == DeformationClass.RELEASED
    assert dict(model.element_properties[2].stiffness) == {"spring": 1e3}
    b.set_mass(2, 1.0)
    assert "a spring-damper has no mass" in problems_of(b)[0]


def test_summary_mentions_inputs():
    """Coordinates and deformations apart, and what an input angle's law counts from."""
    line = slider_crank().summary().splitlines()[1]
    assert line == ("  inputs: coordinates x2.1 (node 2, phi); deformations none (an input "
                    "angle counts from the drawn orientation: 0 is as drawn)")


def test_summary_shortens_long_lists():
    from examples.slider_crank_flex import build_model

    line = build_model(nbeams=4, eps1flex=True).summary().splitlines()[2]
    assert line.startswith("  dynamic: coordinates none; deformations 12 (e2.1 (beam 2, "
                           "elongation), ..., ")
    assert line.endswith("e5.3 (beam 5, bending at q))")


def _flexible_arm(**stiffness):
    """A planar beam clamped at node 1 whose bending is a degree of freedom."""
    b = fm.ModelBuilder("arm")
    b.add_node(1, 0, 0).add_node(3, 1, 0)
    b.add_beam(1, 1, 2, 3, 4).dynamic_deformation(1, 2, 3).set_mass(1, 1.0)
    if stiffness:
        b.set_stiffness(1, **stiffness)
    return b.fix(1).fix(2)


def test_a_flexible_beam_without_stiffness_is_named_at_build():
    """A beam whose bending is dynamic but has no stiffness would fold freely (e2 -> -l
    under gravity): build names the element, its deformations and the keyword."""
    with pytest.raises(fm.ModelError) as caught:
        _flexible_arm().build()
    text = str(caught.value)
    assert "beam 1 is flexible without stiffness" in text
    assert "e1.2 (beam 1, bending at p), e1.3 (beam 1, bending at q)" in text
    assert "set_stiffness(1, bending=...)" in text
    with pytest.raises(fm.ModelError, match=r"e1.1 .* set_stiffness\(1, axial=\.\.\.\)"):
        fm.ModelBuilder("bar").add_node(1, 0, 0).add_node(3, 1, 0).add_beam(
            1, 1, 2, 3, 4).dynamic_deformation(1, 1).set_stiffness(1, bending=1.0).fix(
            1).fix(2).build()


def test_a_zero_stiffness_said_explicitly_builds():
    model = _flexible_arm(axial=1e6, bending=0.0).build()
    assert model.n_dof == 2


def test_a_spacar_file_s_flexible_beam_without_estiff_runs_with_a_note(tmp_path):
    """SPACAR runs such a file, and a file cannot say that a zero is meant: it reads with
    a note at the line that made it flexible (DYNE) instead of an error."""
    path = tmp_path / "arm.dat"
    path.write_text("PLBEAM 1 1 2 3 4\nX 1 0 0\nX 3 1 0\nFIX 1\nFIX 2\nDYNE 1 2 3\n"
                    "END\nHALT\nEM 1 1.0\nEND\nEND\n")
    dat = fm.read_dat(path)
    assert dat.model.n_dof == 2
    assert any(note.startswith("line 6: beam 1 is flexible without stiffness")
               for note in dat.settings.notes)


def test_a_degree_of_freedom_without_mass_is_named_at_build():
    """A double pendulum whose second link was given no mass builds (its statics need
    none) with a warning naming the angle that moves no mass and the keywords; a model
    without any mass is a static one and builds silently."""
    b = fm.ModelBuilder("double pendulum")
    b.add_node(1, 0, 0).add_node(3, 1, 0).add_node(5, 2, 0)
    b.add_rigid_beam(1, 1, 2, 3).add_rigid_beam(2, 3, 4, 5)
    b.fix(1).dynamic_coordinate(2).dynamic_coordinate(4).set_gravity(0, -9.81)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        b.build()                                   # no mass at all: static, no warning
    b.set_mass(1, 1.0)
    with pytest.warns(fm.ModelWarning, match=r"no mass moves with x4\.1 \(node 4, phi\)"
                                             r".*set_mass"):
        b.build()
    b.set_mass(2, 1.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        b.build()


def test_a_released_beam_end_without_stiffness_builds_with_a_warning():
    """A beam released at an end without stiffness is SPACAR's hinge there: it builds,
    with a warning naming the deformation and how to say the hinge is meant (an explicit
    zero), which silences it."""
    def arm(**stiffness):
        b = fm.ModelBuilder("arm")
        b.add_node(1, 0, 0).add_node(3, 1, 0).add_beam(1, 1, 2, 3, 4).release(1, 3)
        if stiffness:
            b.set_stiffness(1, **stiffness)
        return b.fix(1).fix(2).input_coordinate(4)

    with pytest.warns(fm.ModelWarning, match=r"e1\.3 \(beam 1, bending at q\).*"
                                             r"set_stiffness\(1, bending=0\.0\)"):
        arm().build()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        arm(bending=0.0).build()


def _crank(law, absolute=False, extra_beam_angle=None):
    """A crank of 0.1 m drawn at 90 degrees on a pivot; optionally a second arm on it."""
    b = fm.ModelBuilder("crank")
    b.add_node(1, 0, 0).add_node(3, 0, 0.1).add_rigid_beam(1, 1, 2, 3).set_mass(1, 1.0).fix(1)
    if extra_beam_angle is not None:
        b.add_node(5, 0.1 * math.cos(extra_beam_angle), 0.1 * math.sin(extra_beam_angle))
        b.add_rigid_beam(2, 1, 2, 5)
    return b.input_coordinate(2, law=law, absolute=absolute).build()


def test_an_input_angle_given_absolute_starts_as_drawn():
    """absolute=True: Polynomial(pi/2, w) on a crank drawn at 90 degrees starts it as drawn
    and turns it to pi/2 + w t (the pin at 0.1 (cos, sin) of that), the model keeping the
    increment, a Polynomial still; any other law is shifted as well."""
    for law in (fm.Polynomial(math.pi / 2, 1.0), "pi/2 + t"):
        model = _crank(law, absolute=True)
        run = fm.kinematic_analysis(model, [0.0, 1.0])
        np.testing.assert_allclose(run["x3.1"], 0.1 * np.cos(math.pi / 2 + run.t), atol=1e-12)
        np.testing.assert_allclose(run["x3.2"], 0.1 * np.sin(math.pi / 2 + run.t), atol=1e-12)
    assert _crank(fm.Polynomial(math.pi / 2, 1.0), True).input_laws["x2.1"] == \
        fm.Polynomial(0.0, 1.0)


def test_an_increment_that_starts_at_the_drawn_angle_is_warned_about():
    with pytest.warns(fm.ModelWarning, match=r"starts at 1\.5708 rad, the drawn angle .* "
                                             r"absolute=True"):
        _crank(fm.Polynomial(math.pi / 2, 1.0))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        _crank(fm.Polynomial(0.0, 1.0))                      # as drawn: nothing to say
        _crank(fm.Polynomial(math.pi / 2, 1.0), absolute=True)


def test_absolute_needs_one_drawn_angle():
    with pytest.raises(fm.ModelError, match=r"absolute=True: its elements are drawn at "
                                            r"different angles \(element 1 at 90 deg, element "
                                            r"2 at 0 deg\)"):
        _crank(fm.Polynomial(math.pi / 2, 1.0), absolute=True, extra_beam_angle=0.0)
    with pytest.raises(fm.ArgumentError, match="absolute"):
        _crank(fm.Polynomial(0.0, 1.0), absolute="yes")
