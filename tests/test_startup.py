"""What a process pays before it works: ``import flexmbd`` loads its names on first use,
a command imports its own module only, and ``example``/``run`` start OpenBLAS with one
thread (benchmarks/RESULTS.md, issue 33, has the times)."""

import subprocess
import sys

import pytest

import flexmbd as fm


def _python(code: str, **env: str) -> str:
    import os

    environment = {k: v for k, v in os.environ.items() if k != "OPENBLAS_NUM_THREADS"}
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          env={**environment, **env}, timeout=120)
    assert done.returncode == 0, done.stderr
    return done.stdout.strip()


def test_import_flexmbd_loads_no_numpy_and_every_name_on_use():
    code = ("import sys, flexmbd as fm\nprint('numpy' in sys.modules)\n"
            "print(fm.ModelBuilder.__module__, 'numpy' in sys.modules)")
    assert _python(code).split() == ["False", "flexmbd.builder.recording", "True"]


def test_a_lazy_name_is_the_object_not_the_submodule_of_its_name():
    """``flexmbd.studies.sweep`` is a module and ``flexmbd.sweep`` a function: the import of
    the module binds its name in the package, which must not replace the function."""
    assert callable(fm.sweep) and callable(fm.sweep)
    from flexmbd import studies

    assert callable(studies.sweep) and callable(studies.sweep)
    assert fm.engine.__name__ == "flexmbd.engine"  # a submodule by attribute, as before
    with pytest.raises(AttributeError, match="no attribute 'nothing'"):
        fm.nothing
    assert all(hasattr(fm, name) for name in fm.__all__)


def test_a_command_imports_its_own_module_only():
    code = ("import sys, contextlib, io\nfrom flexmbd.cli import main\n"
            "with contextlib.redirect_stdout(io.StringIO()):\n"
            "    main(['example', '--list'])\n"
            "print(' '.join(sorted(m for m in sys.modules if m.startswith('flexmbd'))))")
    modules = _python(code).split()
    for other in ("flexmbd.cli.run", "flexmbd.cli.linear", "flexmbd.cli.course",
                  "flexmbd.studies.sweep", "flexmbd.cli.sweep", "flexmbd.engine"):
        assert other not in modules


@pytest.mark.parametrize("command, given, threads", [
    ("example", None, "1"), ("run", None, "1"), ("modes", None, "None"),
    ("example", "2", "2")])
def test_openblas_starts_with_one_thread_for_example_and_run_unless_chosen(
        command, given, threads):
    code = (f"import os, sys\nfrom flexmbd import cli\ncli._one_blas_thread([{command!r}, 'x'])"
            f"\nprint(os.environ.get('OPENBLAS_NUM_THREADS'))")
    env = {} if given is None else {"OPENBLAS_NUM_THREADS": given}
    assert _python(code, **env) == threads
