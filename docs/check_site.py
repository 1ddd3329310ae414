"""Load every page of the built documentation site in headless Chromium and fail on anything broken.

Usage: ``python docs/check_site.py docs/_build/html`` (what ``make docs-check`` runs).

For each HTML page, served by a local static server on 127.0.0.1 (started and stopped here):
- the browser console has no error (severity SEVERE), e.g. a failed script, image or video load;
- every ``<img>`` has loaded (``complete`` and ``naturalWidth > 0``);
- every ``<video>`` has loaded its metadata (``readyState >= 1``, no ``error``) and has a width;
- every image, video and local link target answers HTTP 200 from the server.

Needs Debian's ``chromium`` and ``chromium-driver`` (``/usr/bin/chromium``, ``/usr/bin/chromedriver``;
``.ci/run`` installs them with apt-get where missing) and selenium (the ``[docs]`` extra). Exit status
0 when every page passes, 1 otherwise (one line per problem), 2 when the browser is missing.
"""

from __future__ import annotations

import functools
import http.server
import shutil
import sys
import threading
import time
import urllib.error
import urllib.request
from pathlib import Path
from urllib.parse import urljoin, urlsplit

#: seconds a page may take to load its videos' metadata
VIDEO_TIMEOUT = 20.0

_PROBE = """
const imgs = Array.from(document.images).map(i => ({src: i.currentSrc || i.src, ok: i.complete && i.naturalWidth > 0}));
const vids = Array.from(document.querySelectorAll('video')).map(v => ({src: v.currentSrc || v.src,
    ready: v.readyState, error: v.error ? v.error.code : null, width: v.videoWidth}));
const links = Array.from(document.querySelectorAll('a[href]')).map(a => a.href);
return {imgs, vids, links};
"""


class _Quiet(http.server.SimpleHTTPRequestHandler):
    def log_message(self, format: str, *args: object) -> None:  # noqa: A002 (stdlib signature)
        pass


class _Server(http.server.ThreadingHTTPServer):
    def handle_error(self, request: object, client_address: object) -> None:
        # a browser that stops a video download part-way closes its socket: not a site problem
        if not isinstance(sys.exc_info()[1], (BrokenPipeError, ConnectionResetError)):
            super().handle_error(request, client_address)  # type: ignore[arg-type]


def _status(url: str) -> int:
    try:
        with urllib.request.urlopen(url, timeout=10) as r:  # noqa: S310 (our own local server)
            return int(r.status)
    except urllib.error.HTTPError as e:
        return int(e.code)


def _driver() -> object:
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    browser = shutil.which("chromium") or shutil.which("chromium-browser")
    driver = shutil.which("chromedriver")
    if not browser or not driver:
        print("check_site: chromium and chromedriver are needed (apt-get install chromium chromium-driver)",
              file=sys.stderr)
        raise SystemExit(2)
    opts = webdriver.ChromeOptions()
    opts.binary_location = browser
    for flag in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage", "--mute-audio",
                 "--autoplay-policy=no-user-gesture-required"):
        opts.add_argument(flag)
    opts.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    return webdriver.Chrome(service=Service(executable_path=driver), options=opts)


def check(site: Path) -> list[str]:
    """Problems found on the site's pages (empty: all pass)."""
    pages = sorted(p.relative_to(site).as_posix() for p in site.rglob("*.html") if "_sources" not in p.parts)
    if not pages:
        return [f"{site}: no HTML pages (run `make docs` first)"]
    handler = functools.partial(_Quiet, directory=str(site))
    server = _Server(("127.0.0.1", 0), handler)
    base = f"http://127.0.0.1:{server.server_address[1]}/"
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    problems: list[str] = []
    seen: dict[str, int] = {}
    drv = _driver()
    try:
        for page in pages:
            drv.get(base + page)  # type: ignore[attr-defined]
            deadline = time.monotonic() + VIDEO_TIMEOUT
            while True:  # videos load asynchronously: wait for their metadata (or an error)
                info = drv.execute_script(_PROBE)  # type: ignore[attr-defined]
                pending = [v for v in info["vids"] if v["ready"] < 1 and v["error"] is None]
                if not pending or time.monotonic() > deadline:
                    break
                time.sleep(0.2)
            for entry in drv.get_log("browser"):  # type: ignore[attr-defined]
                if entry.get("level") == "SEVERE":
                    problems.append(f"{page}: console error: {entry.get('message')}")
            for img in info["imgs"]:
                if not img["ok"]:
                    problems.append(f"{page}: image did not load: {img['src']}")
            for v in info["vids"]:
                if v["ready"] < 1 or v["error"] is not None or not v["width"]:
                    problems.append(f"{page}: video did not load (readyState {v['ready']}, error {v['error']}): "
                                    f"{v['src']}")
            urls = [x["src"] for x in info["imgs"] + info["vids"]] + list(info["links"])
            for url in urls:
                full = urljoin(base + page, url).split("#")[0]
                if not full.startswith(base) or urlsplit(full).path.endswith("/"):
                    continue  # external links are not fetched (CI may be offline); folders are not pages
                if full not in seen:
                    seen[full] = _status(full)
                if seen[full] != 200:
                    problems.append(f"{page}: {url} -> HTTP {seen[full]}")
            print(f"check_site: {page}: {len(info['imgs'])} images, {len(info['vids'])} videos, "
                  f"{len(info['links'])} links", flush=True)
    finally:
        drv.quit()  # type: ignore[attr-defined]
        server.shutdown()
        server.server_close()
    return problems


def main(argv: list[str]) -> int:
    site = Path(argv[0] if argv else "docs/_build/html")
    if not site.is_dir():
        print(f"check_site: {site} is not a folder (run `make docs` first)", file=sys.stderr)
        return 2
    problems = check(site)
    for p in problems:
        print(f"check_site: FAIL {p}", file=sys.stderr)
    print(f"check_site: {'FAILED' if problems else 'passed'}: {len(problems)} problem(s)")
    return 1 if problems else 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
