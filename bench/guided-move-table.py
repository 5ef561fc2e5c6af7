#!/usr/bin/env python3
"""Per partition of each render of bench/guided-move-pilot.sh: the guided move's v_g and c_g
over the lens perturbation's, their product (below 1: the guided move gives less error per
cost) and the move kept. Usage: guided-move-table.py OUT"""
import glob
import re
import subprocess
import sys


def statistics(exr):
    out = subprocess.run(["oiiotool", "--info", "-v", exr], capture_output=True, text=True,
                         check=True).stdout
    stats = {}
    for line in out.splitlines():
        m = re.match(r'\s*partita:stat:(\S+): "?([^"]*)"?', line)
        if m:
            stats[m.group(1)] = m.group(2)
    return stats


def main():
    for exr in sorted(glob.glob(sys.argv[1] + "/*.exr")):
        st = statistics(exr)
        print(exr)
        print("  %-16s %6s %6s %6s  %s" % ("partition", "v", "c", "v c", "kept"))
        for g in range(int(float(st["partitions"]))):
            key = "partition_%d_" % g
            if key + "chain_variance_guided" not in st:
                continue  # the direct light: no chains' pilot
            v = float(st[key + "chain_variance_guided"]) / float(st[key + "chain_variance_lens"])
            c = float(st[key + "mutation_cost_guided"]) / float(st[key + "mutation_cost_lens"])
            print("  %-16s %6.2f %6.2f %6.2f  %s" % (st[key + "type"], v, c, v * c,
                                                     st[key + "move"]))


if __name__ == "__main__":
    main()
