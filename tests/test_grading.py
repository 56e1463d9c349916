"""Course mode as a lecturer grades with it: every answer gets a verdict, no wrong formula
passes, hints say what went wrong, the class table survives whatever happens, and what a
student's file sends is read strictly. (The sandbox itself: tests/test_sandbox.py.)"""

import csv
import json
import time
from pathlib import Path

import numpy as np
import pytest

from flexmbd.cli import main
from flexmbd.course import exercise, grading
from flexmbd.course.check import ERROR, FAILED, PASSED, TIME, check
from flexmbd.course.templates import solution_source, template_source

KINEMATICS = exercise("slider-crank-kinematics")
SOLUTION = solution_source(KINEMATICS)

#: the bodies of parts e, f, h and i in the solution, to replace
F_Q = "    return velocities(phi2, 1.0)[:, None]\n"
E_Q = "    return jacobian(configuration(phi2)) @ first_order_transfer(phi2)\n"
E_QQ = ("    return (jacobian(x) @ second_order_transfer(phi2)\n"
        "            + quadratic(x, first_order_transfer(phi2)[:, 0])[:, None])\n")
#: part i, which no other part uses
XDD = ("    return (first_order_transfer(phi2) * phi2dd + second_order_transfer(phi2) * "
       "phi2d**2)[:, 0]\n")


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


def test_a_nan_answer_gets_a_verdict_and_a_json_report(sandbox, tmp_path, capsys):
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
    from flexmbd.course.compare import diagnose

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



# --- hints that say what went wrong -------------------------------------------------------

JACOBIAN = "    return D\n    # END"


def test_single_precision_is_named_as_such(tmp_path):
    """float32 arithmetic gets the precision hint, not the Newton hint, in the parts
    whose answers it spoils; the same accuracy without float32 gets the other hints."""
    path = _submission(tmp_path, "single", [
        ("    D = np.zeros((4, 8))\n",
         "    D = np.zeros((4, 8), dtype=np.float32)\n    x = np.asarray(x, np.float32)\n"),
        ("    x = drawn_guess(phi2)\n", "    x = drawn_guess(phi2).astype(np.float32)\n"),
        ("if np.max(np.abs(e)) < 1e-13:", "if np.max(np.abs(e)) < 1e-6:")])
    verdicts = _verdicts(check(KINEMATICS, path))
    spoiled = [v for v in verdicts.values() if v.status == FAILED]
    assert spoiled and all("single precision (float32" in v.hint for v in spoiled), spoiled
    assert not any("Newton" in v.hint for v in spoiled)
    rounded = _submission(tmp_path, "rounded", [(JACOBIAN, "    return D.round(6)\n    # END")])
    part = _verdicts(check(KINEMATICS, rounded))["b"]
    assert part.status == FAILED and "single precision" not in part.hint
    assert "finite differences" in part.hint


def test_an_accurate_finite_difference_passes_near_zero_entries(tmp_path):
    """Central differences with a step of 3e-4 agree with the Jacobian to about 5e-8 of
    its size. At the check's configurations an absolute floor of 1e-9 on entries near
    zero (the tolerance before) refuses that; the tolerance of the answer's size takes
    it."""
    from flexmbd.analysis import kinematics
    from flexmbd.course.check import SELF_CHECK_SEED, _calls
    from flexmbd.course.slider_crank_kinematics import model

    h, refused = 3e-4, False
    for (x,) in _calls(KINEMATICS, SELF_CHECK_SEED)[1]["b"].cases:
        exact = kinematics.jacobian(model(), x)
        differences = np.array([(kinematics.deformations(model(), x + h * e)
                                 - kinematics.deformations(model(), x - h * e)) / (2 * h)
                                for e in np.eye(8)]).T
        error, scale = np.abs(differences - exact), np.abs(exact).max()
        assert error.max() < 1e-7 * scale
        refused |= bool(np.any(error > 1e-7 * np.abs(exact) + 1e-9 * max(1.0, scale)))
    assert refused
    body = ("    h, D = 3e-4, np.zeros((4, 8))\n"
            "    for k in range(8):\n"
            "        step = np.zeros(8)\n"
            "        step[k] = h\n"
            "        D[:, k] = (deformations(x + step) - deformations(x - step)) / (2 * h)\n"
            "    return D\n    # END")
    path = _submission(tmp_path, "differences", [(JACOBIAN, body)])
    assert _verdicts(check(KINEMATICS, path))["b"].status == PASSED


def test_a_part_that_prints_until_its_time_is_up_is_told_so(tmp_path):
    path = _submission(tmp_path, "noisy", [(XDD, "    while True:\n"
                                                 "        print(np.arange(200.0))\n")])
    part = _verdicts(check(KINEMATICS, path, timeout=3))["i"]
    assert part.reason == TIME and "time limit" in part.message
    assert "printed" in part.hint and "MB" in part.hint, part.hint


