"""The built site in headless Chromium: the home page and an env page load, with their pictures.

Run by ``bash .ci/docs.sh`` after ``mkdocs build --strict`` (the site in ``site/``, or
``$BABYROBOT_SITE``). The browser is Debian's ``/usr/bin/chromium`` (``.ci/browser.sh``; never
``playwright install``). Screenshots go to ``$BABYROBOT_SCREENSHOTS`` (default: pytest's
temporary folder); their paths are printed. Waits are on the event, with one generous limit (WAIT).
"""

from __future__ import annotations

import functools
import http.server
import os
import posixpath
import re
import shutil
import threading
from pathlib import Path
from urllib.parse import unquote, urljoin, urlparse

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
SITE = Path(os.environ.get("BABYROBOT_SITE", ROOT / "site"))
WAIT = 300_000  # ms: a limit for a loaded machine, never a deadline the test means
CHROMIUM_ARGS = ["--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage", "--no-first-run", "--disable-background-networking"]

# every <img> of the page: its src, whether it finished loading, and its natural size (0 if broken)
IMAGES = """() => Array.from(document.images).map(
    i => ({src: i.getAttribute('src'), complete: i.complete, w: i.naturalWidth, h: i.naturalHeight}))"""


def chromium() -> str:
    for candidate in (os.environ.get("CHROMIUM"), "/usr/bin/chromium", shutil.which("chromium")):
        if candidate and os.access(candidate, os.X_OK):
            return candidate
    pytest.fail("no Chromium: run `bash .ci/browser.sh` (apt-get install -y chromium fonts-liberation) as root")


@pytest.fixture(scope="module")
def server():
    assert (SITE / "index.html").is_file(), f"no built site in {SITE}: run `mkdocs build --strict` first"
    class Quiet(http.server.SimpleHTTPRequestHandler):
        def log_message(self, *args) -> None:  # no line per request in the test output
            pass

    handler = functools.partial(Quiet, directory=str(SITE))
    httpd = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    thread = threading.Thread(target=httpd.serve_forever, daemon=True)
    thread.start()
    yield f"http://127.0.0.1:{httpd.server_address[1]}"
    httpd.shutdown()
    httpd.server_close()


@pytest.fixture(scope="module")
def page():
    from playwright.sync_api import sync_playwright

    with sync_playwright() as pw:
        browser = pw.chromium.launch(executable_path=chromium(), headless=True, args=CHROMIUM_ARGS)
        try:
            yield browser.new_page(viewport={"width": 1280, "height": 900})
        finally:
            browser.close()


def visit(page, url: str) -> list[dict]:
    page.goto(url, wait_until="load", timeout=WAIT)
    page.wait_for_function("() => Array.from(document.images).every(i => i.complete)", timeout=WAIT)
    return page.evaluate(IMAGES)


@pytest.fixture(scope="session")
def shots(tmp_path_factory: pytest.TempPathFactory) -> Path:
    chosen = os.environ.get("BABYROBOT_SCREENSHOTS")
    return Path(chosen) if chosen else tmp_path_factory.mktemp("screenshots")


def screenshot(page, name: str, shots: Path) -> np.ndarray:
    import imageio.v3 as iio

    shots.mkdir(parents=True, exist_ok=True)
    path = shots / f"docs_{name}.png"
    page.screenshot(path=str(path), full_page=False)
    print(f"screenshot: {path}")
    return iio.imread(path)[..., :3]


def header_colour(page) -> list[int]:
    """The header bar's background colour as the theme's CSS computes it, ``[r, g, b]``."""
    css = page.evaluate("() => getComputedStyle(document.querySelector('.md-header')).backgroundColor")
    return [int(v) for v in css[css.index("(") + 1 : css.index(")")].split(",")[:3]]


def colour_share(img: np.ndarray, colour: list[int]) -> float:
    """Share of the top band's pixels (the header bar) in ``colour``."""
    band = img[:40].reshape(-1, 3).astype(int)
    return float((np.abs(band - colour).sum(axis=1) < 12).mean())


def test_home_page_shows_its_title_the_race_animation_and_the_navigation(server, page, shots):
    images = visit(page, f"{server}/")
    assert page.title() == "Baby Robot"
    assert page.locator("h1").first.inner_text().rstrip("¶").strip() == "Baby Robot"
    gif = [i for i in images if i["src"].endswith("race_v0.gif")]
    assert gif and gif[0]["w"] > 0 and gif[0]["h"] > 0, images
    nav = page.locator("nav.md-nav--primary").inner_text()
    for entry in ("Environments", "BabyRobot-v0", "race_v0", "Rules and collisions", "API reference"):
        assert entry in nav, nav
    img = screenshot(page, "home", shots)
    colour = header_colour(page)
    assert colour != [255, 255, 255] and colour_share(img, colour) > 0.5  # the theme's stylesheet loaded and drew the header
    assert img.std() > 20  # text and pictures, not a blank page


