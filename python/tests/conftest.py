"""Shared fixtures: the repository, the command-line tools (for Python-vs-CLI checks) and a
scratch folder. VEHS_BIN_DIR names the folder of the executables (scripts/test.sh: the build
folder); without it, tests that compare with the CLI are skipped unless VEHS_REQUIRE_CLI=1."""
import json
import os
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]


def _bin_dir():
    return Path(os.environ.get("VEHS_BIN_DIR", REPO / "build"))


@pytest.fixture(scope="session")
def repo():
    return REPO


@pytest.fixture(scope="session")
def cli():
    """run(tool, config_dict, workdir) -> CompletedProcess; the config is written to workdir."""
    bins = _bin_dir()
    if not (bins / "identify-vehs").exists():
        if os.environ.get("VEHS_REQUIRE_CLI") == "1":
            pytest.fail(f"VEHS_REQUIRE_CLI=1 but no executables in {bins}")
        pytest.skip(f"no vehs executables in {bins} (set VEHS_BIN_DIR)")

    def run(tool, config, workdir, check=True):
        path = Path(workdir) / f"{tool}.json"
        path.write_text(json.dumps(config))
        proc = subprocess.run([str(bins / tool), str(path), "-q"], cwd=REPO, capture_output=True, text=True)
        if check and proc.returncode != 0:
            raise AssertionError(f"{tool} failed: {proc.stderr}")
        return proc

    return run
