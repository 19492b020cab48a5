"""Fixtures for the browser tests: the `appel` binary serving a page, and headless Chromium
driven through chromedriver (Debian's `chromium` and `chromium-driver`). Without them the tests
skip with a message."""

import os
import shutil
import signal
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def appel_binary():
    path = Path(os.environ.get("APPEL_BIN", ROOT / "target" / "release" / "appel"))
    if not path.exists():
        pytest.skip(f"{path} is missing: build it with cargo build --release")
    return path


@pytest.fixture
def serve():
    """Starts `appel view ARGS...` and returns its URL; stops it with Ctrl-C afterwards."""
    procs = []

    def start(*args):
        p = subprocess.Popen(
            [str(appel_binary()), "view", *args],
            stdout=subprocess.PIPE,
            text=True,
        )
        procs.append(p)
        line = p.stdout.readline()
        url = next((w for w in line.split() if w.startswith("http://")), None)
        assert url, f"no URL in {line!r}"
        return url

    yield start
    for p in procs:
        p.send_signal(signal.SIGINT)
        try:
            assert p.wait(timeout=10) == 0
        finally:
            if p.poll() is None:
                p.kill()


@pytest.fixture(scope="module")
def browser():
    try:
        from selenium import webdriver
        from selenium.webdriver.chrome.service import Service
    except ImportError:
        pytest.skip("selenium is not installed (pip install -r requirements-test.txt)")
    chromium = shutil.which("chromium") or shutil.which("chromium-browser")
    driver_path = shutil.which("chromedriver")
    if not chromium or not driver_path:
        pytest.skip("headless Chromium is missing (apt-get install chromium chromium-driver)")
    options = webdriver.ChromeOptions()
    options.binary_location = chromium
    for arg in ("--headless=new", "--no-sandbox", "--disable-dev-shm-usage", "--window-size=1000,720",
                "--disable-gpu", "--hide-scrollbars"):
        options.add_argument(arg)
    driver = webdriver.Chrome(service=Service(driver_path), options=options)
    driver.set_script_timeout(60)
    yield driver
    driver.quit()
