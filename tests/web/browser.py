"""The browser page, built, served and opened in Debian's headless Chromium
through Selenium: what the browser tests (conftest.py) and
bench/web_frames.py share.

Nothing is downloaded: Selenium drives /usr/bin/chromium through
/usr/bin/chromedriver (Debian's chromium and chromium-driver), and
emscripten's own libraries come with Debian's emscripten package."""
import contextlib
import functools
import http.server
import os
import pathlib
import shutil
import subprocess
import threading

REPOSITORY = pathlib.Path(__file__).resolve().parents[2]
CHROMIUM = "/usr/bin/chromium"
CHROMEDRIVER = "/usr/bin/chromedriver"


class Missing(Exception):
    """A tool the page needs is not installed, or its build failed."""


def build_site(build):
    """Configures `build` with emcmake and builds the page; returns its folder (build/web)."""
    if shutil.which("emcmake") is None:
        raise Missing("emcmake is missing: ./install-deps.sh --web (or --test) installs Debian's emscripten")
    for command in (["emcmake", "cmake", "-S", str(REPOSITORY), "-B", str(build), "-DCMAKE_BUILD_TYPE=Release"],
                    ["cmake", "--build", str(build), "-j2"]):
        done = subprocess.run(command, capture_output=True, text=True)
        if done.returncode != 0:
            raise Missing(f"{' '.join(command)} failed:\n{done.stdout[-3000:]}\n{done.stderr[-3000:]}")
    return pathlib.Path(build) / "web"


class QuietHandler(http.server.SimpleHTTPRequestHandler):
    def log_message(self, *args):
        pass


@contextlib.contextmanager
def serve(folder):
    """The page's address on a static server of `folder`, as `python3 -m http.server` serves it."""
    httpd = http.server.ThreadingHTTPServer(("127.0.0.1", 0), functools.partial(QuietHandler, directory=str(folder)))
    thread = threading.Thread(target=httpd.serve_forever, daemon=True)
    thread.start()
    try:
        yield f"http://127.0.0.1:{httpd.server_address[1]}/index.html"
    finally:
        httpd.shutdown()


def open_chromium():
    """Headless Chromium with software WebGL 2 (SwiftShader) where the machine
    has no GPU, a fixed window, and the console kept for the tests."""
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    for path in (CHROMIUM, CHROMEDRIVER):
        if not os.path.exists(path):
            raise Missing(f"{path} is missing: ./install-deps.sh --test installs Debian's chromium and chromium-driver")
    options = webdriver.ChromeOptions()
    options.binary_location = CHROMIUM
    for argument in ("--headless=new", "--no-sandbox", "--disable-dev-shm-usage", "--enable-unsafe-swiftshader",
                     "--use-angle=swiftshader", "--window-size=1400,1000"):
        options.add_argument(argument)
    options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    driver = webdriver.Chrome(options=options, service=Service(CHROMEDRIVER))
    driver.set_script_timeout(300)
    return driver


class Page:
    """The page open in the browser, through its test hooks (window.caromPage)."""

    def __init__(self, browser, url):
        from selenium.webdriver.support.ui import WebDriverWait

        self.browser = browser
        browser.get_log("browser")  # what earlier pages logged is theirs
        browser.get(url)
        WebDriverWait(browser, 60).until(
            lambda d: d.execute_script("return !!(window.caromPage && window.caromPage.ready)"))

    def js(self, expression, *args):
        return self.browser.execute_script("return " + expression, *args)

    def message(self):
        return self.js("document.getElementById('message').textContent")

    def console_errors(self):
        return [e for e in self.browser.get_log("browser") if e["level"] in ("SEVERE", "WARNING")]
