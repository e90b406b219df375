#!/usr/bin/env python3
"""Renders one hairlab scene path-traced by hairlab and by Mitsuba 3 and says whether the images agree within
their noise.

    pip install mitsuba==3.9.1 numpy    # the version this script was checked with (it pins drjit 1.5.0)
    python3 scripts/mitsuba-check.py [--hairlab target/release/hairlab] [--preset default] [--set K=V]...
        [--width 320 --height 240 --spp 256] [--out DIR]

It runs `hairlab export --format mitsuba`, renders the scene twice with each renderer (seeds 0 and 1, linear
EXR, same size and samples per pixel, Mitsuba's `scalar_rgb` variant: its LLVM variants need a matching LLVM)
and prints, per renderer, the time and the mean radiance, then:

Checked with Mitsuba 3.9.1 only, whose `linearcurve` leaves the shading frame's tangent arbitrary (it sets no
dp_du, so the frame falls back to `coordinate_system(n)`; fixed after 3.9.1), and its `hair` BSDF reads the fibre
axis from that frame.
The images compared here wrap the exported `hair` BSDF in `fibreframe`, a Python BSDF that hands the inner
`hair` the frame whose tangent is the hit segment's axis (from `hair.txt` and the hit's primitive index) and
changes nothing else. The time compared is Mitsuba's on the exported scene as written, without the wrapper
(whose Python calls dominate its own time); the wrapped time is printed too.
  noise      the per-pixel standard deviation of each renderer, from its two seeds: rmse(seed 0, seed 1) / sqrt 2
  cross      rmse(hairlab seed 0, Mitsuba seed 0); with no bias it is sqrt(noise_h^2 + noise_m^2)
  bias       sqrt(max(0, cross^2 - noise_h^2 - noise_m^2)): the per-pixel difference the noise does not explain
  mean diff  the whole image's mean difference (hairlab - Mitsuba) over its standard error (|z| < 3: none)
"""
import argparse, os, subprocess, sys, tempfile, time

import drjit as dr
import numpy as np
import mitsuba as mi

mi.set_variant("scalar_rgb")


def fibre_axes(curve_file):
    """The unit axis of every segment of a linearcurve file, in Mitsuba's primitive order."""
    axes = []
    for block in open(curve_file).read().split("\n\n"):
        points = [np.array(list(map(float, line.split()))[:3]) for line in block.splitlines() if line.strip()]
        axes += [(b - a) / np.linalg.norm(b - a) for a, b in zip(points, points[1:])]
    return np.array(axes)


class FibreFrame(mi.BSDF):
    """The nested `hair` BSDF in the frame whose tangent is the hit segment's axis."""

    axes = None

    def __init__(self, props):
        mi.BSDF.__init__(self, props)
        self.inner = props["inner"]
        self.m_flags = self.inner.flags()
        self.m_components = [self.inner.flags(i) for i in range(self.inner.component_count())]

    def _local(self, si):
        t = mi.Vector3f(*FibreFrame.axes[si.prim_index])
        n = si.sh_frame.n
        s = dr.normalize(dr.cross(t, n))
        frame = mi.Frame3f(s, dr.cross(n, s), n)
        inner = mi.SurfaceInteraction3f(si)
        inner.wi = frame.to_local(si.sh_frame.to_world(si.wi))
        inner.sh_frame = frame
        return frame, inner

    def sample(self, ctx, si, s1, s2, active=True):
        frame, inner = self._local(si)
        bs, w = self.inner.sample(ctx, inner, s1, s2, active)
        bs.wo = si.sh_frame.to_local(frame.to_world(bs.wo))
        return bs, w

    def eval(self, ctx, si, wo, active=True):
        frame, inner = self._local(si)
        return self.inner.eval(ctx, inner, frame.to_local(si.sh_frame.to_world(wo)), active)

    def pdf(self, ctx, si, wo, active=True):
        frame, inner = self._local(si)
        return self.inner.pdf(ctx, inner, frame.to_local(si.sh_frame.to_world(wo)), active)

    def eval_pdf(self, ctx, si, wo, active=True):
        return self.eval(ctx, si, wo, active), self.pdf(ctx, si, wo, active)

    def to_string(self):
        return "FibreFrame"


mi.register_bsdf("fibreframe", lambda props: FibreFrame(props))


def wrapped_scene(scene_dir):
    """The exported scene with its `hair` BSDF inside `fibreframe`."""
    xml = open(os.path.join(scene_dir, "scene.xml")).read()
    start = xml.index('<bsdf type="hair">')
    end = xml.index("</bsdf>", start) + len("</bsdf>")
    inner = xml[start:end].replace('<bsdf type="hair">', '<bsdf type="hair" name="inner">', 1)
    path = os.path.join(scene_dir, "scene_fibreframe.xml")
    open(path, "w").write(xml[:start] + '<bsdf type="fibreframe">' + inner + "</bsdf>" + xml[end:])
    return path


