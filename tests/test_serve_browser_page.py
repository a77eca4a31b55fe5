"""crslab serve's page as a new user meets it (issue 33), in Debian's Chromium driven by Playwright:
the events a run reached and no others, an expectation said once, no panel left from the run
before, the clock at a crash's own time, the angles labelled, the generation crslab new writes,
scopes that keep a steady signal flat, file buttons that read whole."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from test_serve_browser import WAIT_MS, browser, open_bench, server  # noqa: F401 - module fixtures

from crslab.generations import GENERATIONS, NEWEST
from crslab.starters import starter_text

pytestmark = pytest.mark.requires("chromium")

LABS = Path(__file__).parent / "labs"
CRASH = LABS / "crash_after_5s.c"  # a NULL pointer at tick 5100 (t = 5.100 s)
SCENARIO = """name = "crash_then_more"
description = "an expectation before the crash, a hand and a release after it"
end = 25.0

[[event]]
at = 4.5
kind = "expect"
error = 0

[[event]]
at = 9.5
kind = "hand"
motor_deg = [0, 90, 0]
duration = 2.0

[[event]]
at = 23.0
kind = "release"
"""


@pytest.fixture(scope="module")
def page(browser, server):  # noqa: F811
    p = open_bench(browser, server, "alice")
    yield p
    p.context.close()


@pytest.fixture(scope="module")
def crashed(page, tmp_path_factory):
    """The crash lab run on the scenario above, fast: the page once it has said how the run ended."""
    from playwright.sync_api import expect

    scenario = tmp_path_factory.mktemp("page") / "crash_then_more.toml"
    scenario.write_text(SCENARIO)
    page.get_by_test_id("editor").fill(CRASH.read_text())
    page.get_by_test_id("scenario-file").set_input_files(str(scenario))
    page.get_by_test_id("speed").select_option("fast")
    page.get_by_test_id("run").click()
    expect(page.get_by_test_id("diagnosis")).to_contain_text("crashed: ")
    return page


def test_the_events_are_those_the_run_reached_and_an_expectation_is_said_once(crashed):
    events = crashed.locator("#events").inner_text().splitlines()
    assert "t = 4.500 s: expect error = 0: met" in events, events
    assert sum("expect" in line for line in events) == 1, events  # once, with what it expected
    assert not [line for line in events if line.startswith(("t = 9.500 s", "t = 23.000 s"))], events


def test_the_clock_stops_at_the_crash_not_at_its_chunks_start(crashed):
    assert crashed.get_by_test_id("sim-time").text_content() == "t = 5.100 s"


def test_the_angles_say_which_is_the_arms_and_which_the_labs(crashed):
    text = crashed.get_by_test_id("joint-angles").text_content()
    assert re.fullmatch(r"the arm's DH angles \(true\): \S+ \S+ \S+ deg; the lab's motor angles "
                        r"\(what lab\(\) reads, offset-dependent\): \S+ \S+ \S+ deg", text), text


def test_a_check_clears_what_the_run_before_left(crashed, tmp_path):
    """After the crashed run: a watched-variable reply, then a check: Tera Term, the events, the
    angles and the reply are the check's (empty until it says), not the crashed run's."""
    from playwright.sync_api import expect

    page = crashed
    assert page.get_by_test_id("terminal").text_content()  # the run printed before it crashed
    page.get_by_test_id("var-name").fill("no such thing!")
    page.get_by_test_id("var-get").click()
    expect(page.get_by_test_id("var-reply")).to_have_text("a variable: NAME or NAME[i]")
    golden = tmp_path / "golden.txt"
    golden.write_text("# crslab transcript\n# scenario: hands_off\n# end_s: 1.000\n# ----\n")
    page.get_by_test_id("golden-file").set_input_files(str(golden))
    expect(page.get_by_test_id("check-report")).not_to_have_text(re.compile("^checking"))
    assert page.get_by_test_id("terminal").text_content() == ""
    assert page.locator("#events").inner_text() == ""
    assert page.get_by_test_id("var-reply").text_content() == ""
    assert page.get_by_test_id("joint-angles").text_content() == "DH angles: -"
    assert page.get_by_test_id("sim-time").text_content() == "t = 0.000 s"


def test_the_generation_is_crslab_news_and_follows_an_opened_file(page, tmp_path):
    from playwright.sync_api import expect

    expect(page.get_by_test_id("gen-choice")).to_have_value(NEWEST.name)  # crslab new's default
    for gen in GENERATIONS:
        if gen.name not in ("A", "B"):
            continue
        other = "A" if gen.name == "B" else "B"
        page.get_by_test_id("gen-choice").select_option(other)
        lab = tmp_path / f"lab1_{gen.name}.c"
        lab.write_text(starter_text("lab1", gen.name))
        page.get_by_test_id("lab-file").set_input_files(str(lab))
        expect(page.get_by_test_id("lab-name")).to_have_text(lab.name)
        expect(page.get_by_test_id("gen-choice")).to_have_value(gen.name)


def test_a_steady_signal_with_float_noise_draws_flat_and_below_the_title(page):
    """PlotVars of 1.0 with 1e-5 of noise, 2 s of them, drawn on a scope of its own: every pixel of
    the traces (right of the value labels, left of the legend) lies within 3 px of one row (noise is
    not steps across the panel), and none in the title's band."""
    found = page.evaluate("""() => {
        const host = document.createElement("div");
        host.id = "test-scopes";
        host.style.width = "600px";
        document.body.appendChild(host);
        const scopes = new window.CrsScopes.Scopes(host);
        const rows = 2000, cols = 13, data = new Float32Array(rows * cols);
        for (let r = 0; r < rows; r++)  // the panel's four PlotVars: 1.0 and float noise
          for (let c = 0; c < 4; c++) data[r * cols + c] = 1.0 + (((r + c) * 7919) % 3 - 1) * 1e-5;
        const bytes = new Uint8Array(data.buffer);
        let text = "";
        for (const b of bytes) text += String.fromCharCode(b);
        scopes.add({ tick0: 0, rows, data: btoa(text) });
        scopes.windowS = 2;  // the window is the data's 2 s
        scopes.follow(2000);
        scopes.draw();
        const c = scopes.canvases[0], g = c.getContext("2d");
        const img = g.getImageData(0, 0, c.width, c.height).data;
        const ys = [];
        for (let y = 0; y < c.height; y++)
          for (let x = 60; x < c.width - 100; x++) {
            const i = (y * c.width + x) * 4;
            const [r, g, b] = [img[i], img[i + 1], img[i + 2]];
            const spread = Math.max(r, g, b) - Math.min(r, g, b);
                if (img[i + 3] > 64 && spread > 40) ys.push(y);  // a trace's colour, not the text's grey
          }
        host.remove();
        return { ys: [Math.min(...ys), Math.max(...ys)], count: ys.length, title: window.CrsScopes.TITLE_H,
                 labels: [window.CrsScopes.label(1.00081), window.CrsScopes.label(-1.2e-5)] };
    }""")
    assert found["count"] > 100, found
    low, high = found["ys"]
    assert high - low <= 3 and low > found["title"], found
    assert found["labels"] == ["1", "-1.2e-5"]


def test_the_file_buttons_read_whole(page):
    boxes = page.evaluate("""() => [...document.querySelectorAll("label.file")].map((l) => ({
        text: l.innerText.trim(), fits: l.scrollWidth <= l.clientWidth + 1,
        input: l.querySelector("input").getBoundingClientRect().width }))""")
    assert [b["text"] for b in boxes] == ["open…", "scenario file…", "check against a golden file…"], boxes
    assert all(b["fits"] and b["input"] <= 1 for b in boxes), boxes
