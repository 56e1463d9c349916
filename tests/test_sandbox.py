"""Graded files run in an operating-system sandbox: the attacks of a hostile class do not
earn marks, change files, outlive the grading or break it, and honest work is not hurt.

Each attack is checked both ways where it can be: it works in a self-check (so the test
can fail), and it does not in a graded run. These tests need bubblewrap; they are skipped
where it cannot run, unless ``FLEXMBD_REQUIRE_SANDBOX`` is set (``.ci/run`` sets it).
"""

from __future__ import annotations

import csv
import hashlib
import json
import os
import secrets
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from flexmbd.cli import main
from flexmbd.course import exercise
from flexmbd.course.check import ERROR, FAILED, MEMORY, NOT_DONE, PASSED, TIME, _calls, check
from flexmbd.course.grading import grade
from flexmbd.course.sandbox import Limits
from flexmbd.course.templates import solution_source, template_source

KINEMATICS = exercise("slider-crank-kinematics")
SOLUTION = solution_source(KINEMATICS)
REPO = Path(__file__).resolve().parents[1]
LECTURER = REPO / "lecturer" / "solutions" / "slider_crank_kinematics.py"
RUNNER = REPO / "flexmbd" / "course" / "runner.py"
#: the body of part e in the solution
F_Q = "    return velocities(phi2, 1.0)[:, None]\n"
E_Q = "    return jacobian(configuration(phi2)) @ first_order_transfer(phi2)\n"
#: the body of part i, which no other part uses
XDD = ("    return (first_order_transfer(phi2) * phi2dd + second_order_transfer(phi2) * "
       "phi2d**2)[:, 0]\n")


def _submission(folder: Path, name: str, replacements=(), extra: str = "",
                encoding: str = "utf-8") -> Path:
    source = SOLUTION
    for old, new in replacements:
        assert source.count(old) == 1, old
        source = source.replace(old, new)
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / f"{name}.py"
    path.write_text(source + extra, encoding=encoding)
    return path


def _verdicts(report):
    return {p.letter: p for p in report.parts}


def _processes_with(token: str) -> list[str]:
    found = []
    for pid in filter(str.isdigit, os.listdir("/proc")):
        try:
            if token.encode() in Path(f"/proc/{pid}/cmdline").read_bytes():
                found.append(pid)
        except OSError:
            continue
    return found


#: three ways to flexmbd's answers: its checkout on the path, an unconfined Python that
#: imports it, and the lecturer's solution file
ROUTES = {
    "import": f"""
    import sys
    sys.path.insert(0, {str(REPO)!r})
    from flexmbd.analysis import kinematics
    from flexmbd.course.slider_crank_kinematics import model, configuration
    return kinematics.first_order_transfer(model(), configuration(phi2))
""",
    "process": f"""
    import json, subprocess, sys
    code = ("import json, sys; sys.path.insert(0, {str(REPO)!r}); "
            "from flexmbd.analysis import kinematics as k; "
            "from flexmbd.course.slider_crank_kinematics import model, configuration as c; "
            "print(json.dumps(k.first_order_transfer(model(), c(%r)).tolist()))" % phi2)
    for python in (sys.executable, {sys.executable!r}, "/usr/bin/python3"):
        try:
            done = subprocess.run([python, "-c", code], capture_output=True, text=True,
                                  timeout=60)
            return np.array(json.loads(done.stdout))
        except Exception:
            continue
    raise RuntimeError("no Python gave the answer")
""",
    "solutions": f"""
    namespace = {{}}
    exec(open({str(LECTURER)!r}).read(), namespace)
    return namespace["first_order_transfer"](phi2)
""",
}


@pytest.mark.parametrize("route", list(ROUTES))
def test_a_graded_file_reaches_none_of_flexmbd_s_answers(route, sandbox, tmp_path):
    """Each route gives part e its answer in a self-check; none does in a graded run:
    the sandbox has nothing of flexmbd but the template's helper."""
    path = _submission(tmp_path, "cheat", [(F_Q, ROUTES[route])])
    assert _verdicts(check(KINEMATICS, path))["e"].status == PASSED
    part = _verdicts(check(KINEMATICS, path, graded=True, timeout=20))["e"]
    assert part.status == FAILED and part.reason == ERROR, part


def test_the_request_carries_no_answer():
    """What the child is sent: functions and arguments, never a reference."""
    calls, plan = _calls(KINEMATICS, 2026)
    assert {key for call in calls for key in call} <= {"id", "function", "args",
                                                       "substitutes"}
    assert any(p.reference is not None for p in plan.values())   # kept in the grader


