#!/usr/bin/env python3
"""Times `raydiance preview` as a scene author sees it: from saving an edit of
scenes/cornell-area.scn to the first new image in the page, and to the scene's 64 spp, at the
page's default size (the scene's 256x256), in headless Chromium driven over WebDriver.

    cargo build --release && python3 examples/preview_latency.py [EDITS] [RAYDIANCE]

EDITS (default 5) saves, each swapping the spheres' materials; RAYDIANCE defaults to
target/release/raydiance (CARGO_TARGET_DIR is honoured). Needs Debian's chromium and
chromium-driver. The scene is copied to a temporary folder: the repository is not touched.
"""

import json
import os
import shutil
import socket
import statistics
import subprocess
import sys
import tempfile
import time
import urllib.request

EDITS = int(sys.argv[1]) if len(sys.argv) > 1 else 5
TARGET = os.environ.get("CARGO_TARGET_DIR", "target")
RAYDIANCE = sys.argv[2] if len(sys.argv) > 2 else os.path.join(TARGET, "release", "raydiance")

# Records, in the page, when its numbers change: the page puts each new image in place in the
# same task as its numbers.
OBSERVE = """
window.seen = [];
const $ = (id) => document.getElementById(id);
const note = () => seen.push([Date.now(), +$("render").textContent, +$("spp").textContent,
                              !$("glance").hidden]);
new MutationObserver(note).observe(document.querySelector("figcaption"),
                                   {subtree: true, childList: true, characterData: true});
"""


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def webdriver(url, body=None, method="POST"):
    data = None if body is None else json.dumps(body).encode()
    request = urllib.request.Request(url, data=data, method=method,
                                     headers={"Content-Type": "application/json"})
    with urllib.request.urlopen(request) as response:
        return json.load(response)["value"]


def save(path, text):
    """Saves as editors do: a new file renamed over the old one."""
    with open(path + ".new", "w") as f:
        f.write(text)
    os.replace(path + ".new", path)


def main():
    folder = tempfile.mkdtemp()
    for name in ("cornell-area.scn", "lab-box.inc"):
        shutil.copy(os.path.join("scenes", name), folder)
    scene = os.path.join(folder, "cornell-area.scn")
    text = open(scene).read()
    swapped = text.replace("Blue", "Other").replace("Yellow", "Blue").replace("Other", "Yellow")
    preview = subprocess.Popen([RAYDIANCE, "preview", scene, "--listen", "127.0.0.1:0"],
                               stdout=subprocess.PIPE, text=True)
    url = next(w for w in preview.stdout.readline().split() if w.startswith("http://"))
    port = free_port()
    driver = subprocess.Popen(["chromedriver", f"--port={port}"], stdout=subprocess.DEVNULL,
                              stderr=subprocess.DEVNULL)
    base = f"http://127.0.0.1:{port}"
    try:
        for _ in range(200):
            try:
                webdriver(base + "/status", method="GET")
                break
            except OSError:
                time.sleep(0.05)
        args = ["--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage"]
        session = webdriver(base + "/session", {"capabilities": {"alwaysMatch": {
            "browserName": "chrome", "goog:chromeOptions": {"args": args}}}})
        session = f"{base}/session/{session['sessionId']}"
        webdriver(session + "/url", {"url": url})
        webdriver(session + "/execute/sync", {"script": OBSERVE, "args": []})

        def seen():
            return webdriver(session + "/execute/sync", {"script": "return seen", "args": []})

        def wait_for_64(render):
            while not any(r == render and spp == 64 for _, r, spp, _ in seen()):
                time.sleep(0.02)

        wait_for_64(1)
        firsts, full_size, full = [], [], []
        for edit in range(EDITS):
            render = seen()[-1][1] + 1
            saved = time.time() * 1000
            save(scene, swapped if edit % 2 == 0 else text)
            wait_for_64(render)
            mine = [(t, spp, glance) for t, r, spp, glance in seen() if r >= render]
            first, last = mine[0], next(m for m in mine if m[1] == 64)
            sized = next(m for m in mine if not m[2])
            firsts.append(first[0] - saved)
            full_size.append(sized[0] - saved)
            full.append(last[0] - saved)
            kind = "a glance" if first[2] else f"{first[1]} spp"
            print(f"edit {edit + 1}: first image ({kind}) after {first[0] - saved:.0f} ms, "
                  f"first at full size after {sized[0] - saved:.0f} ms, "
                  f"64 spp after {last[0] - saved:.0f} ms")
        print(f"median of {EDITS}: first image {statistics.median(firsts):.0f} ms, first at "
              f"full size {statistics.median(full_size):.0f} ms, "
              f"64 spp {statistics.median(full):.0f} ms")
        webdriver(session, method="DELETE")
    finally:
        driver.kill()
        preview.kill()
        shutil.rmtree(folder)


if __name__ == "__main__":
    main()
