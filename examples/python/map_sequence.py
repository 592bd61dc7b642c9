#!/usr/bin/env python3
"""Maps a stereo sequence with hazmap's Python bindings and plots the last frame's height
and hazard maps of the finest layer. From the repository root, after building:

    PYTHONPATH=build/python /usr/bin/python3 examples/python/map_sequence.py [SEQ]

SEQ defaults to /tmp/hazmap_seq, simulated there first (10 frames of rocks) if missing.
Needs matplotlib (Debian: python3-matplotlib); writes map_sequence.png.
"""
import argparse
import os

import matplotlib
matplotlib.use("Agg")  # a file, no window
import matplotlib.pyplot as plt
from matplotlib.colors import ListedColormap

import hazmap

root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("sequence", nargs="?", default="/tmp/hazmap_seq")
parser.add_argument("--config", default=os.path.join(root, "config", "default.yaml"))
parser.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
parser.add_argument("--out", default="map_sequence.png")
args = parser.parse_args()

if not os.path.isdir(args.sequence):
    hazmap.simulate(args.sequence, scenario="rocks", frames=10, scale=0.4, ground_truth=True)
sequence = hazmap.load_sequence(args.sequence)
pipeline = hazmap.Pipeline(hazmap.load_config(args.config, args.set), sequence["calibration"])
for frame in sequence["frames"]:
    left, right = hazmap.read_image(frame["left"]), hazmap.read_image(frame["right"])
    report = pipeline.process(left, right, frame["T_W_B"], frame["noise"])
    print(f"frame {frame['name']}: {report['points']} points, {report['ms']['total']:.0f} ms")

layer = pipeline.layers[0]
figure, (height_axes, hazard_axes) = plt.subplots(1, 2, figsize=(11, 4.5))
image = height_axes.imshow(layer.height, extent=layer.extent_m, cmap="viridis")
figure.colorbar(image, ax=height_axes, label="height [m]")
# Class 0 unknown, 1 traversable, 2 hazard (hazmap.UNKNOWN, TRAVERSABLE, HAZARD).
hazard_colours = ListedColormap(["0.4", "tab:green", "tab:red"])
hazard_axes.imshow(layer.hazard, extent=layer.extent_m, cmap=hazard_colours, vmin=0, vmax=2,
                   interpolation="nearest")
height_axes.set_title(f"L0 height ({layer.rule}, {layer.resolution_m * 100:g} cm cells)")
hazard_axes.set_title("L0 hazard: red hazard, green traversable, grey unknown")
for axes in (height_axes, hazard_axes):
    axes.set_xlabel("x in W [m]")
    axes.set_ylabel("y in W [m]")
figure.tight_layout()
figure.savefig(args.out, dpi=100)
print(f"wrote {args.out}")
