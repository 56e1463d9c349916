"""The documentation: it builds without warnings, its links resolve, its code runs, and its
API reference and tables follow the library.

The build (``sphinx-build -W``, gallery included, at the reduced resolution of
``FLEXMBD_DOCS_QUICK=1``) runs once per session into a temporary directory; it writes
the generated API pages and gallery into ``docs/generated`` and ``docs/gallery``, which
git ignores.
"""

from __future__ import annotations

import html.parser
import os
import re
import subprocess
import sys
from pathlib import Path
from urllib.parse import unquote, urlsplit

import pytest

import flexmbd as fm
from flexmbd.io.dat import syntax

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
PAGES = sorted(p for p in DOCS.rglob("*.md") if not p.is_relative_to(DOCS / "_build"))
GUIDE_PAGES = [p for p in PAGES if p.name != "benchmarks-record.md"]


# --- the build ---------------------------------------------------------------------------
@pytest.fixture(scope="module")
def site(tmp_path_factory) -> Path:
    """The HTML site, built as the README says, with warnings as errors."""
    out = tmp_path_factory.mktemp("html")
    env = {**os.environ, "FLEXMBD_DOCS_QUICK": "1", "MPLBACKEND": "Agg"}
    done = subprocess.run([sys.executable, "-m", "sphinx", "-W", "-E", "-q", "-b", "html",
                           str(DOCS), str(out)], capture_output=True, text=True, env=env,
                          timeout=600)
    assert done.returncode == 0, f"sphinx-build failed:\n{done.stderr[-5000:]}"
    return out


@pytest.mark.docs
def test_docs_build_without_warnings(site):
    assert (site / "index.html").is_file()
    assert (site / "api.html").is_file()


class _Links(html.parser.HTMLParser):
    """The ids and the href/src targets of one HTML page."""

    def __init__(self):
        super().__init__()
        self.ids: set[str] = set()
        self.targets: list[str] = []

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        if "id" in attrs:
            self.ids.add(attrs["id"])
        if tag == "a" and attrs.get("name"):
            self.ids.add(attrs["name"])
        for key in ("href", "src"):
            if attrs.get(key):
                self.targets.append(attrs[key])


def _parse(page: Path) -> _Links:
    links = _Links()
    links.feed(page.read_text(encoding="utf-8", errors="replace"))
    return links


@pytest.mark.docs
def test_internal_links_resolve(site):
    """Every relative link of every page reaches a file of the site, and its #anchor an id
    of that file; no link leaves the site except to a public web page."""
    pages = {p: _parse(p) for p in site.rglob("*.html")}
    broken = []
    for page, links in pages.items():
        for target in links.targets:
            parts = urlsplit(target)
            if parts.scheme in ("http", "https", "mailto", "data", "javascript"):
                continue
            assert not parts.scheme, f"{page.name}: link {target!r}"
            path = (page.parent / unquote(parts.path)).resolve() if parts.path else page
            if not path.is_relative_to(site.resolve()) or not path.exists():
                broken.append(f"{page.relative_to(site)}: {target}")
                continue
            if parts.fragment and path.suffix == ".html":
                ids = pages[path].ids if path in pages else _parse(path).ids
                if unquote(parts.fragment) not in ids:
                    broken.append(f"{page.relative_to(site)}: {target} (no such anchor)")
    assert not broken, "broken links:\n" + "\n".join(sorted(set(broken)))


@pytest.mark.docs
def test_api_reference_lists_every_public_name(site):
    """A page per name of ``flexmbd.__all__``, linked from the API reference."""
    api = (site / "api.html").read_text()
    missing = [name for name in fm.__all__ if name != "__version__"
               and f'href="generated/flexmbd.{name}.html' not in api]
    assert not missing, f"not in the API reference: {missing}"


@pytest.mark.docs
def test_gallery_runs_every_example_with_pictures_and_animations(site):
    scripts = sorted((ROOT / "examples" / "gallery").glob("plot_*.py"))
    assert len(scripts) >= 5
    animations = 0
    for script in scripts:
        page = site / "gallery" / f"{script.stem}.html"
        text = page.read_text()
        assert "sphx-glr-single-img" in text or "sphx-glr-multi-img" in text, \
            f"{script.name} made no picture"
        animations += "sphx-glr-animation" in text
    assert animations >= 2


@pytest.mark.docs
def test_math_renders_without_a_network(site):
    """MathJax is part of the site: the theory page loads it from the site itself, and no
    page loads a script from elsewhere."""
    theory = (site / "theory.html").read_text()
    assert '_static/mathjax/tex-chtml.js' in theory
    assert (site / "_static" / "mathjax" / "tex-chtml.js").is_file()
    for page in site.rglob("*.html"):
        sources = re.findall(r'<script[^>]*\bsrc="([^"]+)"', page.read_text())
        assert not [s for s in sources if s.startswith(("http:", "https:", "//"))], page


