"""The dashboard in a real headless browser (Debian's chromium, driven through chromedriver by
Selenium): submit a small `partitioned` job from the form, see preview frames arrive, a
partition tile change and the convergence plot draw the combined and the partitions' error
curves, download the EXR, which must equal what `partita get` fetches over gRPC;
see a `pt` job's convergence plot gain points, and cancel it. Screenshots go to $PARTITA_ARTIFACTS/dashboard/.

Chromium and chromedriver are started by the test and addressed by IP (a fresh minimal root has
no /etc/hosts: "localhost" does not resolve there). Where Chromium, chromedriver or Selenium is
missing, the whole class is skipped saying which (ctest shows it as skipped, never as passed)."""
from __future__ import annotations

import os
import shutil
import socket
import subprocess
import tempfile
import time
import unittest
from pathlib import Path

from dashboard_util import DashboardDaemon, artifacts_dir, main

CHROMIUM = "/usr/bin/chromium"
CHROMEDRIVER = "/usr/bin/chromedriver"


def browser_missing() -> str:
    for path in (CHROMIUM, CHROMEDRIVER):
        if not os.access(path, os.X_OK):
            return f"{path} is not installed (Debian packages chromium, chromium-driver)"
    try:
        import selenium  # noqa: F401
    except ImportError:
        return "python3-selenium is not installed"
    return ""


# A fresh minimal root has no /etc/hosts, so "localhost" does not resolve there: chromedriver
# and Chromium are started here and addressed by IP, never by that name (Selenium's own Service
# polls "localhost", and chromedriver reaches a Chromium it starts itself at "localhost").


def free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


