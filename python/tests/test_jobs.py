"""Tests of the package's functions for the remaining command-line jobs (run by ctest as
python.pytest): animate, fields, the weighted averages on surfaces (embed, average forward and
inverse, curve, remesh, transfer) and the spline jobs (create, deform).

Properties, against references made here: an animation's frames are the deformations by the
same cages (bitwise: the same filter on the same weights) and its rest frame is the model;
gradient norms and level sets of linear weights are the analytic ones; the weighted average of
an anchor's indicator weights is the anchor, and forward(inverse(x)) = x where the round trip is
defined; every point the surface filters return is the combination of its triangle's vertices
by its barycentric coordinates (it lies on the surface); the identity spline deforms nothing;
bad input raises BaryLabError.
"""

import json
import os
import subprocess
import xml.etree.ElementTree as ElementTree

import numpy as np
import pytest
from vtkmodules.util import numpy_support

import barylab

vtk_to_numpy = numpy_support.vtk_to_numpy
BARYLAB = os.environ.get("BARYLAB_EXE")  # the command line, when built (ctest sets it)

DATA = os.environ.get("BARYLAB_DATA_DIR",
                      os.path.join(os.path.dirname(__file__), "..", "..", "data"))


def data(name):
    return os.path.join(DATA, name)


# --- animate ------------------------------------------------------------------------------------

@pytest.mark.parametrize("method", ["mvc", "scc"])
def test_animate_frames_are_the_deformations_and_the_rest_frame_is_the_model(method, tmp_path):
    cage = barylab.read(data("cage2d.obj"))
    rest, posed = barylab.points_of(cage), barylab.points_of(barylab.read(data("cage2d_posed.obj")))
    model = barylab.read(data("model2d.obj"))
    X = barylab.points_of(model)
    frames = [rest, 0.5 * (rest + posed), posed]
    F = barylab.animate(model, cage, frames, method, output_dir=tmp_path, prefix="walk",
                        period=3.0)
    assert F.shape == (3,) + X.shape
    np.testing.assert_allclose(F[0], X, rtol=0, atol=1e-12)  # linear precision
    for f in (1, 2):  # the same weights through the same filter: bitwise
        assert np.array_equal(F[f], barylab.deform(model, cage, frames[f], method))
    # the files: one .vtp per frame (the returned points) and a .pvd with times period * f / 3
    collection = ElementTree.parse(tmp_path / "walk.pvd").getroot().find("Collection")
    entries = [(float(d.get("timestep")), d.get("file")) for d in collection]
    assert entries == [(0.0, "walk_000.vtp"), (1.0, "walk_001.vtp"), (2.0, "walk_002.vtp")]
    for f, (_, name) in enumerate(entries):
        assert np.array_equal(barylab.points_of(barylab.read(tmp_path / name)), F[f])


def test_animate_refuses_bad_frames_skeletons_and_prefixes(tmp_path):
    cage = barylab.polygon([[0, 0], [1, 0], [1, 1], [0, 1]])
    model = [[0.5, 0.5], [0.2, 0.7]]
    with pytest.raises(barylab.BaryLabError, match="frame 1 must hold the 4 points"):
        barylab.animate(model, cage, [[[0, 0], [1, 0], [1, 1], [0, 1]], [[0, 0], [1, 0]]])
    with pytest.raises(barylab.BaryLabError, match="no frames"):
        barylab.animate(model, cage, [])
    with pytest.raises(barylab.BaryLabError, match="skeletons"):
        barylab.animate(model, cage, [[[0, 0], [1, 0], [1, 1], [0, 1]]], "bbw")
    with pytest.raises(barylab.BaryLabError, match="prefix"):
        barylab.animate(model, cage, [[[0, 0], [1, 0], [1, 1], [0, 1]]],
                        output_dir=tmp_path, prefix="a/b")


# --- fields -------------------------------------------------------------------------------------

def linear_field_mesh():
    """A triangulated 2 x 1 rectangle with three linear weights (a partition of unity)."""
    from vtkmodules.vtkFiltersCore import vtkTriangleFilter
    from vtkmodules.vtkFiltersSources import vtkPlaneSource
    plane = vtkPlaneSource()
    plane.SetResolution(8, 6)
    plane.SetOrigin(0, 0, 0)
    plane.SetPoint1(2, 0, 0)
    plane.SetPoint2(0, 1, 0)
    triangles = vtkTriangleFilter()
    triangles.SetInputConnection(plane.GetOutputPort())
    triangles.Update()
    mesh = triangles.GetOutput()
    X = barylab.points_of(mesh)
    W = np.c_[X[:, 0] / 2, X[:, 1], 1 - X[:, 0] / 2 - X[:, 1]]
    return mesh, X, W