def test_student_text_reaches_no_terminal_as_control_characters(tmp_path):
    """An error message with escape sequences and a forged "passed" line stays one line
    of plain text in the report."""
    forged = "\\n  2c  positions                  passed\\x1b[2J\\x1b]0;owned\\x07\\u202e"
    path = _submission(tmp_path, "forged", [("    x = drawn_guess(phi2)\n",
                                             f"    raise RuntimeError({forged!r})\n")])
    text = check(KINEMATICS, path).text()
    assert "\x1b" not in text and "\u202e" not in text and "\x07" not in text
    lines = [line for line in text.splitlines() if line.startswith("  2c")]
    assert len(lines) == 1 and "failed" in lines[0], text


# --- the class table ----------------------------------------------------------------------

def _class(folder: Path, names) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    for name in names:
        _submission(folder, name)
    return folder


def test_an_interrupted_grading_keeps_its_rows_and_a_rerun_grades_the_rest(tmp_path):
    """Rows are written as submissions finish; a rerun keeps them (same file, same seed),
    grades the rest and regrades a file that changed."""
    folder = _class(tmp_path / "class", ["ann", "ben", "cat", "dan"])
    out, reports = tmp_path / "grades.csv", tmp_path / "reports"
    seen = []

    def interrupt(student, report):
        seen.append(student)
        if len(seen) == 2:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        grading.grade(KINEMATICS, folder, isolation="none", out=out, reports=reports,
                      jobs=1, progress=interrupt)
    first = {row["student"]: row for row in csv.DictReader(out.read_text().splitlines())}
    assert set(first) == set(seen) and all(r["score"] == "9" for r in first.values())
    assert sorted(p.name for p in reports.iterdir()) == sorted(
        f"{s}.{kind}" for s in seen for kind in ("json", "txt"))
    changed = next(s for s in ["ann", "ben", "cat", "dan"] if s not in seen)
    (folder / f"{seen[0]}.py").write_text(template_source(KINEMATICS))
    graded = []
    grades = grading.grade(KINEMATICS, folder, isolation="none", out=out, reports=reports,
                           progress=lambda student, report: graded.append(
                               (student, report is not None)))
    assert dict(graded) == {seen[0]: True, seen[1]: False, changed: True,
                            ({"ann", "ben", "cat", "dan"} - set(seen) - {changed}).pop(): True}
    rows = {row["student"]: row for row in csv.DictReader(out.read_text().splitlines())}
    assert rows[seen[0]]["score"] == "0" and rows[seen[1]]["score"] == "9"
    assert {row["seed"] for row in rows.values()} == {str(grades.seed)} == {first[seen[1]]["seed"]}
    with pytest.raises(grading.ArgumentError, match="was graded with seed"):
        grading.grade(KINEMATICS, folder, isolation="none", out=out, seed=grades.seed + 1)


def test_every_entry_gets_its_row_whatever_goes_wrong(tmp_path, monkeypatch):
    """A link, a folder with two files, a file and a folder of one student, a file that
    vanishes, and the grader failing on one file: each costs its own row only."""
    folder = _class(tmp_path / "class", ["ann", "gone", "odd"])
    (folder / "link.py").symlink_to(folder / "ann.py")
    (folder / "two").mkdir()
    _class(folder / "two", ["a", "b"])
    _class(folder / "ann", ["work"])
    real = grading.check_content

    def failing(exercise_, file, *args, **kwargs):
        if file.endswith("odd.py"):
            raise RuntimeError("a bug of the grader's")
        return real(exercise_, file, *args, **kwargs)

    monkeypatch.setattr(grading, "check_content", failing)
    real_read = grading.read_submission

    def vanishing(path, **kwargs):
        if Path(path).name == "gone.py":
            Path(path).unlink()
        return real_read(path, **kwargs)

    monkeypatch.setattr(grading, "read_submission", vanishing)
    out = tmp_path / "grades.csv"
    grading.grade(KINEMATICS, folder, isolation="none", out=out, roster=["ann", "zoe"])
    rows = {row["student"]: row for row in csv.DictReader(out.read_text().splitlines())}
    assert set(rows) == {"ann", "gone", "odd", "link", "two", "zoe"}
    assert "two submissions" in rows["ann"]["problem"]
    assert "link" in rows["link"]["problem"] and "2 files" in rows["two"]["problem"]
    assert "cannot read" in rows["gone"]["problem"]
    assert "the grader could not check this file" in rows["odd"]["problem"]
    assert rows["zoe"]["problem"].startswith("no submission") and rows["zoe"]["score"] == "0"
    assert all(r["score"] == "0" for r in rows.values())
    assert all(r["2a reason"] == ERROR for s, r in rows.items() if s != "zoe")


def test_a_roster_lists_who_submitted_nothing(tmp_path, capsys):
    folder = _class(tmp_path / "class", ["ann"])
    roster = tmp_path / "roster.csv"
    roster.write_text("student,email\nann,a@x\nbob,b@x\n")
    assert grading.read_roster(roster) == ["ann", "bob"]
    grades = grading.grade(KINEMATICS, folder, isolation="none", roster=["ann", "bob"])
    assert grades.missing == ["bob"]
    assert "no submission from 1 student(s) of the roster: bob" in grades.summary()
    assert "graded 1 submissions" in grades.summary()


