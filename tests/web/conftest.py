"""Fixtures of the browser tests (browser.py): the page built with
emscripten into build/web, served by a static server and opened in Debian's
headless Chromium. They fail, not skip, where a tool is missing:
./install-deps.sh --test installs them all."""
import os

import pytest

from browser import REPOSITORY, Missing, Page, build_site, open_chromium, serve


@pytest.fixture(scope="session")
def site():
    """The built page's folder: of $CAROM_WEB_BUILD, else of build/web."""
    try:
        return build_site(os.environ.get("CAROM_WEB_BUILD", REPOSITORY / "build" / "web"))
    except Missing as e:
        pytest.fail(str(e))


@pytest.fixture(scope="session")
def server(site):
    with serve(site) as url:
        yield url


@pytest.fixture(scope="session")
def browser():
    try:
        driver = open_chromium()
    except Missing as e:
        pytest.fail(str(e))
    yield driver
    driver.quit()


@pytest.fixture
def open_page(browser, server):
    """open_page(query) opens the page with that query string, paused, and
    checks after the test that the console logged no error or warning."""
    pages = []

    def opener(query=""):
        page = Page(browser, server + query)
        page.js("caromPage.pause()")
        pages.append(page)
        return page

    yield opener
    for page in pages:
        assert page.console_errors() == []
