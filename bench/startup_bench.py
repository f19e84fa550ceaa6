#!/usr/bin/python3
"""Process start-up and first image (issue #7, docs/performance.md section 0), best of N.

    bench/startup_bench.py [BIN] [--runs N] [--rt]

BIN defaults to build/bin/principled. Per run: `render -o /tmp/fi.exr --spp 1 --res 640x360
--threads 2 -q --stats` (whole-process wall and CPU from getrusage(RUSAGE_CHILDREN); exec -> first
image = the child's firstImageUnixSeconds minus the time taken just before the exec), then
`--help`, `info scenes/default.usda` and `plugins`. --rt runs each command under `chrt -f 10`
(SCHED_FIFO, needs root: the other processes on a shared machine cannot preempt it, standing in
for an idle machine). Prints one JSON object, figures in ms, with the load averages seen.
"""
import argparse, json, os, resource, subprocess, time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ap = argparse.ArgumentParser()
ap.add_argument("bin", nargs="?", default=os.path.join(ROOT, "build", "bin", "principled"))
ap.add_argument("--runs", type=int, default=5)
ap.add_argument("--rt", action="store_true")
a = ap.parse_args()
prefix = ["chrt", "-f", "10"] if a.rt else []


def timed(cmd):
    c0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.time()
    w0 = time.perf_counter()
    subprocess.run(prefix + cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, cwd=ROOT, check=True)
    w = time.perf_counter() - w0
    c1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    return t0, w, c1.ru_utime + c1.ru_stime - c0.ru_utime - c0.ru_stime


B = a.bin
res = {"bin": os.path.relpath(B, ROOT), "rt": a.rt, "loads": []}
rows = []
for _ in range(a.runs):
    res["loads"].append(open("/proc/loadavg").read().split()[0])
    st = "/tmp/principled_startup_stats.json"
    t0, wall, cpu = timed([B, "render", "-o", "/tmp/fi.exr", "--spp", "1", "--res", "640x360", "--threads", "2",
                           "-q", "--stats", st])
    j = json.load(open(st))
    _, hwall, hcpu = timed([B, "--help"])
    _, iwall, icpu = timed([B, "info", "scenes/default.usda"])
    _, pwall, pcpu = timed([B, "plugins"])
    rows.append(dict(renderWall=wall, renderCpu=cpu, helpWall=hwall, helpCpu=hcpu, infoWall=iwall, infoCpu=icpu,
                     pluginsWall=pwall, pluginsCpu=pcpu, loadSync=j["loadSeconds"], pass1Wall=j["renderWallSeconds"],
                     pass1Cpu=j["renderCpuSeconds"],
                     # binaries without the startup fields: --help (the loader) + load + pass
                     estimatedExecToFirst=hwall + j["loadSeconds"] + j["renderWallSeconds"],
                     execToFirst=(j["firstImageUnixSeconds"] - t0) if "firstImageUnixSeconds" in j else None,
                     processToFirst=j.get("processToFirstImageSeconds"),
                     processToInit=j.get("processToInitSeconds"),
                     cpuToFirst=j.get("processCpuToFirstImageSeconds")))
for k in rows[0]:
    vals = [r[k] for r in rows if r[k] is not None]
    if vals:
        res[k] = round(min(vals) * 1e3, 1)
print(json.dumps(res))
