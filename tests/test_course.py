"""Course mode (``flexmbd exercise``): the catalogue of exercises and parts."""

from __future__ import annotations

import pytest

from flexmbd.cli import main
from flexmbd.course import EXERCISES, exercise


def test_the_catalogue_follows_the_exercises():
    assert [e.number for e in EXERCISES.values()] == [1, 2, 3, 4]
    for item in EXERCISES.values():
        letters = [p.letter for p in item.parts]
        assert letters == [chr(ord("a") + k) for k in range(len(letters))]
        assert len({p.function for p in item.parts}) == len(item.parts)
        assert all(p.function.isidentifier() for p in item.parts)
    assert len(exercise(1).parts) == 10  # 1a-j
    returns = " ".join(p.returns for p in exercise(2).parts)
    assert all(name in returns for name in ("D (4, 8)", "F_q", "E_q", "F_qq", "E_qq"))
    returns = " ".join(p.returns for p in exercise(3).parts)
    assert all(name in returns for name in ("lumped", "consistent", "Mbar", "tau2",
                                            "sigma(o)", "reactions", "PD"))
    arguments = " ".join(p.arguments for p in exercise(4).parts)
    assert "nbeams" in arguments and "eps1flex" in arguments


def test_exercise_list_prints_every_part(capsys):
    assert main(["exercise", "list"]) == 0
    out = capsys.readouterr().out
    for item in EXERCISES.values():
        assert f"(name: {item.name})" in out
        for part in item.parts:
            assert f"{item.number}{part.letter}  {part.function}({part.arguments})" in out


def test_exercise_list_of_one_exercise_by_number_or_name(capsys):
    assert main(["exercise", "list", "2"]) == 0
    by_number = capsys.readouterr().out
    assert main(["exercise", "list", "slider-crank-kinematics"]) == 0
    assert capsys.readouterr().out == by_number
    assert by_number.startswith("2. ") and "1a" not in by_number


@pytest.mark.parametrize("name", ["5", "sliding_bar"])
def test_an_unknown_exercise_is_a_usage_error(name, capsys):
    assert main(["exercise", "list", name]) == 2
    assert "choose from sliding-bar, slider-crank-kinematics" in capsys.readouterr().err
