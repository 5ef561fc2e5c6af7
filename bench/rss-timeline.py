#!/usr/bin/env python3
"""The resident memory of one command over its run, sampled from /proc every INTERVAL s.
    bench/rss-timeline.py [--interval S] [--out CSV] [--events TXT] -- COMMAND ARGS...
Prints the peak (VmRSS sampled, and the kernel's VmHWM at the last sample) and, with --out, a
CSV of "seconds,rss_mib" (seconds since the start of the command). With --events the command's
stderr is a pseudo-terminal (so that a progress bar draws itself as on a terminal) and each of
its lines (split at CR or LF: every redraw of the bar) is written there as "seconds<TAB>line",
so that the phases the bar names ("prepass", "guides", "render") can be placed on the
timeline. A transient shorter than the interval can be
missed by the samples; VmHWM cannot miss it. Exits with the command's status."""
import argparse
import os
import pty
import re
import subprocess
import sys
import threading
import time


def status_kib(pid, field):
    try:
        with open(f"/proc/{pid}/status") as f:
            for line in f:
                if line.startswith(field + ":"):
                    return int(line.split()[1])
    except (FileNotFoundError, ProcessLookupError):
        return None
    return None


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--interval", type=float, default=0.002)
    ap.add_argument("--out")
    ap.add_argument("--events")
    ap.add_argument("command", nargs=argparse.REMAINDER)
    a = ap.parse_args()
    cmd = a.command[1:] if a.command and a.command[0] == "--" else a.command
    start = time.monotonic()
    master = slave = None
    if a.events:
        master, slave = pty.openpty()
    p = subprocess.Popen(cmd, stderr=slave)
    if slave is not None:
        os.close(slave)
    events = []

    def read_stderr():
        pending = b""
        while True:
            try:
                chunk = os.read(master, 4096)
            except OSError:  # EIO: every writer of the terminal has closed it
                break
            if not chunk:
                break
            t = time.monotonic() - start
            pending += chunk
            parts = re.split(rb"[\r\n]", pending)
            pending = parts.pop()
            events.extend((t, x.decode(errors="replace")) for x in parts if x.strip())
        if pending.strip():
            events.append((time.monotonic() - start, pending.decode(errors="replace")))

    reader = threading.Thread(target=read_stderr) if a.events else None
    if reader:
        reader.start()
    samples, hwm = [], None
    while p.poll() is None:
        rss = status_kib(p.pid, "VmRSS")
        h = status_kib(p.pid, "VmHWM")
        if rss is not None:
            samples.append((time.monotonic() - start, rss / 1024))
        if h is not None:
            hwm = h / 1024
        time.sleep(a.interval)
    if reader:
        reader.join()
        with open(a.events, "w") as f:
            for t, line in events:
                f.write(f"{t:.4f}\t{line}\n")
    if a.out:
        with open(a.out, "w") as f:
            f.write("seconds,rss_mib\n")
            for t, r in samples:
                f.write(f"{t:.4f},{r:.1f}\n")
    peak = max(samples, key=lambda s: s[1]) if samples else (0, 0)
    print(f"rss-timeline: {len(samples)} samples, peak VmRSS {peak[1]:.1f} MiB at {peak[0]:.2f} s, "
          f"VmHWM {hwm if hwm is None else round(hwm, 1)} MiB (last sample), "
          f"exit {p.returncode}", file=sys.stderr)
    return p.returncode


if __name__ == "__main__":
    sys.exit(main())
