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
# Links to files that are not pages of the site (headers, configs, scripts, results) give "target
# not found" warnings that are dropped (setup below; scripts/docs.sh checks first that every
# relative link names an existing file: tests/docs/check_docs.py links). A link to a heading
# (#anchor) that does not resolve stays a warning, an error under -W.
suppress_warnings = ["myst.header"]
html_theme = "alabaster"
html_extra_path = ["_doxygen"]  # the C++ API: _doxygen/cpp/index.html, made by scripts/docs.sh
autodoc_member_order = "bysource"
exclude_patterns = ["_build", "_doxygen"]


def _is_source_file_link(record):
    """A MyST "cross-reference target not found" warning for a link without an #anchor."""
    if getattr(record, "subtype", "") != "xref_missing":
        return False
    m = re.search(r"target not found: '([^']*)'", record.getMessage())
    target = m.group(1) if m else ""
    return bool(target) and "#" not in target


def setup(app):
    import logging

    from sphinx.util.logging import WarningStreamHandler

    class SourceFileLinks(logging.Filter):
        def filter(self, record):
            return not _is_source_file_link(record)

    for handler in logging.getLogger("sphinx").handlers:
        if isinstance(handler, WarningStreamHandler):
            handler.filters.insert(0, SourceFileLinks())  # before the warning count of -W
