# Sphinx configuration of hsbd's documentation site: `make docs` builds it into
# build/docs/html; tests/docs/test_docs.sh (ctest test_docs) builds it with -W -n so that a
# warning, a broken internal link or anchor, or a missing image or file fails make check.
# The pages are the Markdown files of docs/ (MyST); python-api.md documents the module
# `hsbd` from its docstrings (autodoc).
import importlib
import os
import sys

project = "hsbd"
author = "the hsbd authors"
copyright = "the hsbd authors"

# Where `import hsbd` comes from, in this one place: HSBD_PYTHONPATH when set (an absolute
# path: `make docs` and the docs test pass their build's module directory), else the
# module the CMake build makes in build/python.
DOCS = os.path.dirname(os.path.abspath(__file__))
HSBD_PYTHONPATH = os.path.abspath(
    os.environ.get("HSBD_PYTHONPATH", os.path.join(DOCS, "..", "build", "python")))
sys.path.insert(0, HSBD_PYTHONPATH)
try:
    importlib.import_module("hsbd")
    HSBD_IMPORT_ERROR = None
except Exception as e:  # the site still builds; the API page says why it is empty
    HSBD_IMPORT_ERROR = f"{type(e).__name__}: {e}"
    if os.environ.get("HSBD_DOCS_REQUIRE_MODULE") == "1":
        raise RuntimeError(f"import hsbd from {HSBD_PYTHONPATH} failed: {HSBD_IMPORT_ERROR}")
    print(f"docs: import hsbd from {HSBD_PYTHONPATH} failed ({HSBD_IMPORT_ERROR}); "
          "the Python API page says so (make build first)", file=sys.stderr)

extensions = ["myst_parser", "sphinx.ext.autodoc"]
myst_heading_anchors = 4  # [text](page.md#a-heading) links, checked like page links
source_suffix = {".md": "markdown"}
root_doc = "index"
exclude_patterns = ["_build"]
autodoc_default_options = {"members": True, "undoc-members": True}
# The docstrings are written for help(): plain text, shown here as they are (a literal
# block each), so that no character in them is taken for markup. Signatures come from
# the objects (inspect), not from the docstrings' first lines.
autodoc_docstring_signature = False

html_theme = "alabaster"
html_title = "hsbd"
html_theme_options = {"description": "Brownian dynamics of hard bodies, the hard core exact",
                      "fixed_sidebar": True, "page_width": "1100px", "sidebar_width": "250px"}
html_sidebars = {"**": ["about.html", "navigation.html", "searchbox.html"]}

API_BEGIN, API_END = "<!-- api:begin", "<!-- api:end -->"


def api_without_module(app, docname, source):
    """Without an importable module the API page says so instead of an empty listing."""
    if docname != "python-api" or HSBD_IMPORT_ERROR is None:
        return
    text = source[0]
    head, rest = text.split(API_BEGIN, 1)
    tail = rest.split(API_END, 1)[1]
    note = (f"```{{warning}}\nThis build of the site could not import the module `hsbd` "
            f"from `{HSBD_PYTHONPATH}` ({HSBD_IMPORT_ERROR}), so the reference below is "
            f"missing. Build the module (`make build`) and run `make docs` again.\n```\n")
    source[0] = head + note + tail


def docstring_as_text(app, what, name, obj, options, lines):
    if any(line.strip() for line in lines):
        lines[:] = ["::", ""] + ["    " + line for line in lines] + [""]


def setup(app):
    app.connect("source-read", api_without_module)
    app.connect("autodoc-process-docstring", docstring_as_text)
