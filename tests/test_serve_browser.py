"""crslab serve end to end in a real browser: Debian's Chromium, headless, driven by Playwright
(``executable_path``: no browser is downloaded). The page is driven only through its documented
``data-testid`` controls (docs/serve.md). What the page shows is compared with what ``crslab sim``
does with the same lab and scenario."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest
from serve_server import USERS, roster_server

from crslab.regress.transcript import read_golden
from crslab.run.api import simulate
from crslab.sinks.stdout import tera_term_view
from crslab.starters import starter_text

pytestmark = pytest.mark.requires("chromium")

LABS = Path(__file__).parent / "labs"
OWN_LAB1 = Path(__file__).parent.parent / "csrc" / "labs" / "lab1_kinematics.c"
CHROMIUM_FLAGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--no-first-run",
]
WAIT_MS = 120_000


@pytest.fixture(scope="module")
def server(tmp_path_factory):
    yield from roster_server(tmp_path_factory)


@pytest.fixture(scope="module")
def browser(tmp_path_factory):
    from playwright.sync_api import expect, sync_playwright

    expect.set_options(timeout=WAIT_MS)  # a guard against hanging only: the expectations wait on events
    with sync_playwright() as p:
        b = p.chromium.launch(executable_path="/usr/bin/chromium", args=CHROMIUM_FLAGS, headless=True)
        yield b
        b.close()


def open_bench(browser, server, user):
    """A fresh browser context (its own cookies) logged in as ``user`` through the login form."""
    context = browser.new_context(viewport={"width": 1400, "height": 1000})
    page = context.new_page()
    page.set_default_timeout(WAIT_MS)
    page.goto(server.url)
    page.get_by_test_id("login-name").fill(user)
    page.get_by_test_id("login-password").fill(USERS[user][0])
    page.get_by_test_id("login-submit").click()
    page.get_by_test_id("editor").wait_for()
    from playwright.sync_api import expect

    expect(page.locator("#connection")).to_have_text("connected")
    return page


@pytest.fixture(scope="module")
def alice(browser, server):
    page = open_bench(browser, server, "alice")
    yield page
    page.context.close()


def test_the_tour_in_the_page_prints_what_crslab_sim_prints_and_moves_the_arm(alice):
    from playwright.sync_api import expect

    page = alice
    page.get_by_test_id("editor").fill(OWN_LAB1.read_text())
    page.get_by_test_id("scenario").select_option("tour")
    page.get_by_test_id("speed").select_option("2")  # the hand holds for 1.25 s: seen on a busy machine
    # every text the pose line shows, kept by the page itself (polling it from here would sample it
    # only as often as a loaded machine answers)
    page.evaluate("""() => {
        const line = document.querySelector('[data-testid="joint-angles"]');
        window.seenPoses = [];
        new MutationObserver(() => window.seenPoses.push(line.textContent))
            .observe(line, {childList: true, characterData: true, subtree: true});
    }""")
    page.get_by_test_id("run").click()
    expect(page.get_by_test_id("diagnosis")).to_contain_text(re.compile("run finished|crashed"))
    assert "crashed" not in page.get_by_test_id("diagnosis").text_content()
    seen = set(page.evaluate("window.seenPoses"))
    # what crslab sim shows on its stdout (Tera Term's view) for the same lab and scenario
    sim = subprocess.run([sys.executable, "-m", "crslab", "sim", "--lab", str(OWN_LAB1), "--scenario", "tour",
                          "--fast", "--quiet", "--no-stdin"], capture_output=True, check=True)
    expected = sim.stdout.decode("latin-1")
    assert expected == tera_term_view(simulate(OWN_LAB1, "tour").transcript).decode("latin-1")
    expect(page.get_by_test_id("terminal")).to_have_text(expected, use_inner_text=False)
    dh = [
        tuple(float(v) for v in re.search(r"DH angles \(true\): (\S+) (\S+) (\S+)", s).groups())
        for s in seen
        if "DH angles (true): " in s and "deg" in s
    ]
    assert len(set(dh)) >= 10  # the arm moved, frame after frame
    # the tour's hand holds the arm at DH (0, -90, 90) deg (motor zero) from 7 s to 9.5 s
    assert any(abs(a) < 0.5 and abs(b + 90) < 0.5 and abs(c - 90) < 0.5 for a, b, c in dh)


def test_writing_a_watched_variable_changes_what_the_lab_prints_and_stop_stops(alice):
    from playwright.sync_api import expect

    page = alice
    page.get_by_test_id("editor").fill(starter_text("lab1", "A"))
    page.get_by_test_id("speed").select_option("1")
    page.locator("details.options summary").click()
    page.get_by_test_id("no-startup-delay").check()
    page.get_by_test_id("run").click()
    expect(page.get_by_test_id("terminal")).to_contain_text("0.00 ")
    assert "I love robotics" not in page.get_by_test_id("terminal").text_content()
    page.get_by_test_id("var-name").fill("whattoprint")
    page.get_by_test_id("var-value").fill("1")
    page.get_by_test_id("var-set").click()
    expect(page.get_by_test_id("var-reply")).to_contain_text("whattoprint = 1   (from t = ")
    expect(page.get_by_test_id("terminal")).to_contain_text("I love robotics")
    page.get_by_test_id("stop").click()
    expect(page.get_by_test_id("diagnosis")).to_contain_text("interrupted: stopped at t = ")
    expect(page.get_by_test_id("run")).to_be_enabled()
    page.get_by_test_id("no-startup-delay").uncheck()


def test_dragging_a_link_moves_the_arm(alice):
    from playwright.sync_api import expect

    page = alice
    page.get_by_test_id("editor").fill(starter_text("lab1", "A"))
    page.get_by_test_id("scenario").select_option("hands_off")  # nothing else moves the arm
    page.get_by_test_id("speed").select_option("1")
    page.get_by_test_id("duration").fill("600")  # the drag below may take longer than hands_off's 30 s
    page.get_by_test_id("run").click()
    expect(page.get_by_test_id("joint-angles")).to_contain_text("deg")
    angles = page.get_by_test_id("joint-angles")

    def dh() -> list[float]:
        shown = re.search(r"DH angles \(true\): (\S+) (\S+) (\S+)", angles.text_content())
        return [float(v) for v in shown.groups()]

    rest = dh()
    view = page.get_by_test_id("arm").bounding_box()
    x, y = view["x"] + view["width"] / 2 + 40, view["y"] + view["height"] / 2 - 40  # on the forearm at rest
    page.mouse.move(x, y)
    page.mouse.down()
    for k in range(1, 31):  # pull it up and out
        page.mouse.move(x + 3 * k, y - 4 * k)
    for _ in range(20_000):  # the hand's spring pulls the forearm after the mouse, chunk by chunk
        if abs(dh()[1] - rest[1]) > 5.0:
            break
        page.mouse.move(x + 90, y - 120)
    else:
        pytest.fail(f"the arm did not follow the mouse: DH angles {dh()} (at rest {rest})")
    page.mouse.up()
    page.get_by_test_id("stop").click()
    expect(page.get_by_test_id("diagnosis")).to_contain_text("interrupted: stopped at t = ")
    page.get_by_test_id("duration").fill("")  # the scenario's again, for the tests after


def test_check_against_a_golden_file_from_the_page(alice, tmp_path):
    from playwright.sync_api import expect

    lab = tmp_path / "lab1.c"
    lab.write_text(starter_text("lab1", "B"))
    golden = tmp_path / "lab1_golden.txt"
    subprocess.run([sys.executable, "-m", "crslab", "record", "--lab", str(lab), "--duration", "5", "-o",
                    str(golden)], check=True, capture_output=True)
    printed = read_golden(golden).body.count(b"\n")  # 6: the angles, the position, the IK angles, twice
    page = alice
    page.get_by_test_id("editor").fill(lab.read_text())
    page.get_by_test_id("golden-file").set_input_files(str(golden))
    expect(page.get_by_test_id("check-report")).to_have_text(re.compile(rf"^match: {printed} lines"))
    expect(page.get_by_test_id("diagnosis")).to_have_text("check: the run matches the golden file")
    # the editor's lab is what is checked: one that prints its angles in rad does not match (the
    # two lines of motor angles; the others print zeros in either unit)
    page.get_by_test_id("editor").fill(lab.read_text().replace("* 180 / PI", ""))
    page.get_by_test_id("golden-file").set_input_files(str(golden))
    expect(page.get_by_test_id("check-report")).to_have_text(
        re.compile(rf"^mismatch: 2 of {printed} lines differ"))


def test_a_compile_error_marks_its_line(alice):
    from playwright.sync_api import expect

    page = alice
    page.get_by_test_id("editor").fill((LABS / "does_not_compile.c").read_text())
    page.get_by_test_id("build").click()
    expect(page.get_by_test_id("diagnosis")).to_contain_text(
        re.compile("does not compile: line 9: use of undeclared identifier .Kp_gain.")
    )
    lines = page.locator(".cm-content .cm-line")
    expect(lines.nth(8).locator(".cm-lintRange-error")).to_have_count(1)  # line 9, and no other
    expect(page.locator(".cm-content .cm-lintRange-error")).to_have_count(1)


def test_a_c89_habit_is_marked_at_its_line_and_said_in_the_events(alice):
    """The C89 habits the lab builds with: a warning marker at each line, and each said in the
    events in one line, as crslab sim says it on stderr (the lab named as the page names it)."""
    from playwright.sync_api import expect

    page = alice
    page.get_by_test_id("editor").fill((LABS / "implicit_decls_gen_b.c").read_text())
    page.get_by_test_id("build").click()
    name = page.get_by_test_id("lab-name").text_content()
    expect(page.get_by_test_id("diagnosis")).to_have_text(f"{name} compiled")
    said = page.locator("#events .build-warning")
    # malloc, average, free, the implicit int: once each; and malloc's int stored in a pointer
    expect(said).to_have_count(5)
    lines = said.all_text_contents()
    implicit_int = f"warning: {name}:17: a declaration without a type, which C89 makes an int"
    assert lines[0].startswith(implicit_int), lines
    assert any(x.startswith(f"warning: {name}:24: malloc() is called with no declaration before it") and
               x.endswith("returns its pointer in XAR4: the pointer is lost: #include <stdlib.h>")
               for x in lines), lines
    own_call = f"warning: {name}:29: average() is called with no declaration"
    assert any(x.startswith(own_call) for x in lines), lines
    marked = page.locator(".cm-content .cm-line")
    for line in (17, 24, 29):
        expect(marked.nth(line - 1).locator(".cm-lintRange-warning")).to_have_count(1)
    expect(page.locator(".cm-content .cm-lintRange-error")).to_have_count(0)
    # a build of a lab without habits takes them away
    page.get_by_test_id("editor").fill((LABS / "six_params_gen_b.c").read_text())
    page.get_by_test_id("build").click()
    expect(said).to_have_count(0)
    expect(page.locator(".cm-content .cm-lintRange-warning")).to_have_count(0)


def test_a_hostile_lab_shows_its_diagnosis(alice):
    from playwright.sync_api import expect

    page = alice
    page.get_by_test_id("editor").fill((LABS / "hostile" / "read_file.c").read_text())
    page.get_by_test_id("speed").select_option("fast")
    page.get_by_test_id("run").click()
    expect(page.get_by_test_id("diagnosis")).to_contain_text("forbidden: ")
    expect(page.get_by_test_id("diagnosis")).to_contain_text("was stopped by the sandbox: it tried to open")


def test_two_users_cannot_see_each_others_sessions(browser, server, alice):
    from playwright.sync_api import expect

    bob = open_bench(browser, server, "bob")
    try:
        assert alice.get_by_test_id("terminal").text_content()  # alice has run labs
        assert bob.get_by_test_id("terminal").text_content() == ""  # bob sees none of it
        expect(bob.locator("#admin-link")).to_be_hidden()
        alice_session = alice.evaluate("fetch('/api/me').then(r => r.status)")
        assert alice_session == 200
        status = bob.evaluate("document.querySelector('#dl-transcript').href")
        assert status == "" or "session=" not in status
        # bob asking for alice's files by her session's id gets nothing
        sessions = server.request("GET", "/admin", cookie=server.login("ta"))[2].decode()
        ids = re.findall(r"<td>([\w-]{8})</td><td>alice</td>", sessions)
        assert ids
        for short in ids:
            assert (
                bob.evaluate(f"fetch('/api/download/transcript?session={short}').then(r => r.status)") == 404
            )
        assert bob.evaluate("fetch('/admin').then(r => r.status)") == 403
    finally:
        bob.context.close()
