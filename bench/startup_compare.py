#!/usr/bin/python3
"""Start-up cost of several principled binaries side by side (docs/performance.md section 0, branch
`exr`): `ldd` lines, the loader's final relocations and cycles (`LD_DEBUG=statistics BIN --help`), and
best-of-N wall/CPU of `--help` and `render -o /tmp/fi.exr --spp 1 --res 640x360 --threads 2 -q`, the
binaries interleaved so they see the same load.

    bench/startup_compare.py BIN... (RUNS=5, RT=1: under chrt -f 10)
"""
import json, os, resource, subprocess, sys, time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
runs = int(os.environ.get("RUNS", "5")); rt = os.environ.get("RT") == "1"
bins = sys.argv[1:]
pre = ["chrt", "-f", "10"] if rt else []
def timed(cmd):
    c0 = resource.getrusage(resource.RUSAGE_CHILDREN); w0 = time.perf_counter()
    subprocess.run(pre + cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=True, cwd=ROOT)
    w = time.perf_counter() - w0; c1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    return w, c1.ru_utime + c1.ru_stime - c0.ru_utime - c0.ru_stime
res = {}
for b in bins:
    ldd = len(subprocess.run(["ldd", b], capture_output=True, text=True).stdout.splitlines())
    st = subprocess.run([b, "--help"], capture_output=True, text=True, env=dict(os.environ, LD_DEBUG="statistics")).stderr
    rel = [l for l in st.splitlines() if "final number of relocations:" in l][0].split()[-1]
    cyc = [l for l in st.splitlines() if "total startup time in dynamic loader" in l][0].split(":")[-1].strip()
    res[b] = dict(ldd=ldd, relocations=int(rel), loaderCycles=cyc, help=[], render=[])
loads = []
for _ in range(runs):
    loads.append(open("/proc/loadavg").read().split()[0])
    for b in bins:
        res[b]["help"].append(timed([b, "--help"]))
        res[b]["render"].append(timed([b, "render", "-o", "/tmp/fi.exr", "--spp", "1", "--res", "640x360", "--threads", "2", "-q"]))
for b in bins:
    r = res[b]
    for k in ("help", "render"):
        r[k + "WallMs"] = round(min(w for w, _ in r[k]) * 1e3, 1); r[k + "CpuMs"] = round(min(c for _, c in r[k]) * 1e3, 1); del r[k]
print(json.dumps(dict(rt=rt, loads=loads, results=res), indent=1))
