#!/usr/bin/env python3
"""The flight console (issue 25) in headless Chromium during a real-time flight.

    test_console.py TERN MISSION [SCREENSHOT.png]

Flies MISSION with `tern fly --realtime --console`, then checks, against the live flight:
  * the live 3-D view (view3d.js) draws the aircraft where the telemetry puts it (then the page is
    opened again with view3d=0, without it: see main);
  * requests without the token (or with a wrong one, or another Host) get 403, the page with it 200;
    a WebSocket upgrade without the token gets 403;
  * the page's charts update (telemetry frames arrive, flight time advances, uPlot holds points);
  * moving a gain slider with the keyboard changes the gain: the change is in params.csv with
    source "console";
  * 5 s of manual flight by keyboard (M: manual; arrows: right, left, right, pull, push): the surfaces
    follow the sticks (aileron positive while rolling right, elevator negative while pulling), the
    aircraft rolls, and the receiver reports the override; then a (virtual) gamepad through the
    browser's Gamepad API moves them too.
And `tern console` hands out the URL of a `tern serve --realtime --console`, which answers with
the token and refuses without it. Optionally saves a screenshot of the page. Exit status 77 (ctest: skipped) with a message only
when Chromium, chromedriver or Python's selenium is missing here.
"""
import csv
import glob
import os
import select
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
import urllib.error
import urllib.request

SKIP = 77
CHROMIUM = shutil.which("chromium") or "/usr/bin/chromium"
CHROMEDRIVER = shutil.which("chromedriver") or "/usr/bin/chromedriver"


def skip(why):
    print(f"SKIPPED: {why} (make deps installs chromium, chromium-driver and python3-selenium)")
    sys.exit(SKIP)


try:
    from selenium import webdriver
    from selenium.webdriver.common.action_chains import ActionChains
    from selenium.webdriver.common.by import By
    from selenium.webdriver.common.keys import Keys
except ImportError:
    skip("Python's selenium is not installed")
for exe in (CHROMIUM, CHROMEDRIVER):
    if not os.access(exe, os.X_OK):
        skip(f"{exe} not found")


def start_flight(tern, mission, log_dir):
    cmd = [tern, "fly", mission, "--realtime", "--console", "--duration", "50", "--log-dir", log_dir, "-q"]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    deadline = time.time() + 20
    while time.time() < deadline:
        ready, _, _ = select.select([proc.stdout], [], [], 0.5)
        if ready:
            line = proc.stdout.readline()
            print("tern:", line.rstrip())
            if line.startswith("console: "):
                return proc, line.split(" ", 1)[1].strip()
        if proc.poll() is not None:
            break
    proc.kill()
    raise AssertionError("tern printed no console URL")


def status(url, host=None):
    rq = urllib.request.Request(url, headers={"Host": host} if host else {})
    try:
        with urllib.request.urlopen(rq, timeout=5) as r:
            return r.status
    except urllib.error.HTTPError as e:
        return e.code


def ws_upgrade_status(port, path):
    with socket.create_connection(("127.0.0.1", port), timeout=5) as s:
        s.sendall((f"GET {path} HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
                   "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n\r\n").encode())
        return int(s.recv(200).decode().split()[1])


def check_token(url):
    base, token = url.split("/?token=")
    port = int(base.rsplit(":", 1)[1])
    assert status(url) == 200, "the page with its token"
    assert status(base + "/") == 403, "no token"
    assert status(base + "/console.js") == 403, "an asset without the token"
    assert status(base + "/?token=" + "0" * len(token)) == 403, "a wrong token"
    assert status(url, host=f"evil.example:{port}") == 403, "another Host (DNS rebinding)"
    assert ws_upgrade_status(port, "/ws") == 403, "a WebSocket without the token"
    assert ws_upgrade_status(port, "/ws?token=" + token) == 101, "a WebSocket with it"
    print("token: 403 without it, 200 / 101 with it")


def browser():
    opts = webdriver.ChromeOptions()
    opts.binary_location = CHROMIUM
    for a in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage", "--window-size=1500,1050"):
        opts.add_argument(a)
    try:
        return webdriver.Chrome(service=webdriver.ChromeService(executable_path=CHROMEDRIVER), options=opts)
    except AttributeError:  # selenium < 4.10
        from selenium.webdriver.chrome.service import Service
        return webdriver.Chrome(service=Service(CHROMEDRIVER), options=opts)


