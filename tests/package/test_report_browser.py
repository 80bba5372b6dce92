"""The HTML report is a web page: opened in a real browser —
headless Chromium from Debian's ``chromium`` and ``chromium-driver``, driven by
selenium, no browser downloaded at run time — it loads without console errors,
every image is decoded, every table is there, every link to a written file
resolves, and the machine's animation plays (its frames change), pauses and follows
its slider. ``.ci/run`` installs the browser; elsewhere the test is skipped when it is
missing (in CI a missing browser fails)."""

from __future__ import annotations

import os
import shutil
from pathlib import Path
from urllib.parse import unquote, urlparse

import pytest

ROOT = Path(__file__).resolve().parents[2]
DRIVER = shutil.which("chromedriver")
BROWSER = shutil.which("chromium") or shutil.which("chromium-browser")

webdriver = pytest.importorskip("selenium.webdriver")
if DRIVER is None or BROWSER is None:
    if os.environ.get("CI"):
        pytest.fail("CI must have chromium and chromium-driver (.ci/run installs them)")
    pytest.skip("needs Debian's chromium and chromium-driver", allow_module_level=True)


@pytest.fixture(scope="module")
def browser():
    from selenium.webdriver.chrome.service import Service

    opts = webdriver.ChromeOptions()
    for arg in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage"):
        opts.add_argument(arg)
    opts.binary_location = BROWSER
    opts.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    # The driver by its path: selenium's manager would otherwise look one up online.
    drv = webdriver.Chrome(service=Service(DRIVER), options=opts)
    yield drv
    drv.quit()


@pytest.fixture(scope="module", params=["stb_loom", "knife_cutter", "transfer_arm_synthesized"])
def report(request, cli_run) -> Path:
    run = cli_run(ROOT / "examples" / f"{request.param}.toml", "--quiet")
    assert run.code == 0
    return run.out / "report.html"


def _open(browser, report: Path) -> None:
    """Load the page and wait (up to 30 s, for a loaded machine) until the browser
    has built all of it: the Files section is its last."""
    from selenium.webdriver.support.ui import WebDriverWait

    browser.get(report.as_uri())
    WebDriverWait(browser, 30).until(
        lambda b: b.execute_script(
            "return document.readyState === 'complete' && "
            "Array.from(document.querySelectorAll('h2')).some(h => h.textContent === 'Files')"
        )
    )


def test_the_report_loads_whole_in_a_browser(browser, report):
    _open(browser, report)
    logs = browser.get_log("browser")
    assert [e for e in logs if e["level"] in ("SEVERE", "WARNING")] == []
    images = browser.execute_script(
        "return Array.from(document.images).map(i => [i.complete, i.naturalWidth, i.alt])"
    )
    figures = sorted((report.parent / "figures").glob("*.png"))
    assert len(images) == len(figures) > 0
    assert all(done and width > 0 for done, width, _ in images), images
    # every table of the page's source is in the document the browser built
    html = report.read_text("utf-8")
    tables = browser.execute_script("return document.querySelectorAll('table').length")
    assert tables == html.count("<table") > 0
    rows = browser.execute_script(
        "return Array.from(document.querySelectorAll('table')).map(t => t.rows.length)"
    )
    assert min(rows) >= 2, rows  # a header and at least one row each


def test_every_link_to_a_written_file_resolves(browser, report):
    _open(browser, report)
    hrefs = browser.execute_script(
        "return Array.from(document.querySelectorAll('a[href]')).map(a => a.href)"
    )
    local = [h for h in hrefs if h.startswith("file:")]
    assert local, "the report links its files"
    for h in local:
        path = Path(unquote(urlparse(h).path))
        assert path.is_file() and path.parent == report.parent, h


def test_the_machine_moves_when_played(browser, report):
    """Play advances the frame (the slider, the angle shown and every drawing
    change), pause holds it, and the slider sets it."""
    import time

    _open(browser, report)
    pixels = "return Array.from(document.querySelectorAll('canvas')).map(c => c.toDataURL())"
    state = (
        "return [document.getElementById('cm-slider').value, "
        "document.getElementById('cm-angle').textContent]"
    )
    before, shown = browser.execute_script(pixels), browser.execute_script(state)
    assert shown == ["0", "θ = 0.0°"] and len(before) >= 2  # a drawing and the cyclogram
    browser.find_element("id", "cm-play").click()
    time.sleep(0.6)  # 24 frames a second: about 14 frames
    browser.find_element("id", "cm-play").click()  # pause
    held, after = browser.execute_script(state), browser.execute_script(pixels)
    assert held[0] != "0" and held[1] != shown[1]
    moved = [a != b for a, b in zip(before, after, strict=True)]
    assert moved[-1] and any(moved[:-1]), moved  # the cursor, and a mechanism (not all dwell)
    time.sleep(0.3)
    assert browser.execute_script(state) == held  # paused
    browser.execute_script(
        "const s = document.getElementById('cm-slider'); s.value = '60';"
        "s.dispatchEvent(new Event('input'));"
    )
    assert browser.execute_script(state) == ["60", "θ = 180.0°"]
    assert [e for e in browser.get_log("browser") if e["level"] in ("SEVERE", "WARNING")] == []
