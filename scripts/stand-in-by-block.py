#!/usr/bin/env python3
"""Says, over blocks of pixels, how much of the fibres model's error against the path-traced truth is the raster's
stand-in for the light beyond one scattering event (docs/truth.md, "What is left, by scale").

    pip install numpy pillow
    hairlab measure shadows --preset default --frames 1 --truth path-traced --shading chiang --config reference \
        --set render.spp=32 --set render.hair_model=fibres --set render.probe=traced \
        --set render.light_strands=ribbons --out DIR
    python3 scripts/stand-in-by-block.py DIR [--shading chiang] [--block 8]... [--window 9]...

It reads the chain's images `measure shadows` writes into DIR (sRGB over black): the truth
(`truth_path_traced.png`), its one event (`truth_one_event.png`), and the path tracer with the raster's shading at
the first hit, one event (`truth_raster_one_<shading>.png`) and with the raster's stand-ins for the light beyond
it (`truth_raster_<shading>.png`). Over the blocks of B x B pixels wholly in the hair (the pixels where the
stand-ins add more than 0.02 of linear light, so every pixel where the raster draws a strand) it prints, per
block size:
  total      the RMSE of the blocks' sRGB (each block its pixels' mean linear colour) of the raster shading image
             against the truth: the chain's error up to its eye coverage step
  true rest  the same with the truth's own light beyond one event (truth - one event) in place of the raster's
             stand-ins: what is left once the stand-ins are exact, the raster's one event against the truth's
  stand-in   the blocks' ratio of the stand-ins' light to the truth's beyond one event, linear luminance: its
             10th, 50th and 90th percentile and the ratio of the sums
The truth's noise is not removed: a block's mean over B x B pixels has about 1/B of a pixel's.

With --window W (repeatable) it also prints, per pixel over the same hair pixels, the RMSE against the truth of
the raster shading image whose stand-ins are scaled at each pixel by the truth's light beyond one event over the
stand-ins' in the W x W window about it (the hair's pixels in it): the error left by a stand-in exact at the scale
of W pixels and the raster's own within it, the least any probe of that resolution could reach.
"""
import argparse
import os

import numpy as np
from PIL import Image

LUMA = np.array([0.2126, 0.7152, 0.0722])


def linear(path):
    a = np.asarray(Image.open(path).convert("RGB")).astype(np.float64) / 255.0
    return np.where(a <= 0.04045, a / 12.92, ((a + 0.055) / 1.055) ** 2.4)


def srgb(x):
    x = np.clip(x, 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * x ** (1 / 2.4) - 0.055)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("dir")
    ap.add_argument("--shading", default="chiang")
    ap.add_argument("--block", type=int, action="append")
    ap.add_argument("--window", type=int, action="append", default=[])
    args = ap.parse_args()
    read = lambda name: linear(os.path.join(args.dir, name + ".png"))
    truth, one = read("truth_path_traced"), read("truth_one_event")
    raster_one, raster = read(f"truth_raster_one_{args.shading}"), read(f"truth_raster_{args.shading}")
    hair = (raster - raster_one).sum(axis=2) > 0.02
    for b in args.block or [8, 16]:
        h, w = (truth.shape[0] // b) * b, (truth.shape[1] // b) * b
        blocks = lambda img: img[:h, :w].reshape(h // b, b, w // b, b, -1).mean(axis=(1, 3))
        whole = blocks(hair[..., None].astype(np.float64))[..., 0] == 1.0
        t, o, r1, r = (blocks(x)[whole] for x in (truth, one, raster_one, raster))
        rmse = lambda x: np.sqrt(((srgb(x) - srgb(t)) ** 2).mean())
        stand_in, rest = (r - r1) @ LUMA, (t - o) @ LUMA
        ratio = stand_in / np.maximum(rest, 1e-9)
        p10, p50, p90 = np.percentile(ratio, [10, 50, 90])
        print(
            f"{b:>2} x {b:<2} blocks: {whole.sum():4d}  total {rmse(r):.4f}  true rest {rmse(r1 + t - o):.4f}  "
            f"stand-in / truth beyond one event p10 {p10:.2f} p50 {p50:.2f} p90 {p90:.2f}, "
            f"sums {stand_in.sum() / rest.sum():.3f}"
        )
    pixel_rmse = lambda x: np.sqrt(((srgb(x) - srgb(truth)) ** 2)[hair].mean())
    if args.window:
        print(f"per pixel over {hair.sum()} hair pixels: the raster shading {pixel_rmse(raster):.4f}")
    for w in args.window:
        inside = hair.astype(np.float64)
        stand_in = ((raster - raster_one) @ LUMA) * inside
        rest = ((truth - one) @ LUMA) * inside
        scale = box(rest, w) / np.maximum(box(stand_in, w), 1e-12)
        exact_at_w = raster_one + (raster - raster_one) * scale[..., None]
        print(f"  stand-ins exact over {w:>2} x {w:<2} windows: {pixel_rmse(exact_at_w):.4f}")


def box(x, w):
    """The sum of x over the w x w window about each pixel (cut at the image's edges)."""
    c = np.pad(x, ((1, 0), (1, 0))).cumsum(0).cumsum(1)
    h, wd = x.shape
    y0, x0 = np.clip(np.arange(h) - w // 2, 0, h), np.clip(np.arange(wd) - w // 2, 0, wd)
    y1, x1 = np.clip(np.arange(h) + w - w // 2, 0, h), np.clip(np.arange(wd) + w - w // 2, 0, wd)
    return c[y1][:, x1] - c[y0][:, x1] - c[y1][:, x0] + c[y0][:, x0]


if __name__ == "__main__":
    main()
