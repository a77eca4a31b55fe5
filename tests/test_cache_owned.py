"""Issue 38's cache attacks, each made and each refused with its line, and each check at its edges
(a folder or file writable by its group only, not just by all):

- a ``compiled/`` folder that is a link (into another user's folder): the board wrote the ``.cwasm``
  there and crslab sealed what lay at that path afterwards, the other user's module included;
- the ``$TMPDIR`` fallback another user made first: a fresh private folder on every call, every
  build then "does not compile" (15 folders per command);
- zig's prepared C library (``CRSLAB_ZIG_LIBC_DIR``) neither owner-checked nor sealed: another
  user's ``sinf`` linked into a lab printed ``sin(0.5) = 42.0000``;
- and what is loaded is checked when it is loaded: a firmware or a native lab changed after its
  build is refused by the worker.

"Another user" is uid 54321: a folder or file given to it needs root (CI runs as root); as
another user the tests that need one skip, saying so.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from crslab import cache
from crslab.lab import zig
from crslab.lab.build import build_lab
from crslab.lab.firmware import LINK_FLAGS, TARGET
from crslab.run.assemble import make_config
from crslab.run.board_run import BoardRun, RunError
from crslab.worker.wasm_runtime import KeptModule, compiled_module_path

ROOT = Path(__file__).resolve().parents[1]
LAB = ROOT / "csrc" / "labs" / "lab1_kinematics.c"
OTHER = 54321
"""The other user's uid."""
needs_root = pytest.mark.skipif(os.geteuid() != 0,
                                reason="giving a folder or file to another user needs root")


@pytest.fixture(scope="module")
def module_cache(tmp_path_factory):
    """One build cache for the module (the firmware's own objects are built into it once)."""
    return tmp_path_factory.mktemp("cache")


def sim(cache_folder: Path, *args: str, env: dict[str, str] | None = None,
        lab: Path = LAB) -> subprocess.CompletedProcess:
    env = {**os.environ, "CRSLAB_CACHE_DIR": str(cache_folder), **(env or {})}
    return subprocess.run([sys.executable, "-m", "crslab", "sim", "--fast", "--quiet", "--lab", str(lab),
                           "--duration", "0.5", "--no-c28x-check", *args], capture_output=True, text=True,
                          timeout=300, env=env)


def last_line(r: subprocess.CompletedProcess) -> str:
    assert "Traceback" not in r.stderr, r.stderr
    return r.stderr.strip().splitlines()[-1]


def attackers_folder(where: Path) -> Path:
    folder = where / "attacker"
    folder.mkdir(mode=0o777)
    folder.chmod(0o777)
    if os.geteuid() == 0:
        os.chown(folder, OTHER, OTHER)
    return folder


def assert_refused_as_a_link(module_cache: Path, link: Path) -> None:
    """``crslab sim`` with ``link`` in the cache exits 2 with the one line that names it."""
    r = sim(module_cache)
    assert r.returncode == 2
    assert last_line(r) == (f"crslab sim: {link} cannot be used in crslab's cache: it is a symbolic "
                            "link (remove it)")


# -- compiled/ -----------------------------------------------------------------------------------

def test_a_compiled_folder_that_is_a_link_is_refused_with_its_line(module_cache, tmp_path):
    assert sim(module_cache).returncode == 0
    compiled = module_cache / "compiled"
    shutil.rmtree(compiled)
    theirs = attackers_folder(tmp_path)
    compiled.symlink_to(theirs)
    try:
        assert_refused_as_a_link(module_cache, compiled)
        assert list(theirs.iterdir()) == []  # nothing written into it, nothing of it sealed
    finally:
        compiled.unlink()


def test_the_worker_keeps_no_module_in_a_compiled_folder_that_is_a_link(monkeypatch, tmp_path):
    """At the moment of use too: the worker asks for the folder when it loads a firmware."""
    monkeypatch.setenv("CRSLAB_CACHE_DIR", str(tmp_path / "cache"))
    (tmp_path / "cache").mkdir()
    assert compiled_module_path(b"\0asm", 1 << 20, 1 << 19).parent == tmp_path / "cache" / "compiled"
    (tmp_path / "cache" / "compiled").rmdir()
    (tmp_path / "cache" / "compiled").symlink_to(attackers_folder(tmp_path))
    assert compiled_module_path(b"\0asm", 1 << 20, 1 << 19) is None