@pytest.mark.docs
def test_an_element_type_s_page_shows_what_a_user_reads(site):
    """An element type's page: its description and deformation functions, not the
    engine's machinery every type carries (laws, kernels' inputs, drawing, file lines)."""
    for name in ("Beam", "SpatialBeam", "Hinge"):
        page = (site / "generated" / f"flexmbd.{name}.html").read_text()
        assert f'id="flexmbd.{name}.deformations"' in page, name
        for machinery in ("elastic_law", "material_point", "stiffness_line", "__init__"):
            assert machinery not in page, (name, machinery)
    builder = (site / "generated" / "flexmbd.ModelBuilder.html").read_text()
    assert 'id="flexmbd.ModelBuilder.add_beam"' in builder


@pytest.mark.docs
def test_the_theory_page_draws_every_element_type(site):
    """A figure of each element type a user builds with, drawn from its definition."""
    from flexmbd.elements import ELEMENT_TYPES

    theory = (site / "theory.html").read_text()
    for keyword in ELEMENT_TYPES:
        if keyword != "EULER":   # the automatic normalization of Euler parameters
            assert f"{keyword}: its reference and each deformation alone" in theory, keyword


@pytest.mark.docs
def test_theory_citations_are_links(site):
    """"THEORY 5" in a docstring links to that section of the theory page (whose
    anchors the link test checks)."""
    page = (site / "generated" / "flexmbd.mass_matrix.html").read_text()
    assert 'href="../theory.html#theory-5"' in page


def test_read_the_docs_builds_the_site_as_the_readme_says():
    config = (ROOT / ".readthedocs.yaml").read_text()
    assert "configuration: docs/conf.py" in config and "fail_on_warning: true" in config
    assert "- docs" in config


def test_every_gallery_script_builds_its_own_model():
    """A gallery script shows how its model is made, as scikit-fem's and Exudyn's do: its
    ModelBuilder code is in the script, not behind a helper."""
    for script in sorted((ROOT / "examples" / "gallery").glob("plot_*.py")):
        text = script.read_text()
        assert "fm.ModelBuilder(" in text, script.name
        assert "build_model(" not in text, script.name


# --- without a build -----------------------------------------------------------------------
def test_api_source_lists_exactly_the_public_names():
    """``docs/api.rst`` names every entry of ``flexmbd.__all__`` once and nothing else
    (besides the modules it documents), so a new or removed name fails here first."""
    text = (DOCS / "api.rst").read_text()
    names = re.findall(r"^   ([A-Za-z_][A-Za-z0-9_]*)$", text, flags=re.M)
    modules = {"plot", "symbolic", "light", "design"}
    listed = [n for n in names if n not in modules]
    from flexmbd import design  # its own section, under flexmbd.design

    assert sorted(listed) == sorted([*(n for n in fm.__all__ if n != "__version__"),
                                     *design.__all__])
    assert len(listed) == len(set(listed))


def test_every_keyword_has_a_meaning():
    """The user guide's keyword tables are made from these (docs/_ext/flexmbd_tables.py)."""
    for table in (syntax.KINEMATICS, syntax.DYNAMICS):
        for keyword, spec in table.items():
            assert spec.meaning, keyword


def test_nothing_points_outside_the_repository():
    """The README and the docs link into the repository or to public pages, never to
    files next to it (a clone has nothing there)."""
    texts = {p: p.read_text() for p in [ROOT / "README.md", *PAGES, DOCS / "api.rst"]}
    for path, text in texts.items():
        assert "../shared" not in text, path
        for target in re.findall(r"\]\(([^)\s]+)\)", text):
            parts = urlsplit(target)
            if parts.scheme in ("http", "https", "mailto") or not parts.path:
                continue
            resolved = (path.parent / parts.path).resolve()
            assert resolved.is_relative_to(ROOT), f"{path.name}: {target}"
            if resolved.is_relative_to(DOCS / "gallery"):
                # Sphinx-Gallery writes docs/gallery/ at build time (docs/conf.py), from
                # examples/gallery/: a link there needs the gallery's source.
                resolved = ROOT / "examples" / "gallery" / "README.rst"
            assert resolved.exists(), f"{path.name}: {target} does not exist"


# --- the guide's code ------------------------------------------------------------------------
def _blocks(page: Path) -> list[str]:
    return re.findall(r"```python\n(.*?)```", page.read_text(), flags=re.S)


@pytest.mark.parametrize("page", [p for p in GUIDE_PAGES if _blocks(p)],
                         ids=lambda p: str(p.relative_to(DOCS)))
def test_guide_code_runs(page, tmp_path, monkeypatch):
    """The Python blocks of a page run in order, in one namespace, as a reader would paste
    them (a block's ``if __name__ == "__main__":`` part too)."""
    pytest.importorskip("sympy")
    monkeypatch.chdir(tmp_path)  # blocks write files
    namespace = {"__name__": "__main__"}
    for k, block in enumerate(_blocks(page), start=1):
        exec(compile(block, f"{page.relative_to(DOCS)} block {k}", "exec"), namespace)
