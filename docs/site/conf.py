# Sphinx configuration of the documentation site (scripts/docs.sh builds it; see that script).
import os
import re

root = os.environ["VEHS_SOURCE_DIR"]  # set by scripts/docs.sh (this file is copied into the build)
project = "vehs"
version = release = re.search(r"project\(vehs VERSION ([0-9.]+)",
                              open(os.path.join(root, "CMakeLists.txt"), encoding="utf-8").read()).group(1)
extensions = ["myst_parser", "sphinx.ext.autodoc", "sphinx.ext.napoleon"]
source_suffix = {".md": "markdown", ".rst": "restructuredtext"}
root_doc = "index"
myst_heading_anchors = 6  # every heading, as GitHub; tests/docs/check_docs.py checks links to them
myst_enable_extensions = ["dollarmath"]
# Links to source files (headers, configs, scripts) are not pages of the site; scripts/docs.sh
# checks that every relative link of the Markdown pages names an existing file
# (tests/docs/check_docs.py links) before Sphinx runs.
suppress_warnings = ["myst.xref_missing", "myst.header"]
html_theme = "alabaster"
html_extra_path = ["_doxygen"]  # the C++ API: _doxygen/cpp/index.html, made by scripts/docs.sh
autodoc_member_order = "bysource"
exclude_patterns = ["_build", "_doxygen"]
