#!/usr/bin/python3
"""principled against Blender Cycles 3.4 at equal CPU time (issue 7), and variance-per-sample
A/B runs of principled variants.

    bench/peer_equal_time.py [--scene cornell --scene fig_reference] [--res 96]
        [--ladder 4,16,64,256] [--ref-spp 4096] [--threads 2] [--no-cycles]
        [--ours NAME=BINARY[:KEY=VAL,KEY=VAL]] ...      (default: after=build/bin/principled)

Per scene and per principled variant: a reference at --ref-spp with seed 1000, and a ladder with
seed 0 (different seeds: a ladder image is not a prefix of its reference). Cycles: the same, in
two Blender processes (seed 0 ladder + a 1-spp point, seed 1000 reference), through
bench/cycles_render.py. Errors (RMSE of linear RGB, and RMSE of images clamped to [0, 1]) are
taken against (a) the renderer's own reference (= variance: the converged models differ where
they differ by design, docs/performance.md section 5) and (b) the other renderer's reference.

Time is CPU time (the machine is shared; wall time is not comparable): principled's
renderCpuSeconds (path tracing only, no parse/sync/BVH) and Cycles' process CPU of render()
minus its fixed part (sync + BVH + film), which is the intercept of a straight-line fit of CPU
time against spp over the ladder. RMSE at equal CPU time is interpolated in log-log between
ladder points. Output: docs/perf/peer_equal_time.json, docs/perf/peer_<scene>.png. Images are
cached under build/bench/acc/ (delete to re-render).
"""
import argparse
import importlib.machinery
import json
import os
import resource
import subprocess
import sys

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
bench = importlib.machinery.SourceFileLoader("bench", os.path.join(ROOT, "scripts", "bench")).load_module()
CACHE = os.path.join(ROOT, "build", "bench", "acc")
PERF = os.path.join(ROOT, "docs", "perf")


def log(*a):
    print("peer:", *a, file=sys.stderr, flush=True)