def test_grading_needs_a_sandbox_or_the_lecturer_s_word(tmp_path, monkeypatch, capsys):
    """Without bubblewrap, grade refuses and says what to do; --unsafe-in-process grades
    and says once what that leaves open."""
    from flexmbd.course import sandbox as box

    monkeypatch.setattr(box.shutil, "which", lambda name: None)
    folder = _class(tmp_path / "class", ["ann"])
    out = tmp_path / "grades.csv"
    assert main(["exercise", "grade", "2", str(folder), "--out", str(out)]) == 1
    err = capsys.readouterr().err
    assert "bubblewrap" in err and "--unsafe-in-process" in err and not out.exists()
    assert main(["exercise", "check", "2", str(folder / "ann.py"), "--graded"]) == 1
    capsys.readouterr()
    assert main(["exercise", "grade", "2", str(folder), "--out", str(out),
                 "--unsafe-in-process"]) == 0
    err = capsys.readouterr().err
    assert err.count("--unsafe-in-process:") == 1 and "unconfined processes" in err
    assert next(csv.DictReader(out.read_text().splitlines()))["score"] == "9"


# --- what comes back from a student's process --------------------------------------------

@pytest.mark.parametrize("line", [
    b'{"id": 0, "array": 1' + b"1" * 5000 + b', "shape": []}', b"[" * 100000, b"\xff\xfe",
    b'{"id": "0", "array": [1.0]}', b'{"id": 0, "array": {"a": 1}}', b'[1, 2]', b"{}",
    b'{"id": 0, "uses": [1]}', b'{"id": true, "none": true}', b'{"id": 0, "evil": 1}'])
def test_the_results_channel_is_read_strictly(line):
    from flexmbd.course.channel import parse

    assert parse(line) is None
    record = parse(b'{"id": 3, "array": [1.5, NaN], "shape": [2], "uses": ["f"]}')
    assert record["id"] == 3 and record["array"][0] == 1.5 and np.isnan(record["array"][1])


def test_sympy_answers_are_compared_as_trees_of_operations():
    """Equal expressions are equal at random points, different ones are not, and an
    operation outside the list (or a huge number) is not compared: no text of the
    student's is parsed."""
    import sympy as sp

    from flexmbd.course.expressions import equal
    from flexmbd.course.runner import sympy_tree

    x, y = sp.symbols("x y", real=True)
    rng = np.random.default_rng(1)
    reference = sympy_tree(sp.Matrix([[sp.sqrt(x**2 + y**2) - 2, sp.sin(x) * sp.cos(y)]]))
    same = sympy_tree(sp.Matrix([[sp.sqrt((y - 0) ** 2 + x * x) - 2],
                                 [(sp.sin(x + y) + sp.sin(x - y)) / 2]]))
    assert equal(same, reference, ["x", "y"], rng) is True
    other = sympy_tree(sp.Matrix([[sp.sqrt(x**2 + y**2) - 2, sp.sin(x) * sp.sin(y)]]))
    assert equal(other, reference, ["x", "y"], rng) is False
    assert equal({"o": "Function", "a": []}, reference, ["x", "y"], rng) is None
    assert equal({"i": "9" * 5000}, {"i": "1"}, [], rng) is None
    assert equal({"o": "Pow", "a": [{"i": "10"}, {"i": "9" * 30}]}, {"i": "1"}, [], rng) \
        is False
    deep = {"s": "x"}
    for _ in range(5000):
        deep = {"o": "sin", "a": [deep]}
    assert equal(deep, sympy_tree(x), ["x"], rng) in (False, None)


def test_the_table_is_safe_to_open_and_names_identical_files(tmp_path):
    """A student name that a spreadsheet would run as a formula stays text, and files of
    the same content are named in the summary."""
    folder = _class(tmp_path / "class", ["=HYPERLINK(1)", "copy"])
    out = tmp_path / "grades.csv"
    grades = grading.grade(KINEMATICS, folder, isolation="none", out=out)
    names = {row["student"] for row in csv.DictReader(out.read_text().splitlines())}
    assert names == {"'=HYPERLINK(1)", "copy"}
    assert "identical files" in grades.summary() and "=HYPERLINK(1), copy" in grades.summary()
    kept = []
    grading.grade(KINEMATICS, folder, isolation="none", out=out,
                  progress=lambda student, report: kept.append(report is None))
    assert kept == [True, True] and len(list(csv.DictReader(out.read_text().splitlines()))) == 2


def test_an_interrupted_grading_ends_the_runs_it_leaves(tmp_path):
    """Interrupted while a submission loops, grading stops at once, not after its time."""
    folder = _class(tmp_path / "class", ["ann"])
    _submission(folder, "zed", [(F_Q, "    while True:\n        pass\n")])

    def interrupt(student, report):
        raise KeyboardInterrupt

    from flexmbd.course import launch

    with pytest.raises(KeyboardInterrupt):
        grading.grade(KINEMATICS, folder, isolation="none", jobs=2, timeout=60,
                      out=tmp_path / "grades.csv", progress=interrupt)
    begun = time.monotonic()
    while launch._LIVE and time.monotonic() - begun < 10:
        time.sleep(0.05)
    assert not launch._LIVE   # the looping run ended, though 60 s were its due