def wait_until(ready, process, what, timeout=30):
    """ready() until it returns a value, while `process` runs; RuntimeError naming `what`."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        value = ready()
        if value:
            return value
        if process.poll() is not None:
            break
        time.sleep(0.1)
    process.kill()
    raise RuntimeError(f"{what} (exit {process.poll()})")


def listening(port):
    try:
        socket.create_connection(("127.0.0.1", port), timeout=1).close()
        return True
    except OSError:
        return False


def start_chromedriver():
    """chromedriver on a free loopback port: the process and the address to drive it at."""
    port = free_port()
    process = subprocess.Popen([CHROMEDRIVER, f"--port={port}", "--allowed-ips=127.0.0.1"],
                               stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    wait_until(lambda: listening(port), process, f"chromedriver did not listen on port {port}")
    return process, f"http://127.0.0.1:{port}"


def start_chromium(profile):
    """Headless Chromium with its DevTools on 127.0.0.1 (a port it picks and writes to
    DevToolsActivePort in its profile): the process and the DevTools address."""
    process = subprocess.Popen(
        [CHROMIUM, "--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
         "--window-size=1400,1100", "--remote-debugging-address=127.0.0.1",
         "--remote-debugging-port=0", "--user-data-dir=" + profile, "about:blank"],
        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    active = Path(profile) / "DevToolsActivePort"

    def port():
        try:
            first = active.read_text().splitlines()[0]
            return int(first) if first.strip() and listening(int(first)) else 0
        except (OSError, IndexError, ValueError):
            return 0

    return process, f"127.0.0.1:{wait_until(port, process, 'Chromium opened no DevTools port')}"


def wait_for(condition, timeout, what):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        value = condition()
        if value:
            return value
        time.sleep(0.1)
    raise AssertionError(f"timed out after {timeout} s waiting for {what}")


class DashboardBrowserTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        reason = browser_missing()
        if reason:
            raise unittest.SkipTest(reason)
        from selenium import webdriver

        cls.server = DashboardDaemon()
        cls.profile = tempfile.mkdtemp(prefix="partita-chromium-")
        cls.processes = []
        try:
            cls.chromium, devtools = start_chromium(cls.profile)
            cls.processes.append(cls.chromium)
            cls.chromedriver, address = start_chromedriver()
            cls.processes.append(cls.chromedriver)
            # chromedriver attaches to the running Chromium at its DevTools address.
            options = webdriver.ChromeOptions()
            options.binary_location = CHROMIUM
            options.add_experimental_option("debuggerAddress", devtools)
            cls.driver = webdriver.Remote(command_executor=address, options=options)
        except Exception:
            cls.stop_processes()
            raise
        cls.driver.set_page_load_timeout(30)

    @classmethod
    def stop_processes(cls):
        for process in reversed(cls.processes):
            process.terminate()
            try:
                process.wait(timeout=10)
            except subprocess.TimeoutExpired:
                process.kill()
        cls.server.stop()
        shutil.rmtree(cls.profile, ignore_errors=True)

    @classmethod
    def tearDownClass(cls):
        cls.driver.quit()  # attached: this ends the session, not Chromium
        cls.stop_processes()

    def find(self, css):
        from selenium.webdriver.common.by import By
        return self.driver.find_element(By.CSS_SELECTOR, css)

    def screenshot(self, name):
        self.driver.save_screenshot(str(artifacts_dir() / name))

    def set_field(self, css, value):
        field = self.find(css)
        field.clear()
        field.send_keys(str(value))

    def submit_from_form(self, algorithm, seconds, width, height, extra=None, upload=None):
        from selenium.webdriver.support.ui import Select
        self.driver.get(self.server.base + "/")
        wait_for(lambda: len(self.driver.find_elements("css selector", "#algorithm option")) > 1,
                 20, "the algorithms from /api/info")
        Select(self.find("#scene")).select_by_value("cornell")
        Select(self.find("#algorithm")).select_by_value(algorithm)
        Select(self.find("#budget-kind")).select_by_value("BUDGET_KIND_SECONDS")
        self.set_field("#budget-amount", seconds)
        self.set_field("#param-width", width)
        self.set_field("#param-height", height)
        for name, value in (extra or {}).items():
            self.set_field("#param-" + name, value)
        if upload:
            # chromedriver runs on this machine: it reads the path itself (selenium would
            # otherwise try to send the file to a remote grid).
            from selenium.webdriver.remote.file_detector import UselessFileDetector
            self.driver.file_detector = UselessFileDetector()
            self.find("#upload").send_keys(str(upload))
        self.find("#submit-button").click()
        wait_for(lambda: "/job?id=" in self.driver.current_url, 20, "the job page")
        return self.driver.current_url.split("id=")[1]

    def state(self):
        return self.find("#state").text

    def test_submit_watch_and_download_a_partitioned_job(self):
        job_id = self.submit_from_form("partitioned", 8, 128, 96,
                                       {"k": 3, "preview_interval": 0.5})
        # Two frames at least, and a partition's tile replaced at least once after it appeared.
        wait_for(lambda: int(self.find("#combined").get_attribute("data-frames") or 0) >= 2, 60,
                 "two preview frames")
        wait_for(lambda: any(int(img.get_attribute("data-updates") or 0) >= 2
                             for img in self.driver.find_elements("css selector", "#tiles img")),
                 60, "a partition tile to change")
        rows = self.driver.find_elements("css selector", "#partitions tbody tr")
        self.assertGreaterEqual(len(rows), 2, "the partition table lists the partitions")
        # The convergence plot draws the combined image's curve and the partitions' curves.
        wait_for(lambda: int(self.find("#plot").get_attribute("data-curves") or 0) >= 2, 60,
                 "the combined and a partition's error curves")
        self.screenshot("job-rendering.png")
        wait_for(lambda: self.state() == "DONE", 90, "the job to finish")
        self.screenshot("job-done.png")

        # The page's EXR link is the one a user clicks; it must give partita get's bytes.
        link = self.find("#download-exr")
        self.assertNotIn("disabled", link.get_attribute("class"))
        href = link.get_attribute("href")
        status, _, exr = self.server.request("GET", href[len(self.server.base):])
        self.assertEqual(status, 200)
        with tempfile.TemporaryDirectory() as folder:
            out = Path(folder) / "got.exr"
            cli = os.environ["PARTITA_CLI_PATH"]
            subprocess.run([cli, "--server", self.server.daemon.address, "get", job_id,
                            "--out", str(out)], check=True, capture_output=True, timeout=60)
            self.assertEqual(exr, out.read_bytes(), "the dashboard's EXR equals partita get's")

        # The job list shows it, live.
        self.driver.get(self.server.base + "/")
        wait_for(lambda: self.driver.find_elements("css selector", f'tr[data-id="{job_id}"]'),
                 20, "the job in the list")
        self.assertIn("DONE", self.find(f'tr[data-id="{job_id}"]').text)
        self.screenshot("jobs.png")

    def test_a_glb_chosen_in_the_form_is_streamed_and_renders(self):
        # The form streams the file to /api/uploads, then submits a job naming the upload.
        from test_dashboard_http import cornell_glb
        with tempfile.TemporaryDirectory() as folder:
            scene = Path(folder) / "box.glb"
            scene.write_bytes(cornell_glb())
            job_id = self.submit_from_form("pt", 1, 32, 24, upload=scene)
        wait_for(lambda: self.state() == "DONE", 60, "the uploaded scene's job to finish")
        status, job = self.server.json("GET", "/api/jobs/" + job_id)
        self.assertEqual(job["spec"]["scene_file"], "box.glb")
        self.assertIn("glb", job["spec"]["scene"])

    def test_convergence_plot_and_cancel_from_the_job_page(self):
        job_id = self.submit_from_form("pt", 600, 64, 48, {"preview_interval": 0.25})
        wait_for(lambda: self.state() == "RENDERING", 60, "the job to render")
        # pt reports its own error estimate (two interleaved halves) with its progress: the
        # plot gains points as the render goes on.
        plot = lambda: int(self.find("#plot").get_attribute("data-points") or 0)
        first = wait_for(plot, 60, "the convergence plot's first point")
        wait_for(lambda: plot() > first, 60, "the convergence plot to gain points")
        self.screenshot("job-convergence.png")
        self.find("#cancel").click()
        try:
            wait_for(lambda: self.state() == "CANCELLED", 30, "the job to be cancelled")
        except AssertionError:
            self.screenshot("cancel-failed.png")
            shutil.copy(self.server.daemon.log_path, artifacts_dir() / "partitad-cancel-failed.log")
            status, job = self.server.json("GET", "/api/jobs/" + job_id)
            raise AssertionError(f"page state {self.state()!r}, page error "
                                 f"{self.find('#error').text!r}, job {job.get('state')}")
        status, job = self.server.json("GET", "/api/jobs/" + job_id)
        self.assertEqual(job["state"], "JOB_STATE_CANCELLED")
        self.assertEqual(self.find("#cancel").get_attribute("disabled"), "true")


if __name__ == "__main__":
    main()
