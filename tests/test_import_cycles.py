"""No import cycles in crslab/ or csrc/ (tools/import_cycles.py), and the check finds each kind of
cycle it looks for in a small tree made to have one."""

import subprocess
import sys
import textwrap
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
TOOL = ROOT / "tools" / "import_cycles.py"


def run(root: Path) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, str(TOOL), "--root", str(root)], capture_output=True, text=True,
                          timeout=120)


def tree(root: Path, files: dict[str, str]) -> Path:
    for name, text in files.items():
        path = root / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(textwrap.dedent(text))
    return root


def test_crslab_and_csrc_have_no_import_cycles():
    r = run(ROOT)
    assert r.returncode == 0, r.stdout + r.stderr
    assert r.stdout == "no import cycles\n"


def test_a_deferred_or_type_only_import_still_closes_a_module_cycle(tmp_path):
    tree(tmp_path, {
        "crslab/__init__.py": "",
        "crslab/scenario/__init__.py": "",
        "crslab/scenario/event.py": "def kinds():\n    import crslab.scenario.kinds\n",
        "crslab/scenario/kinds.py": "from crslab.scenario.event import kinds\n",
        "crslab/run/__init__.py": "",
        "crslab/run/effects.py": ("from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n"
                                  "    from crslab.run.worker import BoardInstances\n"),
        "crslab/run/worker.py": "from . import effects\n",
    })
    r = run(tmp_path)
    assert r.returncode == 1
    lines = r.stdout.splitlines()
    assert ("python module cycle: crslab.scenario.event -> crslab.scenario.kinds -> crslab.scenario.event"
            in lines)
    assert "    crslab/scenario/event.py:2: imports crslab.scenario.kinds" in lines
    assert "python module cycle: crslab.run.effects -> crslab.run.worker -> crslab.run.effects" in lines
    assert "    crslab/run/worker.py:1: imports crslab.run.effects" in lines
    assert not any("package cycle" in line for line in lines)


def test_packages_that_import_each_other_are_a_cycle_though_no_module_is(tmp_path):
    tree(tmp_path, {
        "crslab/__init__.py": "",
        "crslab/run/__init__.py": "",
        "crslab/run/status.py": "from crslab.regress.transcript import split\n",
        "crslab/regress/__init__.py": "",
        "crslab/regress/transcript.py": "split = str.split\n",
        "crslab/regress/grade.py": "from crslab.run import status\n",
        "crslab/cache.py": "import crslab.run.status\n",  # one way only: no cycle
    })
    r = run(tmp_path)
    assert r.returncode == 1
    assert r.stdout.splitlines() == [
        "python package cycle: crslab.regress -> crslab.run -> crslab.regress",
        "    crslab/regress/grade.py:1: imports crslab.run.status",
        "    crslab/run/status.py:1: imports crslab.regress.transcript",
    ]


def test_c_files_that_call_or_include_each_other_are_a_cycle(tmp_path):
    tree(tmp_path, {
        "csrc/board/ports.h": "void ports_tick(void);\nvoid ports_reply(int n);\n",
        "csrc/board/ports.c": """\
            #include "ports.h"
            #include "link.h"
            void ports_reply(int n) { (void)n; }
            void ports_tick(void)
            {
                link_receive(1); /* a call */
            }
            """,
        "csrc/board/link.h": "void link_receive(int byte);\n",
        "csrc/board/link.c": """\
            #include "link.h"
            static void ports_tick(void) {}  /* its own, not ports.c's */
            void link_receive(int byte)
            {
                const char *s = "ports_reply(";  /* a string is not a call */
                (void)s; ports_tick();
                if (byte) ports_reply(byte);
            }
            """,
        "csrc/board/leaf.c": '#include "ports.h"\nvoid leaf(void) { ports_tick(); }\n',
        "csrc/labs/lab.c": '#include "ports.h"\nvoid lab(void) { ports_tick(); }\nvoid ports_tick(void) {}\n',
    })
    r = run(tmp_path)
    assert r.returncode == 1
    assert r.stdout.splitlines() == [
        "C cycle: csrc/board/link.c -> csrc/board/ports.c -> csrc/board/link.c",
        "    csrc/board/link.c:7: uses ports_reply() of csrc/board/ports.c",
        "    csrc/board/ports.c:6: uses link_receive() of csrc/board/link.c",
    ]


def test_a_tree_without_cycles_passes_and_a_wrong_root_is_one_line(tmp_path):
    tree(tmp_path, {"crslab/__init__.py": "", "crslab/a.py": "import crslab.b\n", "crslab/b.py": "",
                    "csrc/x.c": '#include "y.h"\nint x(void) { return y(); }\n',
                    "csrc/y.h": "int y(void);\n"})
    r = run(tmp_path)
    assert (r.returncode, r.stdout) == (0, "no import cycles\n")
    r = run(tmp_path / "nowhere")
    assert r.returncode == 2 and r.stderr.count("\n") == 1 and "has neither crslab/ nor csrc/" in r.stderr
