#!/usr/bin/python3
"""What writing outputs costs the frame loop of `hazmap run` (issue 20).

Runs the same frames with output off, grids only (JDEM, GeoTIFF) and PNGs plus grids,
each synchronous (output.queue_frames=0) and with the writer thread (queue 2), in
interleaved repetitions, and reads OUT/summary.json: the frame loop's time per frame is
read + rectify + disparity + points + map + hazard + the loop's share of writing (copying
the grids out, or writing them when synchronous, plus any wait for a free slot). The
first frame (map building) is left out. Prints one line per run, then medians over the
repetitions and each case's loop time over the output-off loop of the same repetition.

usage: tools/bench/output_cost.py HAZMAP CONFIG SEQUENCE [--frames A:B] [--repetitions R]
       (e.g. build/hazmap config/cadre_flight.yaml SEQ, SEQ from
        `hazmap simulate --scenario rocks --scale 0.4 --frames 12 --out SEQ`)
"""
import argparse
import collections
import json
import os
import resource
import shutil
import statistics
import subprocess
import tempfile
import time

CASES = [("off", ["output.png=false", "output.jdem=false"]),
         ("jdem", ["output.png=false", "output.format=jdem"]),
         ("geotiff", ["output.png=false", "output.format=geotiff"]),
         ("png+jdem", ["output.png=true", "output.format=jdem"]),
         ("png+geotiff", ["output.png=true", "output.format=geotiff"])]
STAGES = ["read", "rectify", "disparity", "points", "map", "hazard", "write"]


def run_once(args, out, sets):
    shutil.rmtree(out, ignore_errors=True)
    command = [args.hazmap, "run", "--config", args.config, "--sequence", args.sequence,
               "--out", out, "--frames", args.frames, "--quiet"]
    for s in sets:
        command += ["--set", s]
    start = time.monotonic()
    used = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run(command, check=True)
    wall_ms = (time.monotonic() - start) * 1000
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu_ms = (after.ru_utime + after.ru_stime - used.ru_utime - used.ru_stime) * 1000
    summary = json.load(open(os.path.join(out, "summary.json")))
    frames = summary["frames"][1:]
    loop = statistics.median(sum(f["ms"][s] for s in STAGES) for f in frames)
    loop_write = statistics.median(f["ms"]["write"] for f in frames)
    written = summary["output"]["writer_ms_per_written_frame"]
    cpu = summary["output"]["writer_cpu_ms_per_written_frame"]
    size = sum(os.path.getsize(os.path.join(d, n))
               for d, _, names in os.walk(os.path.join(out, "frames")) for n in names)
    n = len(summary["frames"])
    return loop, loop_write, written, cpu, wall_ms / n, cpu_ms / n, size / n / 1e6


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("hazmap")
    p.add_argument("config")
    p.add_argument("sequence")
    p.add_argument("--frames", default="0:12")
    p.add_argument("--repetitions", type=int, default=3)
    args = p.parse_args()
    rows = collections.defaultdict(list)
    off = {}
    with tempfile.TemporaryDirectory(prefix="hazmap_output_cost_") as scratch:
        out = os.path.join(scratch, "out")
        for rep in range(args.repetitions):
            for name, sets in CASES:
                for queue in ([0] if name == "off" else [0, 2]):
                    r = run_once(args, out, sets + ["output.queue_frames=%d" % queue])
                    if name == "off":
                        off[rep] = r[0]
                    rows[(name, queue)].append(r + (r[0] / off[rep],))
                    print("%-12s queue %d rep %d: loop %7.1f ms/frame (its write share %6.1f), "
                          "writer %7.1f ms/frame (CPU %6.1f), wall %7.1f ms/frame (process CPU %6.1f), "
                          "%.2f MB/frame" %
                          ((name, queue, rep) + r), flush=True)
    print("\nmedians over %d repetitions [ms per frame]; ratio = loop / output-off loop of the "
          "same repetition" % args.repetitions)
    print("%-12s %5s %8s %6s %11s %8s %11s %8s %12s %9s" %
          ("case", "queue", "loop", "ratio", "loop write", "writer", "writer CPU", "wall",
           "process CPU", "MB/frame"))
    for (name, queue), rs in rows.items():
        med = [statistics.median(r[i] for r in rs) for i in range(8)]
        print("%-12s %5d %8.1f %6.2f %11.1f %8.1f %11.1f %8.1f %12.1f %9.2f" %
              (name, queue, med[0], med[7], med[1], med[2], med[3], med[4], med[5], med[6]))


if __name__ == "__main__":
    main()
