"""Shared fixtures: the `rtt` program installed beside the module (RTT_CLI, else PATH)."""
import os
import shutil

import pytest


@pytest.fixture(scope="session")
def rtt_cli():
    path = os.environ.get("RTT_CLI") or shutil.which("rtt")
    if not path:
        pytest.skip("the rtt program is not on PATH (set RTT_CLI)")
    return path
