"""The Python module `vesselmesh` against analytic answers and the program (pytest, registered in CTest
as python_module; Debian's /usr/bin/python3, the module from the build folder on PYTHONPATH, the
program in VESSELMESH_PROGRAM). A synthetic pipe of radius 2 mm and length 12 mm (no shared data):
its ends, curvature 1/R around it and 0 along it, one centerline branch of radius R, the distance
map, a remesh equal to the program's, its volume written and read back, steady Poiseuille flow (a
case given as a dict) with the ring WSS against 4 mu Q / (pi R^3) as the C++ tests check it; bad
input raising ValueError with the program's words; the docstrings."""
import json
import math
import os
import subprocess

import numpy as np
import pytest
import vesselmesh as vm

R, L = 2.0, 12.0
PROGRAM = os.environ["VESSELMESH_PROGRAM"]


@pytest.fixture(scope="module")
def pipe(tmp_path_factory):
    work = tmp_path_factory.mktemp("pipe")
    subprocess.run([PROGRAM, "synth", "cylinder", "--radius", str(R), "--length", str(L), "--resolution", "0.4",
                    "-o", str(work / "pipe.stl"), "-q"], check=True)
    points, triangles = vm.read_surface(str(work / "pipe.stl"))
    return work, points, triangles


@pytest.fixture(scope="module")
def remeshed(pipe):
    _, points, triangles = pipe
    return vm.remesh(points, triangles, "uniform", 2000)


def test_arrays_and_info(pipe):
    _, points, triangles = pipe
    assert points.dtype == np.float64 and points.shape[1] == 3
    assert triangles.dtype == np.int32 and triangles.shape[1] == 3
    info = vm.info(points, triangles)
    assert info["points"] == len(points) and not info["closed"]
    assert len(info["ends"]) == 2
    for end in info["ends"]:
        assert end["radius"] == pytest.approx(R, rel=0.02)


def test_curvature_centerline_and_distance(pipe):
    _, points, triangles = pipe
    middle = np.abs(points[:, 2] - L / 2) < L / 4
    c = vm.curvature(points, triangles)
    assert np.median(c["k2"][middle]) == pytest.approx(1 / R, rel=0.03)  # around the pipe
    assert abs(np.median(c["k1"][middle])) < 0.03 / R                    # along it
    branches = vm.centerlines(points, triangles)
    assert len(branches) == 1
    assert np.median(branches[0]["radius"]) == pytest.approx(R, rel=0.05)
    d = vm.distance_map(points, triangles)
    assert np.median(d["distance"][middle]) == pytest.approx(R, rel=0.03)
    field = vm.size_field(points, triangles, "uniform", 2000)
    assert field["metric"].shape == (len(points), 6) and (field["size"] > 0).all()


def test_remesh_is_the_programs(pipe, remeshed):
    work, _, _ = pipe
    points, triangles, stats = remeshed
    cli = subprocess.run([PROGRAM, "remesh", str(work / "pipe.stl"), "--size", "uniform", "--target-triangles", "2000",
                          "-o", str(work / "remeshed.vtp"), "--json", "-q"], check=True, capture_output=True, text=True)
    program = json.loads(cli.stdout)
    assert stats["triangles"] == program["triangles"] == len(triangles)
    assert stats["min_angle_deg"] == pytest.approx(program["min_angle_deg"], abs=0.01)  # the program rounds
    assert stats["min_angle_deg"] >= 20.0
    assert stats["hausdorff"] == pytest.approx(program["hausdorff"], abs=1e-4)
    assert stats["hausdorff_facets"] == pytest.approx(program["hausdorff_facets"], abs=1e-4)
    assert (stats["count_note"] == "") == (program["count_note"] is None)


def test_volume_round_trip(pipe, remeshed):
    work, _, _ = pipe
    volume = vm.volume(remeshed[0], remeshed[1])
    assert set(volume["tag_names"].values()) == {"wall", "inlet", "outlet_1"}
    vm.write_volume(str(work / "pipe.msh"), volume)
    again = vm.read_volume(str(work / "pipe.msh"))
    assert again["tetrahedra"].shape == volume["tetrahedra"].shape
    assert np.allclose(again["points"], volume["points"])


