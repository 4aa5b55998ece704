#!/usr/bin/python3
"""@brief The cost model of foveation (issue 25): each foveation stage's GPU time over the present pass's (a tonemap of
the same pixels, the cheapest full-screen pass) for one or more builds or settings, interleaved.

Each LABEL=COMMAND is a `fovea run` command line (without --json); the commands run round-robin, forwards then
backwards (A B B A ...), --rounds times, so load on the shared machine hits every one alike. Per run the passes'
median GPU ms come from the JSON summary; per command the table gives each stage's median over the runs (ms) and
the median over the runs of its ratio to the same run's present pass, the overhead (map + compaction + temporal +
reconstruction over present) and the frame (the sum of the passes' medians).

usage: tools/fovea_cost.py [--rounds N] [--markdown] LABEL=COMMAND [LABEL=COMMAND ...]
e.g.   tools/fovea_cost.py --rounds 2 "old=/tmp/old/fovea run --eye-size 720x800 --frames 4" \\
           "new=build/release/tools/fovea/fovea run --eye-size 720x800 --frames 4"
"""
import argparse
import json
import shlex
import statistics
import subprocess
import sys

STAGES = [("map", "fovea"), ("compaction", "compact"), ("shading", "shade"), ("temporal", "temporal"),
          ("reconstruction", "reconstruct")]
OVERHEAD = ("fovea", "compact", "temporal", "reconstruct")


def run_once(cmd):
    out = subprocess.run(shlex.split(cmd) + ["--json"], capture_output=True, text=True, timeout=1800)
    if out.returncode != 0:
        sys.exit(f"{cmd}: exit {out.returncode}: {out.stderr.strip()[-400:]}")
    j = json.loads(out.stdout)
    return {p["name"]: p["gpu_ms_median"] for p in j["passes"] if p.get("gpu_ms_median") is not None}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--markdown", action="store_true", help="print the table as markdown")
    ap.add_argument("commands", nargs="+", metavar="LABEL=COMMAND")
    a = ap.parse_args()
    if a.rounds < 1:
        sys.exit("--rounds: at least 1")
    cmds = []
    for c in a.commands:
        if "=" not in c:
            sys.exit(f"{c}: expected LABEL=COMMAND")
        label, cmd = c.split("=", 1)
        cmds.append((label, cmd))
    runs = {label: [] for label, _ in cmds}
    for r in range(a.rounds):
        for order in (cmds, cmds[::-1]):
            for label, cmd in order:
                ms = run_once(cmd)
                runs[label].append(ms)
                print(f"round {r + 1} {label}: " + " ".join(f"{k} {v:.1f}" for k, v in ms.items()), file=sys.stderr)
    head = ["build", "present ms"] + [f"{s} ms (x present)" for s, _ in STAGES] + ["overhead x present", "frame ms"]
    rows = []
    for label, _ in cmds:
        rs = runs[label]
        present = statistics.median(r["present"] for r in rs)
        row = [label, f"{present:.1f}"]
        for _, p in STAGES:
            have = [r for r in rs if p in r]
            if not have:
                row.append("-")
                continue
            ms = statistics.median(r[p] for r in have)
            ratio = statistics.median(r[p] / r["present"] for r in have)
            row.append(f"{ms:.1f} ({ratio:.1f})")
        over = statistics.median(sum(r.get(p, 0.0) for p in OVERHEAD) / r["present"] for r in rs)
        frame = statistics.median(sum(r.values()) for r in rs)
        row += [f"{over:.1f}", f"{frame:.0f}"]
        rows.append(row)
    if a.markdown:
        print("| " + " | ".join(head) + " |")
        print("| " + " | ".join("---" for _ in head) + " |")
        for row in rows:
            print("| " + " | ".join(row) + " |")
    else:
        for row in [head] + rows:
            print("  ".join(row))


if __name__ == "__main__":
    main()