def test_fields_of_linear_weights_are_the_analytic_gradients_and_level_lines(tmp_path):
    mesh, X, W = linear_field_mesh()
    result = barylab.fields(mesh, W, control=1, levels=[0.25, 0.5],
                            output=tmp_path / "f.vtp", level_sets_output=tmp_path / "l.vtp")
    exact = np.array([0.5, 1.0, np.hypot(0.5, 1.0)])  # |grad w_i| of the linear weights
    np.testing.assert_allclose(result["gradient_norm"], np.tile(exact, (len(X), 1)), atol=1e-12)
    np.testing.assert_allclose(result["max"], exact, atol=1e-12)
    lines = result["level_sets"]
    Y = barylab.points_of(lines)
    level = numpy_support.vtk_to_numpy(lines.GetCellData().GetArray("level"))
    assert lines.GetNumberOfCells() > 0 and set(level) == {0.25, 0.5}
    assert np.all(np.isclose(Y[:, 1], 0.25, atol=1e-12) | np.isclose(Y[:, 1], 0.5, atol=1e-12))
    written = barylab.point_array(barylab.read(tmp_path / "f.vtp"), "WeightsGradientNorm")
    np.testing.assert_array_equal(written, result["gradient_norm"])
    assert barylab.read(tmp_path / "l.vtp").GetNumberOfCells() == lines.GetNumberOfCells()


def test_fields_refuse_point_clouds_missing_controls_and_nan_levels():
    mesh, X, W = linear_field_mesh()
    with pytest.raises(barylab.BaryLabError, match="need a mesh"):
        barylab.gradient_norms(X, W)
    with pytest.raises(barylab.BaryLabError, match="control 3 does not exist"):
        barylab.level_sets(mesh, 3, weights=W)
    with pytest.raises(barylab.BaryLabError, match="not finite"):
        barylab.level_sets(mesh, 0, [np.nan], weights=W)


# --- weighted averages on surfaces ----------------------------------------------------------------

@pytest.fixture(scope="module")
def torus():
    surface = barylab.with_embedding(data("wa_torus.obj"), data("wa_torus_embedding.txt"))
    return surface, np.loadtxt(data("wa_anchors.txt"))


def triangles_of(surface):
    polys = surface.GetPolys()
    return numpy_support.vtk_to_numpy(polys.GetConnectivityArray()).reshape(-1, 3)


def assert_on_surface(surface, points, face_id, barycentric, tol=1e-12):
    """Each point is its triangle's vertices combined by its barycentric coordinates."""
    V, T = barylab.points_of(surface), triangles_of(surface)
    ok = face_id >= 0
    assert ok.any()
    np.testing.assert_allclose(barycentric[ok].sum(axis=1), 1.0, atol=1e-12)
    assert np.all(barycentric[ok] >= -1e-12)
    combined = np.einsum("pk,pkd->pd", barycentric[ok], V[T[face_id[ok]]])
    np.testing.assert_allclose(points[ok], combined, atol=tol)


def test_forward_average_of_indicator_weights_is_the_anchor(torus):
    surface, A = torus
    P = barylab.average(surface, A, np.eye(len(A)))
    np.testing.assert_allclose(P, A, atol=1e-9)
    # an embedding computed here (all 130 vertices are landmarks) does the same
    from vtkmodules.vtkFiltersSources import vtkSphereSource
    sphere = vtkSphereSource()
    sphere.SetThetaResolution(16)
    sphere.SetPhiResolution(10)
    sphere.Update()
    E = barylab.embed(sphere.GetOutput(), dimension=4)
    assert E.shape == (130, 4) and np.all(np.isfinite(E))
    S = barylab.points_of(sphere.GetOutput())
    anchors = S[[3, 40, 77, 120]]
    np.testing.assert_allclose(barylab.average(sphere.GetOutput(), anchors, np.eye(4), E),
                               anchors, atol=1e-9)


