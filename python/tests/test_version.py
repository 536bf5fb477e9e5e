"""The version is written once (project(VERSION) in CMakeLists.txt): vehs.__version__, the installed
package's metadata and every tool's --version print the same one."""
import importlib.metadata
import os
import re
import subprocess

import pytest

import vehs

TOOLS = ("simulate-vehs", "identify-vehs", "fpk-stationary", "diagnose-vehs", "vehs-compare")


def cmake_version(repo):
    text = (repo / "CMakeLists.txt").read_text(encoding="utf-8")
    return re.search(r"project\(vehs VERSION ([0-9]+\.[0-9]+\.[0-9]+)", text).group(1)


def test_python_version_is_the_cmake_project_version(repo):
    assert vehs.__version__ == cmake_version(repo)
    assert importlib.metadata.version("vehs") == vehs.__version__


@pytest.mark.parametrize("tool", TOOLS)
def test_tool_version_is_the_python_version(cli, repo, tool):  # cli: skips without executables
    bins = os.environ.get("VEHS_BIN_DIR", str(repo / "build"))
    out = subprocess.run([os.path.join(bins, tool), "--version"], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == f"{tool} (vehs {vehs.__version__})"


def test_changelog_has_the_version(repo):
    text = (repo / "CHANGELOG.md").read_text(encoding="utf-8")
    assert f"## [{vehs.__version__}]" in text, "CHANGELOG.md has no section for the current version"
