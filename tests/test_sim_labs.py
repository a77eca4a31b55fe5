"""Lab files in both framework generations' styles, with the quirks of real ones (docs/framework.md
section 12), compile unmodified and print what they should."""

from pathlib import Path

import numpy as np
import pytest

from crslab.generations import GEN_A, GEN_B
from crslab.lab.build import build_lab
from crslab.run.api import simulate

LABS = Path(__file__).parent / "labs"


def test_gen_a_file_with_libc_named_globals():
    build = build_lab(LABS / "gen_a_libc_names.c")
    assert build.generation == GEN_A and build.printf_buffer_chars == 2048
    run = simulate(LABS / "gen_a_libc_names.c", "hands_off", duration_s=6.2)
    assert run.ok
    lines = run.lines()
    # serial_printf straight from lab(), then printing() after lab() returns, in the same tick
    assert lines[0] == "hello from lab() gen A"
    assert run.calls[0][0] == run.calls[1][0] == 4100
    # printing() ran once per double SWI_post, every 1000 calls; the lab's globals named time,
    # step, gamma, y0 and j1 kept their own values (libc's functions did not take their place)
    assert lines[1:] == [
        f"count {c} time {c} step {7 * c} gamma 2.50 y0 1.0 j1 3.0" for c in (1, 1001, 2001)
    ]


def test_gen_b_2024_file_in_a_cpp_with_uartprint_and_main():
    build = build_lab(LABS / "gen_b_2024.cpp")
    assert build.generation == GEN_B and build.printf_buffer_chars == 136
    run = simulate(LABS / "gen_b_2024.cpp", "hands_off", duration_s=5.2, log=True)
    assert run.ok
    ticks = [t for t, _ in run.calls]
    assert ticks == [4100, 4600, 5100]  # UARTprint polled after lab(): printing() in the same tick
    first = [float(v) for v in run.lines()[0].split()]
    np.testing.assert_allclose(first[:3], np.degrees([0.0, -0.42, 0.24]), atol=0.01)
    assert first[3] == 1  # bool from <stdbool.h> works
    # the LEDs start high and toggle on every print: GPIO34 and GPIO60 change together
    leds = run.log["leds"][:, 0]
    assert leds[0] == 3 and leds[run.log["tick"][:, 0] == 4099][0] == 3
    assert leds[run.log["tick"][:, 0] == 4100][0] == 0
    assert leds[run.log["tick"][:, 0] == 4600][0] == 3


def test_default_lab_is_gen_a_and_watches_whattoprint():
    build = build_lab()
    assert build.generation == GEN_A
    assert [v.name for v in build.watched] == ["whattoprint", "theta1array", "theta2array"]


@pytest.fixture(scope="module")
def own_cache(tmp_path_factory):
    """A build cache of this module's own for the tests that build in it and compare what it holds
    (one, so the firmware's own objects are compiled into it once)."""
    return tmp_path_factory.mktemp("cache")


def test_build_is_cached_by_content(tmp_path, monkeypatch, own_cache):
    monkeypatch.setenv("CRSLAB_CACHE_DIR", str(own_cache))
    lab = tmp_path / "lab.c"
    lab.write_text((LABS / "persistent_tau.c").read_text())
    first = build_lab(lab)
    again = build_lab(lab)
    assert again.image == first.image
    lab.write_text(lab.read_text() + "\n/* edited */\n")
    assert build_lab(lab).image != first.image




def test_a_lab_given_by_the_same_name_in_two_folders_is_one_build_naming_neither(tmp_path, monkeypatch,
                                                                                  own_cache):
    """``crslab serve`` builds each page's lab by its name from the session's own folder: the same
    text is one build (one compile, one wasmtime compilation) whatever the folder, and the module
    names the lab only as given (``__FILE__``, the debug information a trap's backtrace quotes)."""
    monkeypatch.setenv("CRSLAB_CACHE_DIR", str(own_cache))
    text = (LABS / "persistent_tau.c").read_text()
    images = []
    for name in ("first-session-folder", "second-session-folder"):
        folder = tmp_path / name
        folder.mkdir()
        (folder / "lab.c").write_text(text)
        monkeypatch.chdir(folder)
        images.append(build_lab(Path("lab.c")).image)
    assert images[0] == images[1]
    module = images[0].read_bytes()
    assert b"lab.c" in module  # its debug information names the file ...
    assert b"session-folder" not in module  # ... by name only, in neither folder


def test_a_header_the_lab_includes_from_its_folder_names_the_build_too(tmp_path, monkeypatch, own_cache):
    """Editing a header the lab includes from its own folder builds anew: the gain it defines is
    the one the run uses."""
    monkeypatch.setenv("CRSLAB_CACHE_DIR", str(own_cache))
    lab = tmp_path / "lab.c"
    lab.write_text((LABS / "persistent_tau.c").read_text().replace(
        "#include", '#include "gains.h"\n#include', 1))
    (tmp_path / "gains.h").write_text("#define GAIN 1\n")
    first = build_lab(lab)
    assert build_lab(lab).image == first.image
    (tmp_path / "gains.h").write_text("#define GAIN 2\n")
    assert build_lab(lab).image != first.image
