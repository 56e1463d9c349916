"""Property-based fuzzing of the SPACAR reader: mutated example files never raise
anything but the library's own errors, and whatever reads also writes and reads back."""

import os
import time

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import flexmbd as fm
from flexmbd.io.dat import dat_from_text, dat_text
from flexmbd.io.dat.syntax import DYNAMICS, INSTEAD, KINEMATICS, TRANSFER, UNSUPPORTED
from tests.test_dat import DAT_FILES, EVERYTHING
from tests.test_dat_spacar import CANTILEVER
from tests.test_dat_spacar import TRANSFER as SPACAR_TRANSFER
from tests.test_dat_spatial import SPATIAL_EVERYTHING
from tests.test_spatial_rigid_beam import PENDULUM as RIGID_BODY

#: the example files, the files of every keyword, and SPACAR-written lines (SPACAR Light's
#: layout, a transfer-function file with its third block, pre-stresses in SPACAR's order)
SOURCES = [EVERYTHING, SPATIAL_EVERYTHING, *(path.read_text() for path in DAT_FILES),
           CANTILEVER.format(block2=SPACAR_TRANSFER),
           CANTILEVER.format(block2="ESIG 1 1.0 2.0\nXF 6 0 0.4 -1.0 3.0"),
           RIGID_BODY.format(element="RBEAM 1 1 2 3 0 1 0")]
WORDS = sorted({*KINEMATICS, *DYNAMICS, *TRANSFER, *UNSUPPORTED, *INSTEAD, "END", "HALT"})
NUMBERS = ["0", "-1", "1", "2", "3", "7", "99", "2.5", "-0.0", "1e308", "1e400", "nan",
           "-inf", "1D3", "0x10", "1_000", "", "#", "%", "*"]

# reproducible in CI (the landing gate), exploring anew on a developer's machine
FUZZ = settings(max_examples=400 if os.environ.get("CI") else 200, deadline=None,
                derandomize=bool(os.environ.get("CI")),
                suppress_health_check=[HealthCheck.too_slow])


@st.composite
def mutated(draw) -> str:
    """An example file with one to four random edits of lines and words."""
    lines = draw(st.sampled_from(SOURCES)).splitlines()
    for _ in range(draw(st.integers(1, 4))):
        if not lines:
            break
        i = draw(st.integers(0, len(lines) - 1))
        edit = draw(st.sampled_from(["delete", "duplicate", "swap", "word", "insert",
                                     "truncate", "garbage"]))
        if edit == "delete":
            del lines[i]
        elif edit == "duplicate":
            lines.insert(i, lines[i])
        elif edit == "swap":
            j = draw(st.integers(0, len(lines) - 1))
            lines[i], lines[j] = lines[j], lines[i]
        elif edit == "word":
            words = lines[i].split() or [""]
            k = draw(st.integers(0, len(words) - 1))
            words[k] = draw(st.sampled_from(WORDS + NUMBERS) | st.text(max_size=6))
            lines[i] = " ".join(words)
        elif edit == "insert":
            words = draw(st.lists(st.sampled_from(WORDS + NUMBERS), min_size=1, max_size=7))
            lines.insert(i, " ".join(words))
        elif edit == "truncate":
            text = "\n".join(lines)
            return text[:draw(st.integers(0, len(text)))]
        else:
            lines[i] = draw(st.text(max_size=30))
    return "\n".join(lines)


#: a mutated file that reads may well describe a model flexmbd warns about (a beam left
#: without mass or stiffness): a warning is what it should give, not what is tested here
QUIET = pytest.mark.filterwarnings("ignore::flexmbd.ModelWarning")


@QUIET
@FUZZ
@given(mutated())
def test_mutated_files_raise_only_library_errors(text):
    start = time.perf_counter()
    try:
        model, run = dat_from_text(text, "fuzz.dat")
    except fm.InputFileError as error:  # every model error names the file and the line
        assert error.path == "fuzz.dat" and error.line is not None, str(error)
        assert str(error).startswith(f"fuzz.dat:{error.line}: ")
        return
    finally:
        assert time.perf_counter() - start < 5.0  # no input file makes the reader crawl
    # a file that reads is a valid model: it writes and reads back to the same text
    written = dat_text(model, run)
    assert dat_text(*dat_from_text(written, "fuzz.dat")) == written


@QUIET
def test_the_fuzzer_reaches_both_outcomes():
    """Guard against a fuzzer that only ever produces unreadable (or only readable) files."""
    outcomes = set()

    @settings(max_examples=150, deadline=None, derandomize=True)
    @given(mutated())
    def probe(text):
        try:
            dat_from_text(text, "fuzz.dat")
            outcomes.add("read")
        except fm.InputFileError:
            outcomes.add("refused")

    probe()
    assert outcomes == {"read", "refused"}


@pytest.mark.parametrize("source", range(len(SOURCES)))
def test_the_unmutated_sources_read(source):
    assert dat_from_text(SOURCES[source], "source.dat").model.n_dof >= 1
