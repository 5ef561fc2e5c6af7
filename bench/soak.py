#!/usr/bin/python3
"""A soak of partitad (issue #25): many clients, jobs of every algorithm, random cancels,
deletes, watchers that stall or hang up, and kill -9 restarts of the daemon in the middle.

    bench/soak.sh [--clients 50] [--jobs 10] [--restarts 20] [--seed 1] [--build build]

One partitad runs on a store of its own (a temporary folder). CLIENTS threads each submit JOBS
tiny jobs (16x12; every algorithm in turn), each labelled soak-<client>-<job>, and do one of:
wait for it; cancel it at once; delete it once it ended; watch it with previews and hang up
after a few events; or watch it with raw previews and stall (read nothing) for a while. A
killer thread meanwhile kills the daemon with SIGKILL RESTARTS times, at random moments, and
starts it again on the same port and store. A call that fails because the daemon is down is
retried once it is back; a submission whose answer was lost is looked up by its label first,
so that a retry never makes a second job.

At the end, with every job finished, it checks and prints:
  - lost: a job a client was told about (and did not delete) that the daemon no longer lists;
  - duplicated: two jobs of one label;
  - every finished job's state; each done job's EXR is fetched and parsed (fetch failures
    listed); a deleted job must be gone;
  - the daemon's resident memory (VmRSS) idle on the empty store at the start, and idle at
    the end (the last incarnation, after every job) against a fresh daemon started on the same
    store (its baseline: what the finished jobs' records cost by themselves).
Exit status 1 if anything was lost, duplicated, unfetchable, failed, or the memory at the end
is more than --memory-slack MiB above the fresh daemon's.
"""
import argparse
import os
import random
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
ALGORITHMS = ["pt", "bdpt", "mlt", "partitioned", "guided"]
ACTIONS = ["wait", "wait", "cancel", "delete", "watch-hangup", "watch-stall"]


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def rss_mib(pid):
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024
    return 0.0


class Daemon:
    """partitad on a fixed port and store, killed and started again at will."""

    def __init__(self, build, store, port):
        self.args = [str(build / "server" / "partitad"), "--listen", f"127.0.0.1:{port}",
                     "--store", str(store), "--scene-root", str(REPO / "scenes")]
        self.address = f"127.0.0.1:{port}"
        self.log = open(store.parent / "partitad.log", "ab")
        self.process = None
        self.up = threading.Event()
        self.starts = 0

    def start(self):
        self.process = subprocess.Popen(self.args, stdout=self.log, stderr=subprocess.STDOUT,
                                        stdin=subprocess.DEVNULL, start_new_session=True)
        self.starts += 1
        import grpc
        from partita_client.daemon import health_check
        channel = grpc.insecure_channel(self.address)
        deadline = time.monotonic() + 60
        while not health_check(channel):
            if self.process.poll() is not None or time.monotonic() > deadline:
                raise SystemExit(f"soak: partitad did not start (see {self.log.name})")
            time.sleep(0.05)
        channel.close()
        self.up.set()

    def kill(self):
        self.up.clear()
        self.process.send_signal(signal.SIGKILL)
        self.process.wait()

    def stop(self):
        if self.process and self.process.poll() is None:
            self.process.send_signal(signal.SIGTERM)
            self.process.wait(30)


