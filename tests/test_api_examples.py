"""The examples of the API reference run and print what they say, as SciPy's do: every
public function's docstring examples are doctests, and the main functions have one."""

import doctest

import pytest

import flexmbd as fm

#: the functions a new user reaches for first: each shows a call and its result
MAIN = ("simulate", "kinematic_analysis", "static_equilibrium", "linearize",
        "vibration_modes", "buckling", "node_compliance", "load_step_table", "energy",
        "read_dat", "sweep")
PUBLIC = [name for name in fm.__all__ if not name.startswith("_")]


def _examples(name: str) -> list[doctest.DocTest]:
    finder = doctest.DocTestFinder(recurse=False)
    return [test for test in finder.find(getattr(fm, name), name) if test.examples]


@pytest.mark.parametrize("name", MAIN)
def test_a_main_function_has_an_example(name):
    assert _examples(name), f"fm.{name} has no example in its docstring"


@pytest.mark.parametrize("name", [n for n in PUBLIC if _examples(n)])
def test_the_examples_print_what_they_say(name):
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS)
    for test in _examples(name):
        runner.run(test)
    assert runner.failures == 0, f"fm.{name}: {runner.failures} example(s) failed"
