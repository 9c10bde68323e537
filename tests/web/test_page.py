"""The browser page in headless Chromium: it draws the disks where the state
says, steps bit for bit as the native CPU engine, keeps the pairwise scheme's
energy, obeys its controls, and shows bad input without losing the scene."""
import time

import numpy as np
import pytest

import carom

DENSE = """packing = 0.5
boundary = "{boundary}"
collisions = "{scheme}"
dt = 0.01
gravity = [0.0, {gy}]
seed = 7
[[group]]
name = "small"
count = 1500
radius = 1.0
mass = 1.0
temperature = 1.0
[[group]]
name = "large"
count = 300
radius = [1.0, 1.25]
mass = 4.0
temperature = 1.0
"""


def fnv1a(data: bytes) -> str:
    """FNV-1a 64, as web/simulation.cpp's stateHash computes it."""
    value = 0xCBF29CE484222325
    for byte in data:
        value = ((value ^ byte) * 0x100000001B3) & 0xFFFFFFFFFFFFFFFF
    return f"{value:016x}"


def native_hash(path, steps):
    world = carom.World.from_scene(path, engine="cpu")
    world.step(steps)
    disks = np.column_stack([world.positions, world.velocities, world.masses, world.radii]).astype("<f4")
    return fnv1a(disks.tobytes() + int(world.collisions).to_bytes(8, "little"))


@pytest.mark.parametrize("scheme,boundary,gy", [("pairwise", "walls", -1.0), ("pairwise", "periodic", 0.0),
                                                ("simultaneous", "walls", -1.0), ("simultaneous", "periodic", 0.0),
                                                ("events", "walls", 0.0), ("events", "periodic", 0.0)])
def test_the_page_steps_bit_for_bit_as_the_native_engine(open_page, tmp_path, scheme, boundary, gy):
    text = DENSE.format(scheme=scheme, boundary=boundary, gy=gy)
    path = tmp_path / "scene.toml"
    path.write_text(text)
    page = open_page()
    assert page.js("caromPage.load(arguments[0], 'scene.toml')", text) == ""
    assert page.js("caromPage.sim.step(300)") == ""
    assert page.js("caromPage.sim.stateHash()") == native_hash(path, 300)


def test_disks_are_drawn_where_the_state_says(open_page):
    page = open_page("?n=300&packing=0.2&color=mass")
    page.js("caromPage.frames(3)")
    disks = np.array(page.js("Array.from(caromPage.sim.disks())"), dtype=np.float64).reshape(-1, 6)
    # The canvas's pixels, read back through a 2D canvas.
    pixels = page.js("""(() => {
        const c = document.querySelector('canvas'), copy = document.createElement('canvas');
        copy.width = c.width; copy.height = c.height;
        const g = copy.getContext('2d'); g.drawImage(c, 0, 0);
        return [c.width, c.height, Array.from(g.getImageData(0, 0, c.width, c.height).data)];
    })()""")
    width, height, rgba = pixels
    image = np.array(rgba, dtype=np.uint8).reshape(height, width, 4)[:, :, :3].astype(int)
    background = np.array(page.js("caromPage.background"))
    box_w, box_h = page.js("[caromPage.sim.width(), caromPage.sim.height()]")

    def pixel(x, y):
        px, py = page.js("caromPage.worldToCanvas(arguments[0], arguments[1])", x, y)
        return image[int(round(py)), int(round(px))]

    for x, y, *_ in disks[:40]:
        assert np.abs(pixel(x, y) - background).sum() > 60, f"no disk drawn at ({x}, {y})"
    # Points of the box at least a radius from every disk's edge show the background.
    rng = np.random.default_rng(1)
    empty = 0
    for x, y in rng.uniform([2, 2], [box_w - 2, box_h - 2], size=(400, 2)):
        gap = np.hypot(disks[:, 0] - x, disks[:, 1] - y) - disks[:, 5]
        if gap.min() > 1.0:
            empty += 1
            assert np.abs(pixel(x, y) - background).sum() < 30, f"a disk drawn at empty ({x}, {y})"
    assert empty > 20


def test_the_pairwise_scheme_keeps_a_dense_gas_energy_and_the_seeds_heats_it(open_page):
    page = open_page("?n=3000&packing=0.6&speed=10")
    page.js("caromPage.frames(60)")
    assert abs(page.js("caromPage.driftRelative()")) < 1e-6
    page.browser.find_element("css selector", "#scheme option[value='simultaneous']").click()
    page.js("caromPage.frames(60)")
    assert page.js("caromPage.sim.scheme()") == "simultaneous"
    assert page.js("caromPage.driftRelative()") > 1e-3


def choose(page, element_id, value):
    """Sets a control as a user does: its value, then the change event."""
    page.js("""(() => { const e = document.getElementById(arguments[0]);
                e.value = arguments[1]; e.dispatchEvent(new Event('change', {bubbles: true})); })()""",
            element_id, value)