class Soak:
    def __init__(self, args, daemon):
        from partita_client import Client
        self.args = args
        self.daemon = daemon
        self.make_client = lambda: Client(daemon.address, timeout=30)
        self.lock = threading.Lock()
        self.submitted = {}  # label -> job id a client was told
        self.deleted = set()  # labels whose job a client deleted
        self.retries = 0
        self.actions = {a: 0 for a in ACTIONS}

    def call(self, what, done_if_retried=()):
        """what(), retried while the daemon is down (UNAVAILABLE) or restarting. A call whose
        first try may have taken effect before its answer was lost can meet the effect on the
        retry (a delete then finds no job): an error code in `done_if_retried` then means done."""
        from partita_client import PartitaError
        retried = False
        while True:
            try:
                return what()
            except PartitaError as e:
                if retried and e.code in done_if_retried:
                    return None
                if e.code not in ("UNAVAILABLE", "DEADLINE_EXCEEDED", "CANCELLED", "UNKNOWN"):
                    raise
            retried = True
            with self.lock:
                self.retries += 1
            self.daemon.up.wait(120)
            time.sleep(0.05)

    def submit(self, client, label, params):
        """The job's id, submitted once: after a lost answer, its label is looked up first."""
        from partita_client import PartitaError
        while True:
            try:
                return client.submit(params["scene"], label=label, **params["spec"])
            except PartitaError as e:
                if e.code not in ("UNAVAILABLE", "DEADLINE_EXCEEDED", "CANCELLED", "UNKNOWN"):
                    raise
            with self.lock:
                self.retries += 1
            self.daemon.up.wait(120)
            found = self.call(lambda: client.jobs(label=label))
            if found:
                return found[0].id

    def watch(self, client, job_id, raw, stall):
        """Reads a few events and hangs up, or opens a raw-preview stream and reads nothing."""
        from partita_client import PartitaError
        try:
            events = client.watch(job_id, previews=True, raw=raw)
            for i, _ in enumerate(events):
                if stall:
                    time.sleep(random.uniform(0.5, 2.0))  # a watcher that stops reading
                if i >= 2:
                    break
            events.close()  # hang up mid-stream
        except PartitaError:
            pass  # the daemon went down under the stream: a watcher's everyday loss

    def run_client(self, index):
        from partita_client import PartitaError
        rng = random.Random(self.args.seed * 1000 + index)
        client = self.make_client()
        for j in range(self.args.jobs):
            algorithm = ALGORITHMS[(index + j) % len(ALGORITHMS)]
            budget = {"spp": 2} if algorithm in ("pt", "bdpt") else {"mpp": 2}
            spec = dict(algorithm=algorithm, width=16, height=12, seed=j + 1, **budget)
            if algorithm in ("mlt", "partitioned", "guided"):
                spec["bootstrap"] = 4096
            label = f"soak-{index}-{j}"
            job_id = self.submit(client, label, {"scene": "cornell", "spec": spec})
            with self.lock:
                self.submitted[label] = job_id
            action = rng.choice(ACTIONS)
            with self.lock:
                self.actions[action] += 1
            if action == "cancel":
                try:
                    self.call(lambda: client.cancel(job_id))
                except PartitaError as e:
                    if e.code != "FAILED_PRECONDITION":  # a tiny job may finish first
                        raise
            elif action in ("watch-hangup", "watch-stall"):
                self.watch(client, job_id, raw=action == "watch-stall",
                           stall=action == "watch-stall")
            job = self.call(lambda: client.wait(job_id, timeout=600))
            if action == "delete" and job.finished:
                self.call(lambda: client.delete(job_id), done_if_retried=("NOT_FOUND",))
                with self.lock:
                    self.deleted.add(label)
        client.close()

    def kill_restart(self, clients_done):
        rng = random.Random(self.args.seed)
        for _ in range(self.args.restarts):
            time.sleep(rng.uniform(0.2, 1.2))
            if clients_done.is_set():
                break
            self.daemon.kill()
            self.daemon.start()


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--clients", type=int, default=50)
    parser.add_argument("--jobs", type=int, default=10)
    parser.add_argument("--restarts", type=int, default=20)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--build", default=str(REPO / "build"))
    parser.add_argument("--memory-slack", type=float, default=64,
                        help="MiB the idle daemon may hold above a fresh one on the same store")
    args = parser.parse_args()
    build = Path(args.build).resolve()
    sys.path[:0] = [str(build / "python"), str(REPO / "client" / "python")]
    from partita_client import Client

    folder = Path(tempfile.mkdtemp(prefix="partita-soak-"))
    store = folder / "store"
    store.mkdir()
    daemon = Daemon(build, store, free_port())
    daemon.start()
    time.sleep(1)
    rss_start = rss_mib(daemon.process.pid)
    soak = Soak(args, daemon)
    started = time.monotonic()
    clients_done = threading.Event()
    killer = threading.Thread(target=soak.kill_restart, args=(clients_done,))
    killer.start()
    errors = []

    def client_thread(i):
        try:
            soak.run_client(i)
        except Exception as e:  # a client's unexpected error is a finding, not a crash
            errors.append(f"client {i}: {type(e).__name__}: {e}")

    threads = [threading.Thread(target=client_thread, args=(i,)) for i in range(args.clients)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    clients_done.set()
    killer.join()
    seconds = time.monotonic() - started

    # The last incarnation: its own idle start is its baseline; wait for it to settle.
    time.sleep(2)
    client = Client(daemon.address, timeout=60)
    jobs = client.jobs()
    by_label = {}
    for j in jobs:
        by_label.setdefault(j.label, []).append(j)
    lost = [l for l, i in soak.submitted.items() if l not in soak.deleted and l not in by_label]
    duplicated = [l for l, js in by_label.items() if len(js) > 1]
    not_deleted = [l for l in soak.deleted if l in by_label]
    states = {}
    unfinished, unfetchable, failed = [], [], []
    from partita_client import read_exr
    for j in jobs:
        states[j.state] = states.get(j.state, 0) + 1
        if not j.finished:
            unfinished.append(j.label)
        elif j.state == "failed":
            failed.append(f"{j.label} ({j.algorithm}): {j.error}")
        elif j.state == "done":
            try:
                if "combined" not in read_exr(client.fetch(j.id)).layers():
                    unfetchable.append(j.label)
            except Exception as e:
                unfetchable.append(f"{j.label}: {e}")
    requeued = sum(1 for j in jobs if j.stats.get("requeued", 0) > 0)
    rss_end = rss_mib(daemon.process.pid)
    client.close()
    # The baseline for the end: a fresh daemon on the same store, idle (what the jobs' records
    # cost by themselves); what the long-lived one holds above it, it kept from the work.
    daemon.stop()
    daemon.start()
    time.sleep(2)
    rss_fresh = rss_mib(daemon.process.pid)
    daemon.stop()

    print(f"soak: {args.clients} clients x {args.jobs} jobs, {daemon.starts - 2} kill -9 restarts, "
          f"{seconds:.0f} s; actions {soak.actions}; {soak.retries} calls retried while the "
          f"daemon was down")
    print(f"jobs listed {len(jobs)} of {len(soak.submitted)} submitted ({len(soak.deleted)} "
          f"deleted); states {states}; {requeued} ran again after a restart")
    print(f"lost {len(lost)}, duplicated {len(duplicated)}, deleted but listed "
          f"{len(not_deleted)}, unfinished {len(unfinished)}, failed {len(failed)}, done but "
          f"unfetchable {len(unfetchable)}, client errors {len(errors)}")
    print(f"daemon VmRSS idle: {rss_start:.0f} MiB on the empty store at the start; at the end "
          f"{rss_end:.0f} MiB (the last incarnation, after its work) against {rss_fresh:.0f} "
          f"MiB for a fresh daemon on the same store ({len(jobs)} jobs)")
    for what, items in [("lost", lost), ("duplicated", duplicated), ("failed", failed),
                        ("unfetchable", unfetchable), ("client errors", errors),
                        ("unfinished", unfinished), ("deleted but listed", not_deleted)]:
        for item in items[:10]:
            print(f"  {what}: {item}")
    bad = (lost or duplicated or failed or unfetchable or errors or unfinished or not_deleted or
           rss_end > rss_fresh + args.memory_slack)
    if not bad:
        import shutil
        shutil.rmtree(folder, ignore_errors=True)
    else:
        print(f"soak: the store and partitad.log are kept in {folder}")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
