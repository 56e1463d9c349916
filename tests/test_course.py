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


# --- templates, solutions and the checker --------------------------------------------------
import json  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402

from flexmbd.course.check import NOT_DONE, PASSED, check  # noqa: E402
from flexmbd.course.templates import notebook, solution_source, template_source  # noqa: E402

NAMES = list(EXERCISES)


def _write(tmp_path, name, text, suffix=".py"):
    path = tmp_path / f"{name}{suffix}"
    path.write_text(text)
    return path


@pytest.mark.parametrize("name", NAMES)
def test_every_solution_passes_with_full_score(name, tmp_path):
    item = exercise(name)
    report = check(item, _write(tmp_path, item.module, solution_source(item)))
    assert report.score == report.max_score, report.text()
    assert report.exit_status == 0 and report.problem is None


@pytest.mark.parametrize("name", NAMES)
def test_the_template_runs_and_reports_every_part_not_done(name, tmp_path):
    item = exercise(name)
    path = _write(tmp_path, item.module, template_source(item))
    run = subprocess.run([sys.executable, str(path)], capture_output=True, text=True,
                         timeout=120, env={"MPLBACKEND": "Agg", "PATH": ""}, cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    assert " not done yet: " in run.stdout and "Traceback" not in run.stderr
    report = check(item, path)
    assert [p.status for p in report.parts] == [NOT_DONE] * len(item.parts), report.text()
    assert report.score == 0 and report.exit_status == 1
    for part, outcome in zip(item.parts, report.parts, strict=True):
        assert outcome.message == part.hint  # the hint of the part, not a NameError


def test_a_notebook_is_checked_cell_by_cell(tmp_path):
    item = exercise("slider-crank-kinematics")
    solved = notebook(solution_source(item))
    assert check(item, _write(tmp_path, "solved", solved, ".ipynb")).score == 9
    template = json.loads(notebook(template_source(item)))
    assert template["nbformat"] == 4 and any(c["cell_type"] == "markdown"
                                             for c in template["cells"])
    report = check(item, _write(tmp_path, "template", json.dumps(template), ".ipynb"))
    assert report.score == 0 and {p.status for p in report.parts} == {NOT_DONE}


#: typical wrong answers: (exercise, part, text in the solution, the wrong text, hint words)
MISTAKES = [
    ("sliding-bar", "d", "quadratic = (dv @ dv", "quadratic = 0 * (dv @ dv",
     "quadratic velocity term"),
    ("sliding-bar", "e", "n_p @ d])\n", "-(n_p @ d)])\n", "bending"),
    ("sliding-bar", "f", "[-n_p[0], -n_p[1], -e_p @ d, n_p[0], n_p[1]]]",
     "[n_p[0], n_p[1], e_p @ d, -n_p[0], -n_p[1]]]", "bending"),
    ("sliding-bar", "g", "    x = np.array([-L0 * np.cos(phi_p) - 0.1",
     "    phi_p = np.radians(phi_p)\n    x = np.array([-L0 * np.cos(phi_p) - 0.1", "radians"),
    ("sliding-bar", "a", "np.hypot(d[0], d[1]) - L0])", "np.hypot(d[0], d[1])])",
     "length minus l0"),
    ("slider-crank-kinematics", "b", "    return D\n    # END", "    return D.T\n    # END",
     "transposed"),
    ("slider-crank-kinematics", "b", "    return D\n    # END",
     "    return D[:, [0, 1, 2, 4, 3, 5, 6, 7]]\n    # END", "columns out of order"),
    ("slider-crank-kinematics", "i", "+ second_order_transfer(phi2) * phi2d**2",
     "+ 0 * phi2d**2", "quadratic velocity term"),
    ("slider-crank-kinematics", "c", "    x = drawn_guess(phi2)\n",
     "    phi2 = np.deg2rad(phi2)\n    x = drawn_guess(phi2)\n", "radians"),
    ("slider-crank-kinematics", "a", "e += [np.hypot(*d) - l0, n_p @ d]",
     "e += [np.hypot(*d) - l0, -n_p @ d]", "bending"),
    ("slider-crank-dynamics", "b",
     "M[np.ix_(ends, ends)] = M2 / 6 * np.kron([[2, 1], [1, 2]], np.eye(2))",
     "M = rod_mass_lumped(x)", "lumped"),
    ("slider-crank-dynamics", "e", "    xdd = F_q * phi2dd + F_qq * phi2d**2\n    return",
     "    xdd = F_q * phi2dd\n    return", "velocity terms"),
    ("slider-crank-dynamics", "c", "    return np.array([[F_q @ system_mass(x, rod_mass_lumped)",
     "    x, F_q, _ = transfer(np.radians(phi2))\n"
     "    return np.array([[F_q @ system_mass(x, rod_mass_lumped)", "radians"),
    ("slider-crank-dynamics", "a", "-M2 * L2**2 / 6", "0.0", "rotary inertia"),
    ("slider-crank-flex", "a", "-n_p @ d, n_q @ d", "n_p @ d, -n_q @ d", "bending"),
    ("slider-crank-flex", "a", "-n_p @ d, n_q @ d", "-n_p @ d, -n_q @ d", "bending"),
    ("slider-crank-flex", "d", "    return M, h\n", "    return M, 0 * h\n", "h is not zero"),
    ("slider-crank-flex", "f", "f = F_q.T @ (-h - M @ xdd0)", "f = F_q.T @ (0 * h)",
     "velocity terms"),
    ("slider-crank-flex", "b", "[n_p[0], n_p[1], e_p @ d, -n_p[0], -n_p[1], 0.0]",
     "[-n_p[0], -n_p[1], -e_p @ d, n_p[0], n_p[1], 0.0]", "bending"),
]


@pytest.mark.parametrize("name, letter, right, wrong, words", MISTAKES,
                         ids=[f"{m[0]}-{m[1]}-{m[4].split()[0]}" for m in MISTAKES])
def test_typical_wrong_answers_are_caught_with_their_hint(name, letter, right, wrong, words,
                                                          tmp_path):
    item = exercise(name)
    source = solution_source(item)
    assert source.count(right) == 1, right
    report = check(item, _write(tmp_path, "wrong", source.replace(right, wrong)))
    outcome = report.parts[ord(letter) - ord("a")]
    assert outcome.status == "failed", report.text()
    assert "expected" in outcome.message
    assert words in outcome.hint, report.text()
    assert report.exit_status == 1


def test_every_exercise_has_three_typical_mistakes_tested():
    for name in NAMES:
        assert sum(m[0] == name for m in MISTAKES) >= 3


def test_a_sympy_answer_is_accepted_when_equal_to_flexmbd_s(tmp_path):
    item = exercise("sliding-bar")
    source = solution_source(item) + '''

import sympy as sp

X = sp.Matrix(sp.symbols("x_p y_p x_q y_q", real=True))
DX = sp.Matrix([sp.sqrt((X[2] - X[0])**2 + (X[3] - X[1])**2) - 2]).jacobian(X)


def truss_jacobian(x):
    return DX.subs(dict(zip(X, list(x))))
'''
    report = check(item, _write(tmp_path, "sym", source))
    assert report.parts[1].status == PASSED
    assert "SymPy expression equal to flexmbd's" in report.parts[1].message


def test_a_crashing_hanging_or_garbage_printing_file_gets_a_clean_report(tmp_path, capsys):
    """A crash or an endless loop costs the parts that run into it, each alone: the
    parts after it run in a new process."""
    item = exercise("sliding-bar")
    source = solution_source(item)
    crash = source.replace("    d = np.array([x[3] - x[0], x[4] - x[1]])\n    n_p",
                           "    import os\n    os._exit(3)\n    n_p", 1)
    report = check(item, _write(tmp_path, "crash", crash))
    assert [p.status for p in report.parts[:4]] == [PASSED] * 4
    assert "process ended" in report.parts[4].message
    assert report.parts[5].status == PASSED   # the Jacobian does not call e's code
    hang = source.replace("    x = np.array([x_p, 0.0, 0.0, 1.0])\n",
                          "    while True:\n        pass\n", 1)
    report = check(item, _write(tmp_path, "hang", hang), timeout=3)
    assert "time limit" in report.parts[2].message and report.parts[1].status == PASSED
    assert "time limit" in report.parts[3].message   # d calls c's function
    assert [p.status for p in report.parts[4:]] == [PASSED] * 6  # the rigid beam's
    garbage = ("import sys\nprint('\\x00\\xff garbage {]')\nsys.stdout.write('\\n' * 99)\n"
               + source.replace("    return np.array([np.hypot(d[0], d[1]) - L0])",
                                "    print('noise'); return 'hello'", 1))
    report = check(item, _write(tmp_path, "garbage", garbage))
    assert "returned 'hello', not numbers" in report.parts[0].message
    assert [p.status for p in report.parts[4:]] == [PASSED] * 6  # the rigid beam's
    broken = _write(tmp_path, "broken", "def truss_elongation(x)\n    return 1\n")
    report = check(item, broken)
    assert "SyntaxError" in report.problem and report.score == 0
    assert main(["exercise", "check", "1", str(broken)]) == 1
    out, err = capsys.readouterr()
    assert "SyntaxError" in out and "Traceback" not in out + err


def test_exercise_commands_write_files_and_report(sandbox, tmp_path, capsys):
    assert main(["exercise", "start", "sliding-bar", str(tmp_path)]) == 0
    template = tmp_path / "sliding_bar.py"
    assert "not_done('a'" in template.read_text() and "hypot" not in template.read_text()
    assert main(["exercise", "start", "sliding-bar", str(tmp_path)]) == 2  # exists
    assert main(["exercise", "solution", "1", str(tmp_path), "--notebook"]) == 0
    solved = tmp_path / "sliding_bar_solution.ipynb"
    report = tmp_path / "report.json"
    assert main(["exercise", "check", "1", str(solved), "--json", str(report)]) == 0
    data = json.loads(report.read_text())
    assert data["score"] == data["max_score"] == 10 and len(data["tests"]) == 10
    assert main(["exercise", "check", "1", str(template)]) == 1
    assert main(["exercise", "check", "1", str(tmp_path / "missing.py")]) == 2
    assert main(["exercise", "check", "1", str(template), "--json", "/no/such/r.json"]) == 2
    capsys.readouterr()
