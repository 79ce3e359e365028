#!/usr/bin/env python3
"""tern plot's 3-D replay (issue 65) looked at as a person would, in headless Chromium.

    test_plot_view3d.py TERN [SCREENSHOT.png]

Flies the default mission twice for 60 s (a CSV log from home; an MCAP-only log from (300, 0)),
puts the two runs in a fleet (fleet.json) and runs the build's tern plot on it (TERN's
tern-plot: each vehicle's index.html and the fleet's). Then, in headless Chromium with WebGL on
the SwiftShader software renderer:
  * uav1's replay opened at #t=20 and at #t=50: the page has a WebGL context, the scene is not
    empty (a share of the canvas is neither the sky's nor the ground's colour: the grid, tracks,
    markers and aircraft), the aircraft moved (> 100 m in NED, > 20 px on the screen) and the pixels where it was
    and where it is changed between the two screenshots;
  * uav2's replay (read from its flight.mcap) has both tracks and draws;
  * the fleet's replay has both vehicles, each in its own colour, 300 m apart at the start;
  * a truncated run (a killed flight: no truth, no controller_internals, state.csv cut mid-line)
    still draws its estimate and shows one line naming what is missing;
  * a run's own plots hold no view3d.js: one copy beside the runs serves them all, and a run
    copied away from it draws with tern plot's installed copy.
Optionally saves a screenshot of uav1's replay. Exit status 77 (ctest: skipped) with a message
only when Chromium, chromedriver or Python's selenium is missing here.
"""
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time

SKIP = 77
CHROMIUM = shutil.which("chromium") or "/usr/bin/chromium"
CHROMEDRIVER = shutil.which("chromedriver") or "/usr/bin/chromedriver"
REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))


def skip(why):
    print(f"SKIPPED: {why} (make deps installs chromium, chromium-driver and python3-selenium)")
    sys.exit(SKIP)


try:
    from selenium import webdriver
    from selenium.webdriver.common.by import By
except ImportError:
    skip("Python's selenium is not installed")
for exe in (CHROMIUM, CHROMEDRIVER):
    if not os.access(exe, os.X_OK):
        skip(f"{exe} not found")
import matplotlib.image  # noqa: E402  (PNG decoding; tern plot's own dependency)
import numpy as np  # noqa: E402


def browser():
    """Headless Chromium with WebGL on SwiftShader (its CPU renderer: no GPU here)."""
    opts = webdriver.ChromeOptions()
    opts.binary_location = CHROMIUM
    for a in ("--headless=new", "--no-sandbox", "--disable-dev-shm-usage", "--window-size=1200,900",
              "--use-angle=swiftshader", "--enable-unsafe-swiftshader"):
        opts.add_argument(a)
    try:
        return webdriver.Chrome(service=webdriver.ChromeService(executable_path=CHROMEDRIVER), options=opts)
    except AttributeError:  # selenium < 4.10
        from selenium.webdriver.chrome.service import Service
        return webdriver.Chrome(service=Service(CHROMEDRIVER), options=opts)