def test_what_is_sealed_is_what_the_board_wrote_whatever_lies_at_the_path(tmp_path):
    """The board writes a new compilation to a private file crslab made; what another process
    puts at the kept path meanwhile (a link to its own module, a file) is renamed over, never read,
    never sealed."""
    folder = tmp_path / "compiled"
    folder.mkdir(mode=0o700)
    kept = KeptModule(folder / "m.cwasm")
    assert kept.bytes is None and kept.fd >= 0
    assert os.stat(kept.fd).st_mode & 0o777 == 0o600
    os.write(kept.fd, b"the board's machine code")
    theirs = tmp_path / "theirs.cwasm"
    theirs.write_bytes(b"another user's machine code")
    (folder / "m.cwasm").symlink_to(theirs)  # planted between the write and the seal
    assert kept.keep()
    assert not (folder / "m.cwasm").is_symlink()
    assert cache.read_sealed(folder / "m.cwasm") == b"the board's machine code"
    assert theirs.read_bytes() == b"another user's machine code"
    assert sorted(p.name for p in folder.iterdir()) == ["m.cwasm", "m.cwasm.seal"]  # no part left
    (folder / "m.cwasm").write_bytes(b"changed after")
    again = KeptModule(folder / "m.cwasm")
    assert again.bytes is None and not (folder / "m.cwasm").exists()  # never loaded: removed


# -- the fallback ----------------------------------------------------------------------------------

def fallback_env(tmp_path: Path) -> dict[str, str]:
    return {"XDG_CACHE_HOME": "/dev/null/no-home", "TMPDIR": str(tmp_path), "HOME": "/dev/null/no-home"}


def run_without_cache_env(tmp_path: Path) -> subprocess.CompletedProcess:
    env = {k: v for k, v in os.environ.items() if k != "CRSLAB_CACHE_DIR"}
    env.update(fallback_env(tmp_path))
    return subprocess.run([sys.executable, "-m", "crslab", "sim", "--fast", "--quiet", "--duration", "0.5",
                           "--no-c28x-check"], capture_output=True, text=True, timeout=300, env=env)


@needs_root
def test_a_fallback_another_user_made_first_is_one_line_and_no_folder(tmp_path):
    theirs = tmp_path / f"crslab-cache-{os.getuid()}"
    theirs.mkdir()
    theirs.chmod(0o777)
    os.chown(theirs, OTHER, OTHER)
    for _ in range(2):
        r = run_without_cache_env(tmp_path)
        assert r.returncode == 2
        assert last_line(r) == (
            "crslab sim: crslab has no cache it can use: /dev/null/no-home/crslab: it cannot be made (Not a "
            f"directory); {theirs}: it belongs to another user (uid {OTHER}) (set CRSLAB_CACHE_DIR to a "
            "folder of yours)")
        assert "does not compile" not in r.stderr
        assert [p.name for p in tmp_path.iterdir()] == [theirs.name]  # no fresh folders left behind
        assert list(theirs.iterdir()) == []


def test_the_fallback_is_one_folder_a_build_can_use(tmp_path):
    for _ in range(2):
        r = run_without_cache_env(tmp_path)
        assert r.returncode == 0, r.stderr
    assert [p.name for p in tmp_path.iterdir() if p.name.startswith("crslab-cache")] == [
        f"crslab-cache-{os.getuid()}"]


# -- folders and files at their edges ------------------------------------------------------------

@pytest.mark.parametrize("mode", [0o770, 0o707, 0o720, 0o702, 0o777])
def test_a_folder_of_the_cache_open_to_its_group_or_others_is_made_private(tmp_path, mode):
    home = tmp_path / "cache"
    home.mkdir()
    (home / "compiled").mkdir()
    for folder in (home, home / "compiled"):
        folder.chmod(mode)
    os.environ["CRSLAB_CACHE_DIR"] = str(home)
    try:
        assert cache.cache_dir() == home
    finally:
        del os.environ["CRSLAB_CACHE_DIR"]
    assert cache.subfolder(home, "compiled") == home / "compiled"
    assert [oct(f.stat().st_mode & 0o777) for f in (home, home / "compiled")] == ["0o700", "0o700"]
    (home / "readable").mkdir(mode=0o755)
    cache.subfolder(home, "readable")  # read by others: not written by them, left as it is
    assert (home / "readable").stat().st_mode & 0o777 == 0o755


