# SPDX-License-Identifier: Apache-2.0
"""The Cycles side of bench/blender_parity.py: every setting the bench applies must exist in
this Blender and hold afterwards.

blender -b -noaudio --factory-startup --python tests/blender/test_parity_bench.py -- \
    [--module-dir build/lib/python]

The bench set `scene.cycles.filter_glossy = 0`, a name Blender 3.4 does not have (the setting
is `blur_glossy`, "Filter Glossy" in the UI). Cycles' settings are a Python PropertyGroup, so
the misspelt attribute was silently kept and every Cycles reference was rendered with Filter
Glossy 1: glossy closures blurred after a diffuse bounce, which dimmed the caustic of a rough
gold sphere on the floor (area_disk_metal: principled +1.10% at max bounces 1; 1.8x Cycles'
one-bounce floor light). Checked: after setup_cycles() the settings read back as the bench
asked (Filter Glossy 0, no clamping, caustics on, ...), and set_props() refuses an unknown
name with an error naming it; --set KEY=VALUE reaches the delegate settings the add-on sends.
Exit code 0 = pass.
"""
import os
import runpy
import sys
import tempfile

import bpy  # noqa: F401

argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
module_dir = argv[argv.index("--module-dir") + 1] if "--module-dir" in argv else None
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
out = tempfile.mkdtemp(prefix="parity_bench_test_")
# The bench runs at import: with --only none it renders nothing and leaves its functions.
sys.argv = [sys.argv[0], "--", "--out", out, "--only", "none", "--spp", "7", "--max-bounces", "5",
            "--set", "specularFresnel=dielectric,bumpShadowing=0"]
if module_dir:
    sys.argv += ["--module-dir", module_dir]
bench = runpy.run_path(os.path.join(ROOT, "bench", "blender_parity.py"), run_name="parity_bench")

failures = []


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what, flush=True)
    if not ok:
        failures.append(what)


sc = bench["reset"]()
bench["setup_cycles"](sc, 1)
cy = sc.cycles
check(sc.render.engine == "CYCLES", "engine is Cycles")
check(cy.blur_glossy == 0.0, f"Filter Glossy (blur_glossy) is 0 (read back {cy.blur_glossy})")
check(cy.sample_clamp_indirect == 0.0 and cy.caustics_reflective and cy.caustics_refractive,
      "no indirect clamp, caustics on")
for name, want in bench.get("cycles_settings", lambda seed: {})(1).items():
    got = getattr(cy, name)
    same = abs(got - want) < 1e-6 if isinstance(want, float) else got == want
    check(same, f"cycles.{name} = {want!r} (read back {got!r})")
check(cy.samples == 7 and cy.max_bounces == 5, "samples and bounces from the command line")
# --set: extra delegate settings on top of the add-on's, typed (int, float, else token).
import principled_blender  # noqa: E402  (the bench put it on sys.path)

bench["setup_principled"](sc, 0)
extra = principled_blender._settings(sc, False)
check(extra.get("specularFresnel") == "dielectric" and extra.get("bumpShadowing") == 0
      and extra.get("maxDepth") == 5 and extra.get("convergedSamplesPerPixel") == 7,
      f"--set reaches the add-on's settings ({extra})")
set_props = bench.get("set_props")
check(set_props is not None, "the bench sets Cycles' settings through set_props()")
if set_props is not None:
    try:
        set_props(cy, filter_glossy=0.0)
        check(False, "set_props refuses the unknown name filter_glossy")
    except AttributeError as e:
        check("filter_glossy" in str(e) and "blender_parity.py" in str(e),
              f"set_props refuses the unknown name filter_glossy ({e})")

print(f"{len(failures)} failures" if failures else "all passed")
sys.exit(1 if failures else 0)
