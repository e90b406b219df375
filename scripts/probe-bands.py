#!/usr/bin/env python3
"""Splits the fibres model's error against the path-traced truth by where the light comes from and by height in
the image (docs/truth.md, "Where the fibres model's light goes wrong").

    pip install mitsuba numpy pillow    # mitsuba only reads the path tracer's EXR files
    python3 scripts/probe-bands.py [--hairlab target/release/hairlab] [--preset blond]... [--set K=V]... [--spp 64] [--out DIR [--keep]]

Per preset it renders at 320 x 240, each scene with its floor and without (`scene.generator.floor=false`):
  truth      `render.mode=path`, every event, and `render.path.events=one` (one scattering event)
  raster     `render.hair_model=fibres`, Marschner, the depth-peeled reference's shadows (`method.name=reference`)
             under the exact eye transparency (`transparency.name=sorted`), as `measure shadows` draws it; and
             three copies with one part of the eye pass's light kept (the shaders read from a folder with
             `shaders/common/strand_shading.wgsl` and `mesh_bounce.wgsl` edited): `direct` (the light through the
             map's V, Marschner's lobes), `forward` (the light forward-scattered through fibres, dual scattering's
             global term) and `probe` (the light probe's: the meshes' bounce and the hair's own scattered light)
  hair mask  the pixels the raster's hair colour changes (absorber model, no shadows: every strand fragment
             lit), so every pixel where a strand is seen
and prints, over the hair and over six bands of its rows from top to bottom, the linear luminance of each: the
truth and the raster with the floor, the floor's part (with minus without), and without the floor the truth's
one event, the truth's light beyond it and the raster's three parts.
"""
import argparse, os, subprocess, sys, tempfile

import numpy as np
import mitsuba as mi
from PIL import Image

mi.set_variant("scalar_rgb")
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
LUMA = np.array([0.2126, 0.7152, 0.0722])
DIRECT = "return (s * v + scattered) * FIBRE_IRRADIANCE;"
PROBE = "return (a.forward + a.backward) * bounce_at(world);"
KEEP = {
    "direct": (DIRECT.replace("scattered)", "0.0 * scattered)"), PROBE.replace("return ", "return 0.0 * ")),
    "forward": (DIRECT.replace("(s * v", "(0.0 * s * v"), PROBE.replace("return ", "return 0.0 * ")),
    "probe": (DIRECT.replace("(s * v + scattered)", "(0.0 * s * v + 0.0 * scattered)"), PROBE),
}


def shader_folders(work):
    """One shader folder per part kept; fails naming the line when the shaders no longer read as expected."""
    folders = {}
    for part, (strand, probe) in KEEP.items():
        common = os.path.join(work, "shaders-" + part, "common")
        os.makedirs(common, exist_ok=True)
        for name, old, new in [("strand_shading.wgsl", DIRECT, strand), ("mesh_bounce.wgsl", PROBE, probe)]:
            text = open(os.path.join(ROOT, "shaders", "common", name)).read()
            if text.count(old) != 1:
                sys.exit(f"shaders/common/{name}: expected the line `{old}` once; update {sys.argv[0]}")
            open(os.path.join(common, name), "w").write(text.replace(old, new))
        folders[part] = os.path.dirname(common)
    return folders


def render(args, preset, out, sets, shaders=None):
    if args.keep and os.path.exists(out):
        return
    cmd = [args.hairlab, "render", "--preset", preset, "--width", "320", "--height", "240", "--out", out]
    for s in sets:
        cmd += ["--set", s]
    if shaders:
        cmd += ["--shaders", shaders]
    run = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    if run.returncode != 0:
        sys.exit(f"{' '.join(cmd)}\nfailed (exit {run.returncode}): {run.stderr.strip()[-2000:]}")


def linear(path):
    if path.endswith(".exr"):
        return np.array(mi.Bitmap(path), dtype=np.float64)[..., :3]
    x = np.array(Image.open(path).convert("RGB"), dtype=np.float64) / 255
    return np.where(x <= 0.04045, x / 12.92, ((x + 0.055) / 1.055) ** 2.4)


def scene(args, folders, preset, floor):
    """The luminance images of one scene, by name, and its hair mask."""
    base = os.path.join(args.out, f"{preset}-{'floor' if floor else 'nofloor'}")
    sets = [f"scene.generator.floor={'true' if floor else 'false'}", "render.hair_model=fibres",
            "render.shading=marschner", "render.background=[0,0,0]"] + args.set
    path = sets + ["render.mode=path", f"render.spp={args.spp}"]
    raster = sets + ["method.name=reference", "transparency.name=sorted"]
    images = {}
    for name, extra in [("truth", []), ("one", ["render.path.events=one"])]:
        render(args, preset, f"{base}-{name}.exr", path + extra)
        images[name] = linear(f"{base}-{name}.exr")
    render(args, preset, f"{base}-raster.png", raster)
    images["raster"] = linear(f"{base}-raster.png")
    for part, folder in folders.items():
        render(args, preset, f"{base}-{part}.png", raster, folder)
        images[part] = linear(f"{base}-{part}.png")
    masks = []
    for k, colour in enumerate(["[1,1,1]", "[0.25,0.25,0.25]"]):
        out = f"{base}-mask{k}.png"
        render(args, preset, out, sets + ["render.hair_model=absorber", "method.name=none",
                                          f"render.hair_color={colour}"])
        masks.append(linear(out))
    return {k: v @ LUMA for k, v in images.items()}, np.abs(masks[0] - masks[1]).sum(-1) > 0


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--hairlab", default=os.path.join(ROOT, "target", "release", "hairlab"))
    ap.add_argument("--preset", action="append")
    ap.add_argument("--set", action="append", default=[], help="a setting for every render, K=V")
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--out", default=None)
    ap.add_argument("--keep", action="store_true", help="reuse the images already in --out")
    args = ap.parse_args()
    args.out = args.out or tempfile.mkdtemp(prefix="probe-bands-")
    os.makedirs(args.out, exist_ok=True)
    folders = shader_folders(args.out)
    for preset in args.preset or ["default", "blond", "back-lit"]:
        lit, mask = scene(args, folders, preset, True)
        dark, _ = scene(args, folders, preset, False)
        rows = np.where(mask.any(1))[0]
        regions = [("hair", mask)] + [
            (f"rows {b[0]}-{b[-1]}", mask & np.isin(np.arange(mask.shape[0]), b)[:, None])
            for b in np.array_split(rows, 6)
        ]
        print(f"\n{preset} ({mask.sum()} hair pixels; linear luminance, mean over the region)")
        print(f"{'region':>14} | {'truth':>7} {'raster':>7} | floor's part: {'truth':>7} {'raster':>7} | "
              f"no floor: {'one':>7} {'beyond':>7} {'direct':>7} {'forward':>7} {'probe':>7}")
        for name, m in regions:
            mean = lambda images, k: images[k][m].mean()
            print(f"{name:>14} | {mean(lit, 'truth'):7.4f} {mean(lit, 'raster'):7.4f} | "
                  f"{'':>13} {mean(lit, 'truth') - mean(dark, 'truth'):7.4f} "
                  f"{mean(lit, 'raster') - mean(dark, 'raster'):7.4f} | {'':>9} {mean(dark, 'one'):7.4f} "
                  f"{mean(dark, 'truth') - mean(dark, 'one'):7.4f} {mean(dark, 'direct'):7.4f} "
                  f"{mean(dark, 'forward'):7.4f} {mean(dark, 'probe'):7.4f}")
    print(f"\nimages in {args.out}")


if __name__ == "__main__":
    main()
