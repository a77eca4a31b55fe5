"""Suite-wide settings.

In CI (``CI`` set) hypothesis draws the same examples every run, so a red build always
reproduces; locally it keeps exploring new ones.

A test that needs a system program (clang, gdb, GNU Octave, Xvfb) says so with
``@pytest.mark.requires("Xvfb")``: without the program it skips with a reason, so ``make test``
works for any user. ``.ci/run`` installs every such program and sets ``CRSLAB_REQUIRE_ALL=1``,
under which a missing program fails the test instead, so CI exercises every path.
"""

from __future__ import annotations

import compileall
import fcntl
import os
import pickle
import shutil
import signal
import sys
from pathlib import Path

import pytest
from hypothesis import settings

settings.register_profile("ci", derandomize=True, deadline=None, print_blob=True)
if os.environ.get("CI"):
    settings.load_profile("ci")

REQUIRE_ALL_ENV = "CRSLAB_REQUIRE_ALL"

# crslab's own modules compiled to bytecode once, before the first test: the suite starts `python -m
# crslab` some 300 times, and where PYTHONDONTWRITEBYTECODE is set (as on CI's machine) no start
# keeps what it compiled, so each would compile every module of crslab it imports again (about 0.35 s
# of CPU of a start's 0.8 s). A module edited since is compiled afresh (its source is newer).
compileall.compile_dir(Path(__file__).resolve().parents[1] / "crslab", quiet=1)
# ... and the test modules pytest rewrites kept too (each of make test's two workers collects them
# all: 10 s of CPU each without, 4.5 s with)
sys.dont_write_bytecode = False

# zig's C library for wasm32 takes about 20 s of CPU to build: tests that give crslab a build cache
# of their own (CRSLAB_CACHE_DIR) share the user's zig cache instead of building it again each
# (tests/test_zig_first_use.py builds one afresh on purpose)
if "ZIG_GLOBAL_CACHE_DIR" not in os.environ:
    from crslab.lab.zig import zig_cache

    os.environ["ZIG_GLOBAL_CACHE_DIR"] = str(zig_cache())


# zig's C library for the firmware is kept beside crslab, built once (make venv): subprocesses that
# run another installation (tests/test_packaging_wheel.py's fresh venv) use this one's too
# (tests/test_zig_first_use.py prepares one afresh on purpose)
if "CRSLAB_ZIG_LIBC_DIR" not in os.environ:
    from crslab.lab.zig import libc_homes

    os.environ["CRSLAB_ZIG_LIBC_DIR"] = str(libc_homes()[0])


# `make test` runs the suite in two pytest-xdist workers, a file at a time (--dist loadfile): a free
# worker takes the next file of the collection. The files that take longest go first (measured with
# --durations; the rest keep their order), so the two workers end together instead of one running a
# long file alone at the end; xdist's own order (by number of tests: the long files with few tests
# came last) is turned off. The docs test builds the wheel the packaging test shares
# (:func:`installed_wheel`): the packaging test comes once the other worker has had work of its own
# for that long, so it does not wait for the wheel idle.
SLOW_FIRST = (
    "test_docs_commands.py",
    "test_firmware_hostile.py",
    "test_hostile_compile.py",
    "test_packaging_wheel.py",
    "test_wasm_firmware.py",
    "test_c_core.py",
    "test_scenario_expect.py",
    "test_identify_cli.py",
    "test_sweep_dask.py",
    "test_zig_first_use.py",
    "test_regress_cli.py",
    "test_serve_browser.py",
    "test_serve_page_messages.py",
    "test_sandbox_hostile.py",
    "test_generations.py",
    "test_sim_untrusted.py",
    "test_identify_experiments.py",
    "test_debug_gdb.py",
    "test_contest_acceptance.py",
    "test_regress_pytest_plugin.py",
)


