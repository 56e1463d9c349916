"""Shared fixtures: small models from the exercises, and the sandbox of graded runs."""

import os

import matplotlib
import pytest

matplotlib.use("Agg")  # never open a window from the tests

import flexmbd as fm

from .models import slider_crank


@pytest.fixture
def crank_model() -> fm.Model:
    return slider_crank()


@pytest.fixture(scope="session")
def sandbox():
    """The operating-system sandbox of graded runs: skip where bubblewrap cannot make it,
    fail there when ``FLEXMBD_REQUIRE_SANDBOX`` is set (``.ci/run`` sets it)."""
    from flexmbd.course.launch import verify
    from flexmbd.course.sandbox import Bubblewrap
    from flexmbd.errors import SandboxError

    try:
        verify(Bubblewrap())
    except SandboxError as error:
        if os.environ.get("FLEXMBD_REQUIRE_SANDBOX"):
            raise
        pytest.skip(f"no sandbox here: {error}")
