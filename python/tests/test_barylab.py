"""Tests of the Python package barylab (run by ctest as python.pytest, label python).

The same properties as the C++ tests on a few methods (partition of unity, linear
reproduction, non-negativity where the method promises it), against independent references
computed here with numpy (barycentric coordinates of a triangle and a tetrahedron, affine maps,
counts of weights above a threshold), numpy round trips, and exceptions on bad input.
"""

import os

import numpy as np
import pytest

import barylab
from barylab import BaryLabFilters, BaryLabIO

DATA = os.environ.get("BARYLAB_DATA_DIR",
                      os.path.join(os.path.dirname(__file__), "..", "..", "data"))
OUT = os.environ.get("BARYLAB_TEST_OUTPUT_DIR", None)

TRIANGLE = np.array([[0.0, 0.0], [2.0, 0.1], [0.4, 1.5]])
SQUARE = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
# an L-shaped (non-convex) polygon, counter-clockwise
L_SHAPE = np.array([[0, 0], [2, 0], [2, 1], [1, 1], [1, 2], [0, 2]], dtype=float)
TETRA = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
TETRA_FACES = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]  # outward


def barycentric(simplex, points):
    """Barycentric coordinates by solving [S^T; 1] b = [p; 1] (the independent reference)."""
    d = simplex.shape[1]
    A = np.vstack([simplex.T, np.ones(d + 1)])
    rhs = np.vstack([points[:, :d].T, np.ones(len(points))])
    return np.linalg.solve(A, rhs).T


def inside_triangle(n, seed=0):
    rng = np.random.default_rng(seed)
    b = rng.dirichlet(np.ones(3), size=n) * 0.98 + 0.02 / 3
    return b @ TRIANGLE


def inside_polygon_l(n, seed=1):
    rng = np.random.default_rng(seed)
    p = rng.uniform(0.05, 1.95, size=(4 * n, 2))
    keep = ~((p[:, 0] > 0.95) & (p[:, 1] > 0.95))
    return p[keep][:n]


def cube_cage():
    """The unit cube as a closed, outward-oriented triangle surface."""
    V = np.array([[x, y, z] for z in (0, 1) for y in (0, 1) for x in (0, 1)], dtype=float)
    quads = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]]
    F = [t for a, b, c, d in quads for t in ([a, b, c], [a, c, d])]
    return V, F


# --- the package -------------------------------------------------------------------------------

def test_every_wrapped_class_is_in_the_package():
    for module in (BaryLabFilters, BaryLabIO, barylab.BaryLabSpline, barylab.BaryLabSurface):
        names = [n for n in dir(module) if n.startswith("vtkBary")]
        assert names, module.__name__
        for name in names:
            assert getattr(barylab, name) is getattr(module, name)
    for name in ("vtkBaryCoordinates", "vtkBaryCageDeformation", "vtkBaryFileReader",
                 "vtkBaryOFFReader", "vtkBaryMEDITReader", "vtkBaryTGFReader",
                 "vtkBaryLocalityStatistics", "vtkBarySurfaceEmbedding", "vtkBarySplineDeform"):
        assert hasattr(barylab, name), name


def test_methods_and_defaults_come_from_the_filters():
    assert barylab.method_names() == [
        barylab.vtkBaryWeightMethod.GetMethodName(i)
        for i in range(barylab.vtkBaryWeightMethod.NUMBER_OF_METHODS)]
    assert "mvc" in barylab.method_names() and "lbc" in barylab.method_names()
    m = barylab.configure(barylab.vtkBaryWeightMethod(), "lbc", lbc_max_iterations=123)
    assert m.GetMethod() == barylab.vtkBaryWeightMethod.LBC
    assert m.GetLBCMaximumIterations() == 123
    # an untouched setting keeps the filter's default
    assert m.GetTargetNumberOfCells() == barylab.vtkBaryWeightMethod().GetTargetNumberOfCells()


# --- properties of the weights -------------------------------------------------------------------

@pytest.mark.parametrize("method,settings", [("mvc", {}), ("harmonic", {"target_cells": 400})])
def test_triangle_weights_are_its_barycentric_coordinates(method, settings):
    P = inside_triangle(40)
    W = barylab.weights(P, barylab.polygon(TRIANGLE), method, **settings)
    assert W.shape == (40, 3)
    np.testing.assert_allclose(W, barycentric(TRIANGLE, P), atol=1e-10)


