"""A headless Chromium for the results pages: a full-page screenshot, and facts read from the rendered
DOM (so a test checks the page a reader sees, not only its HTML text).

The browser is the system's (Debian: ``chromium-headless-shell``, installed by
``scripts/apt-deps.sh``); nothing is downloaded. Without one, ``find_browser`` returns None and callers
say so.
"""

from __future__ import annotations

import json
import shutil
import subprocess
import tempfile
from pathlib import Path
from typing import Any

from rle_design.errors import RleError

BROWSERS = ("chromium-headless-shell", "chromium", "chromium-browser", "google-chrome")
"""Executables tried in order."""
WIDTH = 1200
"""Window width of screenshots [px]."""
_FLAGS = ("--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars", "--virtual-time-budget=10000")

_PROBE = """<script>window.addEventListener("load", () => {
  const text = (e) => e.textContent.trim();
  const imgs = [...document.images];
  const sections = [...document.querySelectorAll("section.family")].map((s) => ({
    id: s.id,
    images: [...s.querySelectorAll("img")].filter((i) => i.complete && i.naturalWidth > 0).length,
    columns: [...s.querySelectorAll("table.diagnostics tr:first-child th")].map(text),
    means: s.querySelectorAll("tr.mean").length,
  }));
  document.title = JSON.stringify({
    images: imgs.length,
    decoded: imgs.filter((i) => i.complete && i.naturalWidth > 0).length,
    h2: [...document.querySelectorAll("h2")].map(text),
    tables: document.querySelectorAll("table").length,
    height: document.documentElement.scrollHeight,
    sections,
  });
});</script>"""


def find_browser() -> str | None:
    """Path of a headless Chromium on PATH, else None."""
    return next((p for name in BROWSERS if (p := shutil.which(name))), None)


def _run(args: list[str], timeout_s: float) -> str:
    browser = find_browser()
    if browser is None:
        raise RleError(
            f"no headless Chromium on PATH (tried {', '.join(BROWSERS)}); bash scripts/apt-deps.sh installs one",
            code="browser.missing",
        )
    try:
        done = subprocess.run(
            [browser, *_FLAGS, *args], capture_output=True, text=True, timeout=timeout_s, check=False
        )
    except subprocess.TimeoutExpired:
        raise RleError(f"{browser} did not finish in {timeout_s:.0f} s", code="browser.timeout") from None
    if done.returncode != 0:
        raise RleError(f"{browser} failed ({done.returncode}): {done.stderr[-400:]}", code="browser.failed")
    return done.stdout


def page_facts(page: Path, timeout_s: float = 60.0) -> dict[str, Any]:
    """What the browser rendered: image count and how many decoded, the ``h2`` headings, the table count,
    the page height [px] and per family section its decoded images, diagnostics columns and mean rows."""
    html = Path(page).read_text(encoding="utf-8")
    with tempfile.TemporaryDirectory(prefix="rle-page-") as tmp:
        probe = Path(tmp) / "page.html"
        probe.write_text(html.replace("</body>", _PROBE + "</body>", 1), encoding="utf-8")
        dom = _run(["--dump-dom", probe.as_uri()], timeout_s)
    start, end = dom.find("<title>"), dom.find("</title>")
    try:
        import html as html_lib

        return json.loads(html_lib.unescape(dom[start + len("<title>") : end]))
    except ValueError:
        raise RleError(
            "the page's probe did not run (no facts in the rendered title)", code="browser.failed"
        ) from None


def screenshot(page: Path, png: Path, width: int = WIDTH, timeout_s: float = 60.0) -> Path:
    """A full-page PNG of ``page`` at ``width`` px (the height the rendered page takes)."""
    height = int(page_facts(page, timeout_s)["height"])
    png = Path(png).resolve()
    png.parent.mkdir(parents=True, exist_ok=True)
    _run([f"--window-size={width},{height}", f"--screenshot={png}", Path(page).resolve().as_uri()], timeout_s)
    return png
