"""The Python module against analytic answers (run by tests/python/module_test.cpp with Debian's
/usr/bin/python3 and the build's module on PYTHONPATH):
  check_module.py VESSELMESH_PROGRAM WORK_FOLDER EXAMPLES_FOLDER
A pipe of radius 2 mm and length 12 mm (made by `vesselmesh synth`): its two ends, curvature 1/R
around it and 0 along it, one centerline branch of radius R, the distance map, a uniform remesh as the
program's, its volume written and read back, steady Poiseuille flow through it with the WSS on a ring
at mid-length against 4 mu Q / (pi R^3); bad input raising ValueError with the library's message.
Exits 1 naming the first check that fails."""
import json
import math
import subprocess
import sys

import numpy as np
import vesselmesh as vm


def expect(condition, what):
    if not condition:
        print("failed:", what)
        sys.exit(1)
    print("ok:", what)


program, work, examples = sys.argv[1:4]
R, L = 2.0, 12.0
subprocess.run([program, "synth", "cylinder", "--radius", str(R), "--length", str(L), "--resolution", "0.4",
                "-o", f"{work}/pipe.stl", "-q"], check=True)
points, triangles = vm.read_surface(f"{work}/pipe.stl")
expect(points.dtype == np.float64 and points.shape[1] == 3, "points (n, 3) float64")
expect(triangles.dtype == np.int32 and triangles.shape[1] == 3, "triangles (m, 3) int32")
info = vm.info(points, triangles)
expect(len(info["ends"]) == 2 and all(abs(e["radius"] - R) < 0.02 * R for e in info["ends"]),
       f"two ends of radius {R} ({[round(e['radius'], 3) for e in info['ends']]})")
c = vm.curvature(points, triangles)
middle = np.abs(points[:, 2] - L / 2) < L / 4
expect(abs(np.median(c["k2"][middle]) - 1 / R) < 0.03 / R, f"k2 = 1/R ({np.median(c['k2'][middle]):.4f})")
expect(abs(np.median(c["k1"][middle])) < 0.03 / R, f"k1 = 0 ({np.median(c['k1'][middle]):.4f})")
branches = vm.centerlines(points, triangles)
expect(len(branches) == 1, "one centerline branch")
expect(abs(np.median(branches[0]["radius"]) - R) < 0.05 * R, f"its radius R ({np.median(branches[0]['radius']):.3f})")
d = vm.distance_map(points, triangles)
expect(abs(np.median(d["distance"][middle]) - R) < 0.03 * R, "the distance map: R from the centerline")
field = vm.size_field(points, triangles, "uniform", 2000)
expect(field["metric"].shape == (len(points), 6), "a metric per point")
q, t, stats = vm.remesh(points, triangles, "uniform", 2000)
cli = subprocess.run([program, "remesh", f"{work}/pipe.stl", "--size", "uniform", "--target-triangles", "2000", "-o",
                      f"{work}/remeshed.vtp", "--json", "-q"], check=True, capture_output=True, text=True)
expect(stats["triangles"] == json.loads(cli.stdout)["triangles"] == len(t),
       f"remeshed as `vesselmesh remesh --size uniform --target-triangles 2000` ({stats['triangles']} triangles)")
expect(stats["min_angle_deg"] >= 20.0, f"its smallest angle >= 20 ({stats['min_angle_deg']:.1f})")
volume = vm.volume(q, t)
expect(set(volume["tag_names"].values()) == {"wall", "inlet", "outlet_1"}, f"tags {volume['tag_names']}")
vm.write_volume(f"{work}/pipe.msh", volume)
again = vm.read_volume(f"{work}/pipe.msh")
expect(again["tetrahedra"].shape == volume["tetrahedra"].shape, "the volume read back")
case = open(f"{examples}/pipe_steady.toml").read().replace("../build/pipe.msh", f"{work}/pipe.msh")
open(f"{work}/case.toml", "w").write(case)
summary = vm.simulate(f"{work}/case.toml", f"{work}/flow")
expect(summary["status"] == "completed", f"the steady flow ({summary['status']}, residual {summary['steady_residual']:.1e})")
ring = vm.wss_ring(f"{work}/flow", [0, 0, L / 2], [0, 0, 1])
exact = 4 * 0.0035 * 1e-6 / (math.pi * (R * 1e-3) ** 3)  # examples/pipe_steady.toml: 1 mL/s, blood
mean = float(np.mean(ring["wss"]))
expect(ring["closed"] and abs(ring["length"] - 2 * math.pi * R) < 0.02 * 2 * math.pi * R, "a closed ring of 2 pi R")
expect(abs(mean - exact) < 0.05 * exact, f"ring WSS {mean:.4f} Pa against Poiseuille's {exact:.4f} Pa")
try:
    vm.read_surface(f"{work}/missing.stl")
    expect(False, "a missing file raises")
except ValueError as e:
    expect("missing.stl" in str(e), f"ValueError naming the file ({e})")
try:
    vm.curvature(np.zeros((4, 2)), triangles)
    expect(False, "a bad array raises")
except ValueError as e:
    expect("(n, 3)" in str(e), f"ValueError for an (n, 2) array ({e})")
print("all checks passed")