def wait_for(driver, script, what, timeout=15):
    deadline = time.time() + timeout
    while time.time() < deadline:
        v = driver.execute_script(script)
        if v:
            return v
        time.sleep(0.1)
    raise AssertionError(f"timed out waiting for {what}")


def check_view3d(driver):
    """The live 3-D view (view3d.js) draws the aircraft where the telemetry puts it."""
    wait_for(driver, "const v = window.ternConsole && window.ternConsole.view3d.view; "
             "return v && v.frames > 2 && v.where(0) && window.ternConsole.last.state", "the 3-D view drawing the aircraft")
    w, s = driver.execute_script("const c = window.ternConsole; return [c.view3d.view.where(0), c.last.state]")
    assert abs(w["ned"][0] - s["p_n"]) < 50 and abs(w["ned"][1] - s["p_e"]) < 50, f"the 3-D view's aircraft at {w['ned']}"
    print(f"3-D view: the aircraft at NED {[round(x) for x in w['ned']]} m, on the canvas at {[round(x) for x in w['screen']]} px")


def check_charts(driver):
    wait_for(driver, "return window.ternConsole && window.ternConsole.frames > 5", "telemetry frames")
    js = "const c = window.ternConsole; return [c.frames, c.last.t, document.querySelectorAll('#charts .uplot').length]"
    f0, t0, n = driver.execute_script(js)
    time.sleep(1.5)
    f1, t1, _ = driver.execute_script(js)
    assert n == 6, f"{n} charts"
    assert f1 - f0 >= 20, f"only {f1 - f0} frames in 1.5 s (20-50 Hz expected)"
    assert 1.0 < t1 - t0 < 2.5, f"flight time went {t1 - t0:.2f} s in 1.5 s of wall time (--realtime)"
    points = driver.execute_script("return document.querySelector('#chart_roll').querySelector('canvas').width")
    assert points > 0
    print(f"charts: {f1 - f0} frames in 1.5 s, flight time {t0:.1f} -> {t1:.1f} s")


def move_slider(driver):
    slider = driver.find_element(By.CSS_SELECTOR, '.param[data-name^="slc."] input[type=range]:not([disabled])')
    name = slider.find_element(By.XPATH, "..").get_attribute("data-name")
    before = float(slider.get_attribute("value"))
    for _ in range(10):
        slider.send_keys(Keys.ARROW_RIGHT)
    wait_for(driver, f"return document.getElementById('status').textContent.startsWith('{name} = ')", "the console's ack")
    after = float(slider.get_attribute("value"))
    assert after > before, f"{name}: slider did not move ({before} -> {after})"
    driver.find_element(By.TAG_NAME, "header").click()  # focus off the slider: the keys are sticks again
    print(f"slider: {name} {before} -> {after}")
    return name, after


def hold(driver, key, seconds, probe):
    """Holds `key` for `seconds`; returns the last value of the JS expression `probe`."""
    ActionChains(driver).key_down(key).perform()
    time.sleep(seconds)
    v = driver.execute_script("return " + probe)
    ActionChains(driver).key_up(key).perform()
    return v


def fly_gamepad(driver, probe):
    """The Gamepad API as the stick source, with a virtual pad (headless Chromium has no real one):
    right stick half left and half back (mode 2: roll -0.5, pitch +0.5, nose up)."""
    driver.execute_script("""
        navigator.getGamepads = () => [{id: 'virtual pad', axes: [0, 0, -0.5, 0.5], buttons: []}];
        document.getElementById('source').value = 'gamepad';""")
    time.sleep(0.6)
    v = driver.execute_script("return " + probe)
    driver.execute_script("document.getElementById('source').value = 'keyboard';")
    return v


