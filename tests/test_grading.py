"""Course mode as a lecturer grades with it: every answer gets a verdict, no wrong formula
passes, graded runs are confined, and a folder of submissions is graded at once."""

import csv
import json
import time
from pathlib import Path

import pytest

from flexmbd.cli import main
from flexmbd.course import exercise
from flexmbd.course.check import FAILED, NOT_DONE, PASSED, check
from flexmbd.course.templates import solution_source, template_source

KINEMATICS = exercise("slider-crank-kinematics")
SOLUTION = solution_source(KINEMATICS)

#: the bodies of parts e, f and h in the solution, to replace
F_Q = "    return velocities(phi2, 1.0)[:, None]\n"
E_Q = "    return jacobian(configuration(phi2)) @ first_order_transfer(phi2)\n"
E_QQ = ("    return (jacobian(x) @ second_order_transfer(phi2)\n"
        "            + quadratic(x, first_order_transfer(phi2)[:, 0])[:, None])\n")


def _submission(tmp_path: Path, name: str, replacements=(), extra="") -> Path:
    source = SOLUTION
    for old, new in replacements:
        assert source.count(old) == 1, old
        source = source.replace(old, new)
    path = tmp_path / f"{name}.py"
    path.write_text(source + extra)
    return path


def _verdicts(report):
    return {p.letter: p for p in report.parts}


def test_a_nan_answer_gets_a_verdict_and_a_json_report(tmp_path, capsys):
    """NaN where the answer is zero used to crash the checker: no report, no JSON."""
    path = _submission(tmp_path, "nan", [(E_Q, "    return np.full((4, 1), np.nan)\n")])
    report = check(KINEMATICS, path)
    part = _verdicts(report)["f"]
    assert part.status == FAILED and "got nan" in part.message
    out = tmp_path / "report.json"
    assert main(["exercise", "check", "2", str(path), "--json", str(out)]) == 1
    assert json.loads(out.read_text())["tests"][5]["status"] == "failed"
    assert "Traceback" not in capsys.readouterr().err


@pytest.mark.parametrize("value", ["None", "'text'", "{'a': 1}", "np.zeros((4, 1, 1))",
                                   "np.array([1 + 2j] * 4)", "[[np.inf]] * 4", "1e400",
                                   "(np.zeros(4), None)", "object()", "lambda: 0",
                                   "np.zeros(10**6)"])
def test_any_answer_of_any_type_gets_a_verdict(tmp_path, value):
    path = _submission(tmp_path, "odd", [(F_Q, f"    return {value}\n")])
    part = _verdicts(check(KINEMATICS, path))["e"]
    assert part.status == FAILED and part.message


def test_a_zero_answer_does_not_pass_parts_whose_answer_is_zero(tmp_path):
    """E_q and E_qq are zero at every state of the rigid slider-crank; the parts are
    checked with other F_q and F_qq, so a hard-coded zero fails with its reason."""
    path = _submission(tmp_path, "zeros", [(E_Q, "    return np.zeros((4, 1))\n"),
                                           (E_QQ, "    return np.zeros((4, 1))\n")])
    verdicts = _verdicts(check(KINEMATICS, path))
    for letter in "fh":
        assert verdicts[letter].status == FAILED
        assert "did not change" in verdicts[letter].hint
    assert "made of your parts b and e" in verdicts["f"].hint


def test_the_formula_passes_however_it_reaches_f_q(tmp_path):
    """E_q computed from the velocities of part d instead of part e is the same formula."""
    path = _submission(tmp_path, "via_velocities", [
        (E_Q, "    return jacobian(configuration(phi2)) @ velocities(phi2, 1.0)[:, None]\n")])
    assert _verdicts(check(KINEMATICS, path))["f"].status == PASSED


def test_a_transposed_answer_fails_with_its_hint_a_flat_one_passes(tmp_path):
    flat = _submission(tmp_path, "flat", [(F_Q, "    return velocities(phi2, 1.0)\n")])
    assert _verdicts(check(KINEMATICS, flat))["e"].status == PASSED
    row = _submission(tmp_path, "row", [(F_Q, "    return velocities(phi2, 1.0)[None, :]\n"),
                                        (E_Q, "    return (jacobian(configuration(phi2)) @ "
                                              "first_order_transfer(phi2).T).T\n")])
    verdicts = _verdicts(check(KINEMATICS, row))
    assert verdicts["e"].status == FAILED and "transposed" in verdicts["e"].hint
    assert verdicts["f"].status == FAILED


