#!/usr/bin/env python3
"""What the hand felt in real runs (haptex launch ... --out RUN): per run, each finger's peak
commanded force, the largest sign reversal of a force component within 10 ms (0.25 N or more
each way: a force falling to zero with a trace beyond is no buzz; from the mock's
mock_grab_forces.csv), the cuts of a held contact the bridge counted and each resume's peak over
the force held before it (summary.json).

    bench/stall/run_resumes.py RUN [RUN ...]
"""
import csv
import json
import math
import sys
from collections import deque

WINDOW_NS = 10e6
SIDE_N = 0.25  # a reversal goes from this much one way to this much the other (a fall to zero is none)


def largest_reversal(rows, keys):
    largest = 0.0
    history = deque()
    for t, values in rows:
        history.append((t, values))
        while history and t - history[0][0] > WINDOW_NS:
            history.popleft()
        for k in range(len(keys)):
            now = values[k]
            for _, before in history:
                if (before[k] >= SIDE_N and now <= -SIDE_N) or (before[k] <= -SIDE_N and now >= SIDE_N):
                    largest = max(largest, abs(before[k] - now))
    return largest


def main(runs):
    keys = ["thumb_cmd_x", "thumb_cmd_y", "thumb_cmd_z", "index_cmd_x", "index_cmd_y", "index_cmd_z"]
    print("| run | peak N (thumb/index) | largest reversal N | held cuts | resumes: peak / held |")
    print("|---|---|---|---|---|")
    for run in runs:
        rows = []
        peak = [0.0, 0.0]
        with open(run + "/mock_grab_forces.csv") as f:
            for r in csv.DictReader(f):
                values = [float(r[k]) for k in keys]
                rows.append((float(r["time_ns"]), values))
                peak[0] = max(peak[0], math.sqrt(sum(v * v for v in values[:3])))
                peak[1] = max(peak[1], math.sqrt(sum(v * v for v in values[3:])))
        summary = json.load(open(run + "/summary.json"))
        bridge = next(s for s in summary["services"] if s.get("name", s.get("service")) == "device_bridge")
        counters = bridge.get("counters", {})
        cuts = {k[len("held_cuts_"):]: v for k, v in counters.items() if k.startswith("held_cuts_") and v}
        resumes = ", ".join("%.2f/%.2f%s" % (r["peak_n"], r["held_n"], " ended" if r["ended"] else "")
                            for r in bridge.get("resumes", []))
        print("| %s | %.2f / %.2f | %.2f | %s | %s |" % (run, peak[0], peak[1], largest_reversal(rows, keys),
                                                      cuts or "none", resumes or "none"))


if __name__ == "__main__":
    main(sys.argv[1:])