@needs_root
def test_a_folder_of_the_cache_another_user_owns_is_refused_with_its_line(tmp_path):
    home = tmp_path / "cache"
    home.mkdir(mode=0o700)
    (home / "compiled").mkdir(mode=0o700)
    os.chown(home / "compiled", OTHER, OTHER)
    with pytest.raises(cache.CacheError) as caught:
        cache.subfolder(home, "compiled")
    assert str(caught.value) == (f"{home}/compiled cannot be used in crslab's cache: it belongs to another "
                                 f"user (uid {OTHER}) (remove it)")


@pytest.mark.parametrize("mode, sealed", [(0o600, True), (0o644, True), (0o640, True), (0o620, False),
                                          (0o660, False), (0o602, False), (0o666, False)])
def test_a_sealed_file_its_group_or_others_may_write_is_not_loaded(tmp_path, mode, sealed):
    path = tmp_path / "lab.wasm"
    cache.write_sealed(path, b"module", tmp_path)
    assert oct(path.stat().st_mode & 0o777) == "0o600"
    path.chmod(mode)
    assert (cache.read_sealed(path, tmp_path) == b"module") is sealed


@needs_root
def test_a_sealed_file_of_another_user_is_not_loaded(tmp_path):
    path = tmp_path / "lab.wasm"
    cache.write_sealed(path, b"module", tmp_path)
    os.chown(path, OTHER, OTHER)
    assert cache.read_sealed(path, tmp_path) is None
    os.chown(path, 0, 0)
    os.chown(path.with_name("lab.wasm.seal"), OTHER, OTHER)
    assert cache.read_sealed(path, tmp_path) is None


def test_a_sealed_file_copied_under_another_name_is_not_loaded(tmp_path):
    """A seal binds the name: one build's module and seal, copied under another build's name, are
    not that build's."""
    cache.write_sealed(tmp_path / "a.cwasm", b"module a", tmp_path)
    shutil.copy(tmp_path / "a.cwasm", tmp_path / "b.cwasm")
    shutil.copy(tmp_path / "a.cwasm.seal", tmp_path / "b.cwasm.seal")
    assert cache.read_sealed(tmp_path / "a.cwasm", tmp_path) == b"module a"
    assert cache.read_sealed(tmp_path / "b.cwasm", tmp_path) is None


def test_a_sealed_file_that_is_a_link_is_not_loaded(tmp_path):
    cache.write_sealed(tmp_path / "real.wasm", b"module", tmp_path)
    (tmp_path / "lab.wasm").symlink_to(tmp_path / "real.wasm")
    (tmp_path / "lab.wasm.seal").write_text((tmp_path / "real.wasm.seal").read_text())
    assert cache.read_sealed(tmp_path / "real.wasm", tmp_path) == b"module"
    assert cache.read_sealed(tmp_path / "lab.wasm", tmp_path) is None


def test_a_build_folder_planted_as_a_link_is_refused_with_its_line(module_cache, tmp_path):
    assert sim(module_cache).returncode == 0
    [objects] = module_cache.glob("firmware-*")
    copy = tmp_path / "copy"
    shutil.copytree(objects, copy)
    shutil.rmtree(objects)
    objects.symlink_to(copy)
    try:
        assert_refused_as_a_link(module_cache, objects)
    finally:
        objects.unlink()


# -- loaded when it is used: the worker checks again ---------------------------------------------

def run_build(build) -> str:  # noqa: ANN001 - a LabBuild
    config = make_config(LAB, "hands_off", build=build, startup_delay=False)
    try:
        with BoardRun(config) as run:
            run.run(10)
    except RunError as exc:
        return str(exc)
    return "ran"