def pytest_configure(config: pytest.Config) -> None:
    if hasattr(config.option, "loadscopereorder"):  # pytest-xdist: keep the order below
        config.option.loadscopereorder = False
    # A shell without job control starts a command put in the background (`pytest ... &`) with
    # SIGINT ignored, and an ignored signal stays ignored across exec: every crslab the tests
    # start would then ignore the Ctrl-C they send it. A handler of this process's own is reset
    # to the default at exec, so the children get Ctrl-C as from a terminal.
    if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
        signal.signal(signal.SIGINT, signal.default_int_handler)


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    """The files of :data:`SLOW_FIRST` first, in its order; every other test after them, in the
    order collected (a stable sort)."""
    rank = {name: i for i, name in enumerate(SLOW_FIRST)}
    items.sort(key=lambda item: rank.get(item.path.name, len(rank)))


def missing_program(*names: str) -> str | None:
    """The first of ``names`` not on PATH, else None."""
    return next((n for n in names if shutil.which(n) is None), None)


@pytest.hookimpl(tryfirst=True)
def pytest_runtest_setup(item: pytest.Item) -> None:
    """Skip a test marked ``requires(...)`` when a program is missing; fail it under
    ``CRSLAB_REQUIRE_ALL=1``. Before any of its fixtures is set up: a module's browser or nginx,
    started once for all its tests, would otherwise fail on the missing program first."""
    marker = item.get_closest_marker("requires")
    if marker is None:
        return
    missing = missing_program(*marker.args)
    if missing is None:
        return
    if os.environ.get(REQUIRE_ALL_ENV) == "1":
        pytest.fail(f"{REQUIRE_ALL_ENV}=1 but {missing} is not installed")
    pytest.skip(f"needs {missing} (not installed)")


@pytest.fixture
def drawn_figures(monkeypatch: pytest.MonkeyPatch) -> list:
    """Every matplotlib figure saved during the test, in order, kept after it is closed: a test
    checks what a plot command drew (its axes, lines, points), not only that it wrote a file."""
    from matplotlib.figure import Figure

    saved: list = []
    savefig = Figure.savefig

    def keep(self: Figure, *args: object, **kwargs: object) -> object:
        saved.append(self)
        return savefig(self, *args, **kwargs)

    monkeypatch.setattr(Figure, "savefig", keep)
    return saved


@pytest.fixture(scope="session")
def installed_wheel(tmp_path_factory: pytest.TempPathFactory):  # noqa: ANN201 - tests/wheel_install.Installed
    """crslab's wheel built from a clean copy of the checkout and installed as docs/first-lab.md
    says (tests/wheel_install.py): the packaging test and the docs test share it. Under
    pytest-xdist (``make test``: ``-n 2 --dist loadfile``) the first worker to need it builds it
    in the run's shared temporary folder and the others wait for it and use it."""
    from wheel_install import install_wheel

    if not os.environ.get("PYTEST_XDIST_WORKER"):
        return install_wheel(tmp_path_factory.mktemp("packaging"))
    shared = tmp_path_factory.getbasetemp().parent  # the same for every worker of this run
    with (shared / "installed-wheel.lock").open("w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        done = shared / "installed-wheel.pickle"
        if done.exists():
            return pickle.loads(done.read_bytes())
        base = shared / "installed-wheel"
        base.mkdir()
        installed = install_wheel(base)
        done.write_bytes(pickle.dumps(installed))
        return installed


@pytest.fixture(scope="session", autouse=True)
def webassembly_compiler_ready() -> None:
    """zig's C library for WebAssembly, built before the first test (in a fresh CRSLAB_CACHE_DIR
    its first build takes 40-150 s on a loaded 2-core machine): a module's fixture that runs
    ``crslab record`` under a 120 s guard would otherwise spend its guard on it and end the run
    with an error that is no bug. Under pytest-xdist the workers share one cache and zig's own
    lock: the first builds it, the others wait. Without zig nothing is built: the tests that need
    it say so themselves."""
    from crslab.lab.firmware import prepare_zig
    from crslab.lab.zig import ZigMissing

    try:
        prepare_zig()
    except (ZigMissing, RuntimeError):
        pass
