"""Shared fixtures: small models from the exercises."""

import matplotlib
import pytest

matplotlib.use("Agg")  # never open a window from the tests

import flexmbd as fm

from .models import slider_crank


@pytest.fixture
def crank_model() -> fm.Model:
    return slider_crank()
