#!/usr/bin/python3
"""Per-pixel variance of a render over seeds, and its CPU time: the measurement behind the
sampling decisions in docs/performance.md section 5f (Russian roulette, MIS compensation).

    bench/pixel_variance.py SCENE.usda [--spp 64] [--seeds 16] [--res 96] [--threads 2]
        [--bin build/bin/principled] [--region NAME=y0:y1,x0:x1 ...] [--set KEY=VALUE ...]
        [--time-spp 256 --time-runs 3]

Renders the scene with seeds 0..seeds-1, takes each pixel's variance over the seeds (linear RGB,
averaged over channels) and prints its mean over the image and over each region, with the
image mean. With --time-spp, also the median render CPU seconds (one thread, --stats
renderCpuSeconds) and the rays of --time-runs renders. Variance x CPU time is the inverse
efficiency to compare sampling choices by.
"""
import argparse
import importlib.machinery
import json
import os
import subprocess
import sys
import tempfile

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
bench = importlib.machinery.SourceFileLoader("bench", os.path.join(ROOT, "scripts", "bench")).load_module()


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scene")
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--seeds", type=int, default=16)
    ap.add_argument("--res", type=int, default=96)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--bin", default=os.path.join(ROOT, "build", "bin", "principled"))
    ap.add_argument("--region", action="append", default=[], help="NAME=y0:y1,x0:x1 (pixel rows, columns)")
    ap.add_argument("--set", action="append", default=[], dest="settings")
    ap.add_argument("--time-spp", type=int, default=0)
    ap.add_argument("--time-runs", type=int, default=3)
    a = ap.parse_args()
    sets = [x for kv in a.settings for x in ("--set", kv)]
    with tempfile.TemporaryDirectory() as tmp:
        imgs = []
        for seed in range(a.seeds):
            out = os.path.join(tmp, "s%d.exr" % seed)
            subprocess.run([a.bin, "render", a.scene, "-o", out, "--spp", str(a.spp), "--res", "%dx%d" % (a.res, a.res),
                            "--threads", str(a.threads), "-q", "--seed", str(seed)] + sets, check=True)
            imgs.append(bench.read_exr(out))
        stack = np.array(imgs)
        var = stack.var(axis=0, ddof=1).mean(axis=-1)
        result = {"scene": a.scene, "spp": a.spp, "seeds": a.seeds, "settings": a.settings,
                  "pixelVariance": float(var.mean()), "imageMean": float(stack.mean())}
        for r in a.region:
            name, box = r.split("=")
            ys, xs = box.split(",")
            y0, y1 = (int(v) for v in ys.split(":"))
            x0, x1 = (int(v) for v in xs.split(":"))
            result["pixelVariance_" + name] = float(var[y0:y1, x0:x1].mean())
        if a.time_spp > 0:
            runs = []
            for k in range(a.time_runs):
                st = os.path.join(tmp, "t.json")
                subprocess.run([a.bin, "render", a.scene, "-o", os.path.join(tmp, "t.exr"), "--spp", str(a.time_spp),
                                "--res", "%dx%d" % (a.res, a.res), "--threads", "1", "-q", "--stats", st] + sets, check=True)
                s = json.load(open(st))
                runs.append((s["renderCpuSeconds"], s["delegate"]["rays"]))
            runs.sort()
            result["cpuSecondsMedian"] = runs[len(runs) // 2][0]
            result["rays"] = runs[0][1]
            result["varianceTimesCpu"] = result["pixelVariance"] * result["cpuSecondsMedian"]
    print(json.dumps(result, indent=1))


if __name__ == "__main__":
    sys.exit(main())
