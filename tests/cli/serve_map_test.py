#!/usr/bin/python3
"""geovor serve (issue 34), /map in a real browser: headless Chromium (Debian's chromium and
chromium-driver, driven by Selenium) loads the page from the server alone (Leaflet from
libjs-leaflet, the bundled countries, the cells and sites through OGC API - Features), then
clicks the map at several points; each answer shown must be the site GET /nearest gives for the
clicked position, and its distance. Exit 77 (skipped) when Chromium or Selenium is missing.
Usage: serve_map_test.py GEOVOR SITES.csv WORKDIR"""
import json
import os
import signal
import subprocess
import sys
import urllib.request

geovor, sites, work = sys.argv[1:4]
os.makedirs(work, exist_ok=True)
try:
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service
    from selenium.webdriver.common.by import By
    from selenium.webdriver.common.action_chains import ActionChains
    from selenium.webdriver.support.ui import WebDriverWait
except ImportError:
    print("serve_map_test: no python3-selenium; skipped")
    sys.exit(77)
if not (os.path.exists("/usr/bin/chromium") and os.path.exists("/usr/bin/chromedriver")):
    print("serve_map_test: no chromium / chromium-driver; skipped")
    sys.exit(77)

failures = []


def check(ok, what):
    if not ok:
        failures.append(what)


cells = os.path.join(work, "map_cells.geojson")
subprocess.run([geovor, "cells", sites, "-o", cells, "--overwrite", "-q"], check=True, capture_output=True)
server = subprocess.Popen([geovor, "serve", sites, "--cells", cells, "--port", "0", "-q"], stdout=subprocess.PIPE,
                          stderr=subprocess.PIPE, text=True)
driver = None
try:
    base = "http://" + server.stdout.readline().split("http://")[1].split("/")[0]
    options = webdriver.ChromeOptions()
    options.binary_location = "/usr/bin/chromium"
    for a in ["--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage", "--window-size=1000,700",
              "--user-data-dir=" + os.path.join(work, "chromium-profile")]:
        options.add_argument(a)
    driver = webdriver.Chrome(service=Service("/usr/bin/chromedriver"), options=options)
    driver.set_page_load_timeout(60)
    driver.get(base + "/map")
    answer = driver.find_element(By.ID, "answer")
    WebDriverWait(driver, 90).until(lambda d: answer.get_attribute("data-state") == "ready")
    check(driver.execute_script("return typeof L") == "object", "Leaflet loaded from the server")
    check(int(answer.get_attribute("data-cells")) > 5000, f"cells drawn: {answer.get_attribute('data-cells')}")
    check(int(answer.get_attribute("data-sites")) > 5000, f"sites drawn: {answer.get_attribute('data-sites')}")
    paths = driver.find_elements(By.CSS_SELECTOR, "path.leaflet-interactive")
    check(len(paths) > 100, f"{len(paths)} shapes on the map")
    the_map = driver.find_element(By.ID, "map")
    w, h = the_map.size["width"], the_map.size["height"]
    for dx, dy in [(0.5, 0.5), (0.3, 0.35), (0.7, 0.6), (0.55, 0.25)]:
        ActionChains(driver).move_to_element_with_offset(the_map, int(w * (dx - 0.5)), int(h * (dy - 0.5))).click().perform()
        WebDriverWait(driver, 30).until(lambda d: answer.get_attribute("data-state") == "answered")
        lat, lon = answer.get_attribute("data-lat"), answer.get_attribute("data-lon")
        with urllib.request.urlopen(f"{base}/nearest?lat={lat}&lon={lon}", timeout=10) as r:
            want = json.loads(r.read())["features"][0]["properties"]
        site = answer.get_attribute("data-site")
        check(site == str(want["site_index"]), f"click at {lat},{lon}: the page shows site {site}, /nearest {want['site_index']}")
        check(want["site_id"] in answer.text and f"{want['distance_m'] / 1000:.3f} km" in answer.text,
              f"click at {lat},{lon}: the page says {answer.text!r}, /nearest {want['site_id']} {want['distance_m']}")
        driver.execute_script("arguments[0].dataset.state = 'waiting'", answer)
    errors = [e for e in driver.get_log("browser") if e.get("level") == "SEVERE"]
    check(not errors, f"browser errors: {errors[:3]}")
finally:
    if driver:
        driver.quit()
    server.send_signal(signal.SIGTERM)
    try:
        server.wait(timeout=20)
    except subprocess.TimeoutExpired:
        server.kill()
for f in failures:
    print("FAIL:", f)
print(f"serve_map_test: {len(failures)} failures")
sys.exit(1 if failures else 0)
