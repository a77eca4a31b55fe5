"""What the ``crslab`` command imports before it runs anything: every command builds the whole
parser, so a heavy import there delays them all (scipy alone is more than half a second; only
``crslab identify`` fits with it)."""

import subprocess
import sys

PROBE = """
import sys
from crslab.cli import build_parser
build_parser()
print(" ".join(sorted(m for m in ("scipy", "rerun", "matplotlib") if m in sys.modules)))
"""


def test_building_the_parser_imports_neither_scipy_nor_rerun_nor_matplotlib():
    r = subprocess.run([sys.executable, "-c", PROBE], capture_output=True, text=True, check=True)
    assert r.stdout.split() == []
