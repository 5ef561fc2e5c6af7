"""The dashboard's HTTP API against a real partitad on loopback: what it answers, and its
security rules (token, Host header, the X-Partita header on changes, path traversal, huge
headers, slow clients, non-UTF-8 input, a viewer that never reads). Plain http.client and
sockets: what any client could send."""
from __future__ import annotations

import json
import os
import socket
import struct
import subprocess
import tempfile
import threading
import time
import unittest
from pathlib import Path

from dashboard_util import DashboardDaemon, main

SMALL_PT = {"algorithm": "pt", "scene": {"scene_name": "cornell"},
            "parameters": {"width": {"int_value": "32"}, "height": {"int_value": "24"}},
            "budget": {"kind": "BUDGET_KIND_SAMPLES_PER_PIXEL", "amount": 4}}


def long_job(seconds=60, width=64, height=48, preview=None):
    spec = json.loads(json.dumps(SMALL_PT))
    spec["parameters"]["width"] = {"int_value": str(width)}
    spec["parameters"]["height"] = {"int_value": str(height)}
    spec["budget"] = {"kind": "BUDGET_KIND_SECONDS", "amount": seconds}
    if preview:
        spec["parameters"]["preview_interval"] = {"real_value": preview}
    return spec


def cornell_glb():
    """scenes/cornell as one .glb: the .gltf's JSON with its buffer inside (glTF 2.0 5.1)."""
    folder = Path(__file__).resolve().parents[2] / "scenes" / "cornell"
    doc = json.loads((folder / "cornell.gltf").read_text())
    binary = (folder / doc["buffers"][0].pop("uri")).read_bytes()
    binary += b"\0" * (-len(binary) % 4)
    text = json.dumps(doc).encode()
    text += b" " * (-len(text) % 4)
    chunks = (struct.pack("<II", len(text), 0x4E4F534A) + text +
              struct.pack("<II", len(binary), 0x004E4942) + binary)
    return b"glTF" + struct.pack("<II", 2, 12 + len(chunks)) + chunks


def vm_rss_kib(pid):
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1])
    raise AssertionError("no VmRSS")


class DashboardApiTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.server = DashboardDaemon()

    @classmethod
    def tearDownClass(cls):
        cls.server.stop()

    def wait_state(self, job_id, states, timeout=60):
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            status, job = self.server.json("GET", "/api/jobs/" + job_id)
            self.assertEqual(status, 200)
            if job["state"] in states:
                return job
            time.sleep(0.05)
        raise AssertionError(f"job {job_id} never reached {states}")

    def test_pages_and_static_files(self):
        for path, kind in (("/", "text/html"), ("/job?id=x", "text/html"),
                           ("/static/job.js", "text/javascript"), ("/static/style.css", "text/css")):
            status, headers, body = self.server.request("GET", path)
            self.assertEqual(status, 200, path)
            self.assertTrue(headers["Content-Type"].startswith(kind), path)
            self.assertIn("default-src 'self'", headers["Content-Security-Policy"])
            self.assertGreater(len(body), 100)

    def test_submit_follow_and_fetch(self):
        status, job = self.server.json("POST", "/api/jobs", SMALL_PT)
        self.assertEqual(status, 201, job)
        self.assertEqual(job["spec"]["algorithm"], "pt")
        done = self.wait_state(job["id"], ["JOB_STATE_DONE"])
        self.assertEqual(float(done["stats"]["spp"]), 4)
        status, headers, exr = self.server.request("GET", f"/api/jobs/{job['id']}/result.exr")
        self.assertEqual(status, 200)
        self.assertEqual(exr[:4], b"\x76\x2f\x31\x01", "an OpenEXR file")
        self.assertIn("attachment", headers["Content-Disposition"])
        status, headers, png = self.server.request("GET", f"/api/jobs/{job['id']}/preview.png")
        self.assertEqual((status, png[:4]), (200, b"\x89PNG"))
        status, listing = self.server.json("GET", "/api/jobs")
        self.assertIn(job["id"], [j["id"] for j in listing["jobs"]])
        # The event stream of a finished job: its state and its final frame, then it ends.
        status, _, body = self.server.request("GET", f"/api/jobs/{job['id']}/events")
        self.assertEqual(status, 200)
        events = [block.split("\n") for block in body.decode().strip().split("\n\n")]
        names = [lines[0] for lines in events]
        self.assertIn("event: state", names)
        frame = json.loads(events[names.index("event: frame")][1][len("data: "):])
        self.assertTrue(frame["final"])
        self.assertEqual(frame["layers"][0]["name"], "combined")

    def test_refusals_map_to_http_statuses(self):
        cases = [
            ("POST", "/api/jobs", b"{not json", 400, "INVALID_ARGUMENT"),
            ("POST", "/api/jobs", b"\xff\xfe\x00", 400, "INVALID_ARGUMENT"),
            ("POST", "/api/jobs", {"algorithm": "nope", "scene": {"scene_name": "cornell"}}, 400,
             "INVALID_ARGUMENT"),
            ("POST", "/api/jobs", {"algorithm": "pt", "scene": {"scene_name": "no-such-scene"}},
             404, "NOT_FOUND"),
            ("POST", "/api/jobs", {"algorithm": "pt", "scene": {"scene_name": "cornell"},
                                   "parameters": {"width": {"int_value": "100000000"}}}, 429,
             "RESOURCE_EXHAUSTED"),
            ("POST", "/api/jobs", {"algorithm": "pt", "frobnicate": 1}, 400, "INVALID_ARGUMENT"),
            ("GET", "/api/jobs/nope", None, 404, "NOT_FOUND"),
            ("POST", "/api/jobs/nope/cancel", None, 404, "NOT_FOUND"),
            ("DELETE", "/api/jobs/nope", None, 404, "NOT_FOUND"),
            ("GET", "/api/jobs/nope/events", None, 404, "NOT_FOUND"),
            ("GET", "/api/nothing-here", None, 404, "NOT_FOUND"),
        ]
        for method, path, body, want, code in cases:
            status, answer = self.server.json(method, path, body)
            self.assertEqual((status, answer["code"]), (want, code), (method, path, answer))
            self.assertTrue(answer["error"])
        # A lone surrogate in JSON is not text.
        status, answer = self.server.json(
            "POST", "/api/jobs", b'{"algorithm":"pt","label":"\\ud800","scene":{"scene_name":"cornell"}}',
            {"Content-Type": "application/json"})
        self.assertEqual(status, 400, answer)

    def test_result_before_done_and_delete_while_running(self):
        status, job = self.server.json("POST", "/api/jobs", long_job())
        self.assertEqual(status, 201)
        self.wait_state(job["id"], ["JOB_STATE_RENDERING"])
        status, answer = self.server.json("GET", f"/api/jobs/{job['id']}/result.exr")
        self.assertEqual((status, answer["code"]), (409, "FAILED_PRECONDITION"))
        status, answer = self.server.json("DELETE", f"/api/jobs/{job['id']}")
        self.assertEqual((status, answer["code"]), (409, "FAILED_PRECONDITION"))
        status, cancelled = self.server.json("POST", f"/api/jobs/{job['id']}/cancel")
        self.assertEqual(status, 200)
        self.wait_state(job["id"], ["JOB_STATE_CANCELLED"])
        status, _ = self.server.json("DELETE", f"/api/jobs/{job['id']}")
        self.assertEqual(status, 204)
        status, _ = self.server.json("GET", f"/api/jobs/{job['id']}")
        self.assertEqual(status, 404)

    def test_changes_need_the_partita_header(self):
        # A form or a simple cross-origin request cannot carry it.
        status, answer = self.server.json("POST", "/api/jobs", SMALL_PT, {"X-Partita": "0"})
        self.assertEqual((status, answer["code"]), (403, "PERMISSION_DENIED"))

    def test_host_must_be_loopback(self):
        for host in ("evil.example", "192.168.1.10:80", "127.0.0.1.evil.example"):
            status, answer = self.server.json("GET", "/api/jobs", headers={"Host": host})
            self.assertEqual((status, answer["code"]), (403, "PERMISSION_DENIED"), host)
        for host in ("localhost", f"127.0.0.1:{self.server.port}", f"[::1]:{self.server.port}"):
            status, _ = self.server.json("GET", "/api/jobs", headers={"Host": host})
            self.assertEqual(status, 200, host)

    def test_no_path_reaches_the_file_system(self):
        for path in ("/static/../../../../etc/passwd", "/static/..%2f..%2fetc%2fpasswd",
                     "/static/%2e%2e/%2e%2e/etc/passwd", "/static/index.html",
                     "/static/../CMakeLists.txt", "//etc/passwd",
                     "/api/jobs/..%2f..%2f..%2fetc/result.exr", "/api/jobs/../../etc/passwd"):
            status, _, body = self.server.request("GET", path)
            self.assertIn(status, (400, 404), path)
            self.assertNotIn(b"root:", body, path)

    def test_a_scene_streams_to_uploads_and_jobs_name_it(self):
        glb = cornell_glb()
        status, uploaded = self.server.json("POST", "/api/uploads", glb,
                                            {"Content-Type": "model/gltf-binary"})
        self.assertEqual(status, 201, uploaded)
        self.assertEqual(int(uploaded["bytes"]), len(glb))
        spec = json.loads(json.dumps(SMALL_PT))
        spec["scene"] = {"upload_id": uploaded["upload_id"]}
        spec["scene_file"] = "cornell.glb"
        status, job = self.server.json("POST", "/api/jobs", spec)
        self.assertEqual(status, 201, job)
        self.assertEqual(self.wait_state(job["id"], ["JOB_STATE_DONE"])["state"], "JOB_STATE_DONE")
        # Refused: a change without the dashboard's header, a body without a length, and a
        # JSON body over the limit, before it is read (uploads go to /api/uploads).
        status, _, _ = self.server.request("POST", "/api/uploads", glb, {"X-Partita": "0"})
        self.assertEqual(status, 403)
        status, answer = self.server.json("POST", "/api/uploads", b"")
        self.assertEqual((status, answer["code"]), (400, "INVALID_ARGUMENT"), answer)
        status, answer = self.server.json("POST", "/api/jobs", b"{" + b" " * (8 << 20) + b"}",
                                          {"Content-Type": "application/json"})
        self.assertEqual((status, answer["code"]), (429, "RESOURCE_EXHAUSTED"), answer)
        self.assertIn("/api/uploads", answer["error"])

    def test_huge_headers_and_bodies_are_refused(self):
        status, _, _ = self.server.request("GET", "/api/jobs", headers={"X-Big": "a" * 200000})
        self.assertGreaterEqual(status, 400)
        status, _, _ = self.server.request("GET", "/" + "a" * 100000)
        self.assertGreaterEqual(status, 400)
        status, _ = self.server.json("GET", "/api/info")
        self.assertEqual(status, 200, "still serving")

    def test_slow_clients_are_bounded_and_the_daemon_keeps_serving(self):
        # Clients that open connections and trickle a header: each holds one of the dashboard's
        # bounded threads, never memory beyond a header; gRPC is not touched, and once they go the
        # dashboard serves again.
        from partita_client import Client
        pid = self.server.daemon.process.pid
        before = vm_rss_kib(pid)
        sockets = []
        for _ in range(64):
            s = socket.create_connection(("127.0.0.1", self.server.port))
            s.sendall(b"GET /api/jobs HTTP/1.1\r\nHost: localhost\r\n")
            sockets.append(s)
        for round_ in range(3):
            time.sleep(1)
            for s in sockets:
                try:
                    s.sendall(b"X-Slow: %d\r\n" % round_)
                except OSError:
                    pass
        info = Client(self.server.daemon.address).server_info()
        self.assertGreater(info.threads, 0, "gRPC serves during the attack")
        during = vm_rss_kib(pid)
        for s in sockets:
            s.close()
        deadline = time.monotonic() + 30
        while time.monotonic() < deadline:
            try:
                status, _ = self.server.json("GET", "/api/info")
                if status == 200:
                    break
            except OSError:
                pass
            time.sleep(0.2)
        else:
            self.fail("the dashboard did not serve again after the slow clients left")
        # 64 connections' buffers and 32 threads' stacks in use: far below a job's memory.
        self.assertLess(during - before, 64 * 1024, "slow clients cost under 64 MiB")

    def test_a_viewer_that_never_reads_is_dropped(self):
        # A browser tab that stops reading (tiny receive buffer, never reads) while a job sends
        # frames every 0.05 s: it holds at most one frame, the render goes on, and the stream
        # is dropped after the write timeout.
        status, job = self.server.json("POST", "/api/jobs", long_job(8, 256, 192, preview=0.05))
        self.assertEqual(status, 201)
        stalled = socket.socket()
        stalled.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
        stalled.connect(("127.0.0.1", self.server.port))
        stalled.sendall(f"GET /api/jobs/{job['id']}/events HTTP/1.1\r\nHost: localhost\r\n\r\n"
                        .encode())
        pid = self.server.daemon.process.pid
        before = vm_rss_kib(pid)
        peak = before
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline:
            peak = max(peak, vm_rss_kib(pid))
            status, now = self.server.json("GET", f"/api/jobs/{job['id']}")
            if now["state"] == "JOB_STATE_DONE":
                break
            time.sleep(0.1)
        self.assertEqual(now["state"], "JOB_STATE_DONE", "the render went on")
        log = self.server.daemon.log_path
        deadline = time.monotonic() + 30
        while time.monotonic() < deadline and b"event stream to" not in log.read_bytes():
            time.sleep(0.2)
        self.assertIn(f"[job {job['id']}] event stream to", log.read_text(errors="replace"))
        stalled.close()
        # One 256x192 frame of a few layers is under 2 MiB of PNG; the job itself holds more.
        self.assertLess(peak - before, 256 * 1024)


class DashboardTokenTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.folder = tempfile.TemporaryDirectory()
        token = Path(cls.folder.name) / "token"
        token.write_text("s3cret-token\n")
        cls.server = DashboardDaemon(extra_args=["--token-file", str(token)])

    @classmethod
    def tearDownClass(cls):
        cls.server.stop()
        cls.folder.cleanup()

    def test_every_request_needs_the_token(self):
        for path in ("/", "/static/job.js", "/api/jobs", "/api/info", "/api/jobs/x/events"):
            status, _, body = self.server.request("GET", path)
            self.assertEqual(status, 401, path)
            self.assertNotIn(b"s3cret", body)
        status, _, _ = self.server.request("GET", "/api/jobs",
                                           headers={"Authorization": "Bearer wrong"})
        self.assertEqual(status, 401)
        status, _, _ = self.server.request("GET", "/api/jobs",
                                           headers={"Authorization": "Bearer s3cret-token"})
        self.assertEqual(status, 200)

    def test_a_token_in_the_address_logs_the_browser_in(self):
        status, headers, _ = self.server.request("GET", "/?token=s3cret-token")
        self.assertEqual(status, 200)
        cookie = headers["Set-Cookie"]
        self.assertIn("HttpOnly", cookie)
        self.assertIn("SameSite=Strict", cookie)
        value = cookie.split(";")[0]
        status, _, _ = self.server.request("GET", "/api/jobs", headers={"Cookie": value})
        self.assertEqual(status, 200)
        status, _, _ = self.server.request("GET", "/api/jobs",
                                           headers={"Cookie": "partita_token=wrong"})
        self.assertEqual(status, 401)


class DashboardStartTest(unittest.TestCase):
    def test_off_loopback_without_tls_and_token_is_refused_at_start(self):
        partitad = os.environ["PARTITA_PARTITAD"]
        with tempfile.TemporaryDirectory() as folder:
            for address in ("0.0.0.0:0", "[::]:0", "192.0.2.1:8080"):
                proc = subprocess.run([partitad, "--listen", "127.0.0.1:0", "--store", folder,
                                       "--http", address], capture_output=True, text=True,
                                      timeout=30)
                self.assertEqual(proc.returncode, 2, proc.stderr)
                self.assertIn("refusing to serve the dashboard", proc.stderr)
            proc = subprocess.run([partitad, "--listen", "127.0.0.1:0", "--store", folder,
                                   "--http", "unix:/tmp/x"], capture_output=True, text=True,
                                  timeout=30)
            self.assertEqual(proc.returncode, 2)
            self.assertIn("--http takes host:port", proc.stderr)


if __name__ == "__main__":
    main()
