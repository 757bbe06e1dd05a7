#!/usr/bin/env python3
"""Notebook-style: two methods side by side on one frame, with their difference and the metrics
of `penumbra compare`. Each block below is a notebook cell.

    PYTHONPATH=build/release/python python3 examples/python/compare_two_methods.py --out side_by_side
"""
import argparse
import os

import matplotlib

matplotlib.use(os.environ.get("MPLBACKEND", "Agg"))
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import penumbra  # noqa: E402

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--scene", default="default")
parser.add_argument("--methods", default="exact,pcss")
parser.add_argument("--size", default="200x150")
parser.add_argument("--out", default="side_by_side")
args = parser.parse_args()

# %% The scene and the two renders (same light samples, same frame).
scene = penumbra.load_scene(args.scene)
size = tuple(int(v) for v in args.size.split("x"))
a_name, b_name = args.methods.split(",")
a = penumbra.render(scene, method=a_name, size=size, samples=8)
b = penumbra.render(scene, method=b_name, size=size, samples=8)

# %% The metrics `penumbra compare` prints.
metrics = penumbra.compare(a, b)
for key, value in metrics.items():
    print(f"{key:18s} {value}")

# %% Side by side: the beauty images, the visibility, and |difference| on the surface pixels.
def display(rgb):
    return np.clip(rgb, 0, 1) ** (1 / 2.2)


difference = np.where(a.surface, np.abs(a.visibility - b.visibility), np.nan)
fig, axes = plt.subplots(1, 3, figsize=(12, 3.6))
axes[0].imshow(display(a.beauty))
axes[0].set_title(f"{a_name} ({a.stats['times_ms']['total']:.0f} ms)")
axes[1].imshow(display(b.beauty))
axes[1].set_title(f"{b_name} ({b.stats['times_ms']['total']:.0f} ms)")
shown = axes[2].imshow(difference, cmap="inferno", vmin=0)
axes[2].set_title(f"|V difference|, mean in shadow {metrics['mean_abs_shadowed']:.4f}")
fig.colorbar(shown, ax=axes[2])
for ax in axes:
    ax.axis("off")
fig.tight_layout()
os.makedirs(args.out, exist_ok=True)
path = os.path.join(args.out, f"{a_name}_vs_{b_name}.png")
fig.savefig(path, dpi=100)
print(path)