ATTACK = """
import os, signal, subprocess, sys, time

# a daemon, and a double-forked one, that wait for the grader to end and then write
subprocess.Popen([sys.executable, "-c", "import time; time.sleep(2); "
                  "open({victim!r}, 'w').write('pwned')  # {token}"], start_new_session=True)
if os.fork() == 0:
    os.setsid()
    if os.fork() == 0:
        time.sleep(2)
        try:
            open({victim!r}, "w").write("pwned")
        finally:
            os._exit(0)
    os._exit(0)
os.wait()


def attempt(action):
    try:
        action()
        return "done"
    except OSError as error:
        return type(error).__name__


RESULTS = [
    attempt(lambda: open({victim!r}, "w").write("x")),
    attempt(lambda: os.open("grades.json", os.O_WRONLY | os.O_CREAT,
                            dir_fd=os.open({folder!r}, os.O_RDONLY))),
    attempt(lambda: os.remove({classmate!r})),
    attempt(lambda: os.link({classmate!r}, "copy.py")),
    attempt(lambda: open({runner!r}, "a").write("# rewired")),
    attempt(lambda: open("/sandbox/lib/flexmbd/course/runner.py", "a").write("#")),
    attempt(lambda: open("/usr/planted", "w")),
    attempt(lambda: open("/planted", "w")),
    attempt(lambda: open("scratch.txt", "w").write("fine here")),
]
assert RESULTS[-1] == "done" and "done" not in RESULTS[:-1], RESULTS
# no process but this sandbox's is visible: not the grader, not a classmate's checker
for pid in filter(str.isdigit, os.listdir("/proc")):
    line = open(f"/proc/{{pid}}/cmdline", "rb").read()
    assert b"\\x00pytest\\x00" not in line and b"bin/pytest" not in line, line
    assert b"\\x00grade\\x00" not in line, line
"""


def test_nothing_of_a_graded_file_outlives_it_or_changes_a_file_outside(sandbox, tmp_path):
    """Daemons, dir_fd paths, links, a rewired runner, a classmate's file, signals: every
    attempt is refused or dies with the sandbox; the classmate is graded in full."""
    folder = tmp_path / "submissions"
    classmate = _submission(folder, "ada")
    victim = tmp_path / "lecturer.json"
    victim.write_text('{"score": 7}')
    token = f"flexmbd-daemon-{secrets.token_hex(6)}"
    runner_hash = hashlib.sha256(RUNNER.read_bytes()).hexdigest()
    _submission(folder, "mallory", extra=ATTACK.format(
        victim=str(victim), token=token, folder=str(folder), classmate=str(classmate),
        runner=str(RUNNER)))
    grades = grade(KINEMATICS, folder, out=tmp_path / "grades.csv", timeout=20,
                   reports=tmp_path / "reports")
    assert not _processes_with(token)   # at once: nothing of the sandbox survives it
    mallory = grades.reports["mallory"]
    assert mallory.problem is None, mallory.problem   # every attempt failed
    assert mallory.score == mallory.max_score
    assert grades.reports["ada"].score == grades.reports["ada"].max_score
    time.sleep(3)   # the daemons' time to write, had they survived
    assert victim.read_text() == '{"score": 7}'
    assert classmate.read_text() == SOLUTION
    assert hashlib.sha256(RUNNER.read_bytes()).hexdigest() == runner_hash
    assert not (folder / "grades.json").exists()


KILLER = """
import os, signal
for pid in range(1, 30000):
    if pid != os.getpid():
        try:
            os.kill(pid, signal.SIGKILL)
        except OSError:
            pass
"""

FORGER = """
_forged = []


def deformations(x):
    if not _forged:   # lines on the results channel, in the middle of a call
        _forged.append(True)
        for line in (b'{"id": 0, "array": 1' + b"1" * 5000 + b', "shape": []}',
                     b"[" * 100000, b'{"id": 0, "array": "x"}', b"\\xff\\xfe",
                     b'{"loaded": true, "problem": null}'):
            for fd in range(3, 10):
                try:
                    os.write(fd, line + b"\\n")
                except OSError:
                    pass
    return _solved(x)
"""


