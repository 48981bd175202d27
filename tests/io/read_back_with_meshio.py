"""The XDMF and Fluent exports read by meshio (Debian's python3-meshio, its XDMF reader on h5py):
a reader that is not ours. Run by tests/io/export_test.cpp (Export.XdmfAndFluentReadByMeshio) with
Debian's /usr/bin/python3:
  read_back_with_meshio.py XDMF_FOLDER FLUENT_FILE POINTS TETRAHEDRA INTERNAL_FACES NAME=COUNT ...
Exits 1 naming the first difference, 0 when all agree (printing what it checked)."""
import sys

import h5py
import meshio
import numpy as np


def expect(condition, what):
    if not condition:
        print("differs:", what)
        sys.exit(1)


folder, fluent, points, tets, internal = sys.argv[1], sys.argv[2], *map(int, sys.argv[3:6])
tags = {name: int(count) for name, count in (a.split("=") for a in sys.argv[6:])}

mesh = meshio.read(f"{folder}/mesh.xdmf")
expect(mesh.points.shape == (points, 3), f"mesh.xdmf points {mesh.points.shape}")
expect([c.type for c in mesh.cells] == ["tetra"], f"mesh.xdmf cells {[c.type for c in mesh.cells]}")
expect(len(mesh.cells[0].data) == tets, f"mesh.xdmf tetrahedra {len(mesh.cells[0].data)}")
expect(mesh.cells[0].data.min() == 0 and mesh.cells[0].data.max() == points - 1, "tetrahedra's corners from 0")
expect(set(np.unique(mesh.cell_data["cell_tags"][0])) == {1}, "cell_tags")
facets = meshio.read(f"{folder}/facets.xdmf")
expect(np.allclose(facets.points, mesh.points), "facets.xdmf on the mesh's points")
expect([c.type for c in facets.cells] == ["triangle"], "facets.xdmf triangles")
values = facets.cell_data["facet_tags"][0]
for name, count in tags.items():
    expect(name in facets.field_data, f"the name {name} in facets.xdmf")
    tag = int(facets.field_data[name][0])
    expect(int((values == tag).sum()) == count, f"{name} (tag {tag}): {(values == tag).sum()} triangles, not {count}")
# Metres: the volume's points scaled; each tetrahedron positive.
x = mesh.points[mesh.cells[0].data]
volumes = np.einsum("ij,ij->i", np.cross(x[:, 1] - x[:, 0], x[:, 2] - x[:, 0]), x[:, 3] - x[:, 0]) / 6
expect((volumes > 0).all(), f"{(volumes <= 0).sum()} tetrahedra not positive")
with h5py.File(f"{folder}/mesh.h5") as h5:
    expect(sorted(h5.keys()) == ["facets", "mesh"], f"mesh.h5 groups {sorted(h5.keys())}")
    expect(h5["mesh/topology"].shape == (tets, 4), "mesh.h5 /mesh/topology")

msh = meshio.read(fluent, file_format="ansys")
expect(msh.points.shape == (points, 3), f"Fluent points {msh.points.shape}")
expect(np.allclose(msh.points, mesh.points), "Fluent points the XDMF's")
faces = [len(c.data) for c in msh.cells]
expect(faces[0] == internal, f"Fluent interior faces {faces[0]}, not {internal}")
expect(sorted(faces[1:]) == sorted(tags.values()), f"Fluent boundary zones {faces[1:]}, not {sorted(tags.values())}")
print(f"meshio {meshio.__version__}: mesh.xdmf {points} points, {tets} tetrahedra; facets.xdmf {len(values)} "
      f"triangles {tags}; Fluent {points} points, {faces[0]} interior faces, zones {faces[1:]}")