def test_graded_runs_refuse_flexmbd_s_answers(tmp_path):
    """The solutions are not in the package; flexmbd's kinematics answers in a self-check
    but not in a graded run."""
    cheat = _submission(tmp_path, "cheat", [(
        F_Q, "    from flexmbd.analysis import kinematics\n"
             "    from flexmbd.course.slider_crank_kinematics import model, configuration as c\n"
             "    return kinematics.first_order_transfer(model(), c(phi2))\n")])
    assert _verdicts(check(KINEMATICS, cheat, graded=False))["e"].status == PASSED
    part = _verdicts(check(KINEMATICS, cheat, graded=True))["e"]
    assert part.status == FAILED and "not available in a graded check" in part.message
    star = tmp_path / "star.py"
    star.write_text("from flexmbd.course.solutions.slider_crank_kinematics import *\n")
    report = check(KINEMATICS, star, graded=True)
    assert report.score == 0 and "not available in a graded check" in report.problem
    reader = tmp_path / "reader.py"
    reader.write_text("import flexmbd, pathlib\n"
                      "SOURCE = (pathlib.Path(flexmbd.__file__).parent / 'course' / "
                      "'slider_crank_kinematics.py').read_text()\n")
    assert "may not read flexmbd's files" in check(KINEMATICS, reader, graded=True).problem
    examples = Path(__file__).resolve().parents[1] / "examples" / "slider_crank_kinematics.py"
    reader.write_text(f"TEXT = open({str(examples)!r}).read()\n")
    assert "may not read flexmbd's files" in check(KINEMATICS, reader, graded=True).problem


def test_graded_runs_write_only_in_their_scratch_folder(tmp_path):
    victim = tmp_path / "other_student.json"
    victim.write_text('{"score": 7}')
    mine = tmp_path / "mine.txt"
    attack = f"""
import os, subprocess
def attempt(action):
    try:
        action()
        return "done"
    except PermissionError as error:
        return str(error)
RESULTS = [attempt(lambda: open({str(victim)!r}, "w").write('{{"score": 0}}')),
           attempt(lambda: open({str(mine)!r}, "a").write("x")),
           attempt(lambda: os.remove({str(victim)!r})),
           attempt(lambda: subprocess.Popen(["sleep", "60"], start_new_session=True)),
           attempt(lambda: os.fork()),
           attempt(lambda: open("scratch.txt", "w").write("fine here"))]
assert RESULTS[-1] == "done", RESULTS
assert all(r != "done" for r in RESULTS[:-1]), RESULTS
"""
    path = _submission(tmp_path, "attack", extra=attack)
    report = check(KINEMATICS, path, graded=True)
    assert report.problem is None, report.problem   # every attempt was refused
    assert report.score == report.max_score
    assert victim.read_text() == '{"score": 7}' and not mine.exists()


def test_a_submission_runs_alone_in_a_scratch_folder(tmp_path):
    """Files beside a submission are neither imported nor readable from it."""
    (tmp_path / "helpers.py").write_text("VALUE = 1\n")
    (tmp_path / "numpy.py").write_text("raise SystemExit('shadowed')\n")
    path = _submission(tmp_path, "alone", extra="\nimport os\nFILES = sorted(os.listdir('.'))\n"
                                                 "assert FILES == ['alone.py', 'home'], FILES\n"
                                                 "import helpers\n")
    report = check(KINEMATICS, path, graded=True)
    assert "No module named 'helpers'" in report.problem
    assert report.score == report.max_score   # numpy was numpy


def test_printing_does_not_slow_the_check(tmp_path):
    path = _submission(tmp_path, "noisy", [(F_Q, "    for k in range(2000):\n"
                                                 "        print('Newton step', k, phi2)\n"
                                                 "    return velocities(phi2, 1.0)[:, None]\n")])
    begun = time.monotonic()
    report = check(KINEMATICS, path)
    assert report.score == report.max_score
    assert time.monotonic() - begun < 20


