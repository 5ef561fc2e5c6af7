"""The Python client against a real partitad (started once for the suite by LocalDaemon).

Run: PYTHONPATH=<build>/python:client/python PARTITA_PARTITAD=<build>/server/partitad \
     /usr/bin/python3 -m unittest discover -s client/python/tests
(ctest runs it as partita-client-python with exactly that environment.)
"""

from __future__ import annotations

import csv
import json
import os
import subprocess
import sys
import tempfile
import unittest
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
CLIENT_DIR = HERE.parent
sys.path.insert(0, str(CLIENT_DIR))

from partita_client import (Client, LocalDaemon, PartitaError, PreviewEvent,  # noqa: E402
                            ProgressEvent, StateEvent, read_exr, rel_mse, rmse)
from partita_client._stubs import pb2  # noqa: E402
from partita_client.client import job_spec  # noqa: E402

REPO = CLIENT_DIR.parents[1]
SCENES = Path(os.environ.get("PARTITA_SCENE_ROOT", REPO / "scenes"))
CORNELL = SCENES / "cornell" / "cornell.gltf"
TINY = dict(width=32, height=24, spp=2)


class ClientTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.daemon = LocalDaemon(scene_root=SCENES, threads=2)
        cls.client = Client(cls.daemon.address)

    @classmethod
    def tearDownClass(cls):
        cls.client.close()
        cls.daemon.stop()

    def test_submit_watch_result(self):
        job = self.client.submit(CORNELL, algorithm="pt", label="py-basic", **TINY)
        events = list(self.client.watch(job, previews=True))
        self.assertIsInstance(events[0], StateEvent)
        states = [e.job.state for e in events if isinstance(e, StateEvent)]
        self.assertEqual(states[-1], "done", states)
        self.assertTrue(all(e.progress.unit for e in events if isinstance(e, ProgressEvent)))
        previews = [e for e in events if isinstance(e, PreviewEvent)]
        if previews:  # a frame carries PNGs, not raw pixels unless asked
            self.assertIn("combined", previews[-1].layers)
            self.assertTrue(previews[-1].layers["combined"].png.startswith(b"\x89PNG"))
            self.assertIsNone(previews[-1].layers["combined"].rgb)

        layers = self.client.result(job)
        self.assertEqual(next(iter(layers)), "combined")
        self.assertGreater(len(layers), 1)
        for name, img in layers.items():
            self.assertEqual(img.shape, (24, 32, 3), name)
            self.assertEqual(img.dtype, np.float32, name)
            self.assertTrue(np.all(np.isfinite(img)), name)
        combined = layers["combined"]
        self.assertGreater(float(combined.mean()), 0.0)
        total = sum(img for name, img in layers.items() if name != "combined")
        np.testing.assert_allclose(total, combined, rtol=1e-4, atol=1e-5)

        info = self.client.job(job)
        self.assertEqual(info.state, "done")
        self.assertEqual(info.label, "py-basic")
        self.assertEqual(info.scene, Path(CORNELL).name)  # an upload keeps its file's name
        self.assertIsNotNone(info.seconds)
        meta = self.client.metadata(job)
        self.assertIsInstance(meta, dict)

    def test_one_upload_serves_several_jobs(self):
        # A file is streamed ahead of its jobs (UploadScene); jobs name the upload by its id.
        upload_id = self.client.upload(CORNELL)
        self.assertRegex(upload_id, r"^[0-9a-f]{16}$")
        a = self.client.submit("cornell", seed=3, **TINY)
        spec = job_spec("cornell", seed=3, **TINY)
        spec.scene.upload_id = upload_id
        b = self.client._call("SubmitJob", pb2.SubmitJobRequest(spec=spec), "submit").job_id
        np.testing.assert_array_equal(self.client.result(a)["combined"],
                                      self.client.result(b)["combined"])
        with self.assertRaises(PartitaError) as e:  # an id the server never gave
            spec.scene.upload_id = "0123456789abcdef"
            self.client._call("SubmitJob", pb2.SubmitJobRequest(spec=spec), "submit")
        self.assertIn("upload the scene again", str(e.exception))

    def test_an_upload_waits_while_the_server_receives_as_many_as_it_takes(self):
        import threading
        import time
        # Hold all of the server's upload places (4) with streams that sent half their bytes.
        release = threading.Event()

        def held():
            header = pb2.UploadHeader(format=pb2.SCENE_FORMAT_GLB, scene_bytes=10)
            yield pb2.UploadChunk(header=header, data=b"01234")
            release.wait(60)
            yield pb2.UploadChunk(data=b"56789")

        places = self.client.server_info().limits.max_upload_streams
        uploads = self.daemon.store / "uploads"
        before = set(uploads.iterdir())  # finished uploads of other tests stay until they expire
        holders = [self.client._stub.UploadScene.future(held()) for _ in range(places)]
        admitted = lambda: len(set(uploads.iterdir()) - before)
        deadline = time.monotonic() + 20
        while admitted() < places and time.monotonic() < deadline:
            time.sleep(0.02)
        self.assertEqual(admitted(), places, "the held streams are admitted")
        result = {}
        waiter = threading.Thread(target=lambda: result.update(id=self.client.upload(CORNELL)))
        waiter.start()
        waiter.join(1.0)
        self.assertTrue(waiter.is_alive(), "the upload waits for a place")
        release.set()
        waiter.join(60)
        self.assertRegex(result.get("id", ""), r"^[0-9a-f]{16}$")
        for h in holders:
            self.assertTrue(h.result(timeout=30).upload_id)

    def test_raw_final_preview_matches_result(self):
        job = self.client.submit("cornell", **TINY)
        frames = [e for e in self.client.watch(job, previews=True, raw=True)
                  if isinstance(e, PreviewEvent)]
        self.assertTrue(frames, "no preview frame at all")
        final = [f for f in frames if f.final]
        self.assertTrue(final, "no final frame")
        raw = final[-1].layers["combined"].rgb
        self.assertEqual(raw.shape, (24, 32, 3))
        np.testing.assert_allclose(raw, self.client.result(job)["combined"], rtol=1e-6, atol=1e-7)

    def test_scene_by_name_and_wait(self):
        job = self.client.submit("cornell", seed=3, max_depth=2, **TINY)
        done = self.client.wait(job)
        self.assertEqual(done.state, "done")
        self.assertEqual(done.scene, "cornell")

    def test_bdpt_renders_the_point_light_caustic(self):
        job = self.client.submit("cornell-point", algorithm="bdpt", **TINY)
        self.assertEqual(self.client.wait(job).state, "done")
        layers = self.client.result(job)
        self.assertIn("LSSDE", layers)  # light tracing reaches what pt cannot
        self.assertGreater(float(layers["LSSDE"].sum()), 0.0)

    def watch_from_the_queue(self, job_after):
        """Events of the job `job_after()` submits, watched from QUEUED on: two long jobs fill
        the daemon's two slots first, so the watch joins before the job starts (a quick job
        could otherwise pass its pre-pass before a watch on a busy machine joins)."""
        blockers = [self.client.submit("cornell", algorithm="pt", seconds=120, width=16,
                                       height=12) for _ in range(2)]
        job = job_after()
        events = self.client.watch(job)
        first = next(events)
        self.assertEqual(first.job.state, "queued")
        for blocker in blockers:
            self.client.cancel(blocker)
        return job, [first] + list(events)

    def test_mlt_progress_carries_its_phases_and_acceptance(self):
        job, events = self.watch_from_the_queue(lambda: self.client.submit(
            "cornell", algorithm="mlt", mpp=4, width=16, height=12, seed=2))
        states = [e.job.state for e in events if isinstance(e, StateEvent)]
        self.assertEqual(states[-1], "done", states)
        self.assertIn("prepass", states)  # the bootstrap
        progress = [e.progress for e in events if isinstance(e, ProgressEvent)]
        phases = [p.phase for p in progress]
        self.assertIn("bootstrap", phases)
        self.assertEqual(phases[-1], "render", phases)
        self.assertEqual(phases, sorted(phases), "the bootstrap comes first")
        last = progress[-1]
        self.assertEqual(last.unit, "mutations")
        self.assertEqual(last.done, 16 * 12 * 4)
        self.assertEqual(last.fraction, 1.0)
        self.assertGreater(last.rate_per_second, 0.0)
        self.assertGreaterEqual(last.eta_seconds, 0.0)
        self.assertEqual(last.values["mutations"], 16 * 12 * 4)
        self.assertIn("bidirectional", last.acceptance)
        self.assertIn("lens", last.acceptance)
        for name, rate in last.acceptance.items():
            self.assertTrue(0.0 <= rate <= 1.0, (name, rate))
            self.assertEqual(last.values["acceptance_" + name], rate)
        self.assertEqual(next(p for p in progress if p.phase == "bootstrap").acceptance, {})

        stats = self.client.metadata(job)["stats"]
        self.assertEqual(stats["acceptance_lens"], last.acceptance["lens"])
        self.assertGreater(stats["b"], 0.0)
        layers = self.client.result(job)
        self.assertEqual(layers["combined"].shape, (12, 16, 3))
        self.assertGreater(len(layers), 1)  # per-type layers
        with self.assertRaises(PartitaError) as ctx:
            self.client.submit("cornell", algorithm="mlt", spp=4, width=16, height=12)
        self.assertEqual(ctx.exception.code, "INVALID_ARGUMENT")
        self.assertIn("mutations per pixel or seconds", str(ctx.exception))

    def test_target_error_stops_a_pt_job_at_its_estimate(self):
        # pt estimates its own error (two interleaved halves) and stops once it reaches the
        # target: long before the 65536 samples a pixel it may take.
        job = self.client.submit("cornell", algorithm="pt", spp=65536, width=16, height=12,
                                 seed=2, target_error=0.25)
        events = list(self.client.watch(job))
        states = [e.job.state for e in events if isinstance(e, StateEvent)]
        self.assertEqual(states[-1], "done", states)
        estimates = [e.progress.values["error_estimate"] for e in events
                     if isinstance(e, ProgressEvent) and "error_estimate" in e.progress.values]
        self.assertTrue(estimates, "progress carries the error estimate")
        stats = self.client.metadata(job)["stats"]
        self.assertEqual(stats["reached_target_error"], 1.0)
        self.assertLessEqual(stats["error_estimate"], 0.25)
        self.assertLess(stats["spp"], 65536)

    def test_target_error_stops_an_mlt_job_at_its_estimate(self):
        # mlt estimates its own error (two halves of its chains, b's error, two halves of its
        # direct light) and stops there: long before its 4096 mutations a pixel.
        job = self.client.submit("cornell", algorithm="mlt", mpp=4096, width=16, height=12,
                                 seed=2, bootstrap=20000, target_error=0.3)
        events = list(self.client.watch(job))
        states = [e.job.state for e in events if isinstance(e, StateEvent)]
        self.assertEqual(states[-1], "done", states)
        stats = self.client.metadata(job)["stats"]
        self.assertEqual(stats["reached_target_error"], 1.0)
        self.assertLessEqual(stats["error_estimate"], 0.3)
        self.assertLess(stats["mpp"], 4096)

    def test_partitioned_progress_carries_its_partitions(self):
        job, events = self.watch_from_the_queue(lambda: self.client.submit(
            "cornell-glass", algorithm="partitioned", mpp=16, width=16, height=12, seed=2, k=3,
            prepass="pt", bootstrap_samples=4000))
        states = [e.job.state for e in events if isinstance(e, StateEvent)]
        self.assertEqual(states[-1], "done", states)
        self.assertIn("prepass", states)
        progress = [e.progress for e in events if isinstance(e, ProgressEvent)]
        self.assertEqual(progress[0].phase, "prepass")
        self.assertEqual(progress[-1].phase, "render")
        self.assertTrue(all(not p.partitions for p in progress if p.phase == "prepass"))
        last = progress[-1]
        self.assertGreaterEqual(len(last.partitions), 2)
        self.assertEqual(last.partitions[-1].type, "complement")
        self.assertAlmostEqual(sum(p.p for p in last.partitions), 1.0, places=9)
        for part in last.partitions:
            self.assertGreater(part.b, 0.0, part)
            self.assertTrue(0.0 <= part.acceptance <= 1.0, part)
            self.assertGreater(part.gamma, 0.0, part)
        meta = self.client.metadata(job)
        self.assertEqual(meta["parameters"]["prepass"], "pt")
        self.assertEqual(meta["parameters"]["bootstrap"], 4000)
        self.assertEqual(meta["stats"]["partition_0_p"], last.partitions[0].p)
        layers = self.client.result(job)
        self.assertEqual([n for n in layers if n != "combined"],
                         [p.type for p in last.partitions])
        with self.assertRaises(PartitaError) as ctx:
            self.client.submit("cornell", algorithm="partitioned", mpp=4, width=16, height=12,
                               prepass="magic")
        self.assertEqual(ctx.exception.code, "INVALID_ARGUMENT")
        self.assertIn("prepass 'magic' is not one of auto | pt | bdpt", str(ctx.exception))

    def test_environment_color_goes_into_the_spec(self):
        from partita_client.client import job_spec
        spec = job_spec("cornell", environment_color=(0.5, 1, 2), environment_rotation=30)
        rgb = spec.parameters["environment_color"].rgb_value
        self.assertEqual([rgb.r, rgb.g, rgb.b], [0.5, 1.0, 2.0])
        self.assertEqual(spec.parameters["environment_rotation"].int_value, 30)
        with self.assertRaises(ValueError):
            job_spec("cornell", environment_color=(1, 1))
        job = self.client.submit("cornell", environment_color=(1, 1, 1), **TINY)
        self.assertEqual(self.client.wait(job).state, "done")
        # An image goes with a .gltf upload as one more resource.
        spec = job_spec(CORNELL, environment=Path(CORNELL))  # any readable file, for the spec
        self.assertEqual(spec.environment_file, "partita-environment/cornell.gltf")
        self.assertEqual(spec.scene.gltf.resources[-1].uri, spec.environment_file)
        self.assertEqual(job_spec("cornell", environment="sky.hdr").environment_file, "sky.hdr")

    def test_algorithms_declare_their_parameters(self):
        algorithms = self.client.algorithms()
        self.assertEqual(set(algorithms), {"pt", "bdpt", "mlt", "partitioned", "guided"})
        guided = algorithms["guided"]
        self.assertEqual(guided.budgets, ("mpp", "seconds"))
        radius = guided.parameters["radius"]
        self.assertEqual((radius.type, radius.default, radius.min, radius.max, radius.min_exclusive,
                          radius.unit), ("real", 20.0, 0.0, 4096.0, True, "pixels"))
        self.assertEqual(guided.parameters["prepass"].choices, ("auto", "pt", "bdpt"))
        self.assertTrue(guided.parameters["width"].shared)
        self.assertEqual([p.name for p in guided.own_parameters()],
                         ["k", "partitions", "prepass", "bootstrap", "chains", "startup_share", "burn_in",
                          "estimators", "pixel_estimator", "allocation", "direct", "pilot_share",
                          "target_error",
                          "large_step_rate", "y",
                          "radius", "epsilon", "move", "through_specular"])
        self.assertEqual([p.name for p in algorithms["pt"].own_parameters()], ["target_error"])

    def test_submit_checks_parameter_names_before_sending(self):
        with self.assertRaises(ValueError) as ctx:
            self.client.submit("cornell", algorithm="guided", mpp=1, radiuss=3, width=32, height=24)
        self.assertIn("unknown parameter 'radiuss' for guided", str(ctx.exception))
        with self.assertRaises(ValueError):
            self.client.submit("cornell", radius=3, **TINY)  # pt has no radius
        self.assertEqual(self.client.jobs(label="py-names"), [])
        # A value out of range is the server's INVALID_ARGUMENT, naming the parameter.
        with self.assertRaises(PartitaError) as ctx:
            self.client.submit("cornell", algorithm="guided", mpp=1, radius=0, label="py-names",
                               width=32, height=24)
        self.assertEqual(ctx.exception.code, "INVALID_ARGUMENT")
        self.assertIn("radius = 0 is outside (0, 4096] pixels", str(ctx.exception))
        # Older keyword names still reach their parameters.
        job = self.client.submit("cornell", algorithm="mlt", mpp=1, bootstrap_samples=2000,
                                 label="py-names", width=32, height=24)
        self.assertEqual(self.client.wait(job).state, "done")
        self.assertEqual(self.client.metadata(job)["parameters"]["bootstrap"], 2000)

    def test_cancel(self):
        job = self.client.submit("cornell", width=32, height=24, seconds=60, label="py-cancel")
        self.client.cancel(job)
        final = self.client.wait(job, timeout=30)
        self.assertEqual(final.state, "cancelled")
        with self.assertRaises(PartitaError) as ctx:
            self.client.result(job)
        self.assertEqual(ctx.exception.code, "FAILED_PRECONDITION")

    def test_jobs(self):
        a = self.client.submit("cornell", label="py-jobs", **TINY)
        b = self.client.submit("cornell", label="py-jobs", **TINY)
        self.client.wait(a)
        self.client.wait(b)
        listed = self.client.jobs(label="py-jobs")
        self.assertEqual(sorted(j.id for j in listed), sorted([a, b]))
        self.assertTrue(all(j.state == "done" and j.algorithm == "pt" for j in listed))
        self.assertTrue(all(j.state == "done" for j in self.client.jobs(states=["done"])))
        self.assertIn("pt", self.client.algorithms())
        self.assertIn("cornell", self.client.scenes())
        self.assertTrue(self.client.server_info().version)

    def test_errors(self):
        with self.assertRaises(PartitaError) as ctx:
            self.client.submit("cornell", algorithm="nosuch", **TINY)
        self.assertEqual(ctx.exception.code, "INVALID_ARGUMENT")
        with self.assertRaises(PartitaError) as ctx:
            self.client.job("nosuchjob")
        self.assertEqual(ctx.exception.code, "NOT_FOUND")
        with self.assertRaises(PartitaError):
            self.client.submit(SCENES / "missing.gltf")
        with self.assertRaises(ValueError):
            self.client.submit("cornell", colour=3)
        with self.assertRaises(ValueError):
            self.client.submit("cornell", spp=1, mpp=2)
        with Client("127.0.0.1:1", timeout=5) as down:
            with self.assertRaises(PartitaError) as ctx:
                down.jobs()
            self.assertEqual(ctx.exception.code, "UNAVAILABLE")

    def test_refuses_uri_outside_scene_folder(self):
        with tempfile.TemporaryDirectory() as d:
            (Path(d) / "secret.bin").write_bytes(b"x")
            (Path(d) / "s").mkdir()
            scene = Path(d) / "s" / "evil.gltf"
            scene.write_text('{"asset":{"version":"2.0"},"buffers":[{"byteLength":1,'
                             '"uri":"../secret.bin"}]}')
            with self.assertRaisesRegex(PartitaError, "outside"):
                self.client.submit(scene, **TINY)

    def test_metrics(self):
        r = np.zeros((2, 2, 3), np.float32)
        self.assertAlmostEqual(rmse(r + 0.5, r), 0.5, places=6)
        self.assertAlmostEqual(rel_mse(r + 0.1, r), 1.0, places=5)

    def test_sweep_script(self):
        with tempfile.TemporaryDirectory() as d:
            out = Path(d) / "sweep"
            cmd = [sys.executable, str(CLIENT_DIR / "sweep.py"), "cornell", "--server",
                   self.daemon.address, "--algorithm", "pt", "--param1", "spp=1,2",
                   "--param2", "max-depth=1,3", "--set", "width=32", "--set", "height=24",
                   "--reference-spp", "8", "--out-dir", str(out), "-q"]
            proc = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
            self.assertEqual(proc.returncode, 0, proc.stderr)
            with open(out / "sweep.csv") as f:
                rows = list(csv.DictReader(f))
            self.assertEqual([(r["spp"], r["max-depth"]) for r in rows],
                             [("1", "1"), ("1", "3"), ("2", "1"), ("2", "3")])
            for r in rows:
                self.assertEqual(r["state"], "done")
                self.assertEqual(r["algorithm"], "pt")
                self.assertGreater(float(r["rmse"]), 0.0)
                self.assertGreater(float(r["relmse"]), 0.0)
                self.assertGreaterEqual(float(r["seconds"]), 0.0)
            for png in ("grid.png", "rmse.png"):
                self.assertTrue((out / png).read_bytes().startswith(b"\x89PNG"), png)
            ref = read_exr(out / "reference.exr").layers()["combined"]
            self.assertEqual(ref.shape, (24, 32, 3))
            self.assertTrue((out / "renders" / "spp=2_max-depth=3.exr").is_file())

    def test_sweep_script_guided_grid_with_seeds_through_a_private_daemon(self):
        # The Figure 8 study in miniature: rows R, columns |Y'|, two seeds a point, no --server.
        import sweep
        self.assertEqual(sweep.parse_axis(sweep.DEFAULT_ROWS)[0], "radius")
        self.assertEqual(sweep.parse_axis(sweep.DEFAULT_COLUMNS)[0], "y")
        with tempfile.TemporaryDirectory() as d:
            out = Path(d) / "sweep"
            cmd = [sys.executable, str(CLIENT_DIR / "sweep.py"), "cornell-glass", "--algorithm",
                   "guided", "--param1", "radius=2,10", "--param2", "y=8,32", "--seeds", "2",
                   "--set", "width=16", "--set", "height=12", "--set", "mpp=2",
                   "--reference-spp", "8", "--reference-algorithm", "bdpt", "--out-dir",
                   str(out), "-q"]
            proc = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
            self.assertEqual(proc.returncode, 0, proc.stderr)
            with open(out / "sweep.csv") as f:
                reader = csv.DictReader(f)
                rows = list(reader)
            self.assertEqual(reader.fieldnames,
                             ["radius", "y", "algorithm", "seeds", "rmse", "rmse_std", "rmse_se",
                              "relmse", "relmse_std", "relmse_se", "seconds", "jobs", "state"])
            self.assertEqual([(r["radius"], r["y"]) for r in rows],
                             [("2", "8"), ("2", "32"), ("10", "8"), ("10", "32")])
            with open(out / "runs.csv") as f:
                runs = list(csv.DictReader(f))
            self.assertEqual([(r["radius"], r["y"], r["seed"]) for r in runs],
                             [(a, b, s) for a, b in (("2", "8"), ("2", "32"), ("10", "8"),
                                                     ("10", "32")) for s in ("1", "2")])
            for k, r in enumerate(rows):
                self.assertEqual(r["state"], "done")
                self.assertEqual(r["algorithm"], "guided")
                self.assertEqual(r["seeds"], "2")
                per_seed = [float(x["rmse"]) for x in runs[2 * k:2 * k + 2]]
                self.assertEqual(len(set(per_seed)), 2, "two seeds, two different images")
                self.assertAlmostEqual(float(r["rmse"]), np.mean(per_seed), places=6)
                self.assertAlmostEqual(float(r["rmse_std"]), np.std(per_seed, ddof=1), places=6)
                self.assertAlmostEqual(float(r["rmse_se"]), float(r["rmse_std"]) / np.sqrt(2),
                                       places=6)
                self.assertGreater(float(r["relmse"]), 0.0)
                self.assertGreaterEqual(float(r["seconds"]), 0.0)
                self.assertEqual(r["jobs"].split(), [x["job"] for x in runs[2 * k:2 * k + 2]])
            for png in ("grid.png", "rmse.png"):
                self.assertTrue((out / png).read_bytes().startswith(b"\x89PNG"), png)
            ref = json.loads((out / "reference.json").read_text())
            self.assertEqual((ref["algorithm"], ref["parameters"]["width"]), ("bdpt", 16))
            for seed in (1, 2):
                exr = out / "renders" / f"radius=10_y=32_seed={seed}.exr"
                params = json.loads(exr.with_suffix(".json").read_text())["parameters"]
                self.assertEqual((params["radius"], params["y"], params["seed"]), (10.0, 32, seed))
                self.assertEqual(read_exr(exr).layers()["combined"].shape, (12, 16, 3))

    def test_sweep_script_refuses_seeds_with_a_seed_axis(self):
        for extra in (["--param2", "seed=1,2", "--seeds", "2"], ["--seeds", "0"]):
            cmd = [sys.executable, str(CLIENT_DIR / "sweep.py"), "cornell", "--server",
                   self.daemon.address, "--param1", "radius=5", "--reference-spp", "4", *extra]
            proc = subprocess.run(cmd, capture_output=True, text=True, timeout=60)
            self.assertNotEqual(proc.returncode, 0, extra)
            self.assertEqual(len(proc.stderr.strip().splitlines()), 1, proc.stderr)
            self.assertIn("--seeds", proc.stderr)

    def test_sweep_script_refuses_parameters_the_algorithm_ignores(self):
        cmd = [sys.executable, str(CLIENT_DIR / "sweep.py"), "cornell", "--server",
               self.daemon.address, "--algorithm", "pt", "--param1", "y=8,32",
               "--param2", "radius=5,10", "--reference-spp", "4"]
        proc = subprocess.run(cmd, capture_output=True, text=True, timeout=60)
        self.assertNotEqual(proc.returncode, 0)
        self.assertEqual(len(proc.stderr.strip().splitlines()), 1, proc.stderr)
        self.assertIn("ignores y", proc.stderr)

    def test_sweep_script_bad_input(self):
        cmd = [sys.executable, str(CLIENT_DIR / "sweep.py"), "cornell", "--server",
               self.daemon.address, "--param1", "spp=1,x", "--reference-spp", "4"]
        proc = subprocess.run(cmd, capture_output=True, text=True, timeout=60)
        self.assertNotEqual(proc.returncode, 0)
        self.assertEqual(len(proc.stderr.strip().splitlines()), 1, proc.stderr)
        self.assertIn("sweep.py: error:", proc.stderr)


if __name__ == "__main__":
    unittest.main()