def rmse(a, b):
    return float(np.sqrt(np.mean((a - b) ** 2)))


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--hairlab", default="target/release/hairlab")
    p.add_argument("--preset", default="default")
    p.add_argument("--set", action="append", default=[])
    p.add_argument("--width", type=int, default=320)
    p.add_argument("--height", type=int, default=240)
    p.add_argument("--spp", type=int, default=256)
    p.add_argument("--out", default=None, help="keep the scene and the images here")
    p.add_argument("--time-only", action="store_true",
                   help="only time one render of each (hairlab, and Mitsuba on the scene as exported)")
    a = p.parse_args()
    out = a.out or tempfile.mkdtemp(prefix="hairlab-mitsuba-")
    os.makedirs(out, exist_ok=True)
    scene_args = ["--preset", a.preset, "--width", str(a.width), "--height", str(a.height),
                  "--set", f"render.spp={a.spp}"]
    for kv in a.set:
        scene_args += ["--set", kv]
    subprocess.run([a.hairlab, "export", "--format", "mitsuba", *scene_args, "--out", os.path.join(out, "scene")],
                   check=True, stdout=subprocess.DEVNULL)
    images, times = {}, {}
    seeds = (0,) if a.time_only else (0, 1)
    for seed in seeds:
        path = os.path.join(out, f"hairlab_{seed}.exr")
        start = time.perf_counter()
        subprocess.run([a.hairlab, "render", *scene_args, "--set", "render.mode=path", "--set", f"render.seed={seed}",
                        "--out", path], check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        times[("hairlab", seed)] = time.perf_counter() - start
        images[("hairlab", seed)] = np.array(mi.Bitmap(path))[..., :3].astype(np.float64)
    scene_dir = os.path.join(out, "scene")
    FibreFrame.axes = fibre_axes(os.path.join(scene_dir, "hair.txt"))
    start = time.perf_counter()
    mi.render(mi.load_file(os.path.join(scene_dir, "scene.xml")), spp=a.spp, seed=0)
    plain = time.perf_counter() - start
    if a.time_only:
        print(f"{a.preset} {' '.join(a.set)} {a.width}x{a.height}, {a.spp} spp, {os.cpu_count()} cores: hairlab "
              f"{times[('hairlab', 0)]:.2f} s, Mitsuba {plain:.2f} s, hairlab / Mitsuba {times[('hairlab', 0)] / plain:.2f}")
        return
    for seed in (0, 1):
        start = time.perf_counter()
        image = mi.render(mi.load_file(wrapped_scene(scene_dir)), spp=a.spp, seed=seed)
        times[("mitsuba", seed)] = time.perf_counter() - start
        mi.Bitmap(image).write(os.path.join(out, f"mitsuba_{seed}.exr"))
        images[("mitsuba", seed)] = np.array(image)[..., :3].astype(np.float64)
    print(f"{a.preset} {' '.join(a.set)} {a.width}x{a.height}, {a.spp} spp, {os.cpu_count()} cores; files in {out}")
    noise = {}
    for r in ("hairlab", "mitsuba"):
        noise[r] = rmse(images[(r, 0)], images[(r, 1)]) / np.sqrt(2)
        mean = images[(r, 0)].mean(axis=(0, 1))
        label = "mitsuba (fibreframe)" if r == "mitsuba" else r
        print(f"  {label:20} time {times[(r, 0)]:7.2f} s, {times[(r, 1)]:7.2f} s   mean RGB "
              f"({mean[0]:.5f}, {mean[1]:.5f}, {mean[2]:.5f})   noise {noise[r]:.5f}")
    cross = rmse(images[("hairlab", 0)], images[("mitsuba", 0)])
    bias = np.sqrt(max(0.0, cross ** 2 - noise["hairlab"] ** 2 - noise["mitsuba"] ** 2))
    d = (images[("hairlab", 0)] - images[("mitsuba", 0)]).mean(axis=2).ravel()
    z = d.mean() / (d.std(ddof=1) / np.sqrt(d.size))
    ratio = times[("hairlab", 0)] / plain
    print(f"  cross {cross:.5f} (no bias: {np.hypot(noise['hairlab'], noise['mitsuba']):.5f})   bias {bias:.5f}   "
          f"mean diff {d.mean():+.6f} (z = {z:+.2f})")
    print(f"  time: hairlab {times[('hairlab', 0)]:.2f} s, Mitsuba on the scene as exported {plain:.2f} s: "
          f"hairlab / Mitsuba {ratio:.2f}")


if __name__ == "__main__":
    sys.exit(main())