def test_tetrahedron_mean_value_coordinates_are_barycentric():
    rng = np.random.default_rng(2)
    P = rng.dirichlet(np.ones(4), size=30) * 0.96 @ TETRA + 0.01
    W = barylab.weights(P, barylab.polydata(TETRA, TETRA_FACES))
    np.testing.assert_allclose(W, barycentric(TETRA, P), atol=1e-12)


@pytest.mark.parametrize("method,settings,non_negative,tol", [
    ("mvc", {}, False, 1e-12),
    ("harmonic", {"target_cells": 500}, True, 1e-10),
    ("lbc", {"target_cells": 300}, True, 1e-3),
])
def test_partition_of_unity_reproduction_and_sign_on_a_non_convex_cage(
        method, settings, non_negative, tol):
    P = inside_polygon_l(60)
    W = barylab.weights(P, barylab.polygon(L_SHAPE), method, **settings)
    assert W.shape == (len(P), len(L_SHAPE))
    np.testing.assert_allclose(W.sum(axis=1), 1.0, atol=tol)
    if method != "lbc":  # LBC reproduces x only as far as its ADMM converged
        np.testing.assert_allclose(W @ L_SHAPE, P, atol=tol)
    if non_negative:
        assert W.min() >= -1e-12
    else:
        assert W.min() < 0  # MVC are negative somewhere in a non-convex cage


def test_mean_value_coordinates_3d_reproduce_points_in_the_bundled_cage():
    cage = barylab.read(os.path.join(DATA, "cage3d.obj"))
    model = barylab.read(os.path.join(DATA, "model3d.off"))
    W = barylab.weights(model, cage)
    C = barylab.points_of(cage)
    np.testing.assert_allclose(W.sum(axis=1), 1.0, atol=1e-10)
    np.testing.assert_allclose(W @ C, barylab.points_of(model), atol=1e-10)


# --- deformation -----------------------------------------------------------------------------------

def test_an_affine_cage_motion_moves_the_model_affinely():
    P = inside_polygon_l(50)
    A = np.array([[1.2, 0.3], [-0.2, 0.9]])
    b = np.array([0.5, -1.0])
    posed = L_SHAPE @ A.T + b
    X = barylab.deform(P, barylab.polygon(L_SHAPE), posed)
    assert X.shape == (len(P), 3)
    np.testing.assert_allclose(X[:, :2], P @ A.T + b, atol=1e-12)


def test_given_weights_deform_as_computed_ones():
    cage = barylab.polygon(L_SHAPE)
    P = inside_polygon_l(30)
    rng = np.random.default_rng(3)
    posed = L_SHAPE + rng.normal(scale=0.1, size=L_SHAPE.shape)
    W = barylab.weights(P, cage, "harmonic", target_cells=300)
    X = barylab.deform(P, cage, posed, weights=W)
    np.testing.assert_allclose(X[:, :2], W @ posed, atol=1e-12)
    np.testing.assert_allclose(
        barylab.deform(P, cage, posed, "harmonic", target_cells=300), X, atol=1e-12)


def test_free_control_points_keep_the_added_hull_points_fixed():
    controls = SQUARE
    P = np.array([[0.5, 0.5], [1.5, 0.5], [0.2, 0.7]])  # the second one outside the hull
    auto = {"celestial_hull_points": barylab.vtkBaryWeightMethod.HULL_POINTS_AUTO}
    data = barylab.compute_weights(P, controls, "scc", **auto)
    W = barylab.point_array(data, "Weights")
    added = np.array([data.GetFieldData().GetArray("AddedControlPoints").GetTuple3(i)
                      for i in range(W.shape[1] - len(controls))])
    assert len(added) == 4  # the corners of the enlarged bounding box (2D)
    moved = controls + [[0.1, 0.0], [0.0, 0.2], [0.0, 0.0], [-0.1, 0.0]]
    X = barylab.deform(P, controls, moved, "scc", **auto)
    np.testing.assert_allclose(X[:, :2], W @ np.vstack([moved, added[:, :2]]), atol=1e-12)
    np.testing.assert_allclose(barylab.deform(P, controls, controls, "scc", **auto)[:, :2], P,
                               atol=1e-10)


