"""crslab serve's page offers the contest (issue 37), in Debian's Chromium driven by Playwright: its
checkbox runs the lab as ``crslab contest`` does and shows the scorecard when the run's end is
shown; the egg's force on its scale is a fifth scope; the 3D view of a world frames every fixture
(each fixture mesh's box corners projected by three.js's camera land on the screen)."""

from __future__ import annotations

import pytest
from test_serve_browser import WAIT_MS, browser, open_bench, server  # noqa: F401 - module fixtures

from crslab.starters import starter_text

pytestmark = pytest.mark.requires("chromium")


@pytest.fixture(scope="module")
def page(browser, server):  # noqa: F811
    p = open_bench(browser, server, "alice")
    yield p
    p.context.close()


def test_the_view_of_the_contest_world_frames_every_fixture(page):
    found = page.evaluate("""async () => {
        const shapes = await fetch("/api/arm?world=contest").then((r) => r.json());
        const host = document.createElement("div");
        host.style.width = "640px"; host.style.height = "480px";
        document.body.appendChild(host);
        const view = new window.CrsArm.ArmView(host, shapes, () => {});
        view.render();
        const T = view.T;
        view.camera.updateMatrixWorld();
        const fixtures = ["hole", "obstacle", "groove", "egg", "scale"];
        const seen = {};
        view.scene.updateMatrixWorld(true);
        view.scene.traverse((o) => {
          if (!o.isMesh || !fixtures.includes(o.userData.body)) return;
          o.geometry.computeBoundingBox();
          const b = o.geometry.boundingBox;
          const inside = [0, 1, 2, 3, 4, 5, 6, 7].every((i) => {
            const p = new T.Vector3(i & 1 ? b.max.x : b.min.x, i & 2 ? b.max.y : b.min.y,
              i & 4 ? b.max.z : b.min.z).applyMatrix4(o.matrixWorld).project(view.camera);
            return Math.abs(p.x) <= 1 && Math.abs(p.y) <= 1 && Math.abs(p.z) <= 1;  // on the screen
          });
          seen[o.userData.body] = (seen[o.userData.body] ?? true) && inside;
        });
        view.dispose(); host.remove();
        return seen;
    }""")
    assert found == {"hole": True, "obstacle": True, "groove": True, "egg": True, "scale": True}, found


def test_the_contest_checkbox_runs_the_contest_and_shows_its_card(page):
    from playwright.sync_api import expect

    page.get_by_test_id("editor").fill(starter_text("final", "B"))
    page.get_by_test_id("contest").check()
    expect(page.get_by_test_id("world")).to_have_value("contest")   # the contest's world, chosen
    expect(page.get_by_test_id("scenario")).to_be_disabled()         # hands off
    page.get_by_test_id("speed").select_option("fast")
    page.get_by_test_id("run").click()
    card = page.get_by_test_id("scorecard")
    expect(card).to_be_visible(timeout=WAIT_MS)
    lines = card.inner_text().splitlines()
    assert [line.split()[:2] for line in lines[:4]] == [["peg", "done"], ["obstacle", "done"],
                                                       ["groove", "done"], ["egg", "done"]], lines
    assert lines[5].startswith("rest      -0.4200 0.2400 rad: the lab's own")
    expect(page.get_by_test_id("diagnosis")).to_contain_text("run finished at")
    # the egg's scope: a fifth panel, with the band's lines
    expect(page.get_by_test_id("scope-egg")).to_have_count(1)
    assert page.locator("#scopes canvas").count() == 5
    # a run without the contest has no card and no egg scope
    page.get_by_test_id("contest").uncheck()
    page.get_by_test_id("scenario").select_option("hands_off")
    page.locator("details.options summary").click()
    page.get_by_test_id("duration").fill("5")
    page.get_by_test_id("world").select_option("none")
    page.get_by_test_id("run").click()
    expect(page.get_by_test_id("diagnosis")).to_contain_text("run finished at t = 5.000 s")
    expect(page.get_by_test_id("scorecard-panel")).to_be_hidden()
    assert page.locator("#scopes canvas").count() == 4