def test_no_submission_breaks_the_grader_or_a_classmate(sandbox, tmp_path):
    """A file that kills every process it can, one that forges malformed records on the
    results channel, and a link planted where a report goes: every student gets a row,
    the others full marks, and no file outside is written through the link."""
    folder = tmp_path / "submissions"
    _submission(folder, "ada")
    _submission(folder, "killer", extra=KILLER)
    _submission(folder, "forger", [("def deformations(x):", "def _solved(x):")],
                extra="import os\n" + FORGER)
    _submission(folder, "eve")
    reports = tmp_path / "reports"
    reports.mkdir()
    lecturer = tmp_path / "lecturer_notes.txt"
    lecturer.write_text("keep me")
    (reports / "eve.txt").symlink_to(lecturer)
    out = tmp_path / "grades.csv"
    assert main(["exercise", "grade", "2", str(folder), "--out", str(out), "--reports",
                 str(reports), "--timeout", "10"]) == 0
    rows = {row["student"]: row for row in csv.DictReader(out.read_text().splitlines())}
    assert set(rows) == {"ada", "killer", "forger", "eve"}
    assert rows["ada"]["score"] == rows["eve"]["score"] == "9"
    assert rows["killer"]["score"] == "9"   # it killed nothing but its own processes
    assert rows["forger"]["2a"] == "0" and rows["forger"]["2a reason"] == ERROR
    assert "could not be read" in (reports / "forger.txt").read_text()
    assert lecturer.read_text() == "keep me"
    assert not (reports / "eve.txt").is_symlink()
    assert "score 9/9" in (reports / "eve.txt").read_text()


def test_a_table_of_answers_passes_a_self_check_but_not_a_grade(sandbox, tmp_path):
    """The self-check's seed is public; a grade draws its own, so answers computed at
    home for the self-check's configurations do not pass it."""
    _, plan = _calls(KINEMATICS, 2026)
    part = KINEMATICS.part("e")
    table = {repr(round(float(args[0]), 9)): part.answer(*args).tolist()
             for args in plan["e"].cases}
    body = (f"    TABLE = {table!r}\n"
            f"    return np.array(TABLE[repr(round(float(phi2), 9))])\n")
    path = _submission(tmp_path, "table", [(F_Q, body)])
    assert _verdicts(check(KINEMATICS, path))["e"].status == PASSED
    report = check(KINEMATICS, path, graded=True)
    assert report.seed != 2026 and _verdicts(report)["e"].status == FAILED
    again = check(KINEMATICS, path, graded=True, seed=report.seed)   # reproduced
    assert again.text() == report.text()


LIMITS = """
def deformations(x):
    while True:
        if os.fork() == 0:
            time.sleep(60)
            os._exit(0)


def jacobian(x):
    with open("big.bin", "wb") as handle:
        handle.write(b"0" * 16 * 2**20)


def positions(phi2):
    for k in range(40):
        with open(f"part{k}.bin", "wb") as handle:
            handle.write(b"0" * 2**20)


def velocities(phi2, phi2d):
    return np.ones(3 * 2**30 // 8)
"""


def test_the_limits_are_told_apart(sandbox, tmp_path):
    """Processes, file size, the scratch folder's size and memory each fail their part
    with their own reason and hint; the other parts are graded as usual."""
    path = tmp_path / "limits.py"
    path.write_text(SOLUTION + "\nimport os, time\n" + LIMITS)
    limits = Limits(file_size=8 * 2**20, scratch=32 * 2**20)
    verdicts = _verdicts(check(KINEMATICS, path, graded=True, timeout=20, limits=limits))
    assert "processes" in verdicts["a"].hint, verdicts["a"]
    assert "files of at most 8 MB" in verdicts["b"].hint, verdicts["b"]
    assert "holds 32 MB" in verdicts["c"].hint, verdicts["c"]
    assert verdicts["d"].reason == MEMORY and "2 GB" in verdicts["d"].hint, verdicts["d"]


def test_cpu_time_is_a_time_limit_of_its_own(sandbox, tmp_path):
    path = _submission(tmp_path, "spin", [(XDD, "    while True:\n        pass\n")])
    verdicts = _verdicts(check(KINEMATICS, path, graded=True, timeout=30,
                               limits=Limits(cpu=2)))
    assert verdicts["i"].reason == TIME and "CPU time (2 s)" in verdicts["i"].message
    assert all(verdicts[k].status == PASSED for k in "abcdefgh")


HOG = """
def accelerations(phi2, phi2d, phi2dd):
    for _ in range({count}):
        if os.fork() == 0:
            {work}
            os._exit(0)
    while True:
        time.sleep(1)
"""


