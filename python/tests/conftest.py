import os
import pathlib
import subprocess
import sys

import pytest

SOURCE_DIR = pathlib.Path(os.environ.get("FABKIT_SOURCE_DIR", pathlib.Path(__file__).parents[2]))
FABKIT = os.environ.get("FABKIT", str(SOURCE_DIR / "build" / "bin" / "fabkit"))
PROGRAMS = pathlib.Path(__file__).parent / "paper_programs"


@pytest.fixture
def fabkit_cli():
    def run(*args, check=True):
        p = subprocess.run([FABKIT, *map(str, args)], capture_output=True, text=True, timeout=300)
        if check and p.returncode != 0:
            raise AssertionError(f"fabkit {' '.join(map(str, args))}: exit {p.returncode}\n{p.stdout}\n{p.stderr}")
        return p

    return run