def test_race_env_page_shows_the_animation_drawn_by_the_env_and_its_table(server, page, shots):
    from babyrobot_marl import race_v0

    images = visit(page, f"{server}/environments/race_v0/")
    assert page.title().startswith("race_v0")
    gif = [i for i in images if i["src"].endswith("race_v0.gif")]
    assert gif, images
    frame = race_v0.parallel_env(level="race-4", n_robots=4, render_mode="rgb_array")
    frame.reset(seed=0)
    h, w, _ = frame.render().shape
    assert (gif[0]["w"], gif[0]["h"]) == (w, h)  # the GIF is the env's own rgb_array frames
    import urllib.request

    import imageio.v3 as iio

    with urllib.request.urlopen(f"{server}/environments/race_v0/{gif[0]['src']}") as response:
        frames = iio.imread(response.read(), extension=".gif", index=None)
    assert frames.shape[0] > 10 and not (frames[0] == frames[-1]).all()  # an animation: the robots move
    table = page.locator("table").first.inner_text()
    for row in ("Actions", "Observations", "Rewards", "Termination", "Arguments", "Version history"):
        assert row in table, table
    headings = page.locator("h2").all_inner_texts()
    assert any(h.startswith("Version history") for h in headings), headings  # the docstring's sections
    img = screenshot(page, "race_v0", shots)
    assert img.std() > 20


def test_collision_pictures_all_load(server, page, shots):
    images = visit(page, f"{server}/guides/rules/")
    pictures = [i for i in images if "/collisions/" in i["src"]]
    assert len(pictures) == 7, images
    assert all(i["w"] > 0 and i["h"] > 0 for i in pictures), pictures
    screenshot(page, "rules", shots)


def test_tutorial_page_holds_the_executed_notebook_outputs_and_the_canvas_pictures(server, page, shots):
    images = visit(page, f"{server}/tutorials/quickstart/")
    text = page.locator("article").inner_text()
    assert "quickstart notebook: done" in text  # the last cell's output: the notebook ran at build time
    # the live canvas's outputs carry a PNG of their frame: the static page shows those pictures
    pictures = [i for i in images if (i["src"] or "").startswith("data:image/png")]
    assert len(pictures) >= 2 and all(i["w"] > 100 and i["h"] > 100 for i in pictures), images
    screenshot(page, "tutorial_quickstart", shots)


def site_url() -> str:
    m = re.search(r"^site_url:\s*(\S+)", (ROOT / "mkdocs.yml").read_text(encoding="utf-8"), re.M)
    assert m, "mkdocs.yml has no site_url: 404.html's links and sitemap.xml need it"
    return m.group(1) if m.group(1).endswith("/") else m.group(1) + "/"


def site_file(url: str) -> Path:
    """The file of the built site that ``url`` (under site_url) is served from."""
    base = site_url()
    assert url.startswith(base), f"{url} is not under site_url {base}"
    rel = posixpath.normpath("/" + unquote(urlparse(url).path)[len(urlparse(base).path) :]).lstrip("/")
    path = SITE / rel
    return path / "index.html" if path.is_dir() else path


def test_404_page_links_work_at_any_depth():
    # the server answers any missing URL with 404.html: its links must not depend on where that was
    html = (SITE / "404.html").read_text(encoding="utf-8")
    links = [u for u in re.findall(r'(?:href|src)="([^"]+)"', html) if not urlparse(u).scheme and not u.startswith("#")]
    assert len(links) >= 30, links
    for missing in ("no-such-page/", "guides/no/such/page.html"):
        broken = [u for u in links if not site_file(urljoin(site_url() + missing, u)).is_file()]
        assert not broken, f"404.html served at {missing}: broken links {broken}"


def test_sitemap_lists_every_page_at_site_url():
    locs = re.findall(r"<loc>([^<]+)</loc>", (SITE / "sitemap.xml").read_text(encoding="utf-8"))
    pages = [p for p in SITE.rglob("index.html") if "assets" not in p.parts]
    assert len(locs) == len(pages) >= 20, (len(locs), len(pages))
    assert all(site_file(u).is_file() for u in locs)
