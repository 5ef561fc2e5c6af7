#!/usr/bin/python3
"""The idle memory a partitad holds per job it ran (docs/soak.md): 1000 tiny jobs (16x12,
cornell) one after another, VmRSS printed after every 250.
    bench/daemon-memory-per-job.py MODE [ALGORITHM]   (needs make build)
MODE: plain (jobs kept in the store), delete (each deleted once done), watch (each watched with
previews until it ends, then kept)."""
import sys, time, subprocess, os, socket, shutil, tempfile
REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path[:0] = [os.path.join(REPO, "build", "python"), os.path.join(REPO, "client", "python")]
from partita_client import Client
from partita_client.daemon import health_check
import grpc
store = tempfile.mkdtemp()
s = socket.socket(); s.bind(("127.0.0.1", 0)); port = s.getsockname()[1]; s.close()
p = subprocess.Popen([os.path.join(REPO, "build", "server", "partitad"), "--listen", f"127.0.0.1:{port}", "--store", store,
                      "--scene-root", os.path.join(REPO, "scenes")], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
ch = grpc.insecure_channel(f"127.0.0.1:{port}")
while not health_check(ch): time.sleep(0.05)
def rss():
    for l in open(f"/proc/{p.pid}/status"):
        if l.startswith("VmRSS"): return int(l.split()[1]) / 1024
c = Client(f"127.0.0.1:{port}", timeout=60)
mode = sys.argv[1]
alg = sys.argv[2] if len(sys.argv) > 2 else "pt"
print("start", rss())
for batch in range(4):
    for i in range(250):
        kw = {"spp": 1} if alg in ("pt", "bdpt") else {"mpp": 1, "bootstrap": 4096}
        j = c.submit("cornell", algorithm=alg, width=16, height=12, **kw)
        if mode == "watch":
            for e in c.watch(j, previews=True): pass
        c.wait(j)
        if mode == "delete": c.delete(j)
    time.sleep(1)
    print(batch, rss(), flush=True)
p.terminate(); p.wait(); shutil.rmtree(store)
