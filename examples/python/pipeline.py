"""The pipeline from Python: the bundled Y bifurcation remeshed curvature-adapted, its boundary-layer
volume, a steady flow through it and the WSS on a ring of its parent vessel. From the repository
root, after the build (Debian's python3, for which the module is built):
  PYTHONPATH=build/python /usr/bin/python3 examples/python/pipeline.py OUT_FOLDER
"""
import os
import sys

import numpy as np
import vesselmesh as vm

out = sys.argv[1] if len(sys.argv) > 1 else "pipeline-out"
os.makedirs(out, exist_ok=True)

points, triangles = vm.read_surface("data/y_bifurcation.stl", units="mm")
info = vm.info(points, triangles)
print(f"{info['points']} points, {len(info['ends'])} ends of radii",
      ", ".join(f"{e['radius']:.2f}" for e in info["ends"]), "mm")

curvature = vm.curvature(points, triangles)
print(f"mean curvature from {curvature['mean_curvature'].min():.3f} to {curvature['mean_curvature'].max():.3f} 1/mm")

wall, wall_triangles, stats = vm.remesh(points, triangles, kind="curvature", target_triangles=6000)
print(f"remeshed: {stats['triangles']} triangles, smallest angle {stats['min_angle_deg']:.1f} deg")
vm.write_surface(f"{out}/wall.vtp", wall, wall_triangles)

volume = vm.volume(wall, wall_triangles, layers=4, thickness_ratio=0.1)
print(f"volume: {len(volume['points'])} points, {len(volume['tetrahedra'])} tetrahedra, tags {volume['tag_names']}")
vm.write_volume(f"{out}/volume.msh", volume)

outlets = [name for name in volume["tag_names"].values() if name.startswith("outlet")]
case = "\n".join(
    ['mesh = "volume.msh"', 'length_unit = "mm"', "[time]", "steady = true",
     '[[boundary]]', 'tag = "inlet"', 'type = "velocity"', 'profile = "parabolic"', "flow = 2.0"]
    + [f'[[boundary]]\ntag = "{o}"\ntype = "traction"' for o in outlets]
    + ['[[boundary]]', 'tag = "wall"', 'type = "wall"']) + "\n"
with open(f"{out}/case.toml", "w") as f:
    f.write(case)
summary = vm.simulate(f"{out}/case.toml", f"{out}/flow")
print(f"steady flow: {summary['dofs']} unknowns, residual {summary['steady_residual']:.1e}, {summary['seconds']:.1f} s")

branch = vm.centerlines(wall, wall_triangles)[0]
middle = branch["points"][len(branch["points"]) // 2]
direction = branch["points"][-1] - branch["points"][0]
ring = vm.wss_ring(f"{out}/flow", middle.tolist(), (direction / np.linalg.norm(direction)).tolist())
print(f"WSS on the parent vessel's ring: mean {np.mean(ring['wss']):.3f} Pa, "
      f"least {ring['wss'][ring['minimum']]:.3f} Pa at {ring['angle'][ring['minimum']]:.0f} deg")