def test_a_part_is_charged_what_all_its_processes_use(sandbox, tmp_path):
    """A part that leaves its work to many processes is charged their CPU time and held
    to the memory limit together: it is stopped as soon as they have used the part's
    time, or hold more memory than one process may, and cannot starve a classmate."""
    spin = _submission(tmp_path, "spin", extra="\nimport os, time\n" + HOG.format(
        count=20, work="while True: pass"))
    begun = time.monotonic()
    part = _verdicts(check(KINEMATICS, spin, graded=True, timeout=4))["i"]
    assert part.reason == TIME and "used 4 s of CPU time" in part.message, part
    assert time.monotonic() - begun < 12   # 4 s of CPU on two cores, and the rest
    hold = _submission(tmp_path, "hold", extra="\nimport os, time\n" + HOG.format(
        count=3, work="block = np.ones(400 * 2**20 // 8); time.sleep(60)"))
    verdicts = _verdicts(check(KINEMATICS, hold, graded=True, timeout=20,
                               limits=Limits(memory=2**30)))
    part = verdicts["i"]
    assert part.reason == MEMORY and "1 GB of memory together" in part.message, part
    assert all(verdicts[k].status == PASSED for k in "abcdefgh")


def test_honest_work_in_the_sandbox_gets_full_marks(sandbox, tmp_path):
    """A Windows file with a byte-order mark, a notebook, and a file that imports
    Matplotlib and SciPy: all of it runs as Python runs it."""
    bom = _submission(tmp_path, "windows", encoding="utf-8-sig")
    assert bom.read_bytes().startswith(b"\xef\xbb\xbf")
    assert check(KINEMATICS, bom, graded=True).score == 9
    plots = _submission(tmp_path, "plots", extra="\nimport matplotlib.pyplot as plt\n"
                                                 "import scipy.linalg\nplt.plot([0, 1])\n"
                                                 "plt.savefig('figure.png')\n")
    report = check(KINEMATICS, plots, graded=True, timeout=30)
    assert report.problem is None and report.score == 9


def test_the_gradescope_recipe_grades_in_the_sandbox(sandbox, tmp_path, capsys):
    """run_autograder as Gradescope runs it, in a copy of its folders."""
    assert main(["exercise", "recipe", "gradescope", str(tmp_path / "source"), "--exercise",
                 "2", "--points", "f=2"]) == 0
    root = tmp_path / "autograder"
    _submission(root / "submission", "my_work")
    flexmbd = Path(sys.executable).with_name("flexmbd")
    done = subprocess.run([str(tmp_path / "source" / "run_autograder")], capture_output=True,
                          text=True, timeout=300, env={**os.environ, "AUTOGRADER_ROOT": str(root),
                                                       "FLEXMBD": str(flexmbd)})
    assert done.returncode == 0, done.stderr
    results = json.loads((root / "results" / "results.json").read_text())
    assert results["score"] == results["max_score"] == 10
    assert "bubblewrap" in results["extra_data"]["isolation"]
    (root / "submission" / "second.py").write_text("")
    subprocess.run([str(tmp_path / "source" / "run_autograder")], check=True, timeout=60,
                   env={**os.environ, "AUTOGRADER_ROOT": str(root), "FLEXMBD": str(flexmbd)})
    results = json.loads((root / "results" / "results.json").read_text())
    assert results["score"] == 0 and "exactly one" in results["output"]


def test_the_container_recipe_s_image_runs_a_graded_process(sandbox, tmp_path):
    """The image's files run the protocol: here a bubblewrap command over the recipe's
    sandbox folder stands in for `docker run` (no container engine on the test machine)."""
    assert main(["exercise", "recipe", "container", str(tmp_path / "image")]) == 0
    dockerfile = (tmp_path / "image" / "Dockerfile").read_text()
    assert "ENTRYPOINT" in dockerfile and "/sandbox/lib/flexmbd/course/runner.py" in dockerfile
    lib = tmp_path / "image" / "sandbox"
    # the host's folders as they are (a container engine would give its image's), and
    # the image's /sandbox
    host = " ".join(f"--ro-bind /{d} /{d}" if not os.path.islink(f"/{d}") else
                    f"--symlink {os.readlink(f'/{d}')} /{d}" for d in sorted(os.listdir("/"))
                    if d not in ("proc", "dev", "sys", "sandbox", "scratch"))
    # (flexmbd and its checkout are not in the image; its Python and NumPy are)
    hidden = " ".join(f"--tmpfs {REPO / name}" for name in ("flexmbd", "examples",
                                                             "lecturer"))
    stand_in = (f"bwrap {host} {hidden} --ro-bind {lib} /sandbox --dev /dev --proc /proc "
                f"--tmpfs /scratch --chdir /scratch --unshare-all --die-with-parent "
                f"--new-session -- {sys.executable} -I /sandbox/lib/flexmbd/course/runner.py")
    path = _submission(tmp_path, "work", extra="\nimport flexmbd\nassert flexmbd.__file__ == "
                                                 "'/sandbox/lib/flexmbd/__init__.py'\n")
    out = tmp_path / "grades.csv"
    assert main(["exercise", "grade", "2", str(path.parent), "--out", str(out),
                 "--sandbox-command", stand_in]) == 0
    rows = list(csv.DictReader(out.read_text().splitlines()))
    assert rows[0]["score"] == "9" and not rows[0]["problem"], rows[0]
    assert np.all([r == PASSED for k, r in rows[0].items() if k.endswith("reason")])