def fly_manual(driver):
    body = driver.find_element(By.TAG_NAME, "body")
    ActionChains(driver).move_to_element(body).perform()
    ActionChains(driver).send_keys("m").perform()
    wait_for(driver, "return window.ternConsole.last.rc && window.ternConsole.last.rc.override", "the override on rc")
    probe = "[window.ternConsole.last.actuators.delta_a, window.ternConsole.last.actuators.delta_e, window.ternConsole.last.state.phi]"
    # full aileron rolls the Anaconda at 2-3 rad/s: right, back through level, right again
    right = hold(driver, Keys.ARROW_RIGHT, 0.6, probe)
    left = hold(driver, Keys.ARROW_LEFT, 1.2, probe)
    hold(driver, Keys.ARROW_RIGHT, 0.6, probe)
    pull = hold(driver, Keys.ARROW_DOWN, 1.3, probe)
    push = hold(driver, Keys.ARROW_UP, 1.3, probe)
    mode = driver.find_element(By.ID, "mode").text
    pad = fly_gamepad(driver, probe)
    ActionChains(driver).send_keys("m").perform()
    wait_for(driver, "return window.ternConsole.last.rc && !window.ternConsole.last.rc.override", "the override off")
    assert mode == "MANUAL", mode
    assert right[0] > 0.1 and left[0] < -0.1, f"aileron {right[0]} / {left[0]} rad with the roll stick full right / left"
    assert 0.15 < right[2] < 3.0, f"roll {right[2]} rad after 0.6 s of right stick"
    assert pull[1] < -0.1 and push[1] > 0.1, f"elevator {pull[1]} / {push[1]} rad with the stick pulled / pushed"
    assert pad[0] < -0.1 and pad[1] < -0.1, f"aileron, elevator {pad[0]}, {pad[1]} rad with the gamepad's right stick left and back"
    print(f"manual: aileron {right[0]:.3f} / {left[0]:.3f} rad, roll {right[2]:.2f} rad, elevator {pull[1]:.3f} / {push[1]:.3f} rad; "
          f"gamepad: aileron {pad[0]:.3f}, elevator {pad[1]:.3f} rad; back to auto")


def check_params_csv(log_dir, name, value):
    runs = glob.glob(os.path.join(log_dir, "*", "params.csv"))  # the serve check flies none
    assert len(runs) == 1, runs
    with open(runs[0]) as f:
        rows = [r for r in csv.DictReader(f) if r["parameter"] == name and r["source"] == "console"]
    assert rows, f"no console change of {name} in {runs[0]}"
    assert abs(float(rows[-1]["value"]) - value) < 1e-9 * max(1.0, abs(value)), rows[-1]
    print(f"params.csv: {name} = {rows[-1]['value']} at t = {rows[-1]['t [s]']} s (console)")


def check_serve_console(tern, mission, log_dir):
    sock = os.path.join(log_dir, "serve.sock")
    serve = subprocess.Popen([tern, "serve", mission, "--realtime", "--console", "--socket", sock, "--log-dir", log_dir],
                             stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        for _ in range(100):
            if os.path.exists(sock):
                break
            time.sleep(0.1)
        out = subprocess.run([tern, "console", "--socket", sock], capture_output=True, text=True, timeout=10)
        assert out.returncode == 0 and out.stdout.startswith("console: http://127.0.0.1:"), out
        url = out.stdout.split(" ", 1)[1].strip()
        assert status(url) == 200 and status(url.split("?")[0]) == 403, url
        subprocess.run([tern, "remote", "quit", "--socket", sock], capture_output=True, timeout=10)
        serve.wait(timeout=10)
    finally:
        if serve.poll() is None:
            serve.kill()
    print("tern console: the server's URL, 200 with its token, 403 without")


def main():
    tern, mission = sys.argv[1], sys.argv[2]
    shot = sys.argv[3] if len(sys.argv) > 3 else None
    log_dir = tempfile.mkdtemp(prefix="tern_console_")
    started = time.time()
    check_serve_console(tern, mission, log_dir)
    proc, url = start_flight(tern, mission, log_dir)
    driver = None
    try:
        check_token(url)
        try:
            driver = browser()
        except Exception as e:  # noqa: BLE001 (the browser cannot start here: say why)
            proc.kill()
            skip(f"headless Chromium does not start here: {str(e).splitlines()[0]}")
        driver.get(url)
        check_view3d(driver)
        # the rest without the 3-D view: compositing a WebGL canvas in software (no GPU here) slows
        # headless Chromium's input and scripts more than the pilot checks' timing allows
        driver.get(url + "&view3d=0")
        check_charts(driver)
        name, value = move_slider(driver)
        fly_manual(driver)
        if shot:
            time.sleep(2)
            driver.save_screenshot(shot)
            print("screenshot:", shot)
    finally:
        if driver:
            driver.quit()
        if proc.poll() is None:
            proc.send_signal(signal.SIGINT)
        proc.wait(timeout=20)
    check_params_csv(log_dir, name, value)
    shutil.rmtree(log_dir, ignore_errors=True)
    print(f"ok in {time.time() - started:.0f} s")


if __name__ == "__main__":
    main()
