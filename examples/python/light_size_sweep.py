#!/usr/bin/env python3
"""Sweeps the light's size on one scene and plots, per method, the error against `exact` and the
time of a frame (matplotlib). The scene's BVH and each method's preparation are made once: only the
light changes between renders (penumbra.Renderer).

    PYTHONPATH=build/release/python python3 examples/python/light_size_sweep.py --out sweep
"""
import argparse
import os

import matplotlib

matplotlib.use(os.environ.get("MPLBACKEND", "Agg"))
import matplotlib.pyplot as plt  # noqa: E402

import penumbra  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scene", default="default")
    parser.add_argument("--methods", default="raytrace,gears,pcss,wedges")
    parser.add_argument("--scales", default="0.25,0.5,1,2,3", help="light size factors")
    parser.add_argument("--size", default="160x120")
    parser.add_argument("--samples", type=int, default=8)
    parser.add_argument("--out", default="light_size_sweep")
    args = parser.parse_args()
    size = tuple(int(v) for v in args.size.split("x"))
    methods = args.methods.split(",")
    scales = [float(v) for v in args.scales.split(",")]

    scene = penumbra.load_scene(args.scene)
    light = scene.lights[0]
    edge_u, edge_v, radius = light.edge_u, light.edge_v, light.radius
    renderer = penumbra.Renderer()
    error = {m: [] for m in methods}
    time_ms = {m: [] for m in methods}
    for scale in scales:
        light.edge_u = [scale * c for c in edge_u]
        light.edge_v = [scale * c for c in edge_v]
        light.radius = scale * radius
        exact = renderer.render(scene, method="exact", size=size, samples=args.samples)
        for m in methods:
            r = renderer.render(scene, method=m, size=size, samples=args.samples)
            error[m].append(penumbra.compare(exact, r)["mean_abs_shadowed"])
            time_ms[m].append(r.stats["times_ms"]["total"])
            print(f"scale {scale:5.2f}  {m:14s} error {error[m][-1]:.4f}  {time_ms[m][-1]:8.1f} ms")

    os.makedirs(args.out, exist_ok=True)
    fig, (ax_error, ax_time) = plt.subplots(1, 2, figsize=(10, 4))
    for m in methods:
        ax_error.plot(scales, error[m], marker="o", label=m)
        ax_time.plot(scales, time_ms[m], marker="o", label=m)
    ax_error.set(xlabel="light size (× the scene's)", ylabel="mean |V − exact| in shadow",
                 title=f"{args.scene}: error")
    ax_time.set(xlabel="light size (× the scene's)", ylabel="ms per frame", yscale="log",
                title=f"{args.scene}: time, {size[0]}x{size[1]}, {args.samples}² samples")
    ax_error.legend()
    fig.tight_layout()
    path = os.path.join(args.out, "light_size_sweep.png")
    fig.savefig(path, dpi=100)
    print(path)


if __name__ == "__main__":
    main()