def test_inverse_then_forward_reproduces_the_points(torus):
    surface, A = torus
    W = np.loadtxt(data("wa_weights.txt"))
    forward = barylab.average_data(surface, A, W)
    P = barylab.points_of(forward)
    assert_on_surface(surface, P, barylab.point_array(forward, "FaceId")[:, 0].astype(int),
                      barylab.point_array(forward, "Barycentric"))
    inverse = barylab.inverse_average(surface, A, np.vstack([P, A]))
    np.testing.assert_allclose(inverse["weights"].sum(axis=1), 1.0, atol=1e-12)
    np.testing.assert_allclose(inverse["weights"][len(P):], np.eye(len(A)), atol=1e-9)
    defined = inverse["defined"]
    assert defined.sum() >= len(P)  # the averages of the anchors are averages of the anchors
    again = barylab.average(surface, A, inverse["weights"][defined])
    # "defined": the round trip came back within round_trip_tolerance (1e-6) x the mean edge
    V, T = barylab.points_of(surface), triangles_of(surface)
    mean_edge = np.mean([np.linalg.norm(V[T[:, i]] - V[T[:, (i + 1) % 3]], axis=1)
                         for i in range(3)])
    error = np.linalg.norm(again - np.vstack([P, A])[defined], axis=1)
    assert error.max() <= 1e-6 * mean_edge


def test_curve_and_remesh_lie_on_the_surface(torus):
    surface, _ = torus
    curve = barylab.curve_data(surface, data("wa_curve_controls.txt"), samples=4, closed=True)
    assert curve.GetNumberOfPoints() == 8 * 4  # closed: #controls segments
    assert_on_surface(surface, barylab.points_of(curve),
                      barylab.point_array(curve, "FaceId")[:, 0].astype(int),
                      barylab.point_array(curve, "Barycentric"))
    points, quads = barylab.remesh(surface, data("wa_quads.obj"), levels=1, smooth=2)
    assert quads.shape == (32 * 4, 4) and not np.isnan(points).any()
    mesh = barylab.remesh_data(surface, data("wa_quads.obj"), levels=1, smooth=2)
    assert_on_surface(surface, barylab.points_of(mesh),
                      barylab.point_array(mesh, "FaceId")[:, 0].astype(int),
                      barylab.point_array(mesh, "Barycentric"))


def test_transfer_interpolates_on_the_source_and_morphs_to_it(torus, tmp_path):
    source, _ = torus
    X = barylab.points_of(source)
    result = barylab.transfer(source, data("wa_anchors.txt"), data("wa_torus_target.obj"),
                              data("wa_target_anchors.txt"),
                              target_embedding=data("wa_torus_target_embedding.txt"),
                              arrays={"Position": X, "Height": X[:, 2]}, morph=2,
                              morph_dir=tmp_path)
    defined, image = result["defined"], result["source_position"]
    assert 0 < defined.sum() == len(defined) - result["undefined"]
    # a linear field (the source's coordinates) transfers to the image point itself
    np.testing.assert_allclose(result["arrays"]["Position"][defined], image[defined], atol=1e-12)
    np.testing.assert_allclose(result["arrays"]["Height"][defined, 0], image[defined, 2],
                               atol=1e-12)
    assert np.isnan(result["arrays"]["Position"][~defined]).all()
    out = result["data"]
    assert_on_surface(source, image, barylab.point_array(out, "SourceFaceId")[:, 0].astype(int),
                      barylab.point_array(out, "SourceBarycentric"))
    assert result["stretch"].shape == (out.GetNumberOfCells(),)
    assert np.nanmin(result["stretch"]) >= 1 - 1e-9  # >= 1, 1 for a similarity
    assert result["stretch_all"] >= 1 - 1e-9 and result["flipped"].dtype == bool
    T = barylab.points_of(out)
    morph = result["morph"]
    np.testing.assert_array_equal(morph[0], T)
    np.testing.assert_allclose(morph[2][defined], image[defined], atol=1e-15)
    np.testing.assert_array_equal(morph[2][~defined], T[~defined])
    assert sorted(os.listdir(tmp_path)) == ["morph.pvd", "morph_000.vtp", "morph_001.vtp",
                                            "morph_002.vtp"]


def test_surface_jobs_refuse_bad_input(torus):
    surface, A = torus
    with pytest.raises(barylab.BaryLabError, match="rows but the surface has 2016 points"):
        barylab.with_embedding(data("wa_torus.obj"), np.zeros((10, 8)))
    with pytest.raises(barylab.BaryLabError, match="anchor"):
        barylab.average(surface, A + [0, 0, 5], np.eye(len(A)))
    with pytest.raises(barylab.BaryLabError):
        barylab.average(surface, A, np.ones((2, 3)) / 3)  # 3 weights for 9 anchors
    with pytest.raises(barylab.BaryLabError, match="cannot read"):
        barylab.curve(surface, os.path.join(DATA, "missing.txt"))


