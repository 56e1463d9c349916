"""Result files: the CSV numbers are printf's "%.17g", exactly, and read back unchanged."""

import numpy as np

import flexmbd as fm
from flexmbd import _core
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
    assert fm.FlexmbdError  # the module's errors come from flexmbd