def test_steady_flow_and_ring_wss(pipe, remeshed):
    work, _, _ = pipe
    vm.write_volume(str(work / "flow.msh"), vm.volume(remeshed[0], remeshed[1]))
    case = {"mesh": str(work / "flow.msh"), "length_unit": "mm", "fluid": {"density": 1060.0, "viscosity": 0.0035},
            "time": {"steady": True},
            "boundary": [{"tag": "inlet", "type": "velocity", "profile": "parabolic", "flow": 1.0},
                         {"tag": "outlet_1", "type": "traction"}, {"tag": "wall", "type": "wall"}]}
    summary = vm.simulate(case, str(work / "flow"))
    assert summary["status"] == "completed" and summary["steady_residual"] < 1e-6
    ring = vm.wss_ring(str(work / "flow"), [0, 0, L / 2], [0, 0, 1])
    assert ring["closed"] and ring["length"] == pytest.approx(2 * math.pi * R, rel=0.02)
    exact = 4 * 0.0035 * 1e-6 / (math.pi * (R * 1e-3) ** 3)  # Pa: 1 mL/s of blood
    assert float(np.mean(ring["wss"])) == pytest.approx(exact, rel=0.05)


def test_bad_input_raises_with_the_programs_words(pipe):
    work, points, triangles = pipe
    with pytest.raises(ValueError, match="missing.stl"):
        vm.read_surface(str(work / "missing.stl"))
    with pytest.raises(ValueError, match=r"\(n, 3\)"):
        vm.curvature(np.zeros((4, 2)), triangles)
    with pytest.raises(ValueError, match="not among the"):
        vm.info(points, np.array([[0, 1, len(points)]], dtype=np.int32))
    with pytest.raises(ValueError):
        vm.remesh(points, triangles, "finest", 100)
    with pytest.raises(ValueError, match="time.dt: missing"):  # a dict case, read as the file would be
        vm.simulate({"mesh": "nowhere.msh"}, str(work / "never"))
    with pytest.raises(ValueError, match="not a TOML value"):
        vm.simulate({"mesh": None}, str(work / "never"))
    assert issubclass(vm.InputError, ValueError)


def test_help_shows_the_options():
    text = vm.remesh.__doc__
    for option in ("kind", "target_triangles", "uniform", "anisotropic"):
        assert option in text


def test_study_from_a_dict_reads_its_ranking(tmp_path, monkeypatch):
    """vesselmesh.study (issue 53): a tiny study given as a dict (a uniform and a curvature mesh of the
    Y bifurcation, one reference level) runs like `vesselmesh study` and returns what study.json holds."""
    data = os.path.join(os.path.dirname(__file__), "..", "..", "data")
    case = tmp_path / "flow.toml"
    case.write_text(
        'mesh = "replaced.msh"\nlength_unit = "mm"\n[fluid]\ndensity = 1060.0\nviscosity = 0.0035\n'
        "[time]\nsteady = true\n"
        '[[boundary]]\ntag = "inlet"\ntype = "velocity"\nflow = 2.0\n'
        '[[boundary]]\ntag = "outlet_1"\ntype = "traction"\n'
        '[[boundary]]\ntag = "outlet_2"\ntype = "traction"\n'
        '[[boundary]]\ntag = "wall"\ntype = "wall"\n')
    monkeypatch.chdir(tmp_path)
    result = vm.study(
        {"surface": os.path.abspath(os.path.join(data, "y_bifurcation.stl")), "case": "flow.toml",
         "triangles": 2000, "meshes": ["uniform", "curvature"],
         "reference": {"kind": "uniform", "levels": 1, "factor": 1.5}, "volume": {"layers": 2},
         "ring": [{"name": "parent", "point": [0, 0, -10], "normal": [0, 0, 1]}],
         "point": [{"name": "A", "point": [0, 3, 0]}]},
        str(tmp_path / "out"))
    assert [m["name"] for m in result["meshes"]] == ["uniform", "curvature", "level_1"]
    assert result["reference"] == "level_1"
    rankings = result["summary"]["rankings"]
    assert {q["quantity"] for q in rankings} >= {"ring parent: minimum", "point A"}
    for q in rankings:
        assert sorted(o["mesh"] for o in q["order"]) == ["curvature", "uniform"]
        assert [o["place"] for o in q["order"]] == [1, 2]
    assert json.loads((tmp_path / "out" / "study.json").read_text()) == result
    assert "vesselmesh.study() as a dict" in (tmp_path / "out" / "study_input.toml").read_text()
    assert (tmp_path / "out" / "report.html").exists()
    with pytest.raises(ValueError, match="triangles"):
        vm.study({"surface": "nowhere.stl", "case": "flow.toml", "triangles": -3}, str(tmp_path / "never"))
    assert not (tmp_path / "never").exists()