def test_each_control_changes_what_it_names(open_page):
    page = open_page("?n=500")
    assert page.js("caromPage.sim.disks().length") == 6 * 500
    choose(page, "particles", "1500")
    assert page.js("caromPage.sim.disks().length") == 6 * 1500
    assert page.js("caromPage.params().n") == 1500

    assert page.js("caromPage.sim.observables().potential") == 0
    choose(page, "gravity", "2")
    page.js("caromPage.frames(2)")
    assert page.js("caromPage.sim.observables().potential") > 0  # -sum m g.y with g = (0, -2)
    assert page.js("caromPage.sim.disks().length") == 6 * 1500  # gravity changes live: the same disks

    for scheme in ("events", "simultaneous", "pairwise"):
        choose(page, "scheme", scheme)
        assert page.js("caromPage.sim.scheme()") == scheme
        assert page.js("caromPage.params().scheme") == scheme

    choose(page, "boundary", "periodic")
    assert page.js("caromPage.sim.periodic()") is True
    assert page.message() == ""


def test_a_bad_scene_file_is_shown_and_the_running_scene_goes_on(open_page):
    page = open_page("?n=400")
    before = page.js("caromPage.sim.stateHash()")
    steps = page.js("caromPage.sim.observables().steps")
    message = page.js("caromPage.load('packing = 0.3\\n[[group]]\\ncount = -5\\n', 'bad.toml')")
    assert "bad.toml" in message and "count" in message
    assert "bad.toml" in page.message()
    assert page.js("caromPage.sim.stateHash()") == before
    assert page.js("caromPage.sim.disks().length") == 6 * 400
    page.js("caromPage.frames(2)")
    assert page.js("caromPage.sim.observables().steps") == steps + 2


def test_a_bad_link_is_shown_and_the_scene_starts_with_the_default(open_page):
    page = open_page("?n=abc&scheme=fast&packing=0.3")
    message = page.message()
    assert "n=abc" in message and "scheme=fast" in message
    assert page.js("caromPage.params().scheme") == "pairwise"
    assert page.js("caromPage.params().packing") == 0.3
    assert page.js("caromPage.sim.disks().length") == 6 * page.js("caromPage.params().n")


def test_a_link_carries_the_scene(open_page):
    page = open_page("?n=800&packing=0.4&boundary=periodic&scheme=events&mix=0.25&radius_b=1.5&mass_b=3&seed=9")
    assert page.message() == ""
    assert page.js("caromPage.sim.scheme()") == "events"
    assert page.js("caromPage.sim.periodic()") is True
    masses = page.js("Array.from(caromPage.sim.disks()).filter((_, i) => i % 6 == 4)")
    assert sorted(set(masses)) == [1.0, 3.0] and masses.count(3.0) == 200


def test_screenshot(open_page, site):
    """The docs' picture (docs/web.md): a dense mixture after a few frames."""
    page = open_page("?n=4000&packing=0.5&mix=0.2&radius_b=1.4&speed=5")
    assert page.message() == ""
    page.browser.set_window_size(1800, 1000)
    page.js("caromPage.frames(40)")
    page.js("caromPage.play()")
    time.sleep(2)  # the plots and the status refresh a few times a second
    picture = site.parent / "screenshot.png"  # beside the page's folder, which stays publishable as it is
    page.browser.save_screenshot(str(picture))
    assert picture.stat().st_size > 10000


def pointer(page, kind, x, y):
    """A pointer event of `kind` at world point (x, y) on the disks' canvas."""
    page.js("""(() => { const c = document.getElementById('view'), r = c.getBoundingClientRect();
        const [px, py] = caromPage.worldToCanvas(arguments[1], arguments[2]);
        c.dispatchEvent(new PointerEvent(arguments[0], {bubbles: true, pointerId: 1, button: 0, isPrimary: true,
            clientX: r.left + px * r.width / c.width, clientY: r.top + py * r.height / c.height})); })()""",
            kind, x, y)


def test_the_mouse_drags_a_disk_and_drops_a_burst(open_page):
    page = open_page("?n=200&packing=0.1")
    disks = np.array(page.js("Array.from(caromPage.sim.disks())")).reshape(-1, 6)
    width, height = page.js("[caromPage.sim.width(), caromPage.sim.height()]")
    x, y = disks[0, :2]
    target = (width / 2, height / 2) if np.hypot(x - width / 2, y - height / 2) > 10 else (width / 4, height / 4)
    pointer(page, "pointerdown", x, y)
    pointer(page, "pointermove", *target)
    time.sleep(0.5)  # the held disk follows the pointer at the next frames
    pointer(page, "pointerup", *target)
    moved = np.array(page.js("Array.from(caromPage.sim.disks()).slice(0, 2)"))
    assert np.hypot(*(moved - target)) < 0.01

    # Where no disk is within reach: a burst of 12 more.
    gaps = [(np.hypot(disks[:, 0] - px, disks[:, 1] - py) - disks[:, 5]).min()
            for px, py in [(width * a, height * b) for a in (0.2, 0.4, 0.6, 0.8) for b in (0.2, 0.4, 0.6, 0.8)]]
    a, b = divmod(int(np.argmax(gaps)), 4)
    pointer(page, "pointerdown", width * (0.2 + 0.2 * a), height * (0.2 + 0.2 * b))
    assert page.js("caromPage.sim.disks().length") == 6 * 212
    assert page.message() == ""
