"""Sphinx configuration of the flexmbd documentation.

Build: ``pip install -e '.[docs]' && sphinx-build -W -b html docs docs/_build/html``.
The gallery runs every script of ``examples/gallery`` at build time; with
``FLEXMBD_DOCS_QUICK=1`` in the environment the scripts take fewer steps and
frames (the test suite builds the docs that way).
"""

from __future__ import annotations

import logging
import os
import re
import sys
from pathlib import Path

import matplotlib

import flexmbd

matplotlib.use("Agg")
logging.getLogger("matplotlib.animation").setLevel(logging.WARNING)  # "saving with ..." lines
sys.path.insert(0, str(Path(__file__).parent / "_ext"))

project = "flexmbd"
author = "the flexmbd developers"
copyright = "2026, the flexmbd developers"
release = flexmbd.__version__
version = release

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.napoleon",
    "sphinx.ext.mathjax",
    "sphinx-mathjax-offline",   # MathJax 3 copied into the site: math renders offline
    "element_figures",          # the theory page's figures of the element types
    "sphinx_gallery.gen_gallery",
    "flexmbd_tables",
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
exclude_patterns = ["_build", "gallery/*.ipynb", "gallery/*.py", "gallery/*.zip",
                    "gallery/*.md5", "gallery/*.codeobj.json", "**sg_execution_times.rst"]
root_doc = "index"

# MyST: $...$ maths, ::: fences, anchors for links to headings of other pages
myst_enable_extensions = ["dollarmath", "colon_fence", "deflist"]
myst_heading_anchors = 3

# API reference: one page per name of flexmbd.__all__, from the docstrings
autosummary_generate = True
templates_path = ["_templates"]   # classes: no __init__ entry; element types: no machinery
autodoc_default_options = {"members": True, "show-inheritance": True}
autodoc_member_order = "bysource"
autodoc_typehints = "signature"
napoleon_google_docstring = True
napoleon_numpy_docstring = False

sphinx_gallery_conf = {
    "examples_dirs": "../examples/gallery",
    "gallery_dirs": "gallery",
    "filename_pattern": r"plot_",
    "matplotlib_animations": (True, "jshtml"),
    "within_subsection_order": "FileNameSortKey",
    "download_all_examples": False,
    "remove_config_comments": True,
    "show_memory": False,
    # no page of execution times: it loads jQuery and DataTables from CDNs (offline site)
    "write_computation_times": False,
    "plot_gallery": "True",
    # every build runs every script, so a quick build's pictures never stand in for a full one
    "run_stale_examples": True,
    # matplotlib's defaults, then Pillow for the animations' thumbnails (no ffmpeg needed)
    "reset_modules": ("matplotlib", "gallery_setup.pillow_writer"),
}

html_theme = "furo"
html_title = f"flexmbd {release}"
html_static_path: list[str] = []
# quick builds say so on every page, so a reduced gallery is never mistaken for the real one
if os.environ.get("FLEXMBD_DOCS_QUICK") == "1":
    html_title += " (quick build: reduced gallery resolution)"


#: of an element type's members, those a user reads: its definition (the deformations) and
#: names; the rest (laws, kernels' inputs, drawing, file lines) is the engine's machinery
ELEMENT_MEMBERS_SHOWN = {"deformations", "keyword", "name", "deformation_names",
                         "stiffness_values", "damping_values"}


def _element_machinery(app, what, name, obj, skip, options):
    """Skip an element type's machinery (a member that every element type has, from
    their base class), so that its page shows what a user reads: the description and
    the deformation functions; and a class's ``__init__``, which its signature shows."""
    from flexmbd.elements.base import ElementType

    if what != "class":
        return None
    if name == "__init__":   # the class's own signature and docstring say it
        return True
    if name in ELEMENT_MEMBERS_SHOWN or not hasattr(ElementType, name):
        return None
    return True


def _theory_links(app, what, name, obj, options, lines):
    """"THEORY n" in a docstring is a link to section n of the theory page (its label
    ``theory-n``); the spatial theory's sections and the flexure notes link to the
    spatial section and the flexure guide, their pages in this site."""
    for k, line in enumerate(lines):
        line = re.sub(r"THEORY-SPATIAL(?: \d+)?",
                      lambda found: f":ref:`{found[0]} <theory-11>`", line)
        line = re.sub(r"THEORY (\d+)",
                      lambda found: f":ref:`THEORY {found[1]} <theory-{found[1]}>`", line)
        lines[k] = re.sub(r"FLEXURES \d+",
                          lambda found: f":doc:`{found[0]} </guide/flexures>`", line)


def setup(app):
    app.connect("autodoc-skip-member", _element_machinery)
    app.connect("autodoc-process-docstring", _theory_links)