def test_skinning_with_translations_translates():
    P = inside_triangle(20)
    W = barycentric(TRIANGLE, P)
    T = np.zeros((3, 3, 4))
    T[:, :, :3] = np.eye(3)
    T[:, :, 3] = [0.5, -2.0, 1.0]
    X = barylab.skin(P, W, T)
    np.testing.assert_allclose(X, np.c_[P, np.zeros(len(P))] + [0.5, -2.0, 1.0], atol=1e-13)


# --- statistics --------------------------------------------------------------------------------------

def test_statistics_and_locality_match_numpy():
    P = inside_polygon_l(80)
    W = barylab.weights(P, barylab.polygon(L_SHAPE), "harmonic", target_cells=400)
    threshold = 1e-3 / W.shape[1]
    s = barylab.statistics(P, W, cage=barylab.polygon(L_SHAPE))
    assert s["points"] == len(P) and s["controls"] == W.shape[1]
    assert s["min_weight"] == pytest.approx(W.min(), abs=0)
    assert s["max_weight"] == pytest.approx(W.max(), abs=0)
    assert s["max_partition_error"] == pytest.approx(np.abs(W.sum(1) - 1).max(), abs=1e-15)
    assert s["max_reproduction_error"] < 1e-10
    counts = (W > threshold).sum(axis=1)
    np.testing.assert_array_equal(s["histogram"], np.bincount(counts))

    loc = barylab.locality(P, W)  # bare points: every point counts the same
    assert loc["measure"] == "uniform" and loc["threshold"] == pytest.approx(threshold)
    assert loc["mean_support"] == pytest.approx(counts.mean(), rel=1e-12)
    assert loc["max_support"] == counts.max()
    np.testing.assert_allclose(loc["influence_fraction"], (W > threshold).mean(axis=0))
    np.testing.assert_allclose(loc["Q"], [(counts >= k).mean() for k in loc["k"]])
    assert np.all(np.diff(loc["P"]) >= 0) and 0 <= loc["P"].min() and loc["P"].max() <= 1


def test_reduce_keeps_the_weights_above_the_threshold_renormalised():
    P = inside_polygon_l(60)
    W = barylab.weights(P, barylab.polygon(L_SHAPE), "harmonic", target_cells=400)
    threshold = 0.05
    sparse = barylab.reduce(P, W, threshold=threshold)
    keep = W > threshold
    expected = np.where(keep, W, 0.0)
    expected /= expected.sum(axis=1, keepdims=True)
    assert sparse["K"] == keep.sum(axis=1).max()
    assert sparse["nonzeros"] == keep.sum()
    np.testing.assert_allclose(barylab.dense(sparse, W.shape[1]), expected, atol=1e-15)
    assert sparse["partition_error"] < 1e-14
    for row, idx in zip(keep, sparse["indices"]):  # kept controls in increasing order, then -1
        np.testing.assert_array_equal(idx[idx >= 0], np.flatnonzero(row))
        assert np.all(idx[len(np.flatnonzero(row)):] == -1)
    with pytest.raises(ValueError, match="renormalization"):
        barylab.reduce(P, W, renormalization="sum")


# --- numpy round trips and files -----------------------------------------------------------------------

def test_points_and_weights_round_trip_through_vtk_and_a_file(tmp_path):
    P = inside_triangle(25)
    poly = barylab.polydata(P)
    np.testing.assert_array_equal(barylab.points_of(poly)[:, :2], P)
    data = barylab.compute_weights(P, barylab.polygon(TRIANGLE))
    W = barylab.point_array(data, "Weights")
    path = barylab.write(data, tmp_path / "weights.vtp")
    back = barylab.read(path)
    np.testing.assert_array_equal(barylab.point_array(back, "Weights"), W)
    np.testing.assert_array_equal(barylab.points_of(back), barylab.points_of(data))
    # weights given as numpy come back unchanged
    s = barylab.statistics(P, W)
    assert s["max_weight"] == W.max()


def test_the_file_reader_is_a_pipeline_source_of_the_files_type():
    reader = barylab.vtkBaryFileReader()
    reader.SetFileName(os.path.join(DATA, "model3d.off"))
    coordinates = barylab.vtkBaryCoordinates()
    coordinates.SetInputConnection(reader.GetOutputPort())
    coordinates.SetCageData(barylab.read(os.path.join(DATA, "cage3d.obj")))
    barylab.run(coordinates)
    assert coordinates.GetOutputDataObject(0).IsA("vtkPolyData")
    assert barylab.vtkBaryFileReader.CanReadFile("a.mesh")
    assert not barylab.vtkBaryFileReader.CanReadFile("a.xyz")