def test_gradescope_json_is_complete(tmp_path):
    report = check(KINEMATICS, _submission(tmp_path, "full"), points={"f": 2.0})
    data = report.gradescope()
    assert {"score", "execution_time", "output", "visibility", "stdout_visibility",
            "tests"} <= set(data)
    assert data["score"] == data["max_score"] == 10.0
    for test in data["tests"]:
        assert {"name", "score", "max_score", "status", "output", "visibility"} <= set(test)
    broken = tmp_path / "broken.py"
    broken.write_text("def deformations(x)\n")
    data = check(KINEMATICS, broken).gradescope()
    assert data["score"] == 0 and "did not load" in data["output"] and "SyntaxError" in \
        data["output"]


def test_check_can_exit_zero_for_autograders(tmp_path):
    template = tmp_path / "template.py"
    template.write_text(template_source(KINEMATICS))
    assert main(["exercise", "check", "2", str(template)]) == 1
    assert main(["exercise", "check", "2", str(template), "--exit-zero"]) == 0
    assert main(["exercise", "check", "2", str(template), "--points", "z=1"]) == 2


def test_grading_a_folder(tmp_path, capsys):
    """Full marks, a template, an endless loop in one part and a cheat: one row each, a
    report each, and a summary; the loop costs its part only."""
    folder = tmp_path / "submissions"
    folder.mkdir()
    _submission(folder, "ada")
    (folder / "bob.py").write_text(template_source(KINEMATICS))
    _submission(folder, "cy", [(E_Q, "    while True:\n        pass\n")])
    (folder / "dee").mkdir()
    _submission(folder / "dee", "work", [(F_Q, "    from flexmbd.analysis import kinematics\n"
                                               "    return 0\n")])
    out = tmp_path / "grades.csv"
    begun = time.monotonic()
    assert main(["exercise", "grade", "2", str(folder), "--out", str(out), "--timeout", "3",
                 "--points", "f=2"]) == 0
    assert time.monotonic() - begun < 60
    rows = {row["student"]: row for row in csv.DictReader(out.open())}
    assert set(rows) == {"ada", "bob", "cy", "dee"}
    assert rows["ada"]["score"] == "10" and rows["ada"]["max_score"] == "10"
    assert rows["bob"]["score"] == "0"
    assert rows["cy"]["2f"] == "0" and rows["cy"]["2e"] == "1" and rows["cy"]["score"] == "8"
    assert rows["dee"]["2e"] == "0"
    reports = tmp_path / "grades_reports"
    assert "time limit" in (reports / "cy.txt").read_text()
    assert "not available in a graded check" in (reports / "dee.txt").read_text()
    assert json.loads((reports / "bob.json").read_text())["tests"][0]["output"].startswith(
        NOT_DONE)
    printed = capsys.readouterr().out
    assert "graded 4 submissions" in printed and "parts most often not passed" in printed


def test_the_package_ships_templates_not_solutions(monkeypatch, tmp_path, capsys):
    """The solution bodies live in the repository's lecturer/solutions, not in the package
    students install; the templates it ships are those the solutions make."""
    from flexmbd.course import EXERCISES, templates

    package = Path(templates.__file__).resolve().parents[1]
    shipped = [p for p in package.rglob("*.py") if p.name != "templates.py"]
    assert not [p for p in shipped if "# BEGIN SOLUTION" in p.read_text()]
    assert not (package / "course" / "solutions").exists()
    for item in EXERCISES.values():
        assert templates.template_source(item) == templates.make_template(
            item, templates.solution_source(item)), "run python -m flexmbd.course.templates"
    monkeypatch.setattr(templates, "REPOSITORY_SOLUTIONS", tmp_path / "nowhere")
    monkeypatch.delenv("FLEXMBD_SOLUTIONS", raising=False)
    assert main(["exercise", "solution", "2", str(tmp_path)]) == 2
    assert "lecturer/solutions" in capsys.readouterr().err
    given = Path(__file__).resolve().parents[1] / "lecturer" / "solutions"
    assert main(["exercise", "solution", "2", str(tmp_path), "--from", str(given)]) == 0
    assert (tmp_path / "slider_crank_kinematics_solution.py").read_text() == SOLUTION


NEWTON = "    x = drawn_guess(phi2)\n    x[[0, 1, 2, 7]] = [0.0, 0.0, phi2, 0.0]\n"


