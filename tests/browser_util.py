"""A headless Chromium for the tests that look at a page as a person sees it: the report's
``index.html`` and the DEM study's page.

Talks to chromedriver through the W3C WebDriver HTTP protocol directly (standard library
only), so the only requirement is the Debian packages ``chromium`` and ``chromium-driver``.
"""

import json
import shutil
import socket
import subprocess
import time
import urllib.error
import urllib.request

import pytest

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser") or shutil.which(
    "google-chrome")
CHROMEDRIVER = shutil.which("chromedriver")

needs_browser = pytest.mark.skipif(
    not (CHROMIUM and CHROMEDRIVER),
    reason="headless browser test needs chromium and chromedriver on PATH "
    "(Debian: apt-get install chromium chromium-driver)")


def _request(method, url, body=None, timeout=60):
    data = None if body is None else json.dumps(body).encode()
    req = urllib.request.Request(url, data=data, method=method,
                                 headers={"Content-Type": "application/json"})
    with urllib.request.urlopen(req, timeout=timeout) as resp:
        return json.loads(resp.read().decode() or "{}")


@pytest.fixture
def webdriver():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    proc = subprocess.Popen([CHROMEDRIVER, f"--port={port}"], stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL)
    base = f"http://127.0.0.1:{port}"
    try:
        for _ in range(100):
            try:
                if _request("GET", f"{base}/status", timeout=2)["value"]["ready"]:
                    break
            except (urllib.error.URLError, OSError, KeyError):
                pass
            time.sleep(0.1)
        caps = {"capabilities": {"alwaysMatch": {
            "browserName": "chrome",
            "goog:chromeOptions": {"binary": CHROMIUM, "args": [
                "--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
                "--window-size=1400,1000"]},
        }}}
        session = _request("POST", f"{base}/session", caps)["value"]["sessionId"]
        yield f"{base}/session/{session}"
        _request("DELETE", f"{base}/session/{session}")
    finally:
        proc.terminate()
        proc.wait(timeout=10)