def ours(binary, scene, out, spp, res, threads, seed, settings):
    stats = out + ".stats.json"
    if not (os.path.exists(out) and os.path.exists(stats)):
        cmd = [binary, "render", os.path.join(ROOT, "scenes", scene + ".usda"), "-o", out, "--spp", str(spp),
               "--res", f"{res}x{res}", "--threads", str(threads), "--seed", str(seed), "--stats", stats, "-q",
               "--set", "defaultLighting=0"]
        for kv in settings:
            cmd += ["--set", kv]
        log(" ".join(cmd))
        r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
        subprocess.run(cmd, check=True)
        r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
        s = json.load(open(stats))
        s["processCpuSeconds"] = (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
        json.dump(s, open(stats, "w"), indent=1)
    s = json.load(open(stats))
    # Binaries older than the acc branch do not report renderCpuSeconds: process CPU minus the
    # (single-threaded) load time stands in for it.
    cpu = s.get("renderCpuSeconds")
    if cpu is None:
        cpu = max(1e-4, s.get("processCpuSeconds", 0.0) - s.get("loadSeconds", 0.0))
    return dict(spp=spp, cpuSeconds=cpu, wallSeconds=s["renderWallSeconds"], load=bench.load())


def cycles(scene, outdir, spps, res, threads, seed):
    stamp = os.path.join(outdir, "done_" + ",".join(map(str, spps)))
    if not os.path.exists(stamp):
        cmd = ["blender", "-b", "-noaudio", "--factory-startup", "--python", os.path.join(ROOT, "bench", "cycles_render.py"),
               "--", os.path.join(ROOT, "scenes", "desc", scene + ".json"), outdir, "--res", str(res), "--threads",
               str(threads), "--spp", ",".join(map(str, spps)), "--seed", str(seed)]
        log(" ".join(cmd))
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        open(stamp, "w").write(" ".join(cmd))
    return json.load(open(os.path.join(outdir, "cycles_times.json")))


def metrics(img, ref):
    d = img - ref
    # robustRmse: clamped RMSE without the 1 % of pixels with the largest error. On the sun-lit
    # figure scenes > 90 % of the clamped error sits in < 10 pixels: sun caustics through the
    # near-mirror sphere (ground -> sphere -> sun), ~1 event per pixel per 4096 samples, in the
    # ladder image or in the reference; this figure shows the noise of everything else.
    e = np.sort(np.mean((np.clip(img, 0, 1) - np.clip(ref, 0, 1)) ** 2, axis=2).ravel())
    keep = e[: len(e) - max(1, len(e) // 100)]
    return dict(rmse=float(np.sqrt(np.mean(d * d))), displayRmse=bench.display_rmse(img, ref),
                robustRmse=float(np.sqrt(np.mean(keep))))


def at_time(points, key, t):
    """log-log interpolation of points[key] at CPU time t (None outside the measured range)."""
    ts = np.array([p["cpuSeconds"] for p in points])
    es = np.array([p[key] for p in points])
    order = np.argsort(ts)
    ts, es = ts[order], es[order]
    if t < ts[0] or t > ts[-1] or np.any(ts <= 0):
        return None
    return float(np.exp(np.interp(np.log(t), np.log(ts), np.log(es))))


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--scene", action="append", default=[])
    p.add_argument("--res", type=int, default=96)
    p.add_argument("--ladder", default="4,16,64,256")
    p.add_argument("--ref-spp", type=int, default=4096)
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--ours", action="append", default=[])
    p.add_argument("--no-cycles", action="store_true")
    p.add_argument("--out", default=os.path.join(PERF, "peer_equal_time.json"))
    a = p.parse_args()
    scenes = a.scene or ["cornell", "fig_reference"]
    ladder = [int(x) for x in a.ladder.split(",")]
    variants = {}
    for spec in a.ours or [f"after={os.path.join(ROOT, 'build', 'bin', 'principled')}"]:
        name, rest = spec.split("=", 1)
        binary, _, sets = rest.partition(":")
        variants[name] = (binary, [kv for kv in sets.split(",") if kv])
    result = dict(res=a.res, ladder=ladder, referenceSpp=a.ref_spp, threads=a.threads,
                  variants={k: dict(binary=v[0], settings=v[1]) for k, v in variants.items()}, scenes={})
    for scene in scenes:
        sres = dict(curves={}, references={})
        refs = {}
        for vname, (binary, sets) in variants.items():
            d = os.path.join(CACHE, f"{scene}_{a.res}", vname)
            os.makedirs(d, exist_ok=True)
            rpath = os.path.join(d, f"ref_{a.ref_spp}.exr")
            sres["references"][vname] = ours(binary, scene, rpath, a.ref_spp, a.res, a.threads, 1000, sets)
            refs[vname] = bench.read_exr(rpath)
            pts = []
            for spp in ladder:
                path = os.path.join(d, f"ladder_{spp}.exr")
                m = ours(binary, scene, path, spp, a.res, a.threads, 0, sets)
                img = bench.read_exr(path)
                m.update(metrics(img, refs[vname]))
                pts.append(m)
                log(f"{scene} {vname} {spp} spp: cpu {m['cpuSeconds']:.3f}s rmse {m['rmse']:.4g} clamped {m['displayRmse']:.4g}")
            sres["curves"][vname] = pts
        if not a.no_cycles:
            d = os.path.join(CACHE, f"{scene}_{a.res}", "cycles")
            times = cycles(scene, d, [1] + ladder, a.res, a.threads, 0)
            rtimes = cycles(scene, d + "_ref", [a.ref_spp], a.res, a.threads, 1000)
            cref = bench.read_exr(os.path.join(d + "_ref", f"cycles_{a.ref_spp}.exr"))
            refs["cycles"] = cref
            xs = np.array([1] + ladder, float)
            ys = np.array([times[str(s)]["cpuSeconds"] for s in [1] + ladder])
            slope, fixed = np.polyfit(xs, ys, 1)
            pts = []
            for spp in ladder:
                img = bench.read_exr(os.path.join(d, f"cycles_{spp}.exr"))
                t = times[str(spp)]
                m = dict(spp=spp, cpuSeconds=max(1e-4, t["cpuSeconds"] - fixed), totalCpuSeconds=t["cpuSeconds"],
                         wallSeconds=t["wallSeconds"])
                m.update(metrics(img, cref))
                first = next(iter(variants))
                m["vsPrincipledReference"] = metrics(img, refs[first])
                pts.append(m)
                log(f"{scene} cycles {spp} spp: cpu {m['cpuSeconds']:.3f}s (total {t['cpuSeconds']:.3f}) rmse {m['rmse']:.4g} clamped {m['displayRmse']:.4g}")
            sres["curves"]["cycles"] = pts
            sres["cyclesFixedCpuSeconds"] = float(fixed)
            sres["cyclesCpuSecondsPerSpp"] = float(slope)
            sres["references"]["cycles"] = dict(spp=a.ref_spp, cpuSeconds=rtimes[str(a.ref_spp)]["cpuSeconds"])
            for vname in variants:
                for m in sres["curves"][vname]:
                    img = bench.read_exr(os.path.join(CACHE, f"{scene}_{a.res}", vname, f"ladder_{m['spp']}.exr"))
                    m["vsCyclesReference"] = metrics(img, cref)
                diff = refs[vname] - cref
                sres.setdefault("converged", {})[vname] = dict(
                    rmse=float(np.sqrt(np.mean(diff ** 2))), displayRmse=bench.display_rmse(refs[vname], cref),
                    meanRelative=[float(x) for x in (refs[vname].mean(axis=(0, 1)) / cref.mean(axis=(0, 1)) - 1.0)])
            # Equal CPU time: at each principled ladder point's CPU time, Cycles' interpolated error.
            for vname in variants:
                eq = []
                for m in sres["curves"][vname]:
                    row = dict(spp=m["spp"], cpuSeconds=m["cpuSeconds"])
                    for key in ("rmse", "displayRmse", "robustRmse"):
                        c = at_time(pts, key, m["cpuSeconds"])
                        row[key] = m[key]
                        row["cycles_" + key] = c
                        row["cyclesOverOurs_" + key] = (c / m[key]) if c else None
                    eq.append(row)
                sres.setdefault("equalCpuTime", {})[vname] = eq
        result["scenes"][scene] = sres
        chart(scene, sres, a)
    old = json.load(open(a.out)) if os.path.exists(a.out) else {}
    old.setdefault("runs", {})
    key = ",".join(variants) + ("" if a.no_cycles else ",cycles")
    for s, v in result["scenes"].items():
        old["runs"].setdefault(s, {})[key] = dict({k: result[k] for k in ("res", "ladder", "referenceSpp", "threads", "variants")}, **v)
    json.dump(old, open(a.out, "w"), indent=1)
    log("wrote", a.out)


def chart(scene, sres, a):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(1, 3, figsize=(15, 4.2))
    for name, pts in sres["curves"].items():
        t = [p["cpuSeconds"] for p in pts]
        style = "k^--" if name == "cycles" else "o-"
        for x, key in zip(ax, ("rmse", "displayRmse", "robustRmse")):
            x.loglog(t, [p[key] for p in pts], style, label=name if name != "cycles" else "Cycles 3.4")
    for x, yl in zip(ax, ("RMSE (linear RGB) vs own reference", "RMSE clamped to [0,1] vs own reference",
                          "clamped RMSE without the worst 1 % of pixels")):
        x.set_xlabel(f"CPU seconds, path tracing only ({a.threads} threads)")
        x.set_ylabel(yl)
        x.grid(True, which="both", alpha=0.3)
    ax[0].legend(fontsize=8)
    fig.suptitle(f"{scene}: {a.res}x{a.res}, spp {a.ladder}, references {a.ref_spp} spp (seed 1000)")
    fig.tight_layout()
    fig.savefig(os.path.join(PERF, f"peer_{scene}.png"), dpi=80)
    plt.close(fig)


if __name__ == "__main__":
    main()
