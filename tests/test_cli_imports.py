"""What the ``crslab`` command imports before it runs anything: ``crslab --help`` builds the whole
parser, so a heavy import there delays it (scipy alone is more than half a second; only ``crslab
identify`` fits with it); ``crslab COMMAND`` imports only COMMAND's module."""

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


def test_each_command_module_registers_the_commands_the_map_names():
    import importlib

    from crslab.cli import COMMANDS, GROUPS, OneLineParser
    for module, names in COMMANDS.items():
        sub = OneLineParser(prog="probe").add_subparsers(parser_class=OneLineParser)
        importlib.import_module(module).register(sub)
        assert tuple(sub.choices) == names, module
    listed = sorted(n for names in GROUPS.values() for n in names if n != "help")
    assert sorted(n for names in COMMANDS.values() for n in names) == listed


ONE_COMMAND = """
import sys
from crslab.cli import main
try:
    main(["contest", "--help"])
except SystemExit:
    pass
PROBED = ("crslab.identify.fit", "crslab.cli.serve_commands", "crslab.cli.sim_commands",
          "crslab.cli.contest_commands")
print("@@", " ".join(sorted(m for m in PROBED if m in sys.modules)))
"""


def test_a_command_imports_only_its_own_module():
    r = subprocess.run([sys.executable, "-c", ONE_COMMAND], capture_output=True, text=True, check=True)
    assert r.stdout.split("@@")[-1].split() == ["crslab.cli.contest_commands"], r.stdout[-300:]


ONE_RUN = """
import sys
from crslab.cli import main
try:
    main(["sim", "--fast", "--no-startup-delay", "--duration", "0.002", "--quiet"])
except SystemExit:
    pass
SLOW = ("pycparser", "cffi.cparser", "importlib.metadata")
print("@@", " ".join(sorted(m for m in SLOW if m in sys.modules)))
"""


def test_a_webassembly_run_parses_no_c_header_in_the_crslab_process():
    """The crslab process reads the shared block and the board's constants through crslab._core's
    compiled declarations and libseccomp's version through ctypes: cffi's C parser (pycparser, about
    a tenth of a second of a command's start) is never loaded; nor is importlib.metadata (zig's
    version, in a cached build's key, is read from its package's folder name)."""
    r = subprocess.run([sys.executable, "-c", ONE_RUN], capture_output=True, text=True, check=True)
    assert r.stdout.split("@@")[-1].split() == [], r.stdout[-300:]
