"""Sphinx configuration of the vvea-design documentation.

Build: ``python -m sphinx -W -b html docs docs/_build/html`` from the repository root
(``tests/docs/test_docs_build.py`` runs exactly this with warnings as errors). The build
needs no network: no intersphinx, no remote images.

Generated at build time (``docs/_ext/vvea_docs.py``, all ignored by git):

* ``reference/_face.rst``: the autosummary table of ``vvea_design.__all__`` (the face);
* ``reference/_schemas/*.md``: tables of the shipped JSON Schemas;
* ``reference/generated/``: autosummary stubs;
* ``auto_examples/``: the sphinx-gallery pages of ``examples/*.py``. The examples run at their
  small size (``VVEA_EXAMPLES_SMALL=1``); ``-D plot_gallery=0`` builds the pages without running
  them (the docs-build test does that: the examples are run by ``tests/docs/test_examples.py``).
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(HERE / "_ext"))
sys.path.insert(0, str(ROOT))  # document the vvea_design of this checkout
os.environ.setdefault("VVEA_EXAMPLES_SMALL", "1")  # the gallery runs the examples at their small size
os.environ.setdefault("MPLBACKEND", "Agg")

import vvea_design  # noqa: E402

project = "vvea-design"
author = "vvea-design contributors"
copyright = "vvea-design contributors"  # noqa: A001
release = version = vvea_design.__version__

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "numpydoc",
    "sphinx_gallery.gen_gallery",
    "vvea_docs",
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
root_doc = "index"
exclude_patterns = ["_build", "**/README.md", "auto_examples/*.ipynb", "auto_examples/*.py",
                    "auto_examples/*.zip", "auto_examples/*.json", "auto_examples/*.md5",
                    "sg_execution_times.rst"]
templates_path = ["_templates"]
suppress_warnings = ["myst.header"]  # the explanation pages keep their own heading depth

# -- MyST: the Markdown pages stay Markdown -------------------------------------------------------
myst_enable_extensions = ["colon_fence", "dollarmath", "deflist"]
myst_heading_anchors = 3

# -- API reference: autosummary + numpydoc over the docstrings --------------------------------------
autosummary_generate = True
autosummary_imported_members = False
autodoc_typehints = "none"  # numpydoc's Parameters sections carry types and units
autodoc_mock_imports: list[str] = []
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False
numpydoc_validation_checks: set[str] = set()  # tests/package/test_hygiene.py checks the docstrings

# -- sphinx-gallery: examples/*.py are the gallery (and run as tests) ------------------------------
sphinx_gallery_conf = {
    "examples_dirs": str(ROOT / "examples"),
    "gallery_dirs": "auto_examples",
    "filename_pattern": r"/(plot_|example_)",  # every example runs when the gallery is executed
    "ignore_pattern": r"(__init__|conftest)\.py",
    "download_all_examples": False,
    "remove_config_comments": True,
    "within_subsection_order": "FileNameSortKey",
    "write_computation_times": False,
    "show_memory": False,
    "show_signature": False,
    "first_notebook_cell": None,
}

# -- HTML --------------------------------------------------------------------------------------------
html_theme = "pydata_sphinx_theme"
html_title = f"vvea-design {release}"
html_theme_options = {
    "navigation_with_keys": False,
    "show_toc_level": 2,
    "secondary_sidebar_items": ["page-toc"],
    "footer_start": ["copyright"],
    "footer_end": [],
}
html_static_path: list[str] = []
html_last_updated_fmt = None
html_show_sourcelink = False
