"""Sphinx configuration of carom's documentation.

Build it from the repository's root (docs/building.md):

    .venv/bin/sphinx-build -W --keep-going docs build/docs

The pages are Markdown (MyST). The C++ reference comes from the public
headers, include/carom/, through Doxygen (run here, into the build's cache
folder) and Breathe; the Python reference from the installed package's
docstrings (sphinx.ext.autodoc: `pip install .` first).
"""
import pathlib
import shutil
import subprocess

from sphinx.errors import ConfigError

DOCS = pathlib.Path(__file__).resolve().parent
REPOSITORY = DOCS.parent

project = "carom"
author = "the carom authors"
copyright = "the carom authors"
try:
    import re
    version = release = re.search(r"project\(carom VERSION ([0-9.]+)",
                                  (REPOSITORY / "CMakeLists.txt").read_text()).group(1)
except (OSError, AttributeError):
    version = release = ""

extensions = ["myst_parser", "breathe", "sphinx.ext.autodoc"]
source_suffix = {".md": "markdown"}
root_doc = "index"
exclude_patterns = ["_build", "requirements.txt"]
myst_heading_anchors = 3
myst_enable_extensions = ["dollarmath"]

html_theme = "furo"
html_title = "carom"
html_static_path = []

# The C++ reference: Doxygen's XML of include/carom/, made at every build.
breathe_projects = {}
breathe_default_project = "carom"
breathe_domain_by_extension = {"h": "cpp"}
breathe_default_members = ("members",)
# The reference lists each header on its own; every header opens namespace
# carom, which the C++ domain would otherwise report as declared twice.
suppress_warnings = ["duplicate_declaration.cpp"]

DOXYFILE = """
PROJECT_NAME           = carom
INPUT                  = {input}
FILE_PATTERNS          = *.h
RECURSIVE              = NO
OUTPUT_DIRECTORY       = {output}
GENERATE_XML           = YES
GENERATE_HTML          = NO
GENERATE_LATEX         = NO
XML_PROGRAMLISTING     = NO
EXTRACT_ALL            = YES
EXTRACT_PRIVATE        = NO
EXTRACT_STATIC         = YES
JAVADOC_AUTOBRIEF      = YES
QUIET                  = YES
WARNINGS               = NO
WARN_IF_UNDOCUMENTED   = NO
WARN_LOGFILE           = {output}/warnings.log
ENABLE_PREPROCESSING   = YES
MACRO_EXPANSION        = YES
STRIP_FROM_INC_PATH    = {include}
"""


def run_doxygen(app):
    """Doxygen reads include/carom/ and writes its XML into the build's cache folder."""
    doxygen = shutil.which("doxygen")
    if doxygen is None:
        raise ConfigError("doxygen is not installed: the C++ reference needs it "
                          "(./install-deps.sh --docs, or apt-get install doxygen)")
    output = pathlib.Path(app.doctreedir) / "doxygen"
    output.mkdir(parents=True, exist_ok=True)
    config = DOXYFILE.format(input=REPOSITORY / "include" / "carom", output=output,
                             include=REPOSITORY / "include")
    subprocess.run([doxygen, "-"], input=config, text=True, check=True, cwd=REPOSITORY)
    app.config.breathe_projects = {"carom": str(output / "xml")}


def literal_docstrings(app, what, name, obj, options, lines):
    """The package's docstrings are plain text, not reStructuredText: shown as
    written (a literal block), so that their layout is kept and no line of
    them is read as markup."""
    if not any(line.strip() for line in lines):
        return
    text = list(lines)
    lines[:] = ["::", ""] + ["    " + line for line in text] + [""]


def setup(app):
    app.connect("builder-inited", run_doxygen)
    app.connect("autodoc-process-docstring", literal_docstrings)
