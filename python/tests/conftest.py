"""Shared fixtures: the CLI binary (for the comparisons) and small run lengths."""

import os
import shutil
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]


def find_cli():
    """The geardyn binary built from this repository: $GEARDYN_CLI, else release/geardyn of
    $CARGO_TARGET_DIR, else target/release/geardyn of the repository."""
    candidates = []
    if os.environ.get("GEARDYN_CLI"):
        candidates.append(Path(os.environ["GEARDYN_CLI"]))
    if os.environ.get("CARGO_TARGET_DIR"):
        candidates.append(Path(os.environ["CARGO_TARGET_DIR"]) / "release" / "geardyn")
    candidates.append(REPO / "target" / "release" / "geardyn")
    for c in candidates:
        if c.is_file() and os.access(c, os.X_OK):
            return c
    return None


@pytest.fixture(scope="session")
def cli():
    """Runs the CLI: ``cli("simulate", "--preset", "classic", ...)`` -> CompletedProcess.
    Skips the test when the binary has not been built."""
    exe = find_cli()
    if exe is None:
        pytest.skip("target/release/geardyn not built (cargo build --release -p geardyn-cli)")

    def run(*args, check=True):
        p = subprocess.run(
            [str(exe), *map(str, args)],
            capture_output=True,
            text=True,
            stdin=subprocess.DEVNULL,
        )
        if check and p.returncode != 0:
            raise AssertionError(f"geardyn {' '.join(map(str, args))} failed:\n{p.stderr}")
        return p

    return run


@pytest.fixture()
def out(tmp_path):
    """A fresh output folder for one CLI command."""
    d = tmp_path / "out"
    yield d
    shutil.rmtree(d, ignore_errors=True)