def fly(tern, logs, *extra):
    r = subprocess.run([tern, "fly", os.path.join(REPO, "configs", "missions", "default.yaml"), "--duration", "60",
                        "--log-dir", logs, "-q", *extra], capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr[-2000:]
    return next(line.split(" ", 1)[1].strip() for line in r.stdout.splitlines() if line.startswith("log: "))


def open_at(driver, page, t):
    """The replay at #t=t, drawn; returns window.ternView3d's time, frames and aircraft."""
    driver.get(f"file://{page}#t={t}")
    deadline = time.time() + 30
    while time.time() < deadline:
        s = driver.execute_script("const s = window.ternView3d; return s && s.view.frames > 0 ? "
                                  "{t: s.drawnT, frames: s.view.frames, where: s.where, "
                                  "gl: !!s.view.renderer.getContext()} : null")
        if s and s["t"] is not None and abs(s["t"] - t) < 1e-6 and s["where"]:
            return s
        time.sleep(0.2)
    raise AssertionError(f"{page}#t={t}: the replay did not draw in 30 s")


def shot(driver, path):
    """The replay's canvas as an H x W x 3 array of 0..255."""
    canvas = driver.find_element(By.CSS_SELECTOR, "#view3d canvas")
    driver.execute_script("arguments[0].scrollIntoView()", canvas)
    canvas.screenshot(path)
    return (matplotlib.image.imread(path)[:, :, :3] * 255).round().astype(int)


def region(img, xy, half=25):
    x, y = int(round(xy[0])), int(round(xy[1]))
    return img[max(0, y - half):y + half, max(0, x - half):x + half]


def check_replay(driver, page, tmp, keep=None):
    """Opens the page at two times: not empty, the aircraft moved, its pixels changed."""
    a = open_at(driver, page, 20)
    img_a = shot(driver, os.path.join(tmp, "a.png"))
    b = open_at(driver, page, 50)
    img_b = shot(driver, os.path.join(tmp, "b.png"))
    assert a["gl"], "no WebGL context"
    plain = [np.array([int(c[k:k + 2], 16) for k in (1, 3, 5)]) for c in driver.execute_script(
        "return [TernView3D.SKY, TernView3D.GROUND]")]  # view3d.js's sky and ground colours
    drawn = np.all([np.any(np.abs(img_a - c) > 12, axis=2) for c in plain], axis=0).mean()
    assert drawn > 0.005, f"the scene is empty: {drawn:.4f} of the canvas is neither sky nor ground"
    pa, pb = a["where"][0], b["where"][0]
    moved = float(np.hypot(pb["ned"][0] - pa["ned"][0], pb["ned"][1] - pa["ned"][1]))
    px = float(np.hypot(pb["screen"][0] - pa["screen"][0], pb["screen"][1] - pa["screen"][1]))
    assert moved > 100, f"the aircraft moved {moved:.0f} m in 30 s"
    assert px > 20, f"the aircraft moved {px:.0f} px on the screen"
    scale = img_a.shape[1] / driver.execute_script("return document.querySelector('#view3d canvas').clientWidth")
    for where, name in ((pa["screen"], "where it was"), (pb["screen"], "where it is")):
        xy = (where[0] * scale, where[1] * scale)
        changed = np.any(np.abs(region(img_a, xy) - region(img_b, xy)) > 30, axis=2).mean()
        assert changed > 0.02, f"{page}: nothing changed {name} ({changed:.3f} of the pixels)"
    if keep:
        shutil.copyfile(os.path.join(tmp, "b.png"), keep)
    print(f"{page}: {drawn:.3f} of the canvas drawn on sky and ground; aircraft moved {moved:.0f} m, {px:.0f} px")


def data_of(plots):
    with open(os.path.join(plots, "view3d_data.js"), encoding="utf-8") as f:
        text = f.read()
    return json.loads(text[text.index("{"):text.rindex("}") + 1])


def truncated_run(src, dst):
    """A copy of src as a killed flight without truth and controller_internals, state.csv cut mid-line."""
    shutil.copytree(src, dst, ignore=shutil.ignore_patterns("plots"))
    for name in ("truth", "controller_internals"):
        os.remove(os.path.join(dst, "topics", name + ".csv"))
    path = os.path.join(dst, "topics", "state.csv")
    with open(path, encoding="utf-8") as f:
        text = f.read()
    with open(path, "w", encoding="utf-8") as f:
        f.write(text[:len(text) * 2 // 3])


def main(tern, keep):
    plot = os.path.join(os.path.dirname(os.path.abspath(tern)), "tern-plot")
    share = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(tern))), "share", "tern", "plot")
    if not os.path.isfile(os.path.join(share, "view3d.js")):
        raise AssertionError(f"{share}/view3d.js missing: the build did not bundle the 3-D view (make deps, rebuild)")
    tmp = tempfile.mkdtemp(prefix="tern_view3d_")
    try:
        logs = os.path.join(tmp, "runs")
        a = fly(tern, logs)
        b = fly(tern, logs, "--log-format", "mcap", "--set", "sim.init_position=[300,0]")
        fleet = os.path.join(tmp, "fleet")
        os.makedirs(fleet)
        shutil.copytree(a, os.path.join(fleet, "uav1"))
        shutil.copytree(b, os.path.join(fleet, "uav2"))
        with open(os.path.join(fleet, "fleet.json"), "w") as f:
            json.dump({"mission": "two", "seed": 1, "vehicles": ["uav1", "uav2"], "coordination": False}, f)
        r = subprocess.run([plot, fleet], capture_output=True, text=True, timeout=600)
        assert r.returncode == 0, r.stderr[-2000:]
        plots = os.path.join(fleet, "plots")
        one, mcap, both = (data_of(os.path.join(plots, d)) for d in ("uav1", "uav2", ""))
        for d in (one, mcap):
            v = d["vehicles"][0]
            assert v["truth"] and v["state"] and v["ghost"] and v["path"] and v["wind"], f"a topic missing: {d['missing']}"
            assert d["missing"] == [], d["missing"]
            assert v["dims"]["b"] > 0 and v["dims"]["nose"] > 0 and v["dims"]["tail"] > 0
        assert len(both["vehicles"]) == 2 and both["vehicles"][0]["colour"] != both["vehicles"][1]["colour"]
        n0 = [v["truth"]["ned"][0] for v in both["vehicles"]]
        assert abs(n0[1] - n0[0] - 300) < 1, f"the fleet's vehicles start {n0[1] - n0[0]:.1f} m apart (300 flown)"

        truncated = os.path.join(tmp, "truncated")
        truncated_run(a, truncated)
        r = subprocess.run([plot, truncated], capture_output=True, text=True, timeout=600)
        assert r.returncode == 0, r.stderr[-2000:]
        lines = data_of(os.path.join(truncated, "plots"))["missing"]
        assert len(lines) == 1 and "truth" in lines[0] and "controller_internals" in lines[0], lines

        # one copy of the scene beside the runs, not one per run (issue 80); a run moved away from
        # its siblings still opens, with the installed copy
        r = subprocess.run([plot, a], capture_output=True, text=True, timeout=600)
        assert r.returncode == 0, r.stderr[-2000:]
        assert not os.path.exists(os.path.join(a, "plots", "view3d.js")), "view3d.js copied into the run"
        shared = [f for f in os.listdir(logs) if f.startswith("tern-view3d-") and f.endswith(".js")]
        assert len(shared) == 1, f"the runs' directory holds {shared}"
        moved = os.path.join(tmp, "elsewhere", "lone")
        shutil.copytree(a, moved)

        driver = browser()
        try:
            check_replay(driver, os.path.join(moved, "plots", "index.html"), tmp)
            print("a run moved away from the shared view3d.js: drawn with the installed one")
            check_replay(driver, os.path.join(plots, "uav1", "index.html"), tmp, keep)
            check_replay(driver, os.path.join(plots, "uav2", "index.html"), tmp)
            s = open_at(driver, os.path.join(plots, "index.html"), 30)
            assert len(s["where"]) == 2 and all(s["where"]), s["where"]
            s = open_at(driver, os.path.join(truncated, "plots", "index.html"), 20)
            shown = driver.find_element(By.CSS_SELECTOR, ".view3d-missing").text
            assert shown == lines[0], shown
            print(f"truncated run: drawn, and says: {shown}")
        finally:
            driver.quit()
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    print("view3d: ok")


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2] if len(sys.argv) > 2 else None)