def test_hints_where_students_get_stuck(tmp_path):
    """A missing return, F_qq = 0, a loose Newton tolerance, and the parts that fail
    because an earlier one does."""
    path = _submission(tmp_path, "stuck", [
        (F_Q, "    velocities(phi2, 1.0)[:, None]\n"),
        ("    F_qq[DEPENDENT] = np.linalg.solve(D[:, DEPENDENT], -quadratic(x, velocities(phi2, "
         "1.0)))\n", ""),
    ])
    verdicts = _verdicts(check(KINEMATICS, path))
    assert "returned None" in verdicts["e"].message and "return" in verdicts["e"].hint
    assert "F_qq is not zero" in verdicts["g"].hint
    assert "uses 2e (first_order_transfer)" in verdicts["f"].hint and "fix it first" in \
        verdicts["f"].hint
    assert "2e (first_order_transfer)" in verdicts["i"].hint   # it failed there first
    loose = _submission(tmp_path, "loose", [("if np.max(np.abs(e)) < 1e-13:",
                                             "if np.max(np.abs(e)) < 1e-3:")])
    part = _verdicts(check(KINEMATICS, loose))["c"]
    assert part.status == FAILED and "tighten its tolerance" in part.hint


def test_the_same_configuration_a_turn_away_passes(tmp_path):
    """A Newton start at phi4 + 2 pi converges to the same configuration."""
    path = _submission(tmp_path, "turned", [(NEWTON, NEWTON + "    x[5] += 2 * np.pi\n")])
    assert _verdicts(check(KINEMATICS, path))["c"].status == PASSED


def test_a_load_failure_is_reported_as_such(tmp_path):
    """Parts after a failing import are 'not defined: the file stopped loading', not 'not
    done'; input() says why it fails; display() works as in a notebook."""
    stopped = _submission(tmp_path, "stopped", [
        ("def velocities(phi2, phi2d):", "import nosuchmodule\n\n\ndef velocities(phi2, phi2d):")])
    report = check(KINEMATICS, stopped)
    assert "ModuleNotFoundError" in report.problem and "line" in report.problem
    verdicts = _verdicts(report)
    assert verdicts["a"].status == PASSED
    assert verdicts["d"].status == FAILED and "stopped loading" in verdicts["d"].message
    asking = _submission(tmp_path, "asking", extra="\nN = int(input('how many? '))\n")
    assert "input() waits for a keyboard" in check(KINEMATICS, asking).problem
    shown = _submission(tmp_path, "shown", extra="\ndisplay(deformations(drawn_guess(1.0)))\n")
    report = check(KINEMATICS, shown)
    assert report.problem is None and report.score == report.max_score


def test_half_the_velocity_terms_of_4f_are_recognised():
    """The two velocity terms of 4f's right-hand side, each left out, are named."""
    from flexmbd.course import slider_crank_flex as flex
    from flexmbd.course.check import diagnose

    item = exercise("slider-crank-flex")
    part = item.part("f")
    args = part.cases(__import__("numpy").random.default_rng(3))[1]
    expected = part.answer(*args)
    for keep, words in (("h", "only the first"), ("F_qq", "only the second")):
        hint = diagnose(part, args, flex.half_velocity_terms(*args, keep=keep), expected)
        assert "half of the velocity terms" in hint and words in hint


def test_notebook_templates_have_a_cell_per_part():
    from flexmbd.course import EXERCISES
    from flexmbd.course.templates import notebook

    for item in EXERCISES.values():
        cells = ["".join(c["source"]) for c in json.loads(notebook(template_source(item)))[
            "cells"] if c["cell_type"] == "code"]
        for part in item.parts:
            holding = [c for c in cells if f"def {part.function}(" in c]
            assert len(holding) == 1
            assert sum(f"def {p.function}(" in holding[0] for p in item.parts) == 1


def test_the_other_assembly_branch_is_named(tmp_path):
    path = _submission(tmp_path, "branch", [(NEWTON, NEWTON + "    x[5] = np.pi - x[5]\n"
                                                            "    x[6] = x[3] - 1.8\n")])
    part = _verdicts(check(KINEMATICS, path))["c"]
    assert part.status == FAILED and "other assembly branch" in part.hint
