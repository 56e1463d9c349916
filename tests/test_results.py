"""Result files: the CSV numbers are printf's "%.17g", exactly, and read back unchanged."""

import errno
from pathlib import Path

import numpy as np
import pytest

from flexmbd.engine import _core
from flexmbd.errors import OutputError
from flexmbd.results import write_csv


def test_numbers_are_written_as_printf_17g():
    """The core formats most numbers by extended-precision arithmetic and hands the few near
    a rounding tie to printf: the text must be printf's for every kind of double."""
    rng = np.random.default_rng(7)
    bits = rng.integers(0, 2**64 - 1, size=200_000, dtype=np.uint64)
    values = bits.view(np.float64)
    values = values[np.isfinite(values)]
    decimal = np.array([round(float(v), int(k)) for v, k in zip(
        rng.normal(size=20_000) * 10.0 ** rng.integers(-9, 9, size=20_000),
        rng.integers(0, 13, size=20_000), strict=True)])
    edges = [0.0, -0.0, 5e-324, 2.2250738585072014e-308, 1.7976931348623157e308, 0.1, 1e-5,
             1e-4, 9.999999999999999e16, 1e17, 123456789012345678.0, 1e100, -1e-100,
             float("nan"), float("inf"), float("-inf")]
    for x in np.concatenate([values, decimal, edges]):
        assert _core.format_17g(x) == f"{x:.17g}"


def test_csv_reads_back_to_the_same_doubles(tmp_path):
    rng = np.random.default_rng(8)
    columns = {"t": np.linspace(0.0, 1.0, 7), "a": rng.normal(size=7) * 1e-9,
               "b": rng.normal(size=7) * 1e12}
    path = write_csv(tmp_path / "r.csv", columns)
    header, *rows = path.read_text().splitlines()
    assert header == "t,a,b" and len(rows) == 7
    data = np.loadtxt(rows, delimiter=",")
    for k, values in enumerate(columns.values()):
        np.testing.assert_array_equal(data[:, k], values)
    empty = write_csv(tmp_path / "e.csv", {"t": np.zeros(0), "x": np.zeros(0)})
    assert empty.read_text() == "t,x\n"


def test_a_long_table_of_strided_columns_is_every_number_as_printf_writes_it(tmp_path):
    """The core writes the rows in 64 kB pieces from columns that are views with strides:
    5000 rows of 20 columns (1.9 MB of text) give exactly Python's own "%.17g" lines."""
    rng = np.random.default_rng(9)
    table = rng.normal(size=(5000, 20)) * 10.0 ** rng.integers(-12, 12, size=(5000, 20))
    table[::7, 3], table[::11, 5] = 0.0, -0.0
    columns = {f"c{k}": table[:, k] for k in range(20)}  # every column a strided view
    text = write_csv(tmp_path / "long.csv", columns).read_text()
    expected = "".join(",".join(f"{x:.17g}" for x in row) + "\n" for row in table)
    assert text == ",".join(columns) + "\n" + expected


@pytest.mark.skipif(not Path("/dev/full").exists(), reason="needs /dev/full (Linux)")
def test_a_full_disk_is_an_output_error():
    """The core's own writes report the operating system's error (ENOSPC), which
    :func:`write_csv` names as an :class:`OutputError` with the path."""
    with open("/dev/full", "wb") as full, pytest.raises(OSError) as caught:
        _core.csv_write(full.fileno(), [np.arange(20000.0)])
    assert caught.value.errno == errno.ENOSPC
    with pytest.raises(OutputError, match="cannot write /dev/full"):
        write_csv("/dev/full", {"t": np.arange(20000.0)})


def test_a_reaction_column_of_a_run_without_reactions_says_how_to_get_it():
    """``res["f2.1"]`` of a simulation run without reactions names ``with_reactions``; the
    attributes answer to their columns' prefixes too (``res.sig``, ``res.f``)."""
    import flexmbd as fm
    from examples.slider_crank_flex import build_model

    model = build_model(nbeams=1)
    plain = fm.simulate(model, np.linspace(0.0, 0.01, 3))
    with pytest.raises(fm.ColumnError, match=r"'f2\.1' is a reaction .* with_reactions=True"):
        plain["f2.1"]
    with pytest.raises(fm.ColumnError, match=r"node 99 is not in the model"):
        plain["f99.1"]
    kept = fm.simulate(model, np.linspace(0.0, 0.01, 3), with_reactions=True)
    assert kept.f is kept.reactions and kept.sig is kept.sigma
    assert np.array_equal(kept["f2.1"], kept.f[:, model._coordinate_index("x2.1")])
