#!/usr/bin/python3
"""principled against Blender Cycles 3.4 at equal CPU time (issue 7), and variance-per-sample
A/B runs of principled variants.

    bench/peer_equal_time.py [--scene cornell --scene fig_reference] [--res 96]
        [--ladder 4,16,64,256] [--ref-spp 4096] [--ref-runs 2] [--seed-budget 512]
        [--min-seeds 2] [--max-seeds 32] [--threads 2] [--no-cycles]
        [--ours NAME=BINARY[:KEY=VAL,KEY=VAL]] ...      (default: after=build/bin/principled)

Per scene and per principled variant: --ref-runs references at --ref-spp with seeds 1000,
1001, ..., and a ladder with seeds 0, 1, ... (different seeds: a ladder image is not a prefix of
its reference). Cycles: the same, through bench/cycles_render.py, one Blender process for the
ladder (all its seeds + a 1-spp point) and one per reference run. Errors (RMSE of linear RGB, and RMSE of images clamped to [0, 1]) are
taken against (a) the renderer's own reference (= variance: the converged models differ where
they differ by design, docs/performance.md section 5) and (b) the other renderer's reference.

Time is CPU time (the machine is shared; wall time is not comparable): principled's
renderCpuSeconds (path tracing only, no parse/sync/BVH) and Cycles' process CPU of render()
minus its fixed part (sync + BVH + film), which is the intercept of a straight-line fit of CPU
time against spp over the ladder. RMSE at equal CPU time is interpolated in log-log between
ladder points. Output: docs/perf/peer_equal_time.json, docs/perf/peer_<scene>.png. Images are
cached under build/bench/acc/ (delete to re-render).

Expected error, not one image's (issue 7). On the sun-lit figure scenes almost all of the squared
error sits in a handful of pixels whose paths are rare and very bright: the sun's reflection in the
0.02-roughness sphere covers ~1 % of one pixel (radiance ~3e4 there), and floor -> sphere -> sun
caustics reach a floor pixel about once in 10^4 samples with ~1e4 each. One image per ladder point
therefore measures whether that seed hit them: at 4-32 spp the glint pixel is usually missed and
the RMSE stays ~2.6 (= that pixel's value / 96) whatever the spp, and the reference's own noise
in that pixel is a floor under every point. So each ladder point is rendered with several seeds
(--seed-budget / spp of them, within [--min-seeds, --max-seeds]; seed 0 is the image the single-
seed versions used) and the reference is the mean of --ref-runs independent runs (seeds 1000,
1001, ...; the first is the old reference). Reported per point: `rmse` = sqrt(mean over seeds of
the MSE against the reference, minus the reference's own variance), where the latter is estimated
per pixel from the spread of the reference runs (s^2 / runs, unbiased: E[(X - R)^2] = Var X +
Var R for independent X and R of the same mean); `rmseRaw` without that subtraction, `rmseSeed0`
the old single-image figure, `rmseMedian` the median single image's (what one render typically
shows; below `rmse` when rare bright paths dominate), `rmseStdErr` the standard error over seeds (delta method), and
`worstPixelShare` the fraction of the summed squared error in the single worst pixel. The
clamped and robust metrics are averaged over seeds the same way (as RMS), without the correction
(clamped values are bounded; their reference noise is negligible).
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


def cycles(scene, outdir, spps, res, threads, seed, nseeds=None):
    nseeds = nseeds or [1] * len(spps)
    stamp = os.path.join(outdir, "done_" + ",".join(map(str, spps)) + ("" if set(nseeds) == {1} else "_seeds" + ",".join(map(str, nseeds))))
    if not os.path.exists(stamp):
        cmd = ["blender", "-b", "-noaudio", "--factory-startup", "--python", os.path.join(ROOT, "bench", "cycles_render.py"),
               "--", os.path.join(ROOT, "scenes", "desc", scene + ".json"), outdir, "--res", str(res), "--threads",
               str(threads), "--spp", ",".join(map(str, spps)), "--seed", str(seed), "--seeds", ",".join(map(str, nseeds))]
        log(" ".join(cmd))
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        open(stamp, "w").write(" ".join(cmd))
    return json.load(open(os.path.join(outdir, "cycles_times.json")))


def cycles_key(spp, seed, base):
    return str(spp) if seed == base else f"{spp}_seed{seed}"


def seeds_for(spp, a):
    return int(min(a.max_seeds, max(a.min_seeds, a.seed_budget // spp)))


def reference(runs):
    """Mean of independent reference runs and the per-pixel variance of that mean (s^2 / runs;
    zero with one run)."""
    runs = np.array(runs)
    mean = runs.mean(axis=0)
    var = runs.var(axis=0, ddof=1) / len(runs) if len(runs) > 1 else np.zeros_like(mean)
    return mean, var


def expected(imgs, ref, refvar):
    """Errors of several independent images of one ladder point against a reference (see the
    module docstring)."""
    per = [metrics(img, ref) for img in imgs]
    mses = np.array([p["rmse"] ** 2 for p in per])
    noise = float(np.mean(refvar))
    mse = float(mses.mean())
    sq = sum(np.mean((img - ref) ** 2, axis=2) for img in imgs)
    out = dict(rmse=float(np.sqrt(max(mse - noise, 0.0))), rmseRaw=float(np.sqrt(mse)), rmseSeed0=per[0]["rmse"],
               rmseMedian=float(np.median([p["rmse"] for p in per])),
               rmseStdErr=float(mses.std(ddof=1) / np.sqrt(len(mses)) / (2 * np.sqrt(max(mse - noise, 1e-30))))
               if len(mses) > 1 else None,
               referenceNoiseRmse=float(np.sqrt(noise)), seeds=len(imgs),
               worstPixelShare=float(sq.max() / max(sq.sum(), 1e-30)),
               worstPixel=[int(v) for v in np.unravel_index(int(np.argmax(sq)), sq.shape)])
    for key in ("displayRmse", "robustRmse"):
        out[key] = float(np.sqrt(np.mean([p[key] ** 2 for p in per])))
    # rmseSpread: the expected RMSE against the renderer's own converged mean from the seeds
    # alone, sqrt(mean over pixels of the per-pixel variance across seeds (ddof 1)); unbiased for
    # an unbiased renderer and free of the reference's noise (which, for a rare bright glint, a
    # two-run reference estimates poorly). Needs many seeds for rare paths.
    if len(imgs) > 1:
        out["rmseSpread"] = float(np.sqrt(np.mean(np.array(imgs).var(axis=0, ddof=1))))
    return out


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


def at_time(points, key, t, extrapolate=False):
    """log-log interpolation of points[key] at CPU time t (None outside the measured range, unless
    extrapolate: then beyond either end by the Monte Carlo rate, error proportional to t^-1/2)."""
    ts = np.array([p["cpuSeconds"] for p in points])
    es = np.array([p[key] for p in points])
    order = np.argsort(ts)
    ts, es = ts[order], es[order]
    if np.any(ts <= 0):
        return None
    if extrapolate and t < ts[0]:
        return float(es[0] * np.sqrt(ts[0] / t))
    if extrapolate and t > ts[-1]:
        return float(es[-1] * np.sqrt(ts[-1] / t))
    if t < ts[0] or t > ts[-1]:
        return None
    return float(np.exp(np.interp(np.log(t), np.log(ts), np.log(es))))


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--scene", action="append", default=[])
    p.add_argument("--res", type=int, default=96)
    p.add_argument("--ladder", default="4,16,64,256")
    p.add_argument("--ref-spp", type=int, default=4096)
    p.add_argument("--ref-runs", type=int, default=2, help="independent reference runs averaged (seeds 1000, 1001, ...)")
    p.add_argument("--seed-budget", type=int, default=512, help="seeds per ladder point = budget / spp, clamped")
    p.add_argument("--min-seeds", type=int, default=2)
    p.add_argument("--max-seeds", type=int, default=32)
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--ours", action="append", default=[])
    p.add_argument("--no-cycles", action="store_true")
    p.add_argument("--out", default=os.path.join(PERF, "peer_equal_time.json"))
    a = p.parse_args()
    scenes = a.scene or ["cornell", "fig_reference"]
    ladder = [int(x) for x in a.ladder.split(",")]
    nseeds = [seeds_for(spp, a) for spp in ladder]
    variants = {}
    for spec in a.ours or [f"after={os.path.join(ROOT, 'build', 'bin', 'principled')}"]:
        name, rest = spec.split("=", 1)
        binary, _, sets = rest.partition(":")
        variants[name] = (binary, [kv for kv in sets.split(",") if kv])
    result = dict(res=a.res, ladder=ladder, referenceSpp=a.ref_spp, referenceRuns=a.ref_runs, seeds=nseeds,
                  threads=a.threads, variants={k: dict(binary=v[0], settings=v[1]) for k, v in variants.items()},
                  scenes={})
    for scene in scenes:
        sres = dict(curves={}, references={})
        refs, refvars = {}, {}
        for vname, (binary, sets) in variants.items():
            d = os.path.join(CACHE, f"{scene}_{a.res}", vname)
            os.makedirs(d, exist_ok=True)
            runs = []
            for j in range(a.ref_runs):
                rpath = os.path.join(d, f"ref_{a.ref_spp}.exr" if j == 0 else f"ref_{a.ref_spp}_seed{1000 + j}.exr")
                r = ours(binary, scene, rpath, a.ref_spp, a.res, a.threads, 1000 + j, sets)
                if j == 0:
                    sres["references"][vname] = r
                runs.append(bench.read_exr(rpath))
            refs[vname], refvars[vname] = reference(runs)
            pts = []
            for spp, n in zip(ladder, nseeds):
                imgs, ms = [], []
                for seed in range(n):
                    path = os.path.join(d, f"ladder_{spp}.exr" if seed == 0 else f"ladder_{spp}_seed{seed}.exr")
                    ms.append(ours(binary, scene, path, spp, a.res, a.threads, seed, sets))
                    imgs.append(bench.read_exr(path))
                m = dict(ms[0], cpuSeconds=float(np.mean([x["cpuSeconds"] for x in ms])),
                         wallSeconds=float(np.mean([x["wallSeconds"] for x in ms])))
                m.update(expected(imgs, refs[vname], refvars[vname]))
                pts.append(m)
                log(f"{scene} {vname} {spp} spp x{n}: cpu {m['cpuSeconds']:.3f}s rmse {m['rmse']:.4g} (+-{m['rmseStdErr'] or 0:.2g}; "
                    f"seed 0 {m['rmseSeed0']:.4g}) clamped {m['displayRmse']:.4g} robust {m['robustRmse']:.4g}")
            sres["curves"][vname] = pts
        if not a.no_cycles:
            d = os.path.join(CACHE, f"{scene}_{a.res}", "cycles")
            times = cycles(scene, d, [1] + ladder, a.res, a.threads, 0, [1] + nseeds)
            runs = []
            for j in range(a.ref_runs):
                rd = d + "_ref" + ("" if j == 0 else f"_seed{1000 + j}")
                rt = cycles(scene, rd, [a.ref_spp], a.res, a.threads, 1000 + j)
                if j == 0:
                    rtimes = rt
                runs.append(bench.read_exr(os.path.join(rd, f"cycles_{a.ref_spp}.exr")))
            cref, crefvar = reference(runs)
            refs["cycles"], refvars["cycles"] = cref, crefvar
            xs = np.array([t["spp"] if "spp" in t else int(k) for k, t in times.items()], float)
            ys = np.array([t["cpuSeconds"] for t in times.values()])
            slope, fixed = np.polyfit(xs, ys, 1)
            pts = []
            first = next(iter(variants))
            for spp, n in zip(ladder, nseeds):
                keys = [cycles_key(spp, seed, 0) for seed in range(n)]
                imgs = [bench.read_exr(os.path.join(d, f"cycles_{k}.exr")) for k in keys]
                cpu = float(np.mean([times[k]["cpuSeconds"] for k in keys]))
                m = dict(spp=spp, cpuSeconds=max(1e-4, cpu - fixed), totalCpuSeconds=cpu,
                         wallSeconds=float(np.mean([times[k]["wallSeconds"] for k in keys])))
                m.update(expected(imgs, cref, crefvar))
                m["vsPrincipledReference"] = expected(imgs, refs[first], refvars[first])
                pts.append(m)
                log(f"{scene} cycles {spp} spp x{n}: cpu {m['cpuSeconds']:.3f}s (total {cpu:.3f}) rmse {m['rmse']:.4g} "
                    f"(+-{m['rmseStdErr'] or 0:.2g}; seed 0 {m['rmseSeed0']:.4g}) clamped {m['displayRmse']:.4g} robust {m['robustRmse']:.4g}")
            sres["curves"]["cycles"] = pts
            sres["cyclesFixedCpuSeconds"] = float(fixed)
            sres["cyclesCpuSecondsPerSpp"] = float(slope)
            sres["references"]["cycles"] = dict(spp=a.ref_spp, cpuSeconds=rtimes[str(a.ref_spp)]["cpuSeconds"])
            for vname in variants:
                for m, n in zip(sres["curves"][vname], nseeds):
                    dv = os.path.join(CACHE, f"{scene}_{a.res}", vname)
                    imgs = [bench.read_exr(os.path.join(dv, f"ladder_{m['spp']}.exr" if seed == 0 else f"ladder_{m['spp']}_seed{seed}.exr"))
                            for seed in range(n)]
                    m["vsCyclesReference"] = expected(imgs, cref, crefvar)
                diff = refs[vname] - cref
                noise = float(np.mean(refvars[vname] + crefvar))
                sres.setdefault("converged", {})[vname] = dict(
                    rmse=float(np.sqrt(max(np.mean(diff ** 2) - noise, 0.0))), rmseRaw=float(np.sqrt(np.mean(diff ** 2))),
                    displayRmse=bench.display_rmse(refs[vname], cref),
                    meanRelative=[float(x) for x in (refs[vname].mean(axis=(0, 1)) / cref.mean(axis=(0, 1)) - 1.0)])
            # Equal CPU time: at each principled ladder point's CPU time, Cycles' interpolated error.
            # Two time models. "measured": our renderCpuSeconds per point against Cycles' CPU minus
            # its fitted fixed part (the intercept). At 4 spp that difference is a few ms of a fit
            # residual (fig_reference once gave Cycles 0.0037 s for 4 spp), so the low-spp
            # comparison rests on noise. "marginal": both renderers' time is slope x spp of a
            # straight-line fit of CPU time against spp over their own ladder, i.e. the cost of
            # sampling alone with every fixed cost (sync, BVH, per-pass overhead) removed for both.
            def marginal(points):
                xs = np.array([q["spp"] for q in points], float)
                slope = np.polyfit(xs, np.array([q.get("totalCpuSeconds", q["cpuSeconds"]) for q in points]), 1)[0]
                if not slope > 0:
                    raise SystemExit(f"{scene}: CPU time does not grow with spp (slope {slope}); re-run the ladder")
                return [dict(q, cpuSeconds=float(slope * q["spp"])) for q in points], float(slope)
            cmarg, cslope = marginal(pts)
            sres["cyclesMarginalCpuSecondsPerSpp"] = cslope
            for vname in variants:
                omarg, oslope = marginal(sres["curves"][vname])
                sres.setdefault("marginalCpuSecondsPerSpp", {})[vname] = oslope
                for model, ours_pts, cyc_pts in (("equalCpuTime", sres["curves"][vname], pts),
                                                 ("equalMarginalCpuTime", omarg, cmarg)):
                    eq = []
                    for m in ours_pts:
                        row = dict(spp=m["spp"], cpuSeconds=m["cpuSeconds"])
                        for key in ("rmse", "rmseRaw", "rmseSeed0", "rmseMedian", "displayRmse", "robustRmse", "rmseSpread"):
                            if key not in m or any(key not in q for q in cyc_pts):
                                continue
                            c = at_time(cyc_pts, key, m["cpuSeconds"], extrapolate=model == "equalMarginalCpuTime")
                            ct = [q["cpuSeconds"] for q in cyc_pts]
                            row["cyclesExtrapolated"] = not (min(ct) <= m["cpuSeconds"] <= max(ct))
                            row[key] = m[key]
                            row["cycles_" + key] = c
                            row["cyclesOverOurs_" + key] = (c / m[key]) if c and m[key] > 0 else None
                        eq.append(row)
                    sres.setdefault(model, {})[vname] = eq
        result["scenes"][scene] = sres
        chart(scene, sres, a)
    old = json.load(open(a.out)) if os.path.exists(a.out) else {}
    old.setdefault("runs", {})
    key = ",".join(variants) + ("" if a.no_cycles else ",cycles") + f",seeds{a.seed_budget},refx{a.ref_runs}"
    for s, v in result["scenes"].items():
        old["runs"].setdefault(s, {})[key] = dict({k: result[k] for k in ("res", "ladder", "referenceSpp", "referenceRuns", "seeds", "threads", "variants")}, **v)
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
    for x, yl in zip(ax, ("expected RMSE (linear RGB) vs own reference", "RMSE clamped to [0,1] vs own reference",
                          "clamped RMSE without the worst 1 % of pixels")):
        x.set_xlabel(f"CPU seconds, path tracing only ({a.threads} threads)")
        x.set_ylabel(yl)
        x.grid(True, which="both", alpha=0.3)
    ax[0].legend(fontsize=8)
    fig.suptitle(f"{scene}: {a.res}x{a.res}, spp {a.ladder} (seeds per point {[seeds_for(int(x), a) for x in a.ladder.split(',')]}), "
                 f"references {a.ref_runs} x {a.ref_spp} spp (seeds 1000..)")
    fig.tight_layout()
    fig.savefig(os.path.join(PERF, f"peer_{scene}.png"), dpi=80)
    plt.close(fig)


if __name__ == "__main__":
    main()