# --- bad input: exceptions with the filter's message, nothing printed -----------------------------------

def test_open_cage_raises_with_the_filters_message(capfd):
    V, F = cube_cage()
    with pytest.raises(barylab.BaryLabError, match="(?i)boundary|closed|open"):
        barylab.weights([[0.5, 0.5, 0.5]], barylab.polydata(V, F[:-1]))
    assert capfd.readouterr().err == ""


def test_nan_points_raise(capfd):
    P = inside_triangle(5)
    P[2, 0] = np.nan
    with pytest.raises(barylab.BaryLabError, match="(?i)nan|finite"):
        barylab.weights(P, barylab.polygon(TRIANGLE))
    assert capfd.readouterr().err == ""


def test_mismatched_sizes_raise(capfd):
    P = inside_triangle(5)
    with pytest.raises(barylab.BaryLabError, match="(?i)point"):
        barylab.deform(P, barylab.polygon(TRIANGLE), TRIANGLE[:2])
    with pytest.raises(ValueError, match="one row per point"):
        barylab.statistics(P, np.ones((4, 3)) / 3)
    with pytest.raises(ValueError, match="shape"):
        barylab.weights(np.ones((3, 4)), barylab.polygon(TRIANGLE))
    with pytest.raises(barylab.BaryLabError, match="(?i)component|control"):
        barylab.statistics(P, np.ones((5, 4)) / 4, cage=barylab.polygon(TRIANGLE))
    assert capfd.readouterr().err == ""


def test_unreadable_files_raise_naming_the_file(tmp_path, capfd):
    bad = tmp_path / "broken.off"
    bad.write_text("OFF\n3 1 0\n0 0 0\n1 0 0\n")  # a vertex and the face missing
    with pytest.raises(barylab.BaryLabError, match="broken.off"):
        barylab.read(bad)
    with pytest.raises(barylab.BaryLabError, match="missing.obj"):
        barylab.read(tmp_path / "missing.obj")
    with pytest.raises(barylab.BaryLabError, match="(?i)extension|format"):
        barylab.read(tmp_path / "points.xyz")
    with pytest.raises(barylab.BaryLabError, match="no_such_folder"):
        barylab.write(barylab.polydata(TRIANGLE), tmp_path / "no_such_folder" / "t.vtp")
    assert capfd.readouterr().err == ""


def test_user_weights_are_passed_to_the_filter_which_checks_them():
    P = np.array([[0.3, 0.4], [0.6, 0.5]])
    plain = barylab.weights(P, SQUARE, "tcc")
    weighted = barylab.weights(P, SQUARE, "tcc", user_weights=[1, 2, 3, 4])
    np.testing.assert_allclose(weighted.sum(axis=1), 1.0, atol=1e-12)
    assert np.abs(weighted - plain).max() > 1e-3
    with pytest.raises(barylab.BaryLabError, match="user_weights.*>= 0"):
        barylab.weights(P, SQUARE, "tcc", user_weights=[1, -1, 1, 1])
    with pytest.raises(barylab.BaryLabError, match="2 entries but there are 4 control points"):
        barylab.weights(P, SQUARE, "tcc", user_weights=[1, 1])


def test_bad_settings_raise_instead_of_clamping():
    cage = barylab.polygon(TRIANGLE)
    with pytest.raises(barylab.BaryLabError, match="unknown method 'nope'.*mvc"):
        barylab.weights(TRIANGLE.mean(axis=0, keepdims=True), cage, "nope")
    with pytest.raises(barylab.BaryLabError, match="unknown setting 'no_such_key'"):
        barylab.weights(TRIANGLE.mean(axis=0, keepdims=True), cage, no_such_key=1)
    with pytest.raises(barylab.BaryLabError, match="target_cells.*outside its range"):
        barylab.weights(TRIANGLE.mean(axis=0, keepdims=True), cage, "harmonic", target_cells=-5)
    with pytest.raises(barylab.BaryLabError, match="lambda"):
        barylab.weights(TRIANGLE.mean(axis=0, keepdims=True), cage, "bbw", **{"lambda": np.nan})