@pytest.mark.parametrize("native", [False, True], ids=["wasm", "native"])
def test_a_firmware_changed_after_its_build_is_refused_when_it_is_loaded(module_cache, native):
    build = build_lab(LAB, cache=module_cache, native=native)
    assert run_build(build) == "ran"
    data = build.image.read_bytes()
    try:
        build.image.write_bytes(data[:-1] + bytes([data[-1] ^ 1]))  # one bit
        message = run_build(build)
        assert f"{build.image.name} is not " in message
        assert "(its seal does not hold): build it again" in message
        assert "\n" not in message
    finally:
        build.image.write_bytes(data)
    assert run_build(build) == "ran"


# -- zig's prepared C library -------------------------------------------------------------------

@pytest.fixture
def own_libc(tmp_path):
    """A copy of the installation's prepared C library in a folder of this user's (0755, as kept)."""
    libc = zig.prepared(TARGET, LINK_FLAGS)
    assert libc is not None
    home = tmp_path / "libc"
    home.mkdir(mode=0o755)
    shutil.copytree(libc.folder, home / libc.folder.name)
    return home / libc.folder.name


def libc_line(module_cache: Path, home: Path) -> str:
    r = sim(module_cache, env={zig.LIBC_ENV: str(home)})
    assert r.returncode == 2, r.stderr
    return last_line(r)


def test_a_prepared_c_library_of_this_users_is_linked(module_cache, own_libc):
    r = sim(module_cache, env={zig.LIBC_ENV: str(own_libc.parent)})
    assert r.returncode == 0, r.stderr


PREFIX = "crslab sim: the WebAssembly compiler cannot be used: CRSLAB_ZIG_LIBC_DIR: "


@pytest.mark.parametrize("mode", [0o664, 0o646], ids=["group", "others"])
def test_a_c_library_file_others_may_write_is_refused(module_cache, own_libc, mode):
    (own_libc / "01-libc.a").chmod(mode)
    assert libc_line(module_cache, own_libc.parent) == (
        f"{PREFIX}{own_libc} cannot be linked into a lab: 01-libc.a is missing, a link, another user's or "
        "writable by others")


@pytest.mark.parametrize("mode", [0o775, 0o757], ids=["group", "others"])
def test_a_c_library_folder_others_may_write_is_refused(module_cache, own_libc, mode):
    own_libc.chmod(mode)
    assert libc_line(module_cache, own_libc.parent) == (
        f"{PREFIX}{own_libc} cannot be linked into a lab: its group or others may write it")


def test_a_c_library_changed_since_it_was_built_is_refused(module_cache, own_libc):
    """Another ``sinf`` in its libc.a: the digest recorded when it was built no longer holds."""
    path = own_libc / "01-libc.a"
    data = bytearray(path.read_bytes())
    data[len(data) // 2] ^= 0xFF
    path.write_bytes(bytes(data))
    assert libc_line(module_cache, own_libc.parent) == (
        f"{PREFIX}{own_libc} cannot be linked into a lab: 01-libc.a changed since it was built")


def test_a_c_library_file_that_is_a_link_is_refused(module_cache, own_libc, tmp_path):
    moved = tmp_path / "elsewhere.a"
    (own_libc / "01-libc.a").rename(moved)
    (own_libc / "01-libc.a").symlink_to(moved)
    assert libc_line(module_cache, own_libc.parent).endswith(
        "01-libc.a is missing, a link, another user's or writable by others")


@needs_root
def test_another_users_c_library_is_refused(module_cache, own_libc):
    """The attack of the issue: the folder CRSLAB_ZIG_LIBC_DIR names holds another user's build."""
    os.chown(own_libc / "01-libc.a", OTHER, OTHER)
    assert libc_line(module_cache, own_libc.parent).endswith(
        "01-libc.a is missing, a link, another user's or writable by others")
    for path in [own_libc, *own_libc.iterdir()]:
        os.chown(path, OTHER, OTHER)
    assert libc_line(module_cache, own_libc.parent) == (
        f"{PREFIX}{own_libc} cannot be linked into a lab: it belongs to another user (uid {OTHER})")
    os.chown(own_libc.parent, OTHER, OTHER)
    assert libc_line(module_cache, own_libc.parent) == (
        f"crslab sim: the WebAssembly compiler cannot be used: CRSLAB_ZIG_LIBC_DIR={own_libc.parent} cannot "
        f"hold the C library crslab links into a lab: it belongs to another user (uid {OTHER})")