def test_a_graded_file_imports_and_reads_nothing_of_flexmbd(sandbox, tmp_path):
    """An import of flexmbd's engine fails with a hint that says why; flexmbd's files, its
    examples and the lecturer's solutions are not there to read."""
    cheat = _submission(tmp_path, "cheat", [(
        F_Q, "    from flexmbd.analysis import kinematics\n"
             "    return kinematics\n")])
    part = _verdicts(check(KINEMATICS, cheat, graded=True))["e"]
    assert part.status == FAILED and "ModuleNotFoundError" in part.message
    assert "nothing of flexmbd but the template's helper" in part.hint
    star = tmp_path / "star.py"
    star.write_text("from flexmbd.course.slider_crank_kinematics import *\n")
    report = check(KINEMATICS, star, graded=True)
    assert report.score == 0 and "ModuleNotFoundError" in report.problem
    examples = REPO / "examples" / "slider_crank_kinematics.py"
    for target in ("pathlib.Path(flexmbd.__file__).parent / 'course' / "
                   "'slider_crank_kinematics.py'", repr(str(examples)), repr(str(LECTURER))):
        reader = tmp_path / "reader.py"
        reader.write_text(f"import flexmbd, pathlib\nSOURCE = open({target}).read()\n")
        assert "FileNotFoundError" in check(KINEMATICS, reader, graded=True).problem


def test_a_graded_file_runs_alone_in_its_scratch_folder(sandbox, tmp_path):
    """Files beside a submission are neither imported nor readable from it: its folder
    holds its copy and nothing else."""
    (tmp_path / "helpers.py").write_text("VALUE = 1\n")
    (tmp_path / "numpy.py").write_text("raise SystemExit('shadowed')\n")
    path = _submission(tmp_path, "alone", extra="\nimport os\nFILES = sorted(os.listdir('.'))\n"
                                                 "assert FILES == ['alone.py'], FILES\n"
                                                 "import helpers\n")
    report = check(KINEMATICS, path, graded=True)
    assert "No module named 'helpers'" in report.problem
    assert report.score == report.max_score   # numpy was numpy


def test_grading_a_folder(sandbox, tmp_path, capsys):
    """Full marks, a template, an endless loop in one part and a cheat: one row each, with
    per part the points and the reason, a report each, and a summary; the loop costs its
    part only."""
    folder = tmp_path / "submissions"
    folder.mkdir()
    _submission(folder, "ada")
    (folder / "bob.py").write_text(template_source(KINEMATICS))
    _submission(folder, "cy", [(E_Q, "    while True:\n        pass\n")])
    (folder / "dee").mkdir()
    _submission(folder / "dee", "work", [(F_Q, "    from flexmbd.analysis import kinematics\n"
                                               "    return 0\n")])
    out = tmp_path / "grades.csv"
    assert main(["exercise", "grade", "2", str(folder), "--out", str(out), "--timeout", "3",
                 "--points", "f=2"]) == 0
    rows = {row["student"]: row for row in csv.DictReader(out.read_text().splitlines())}
    assert set(rows) == {"ada", "bob", "cy", "dee"}
    assert rows["ada"]["score"] == "10" and rows["ada"]["max_score"] == "10"
    assert rows["bob"]["score"] == "0" and rows["bob"]["2a reason"] == "not defined"
    assert rows["cy"]["2f"] == "0" and rows["cy"]["2e"] == "1" and rows["cy"]["score"] == "8"
    assert rows["cy"]["2f reason"] == TIME and rows["cy"]["2e reason"] == PASSED
    assert rows["dee"]["2e"] == "0" and rows["dee"]["2e reason"] == ERROR
    seeds = {row["seed"] for row in rows.values()}
    assert len(seeds) == 1 and seeds != {"2026"}
    assert all(row["sha256"] and row["flexmbd_version"] and row["graded_at"]
               for row in rows.values())
    reports = tmp_path / "grades_reports"
    assert "time limit" in (reports / "cy.txt").read_text()
    assert "nothing of flexmbd" in (reports / "dee.txt").read_text()
    assert json.loads((reports / "bob.json").read_text())["tests"][0]["output"].startswith(
        NOT_DONE)
    printed = capsys.readouterr().out
    assert "graded 4 submissions" in printed and "parts most often not passed" in printed