# --- splines ------------------------------------------------------------------------------------

def test_the_identity_spline_deforms_nothing():
    rng = np.random.default_rng(3)
    M = np.c_[rng.uniform(-0.95, 0.95, 40), rng.uniform(-0.45, 0.45, 40), np.zeros(40)]
    grid = barylab.spline_create(data("spline_domain.obj"))
    assert grid.GetClassName() == "vtkUnstructuredGrid"
    Y, J = barylab.spline_deform(grid, M)
    np.testing.assert_allclose(Y, M, atol=1e-13)
    np.testing.assert_allclose(J, 1.0, atol=1e-12)
    prism = barylab.spline_create([[-1, -0.5], [1, -0.5], [1, 0.5], [-1, 0.5]],
                                  target_triangles=20, prism=(-0.2, 0.2))
    M[:, 2] = rng.uniform(-0.2, 0.2, 40)
    Y, _ = barylab.spline_deform(prism, M)
    np.testing.assert_allclose(Y, M, atol=1e-13)


def test_spline_jobs_refuse_bad_input():
    grid = barylab.spline_create(data("spline_domain.obj"))
    with pytest.raises(barylab.BaryLabError, match="outside the spline's domain"):
        barylab.spline_deform(grid, [[5.0, 5.0, 0.0]])
    with pytest.raises(barylab.BaryLabError, match="go together"):
        barylab.spline_create(data("spline_domain.obj"), fit_from=[[0, 0, 0]])
    with pytest.raises(barylab.BaryLabError):
        barylab.spline_create(data("spline_domain.obj"), degree=3)


def test_spline_edit_moves_the_anchor_exactly_and_keeps_c1(tmp_path):
    # DECLeS (§4): the anchor moves by exactly the given displacement, a few neighbours follow,
    # the C1 conditions still hold; the same edits through the command line's JSON parser give
    # the same spline, bit for bit
    grid = barylab.spline_create(data("spline_domain.obj"))
    X = barylab.points_of(grid)
    i = int(np.argmin(np.linalg.norm(X[:, :2], axis=1)))
    edits = [{"op": "translate", "index": i, "by": [0.05, -0.02], "delta_max": 2},
             {"op": "rotate", "near": list(X[i, :2]), "center": [0.0, 0.0],
              "angle_degrees": 3.0}]
    edited = barylab.spline_edit_data(grid, edits[:1])
    Y = barylab.points_of(edited)
    np.testing.assert_allclose(Y[i] - X[i], [0.05, -0.02, 0.0], atol=1e-15)
    moved = np.abs(Y - X).max(axis=1) > 0
    assert 1 < moved.sum() < len(X) // 10, moved.sum()
    assert vtk_to_numpy(edited.GetFieldData().GetArray("Residual"))[0] < 1e-9
    # a rotation by 0 degrees is the identity
    np.testing.assert_allclose(
        barylab.spline_edit(grid, [dict(edits[1], angle_degrees=0.0)]), X, atol=1e-15)
    # against `barylab spline edit` with the same EDITS.json
    if BARYLAB is None:
        pytest.skip("no barylab executable (BARYLAB_EXE) to compare with")
    spline_file, edits_file = tmp_path / "s.vtu", tmp_path / "e.json"
    barylab.write(grid, str(spline_file))
    edits_file.write_text(json.dumps({"edits": edits}))
    out = tmp_path / "cli.vtu"
    subprocess.run([BARYLAB, "spline", "edit", "--spline", str(spline_file), "--edits",
                    str(edits_file), "--output", str(out), "-q"], check=True)
    np.testing.assert_array_equal(barylab.spline_edit(grid, str(edits_file)),
                                  barylab.points_of(barylab.read(str(out))))


def test_spline_edit_refuses_bad_edits():
    grid = barylab.spline_create(data("spline_domain.obj"))
    for edit, message in [({"op": "twist", "index": 0}, "op"),
                          ({"op": "translate", "index": 0, "by": [1, 0], "colour": 1}, "unknown key"),
                          ({"op": "translate", "by": [1, 0]}, "names no anchor"),
                          ({"op": "scale", "index": 0, "center": [0, 0]}, "needs"),
                          ({"op": "translate", "index": 0, "by": [0.1], "spline": "top"},
                           "not a 2.5D"),
                          ({"op": "translate", "index": 10 ** 9, "by": [0.1, 0]}, "edit 0")]:
        with pytest.raises(barylab.BaryLabError, match=message):
            barylab.spline_edit(grid, [edit])
