"""Weighted averages on surfaces (Panozzo et al. 2013) from Python: the ``barylab embed``,
``average`` (forward and ``--inverse``), ``curve``, ``remesh`` and ``transfer`` jobs over the
wrapped filters of barylab.BaryLabSurface, numpy in and out.

Every computation is the filters' (vtkBarySurfaceEmbedding, vtkBaryWeightedAverage,
vtkBarySurfaceWeights, vtkBarySurfaceCurve, vtkBarySurfaceRemesh,
vtkBarySurfaceCorrespondence); settings take the command line's names (``--max-iterations`` is
``max_iterations``) and, left at None, the filter's default (the core option structs'). A
surface is a vtkPolyData of triangles (or a file); its embedding is an (n_points, D) array, a
file (text: one line per vertex; or a .vtp/.vtu/.vtk with an ``Embedding`` array), or None:
computed with the defaults, as the command line does without ``--embedding``. Points on the
surface (anchors, controls, queries) are (n, 3) arrays, data files or text files (x y z a line).
"""

import os

import numpy as np
from vtkmodules.util import numpy_support
from vtkmodules.vtkCommonDataModel import vtkPolyData

from ._pipeline import (
    BaryLabError,
    _as_dataset,
    point_array,
    points_of,
    polydata,
    read,
    run,
    write,
    write_time_series,
)
from .BaryLabSurface import (
    vtkBarySurfaceCorrespondence,
    vtkBarySurfaceCurve,
    vtkBarySurfaceEmbedding,
    vtkBarySurfaceRemesh,
    vtkBarySurfaceWeights,
    vtkBaryWeightedAverage,
)

EMBEDDING = "Embedding"
_DATA_EXTENSIONS = (".vtp", ".vtu", ".vtk", ".obj", ".stl", ".ply", ".off", ".mesh", ".tgf")
_LANDMARK_METHODS = {"decimation": vtkBarySurfaceEmbedding.LANDMARKS_DECIMATION,
                     "farthest-point": vtkBarySurfaceEmbedding.LANDMARKS_FARTHEST_POINT}


def _is_data_file(path):
    return os.fspath(path).lower().endswith(_DATA_EXTENSIONS)


def _load_text(path, what):
    try:
        values = np.loadtxt(os.fspath(path), ndmin=2)
    except (OSError, ValueError) as error:
        raise BaryLabError(f"cannot read {what} '{os.fspath(path)}': {error}") from None
    return values


def _surface(surface, name="surface"):
    data = _as_dataset(surface, name)
    if not isinstance(data, vtkPolyData):
        raise BaryLabError(f"the {name} must be a triangle surface (vtkPolyData), "
                           f"not a {data.GetClassName()}")
    return data


def _surface_points(points, name):
    """Points on a surface: an (n, 3) array, a VTK point set, a data file or a text file."""
    if isinstance(points, (str, os.PathLike)) and not _is_data_file(points):
        return polydata(_load_text(points, name))
    return _as_dataset(points, name)


def _matrix(values, name):
    if isinstance(values, (str, os.PathLike)):
        return _load_text(values, name)
    m = np.asarray(values, dtype=np.float64)
    return m.reshape(1, -1) if m.ndim == 1 else m


def _set(setter, value, cast=float):
    if value is not None:
        setter(cast(value))


def _copy(data):
    result = data.NewInstance()
    result.ShallowCopy(data)
    return result


def _vtk_array(values, name):
    a = np.ascontiguousarray(np.asarray(values, dtype=np.float64))
    array = numpy_support.numpy_to_vtk(a if a.ndim == 2 else a.reshape(-1, 1), deep=True)
    array.SetName(name)
    return array


def _finish(data, output):
    if output is not None:
        write(data, output)
    return data


# --- the embedding ----------------------------------------------------------------------------

def embed_data(surface, dimension=None, landmarks=None, landmark_method=None,
               stress_tolerance=None, max_iterations=None, heat_time_factor=None,
               quality_sources=None, threads=None, output=None):
    """The ``barylab embed`` job as a VTK data set (vtkBarySurfaceEmbedding): a shallow copy of
    ``surface`` with the point array ``Embedding`` (D components) and the field data
    ``Landmarks`` and ``EmbeddingQuality``. ``landmark_method``: "decimation" or
    "farthest-point". ``output`` (optional): a .vtp/.vtu/.vtk to write it to."""
    filter_ = vtkBarySurfaceEmbedding()
    filter_.SetInputData(_surface(surface))
    _set(filter_.SetDimension, dimension, int)
    _set(filter_.SetNumberOfLandmarks, landmarks, int)
    if landmark_method is not None:
        if landmark_method not in _LANDMARK_METHODS:
            raise BaryLabError(f"unknown landmark method '{landmark_method}' "
                               f"(one of: {', '.join(_LANDMARK_METHODS)})")
        filter_.SetLandmarkMethod(_LANDMARK_METHODS[landmark_method])
    _set(filter_.SetStressTolerance, stress_tolerance)
    _set(filter_.SetMaximumIterations, max_iterations, int)
    _set(filter_.SetHeatTimeFactor, heat_time_factor)
    _set(filter_.SetQualitySources, quality_sources, int)
    _set(filter_.SetNumberOfThreads, threads, int)
    filter_.SetEmbeddingArrayName(EMBEDDING)
    run(filter_)
    return _finish(_copy(filter_.GetOutput()), output)


def embed(surface, **settings):
    """The Euclidean embedding of ``surface`` as an (n_points, D) array (see embed_data for the
    settings)."""
    return point_array(embed_data(surface, **settings), EMBEDDING)


def with_embedding(surface, embedding=None):
    """A shallow copy of ``surface`` carrying its embedding as the point array ``Embedding``:
    ``embedding`` an (n_points, D) array, a file (text, one line per vertex; or a data file with
    an ``Embedding`` array), or None: the surface's own ``Embedding`` array if it has one, else
    computed with the defaults (embed_data)."""
    data = _surface(surface)
    if embedding is None:
        if data.GetPointData().GetArray(EMBEDDING) is not None:
            return data
        return embed_data(data)
    if isinstance(embedding, (str, os.PathLike)) and _is_data_file(embedding):
        E = point_array(read(embedding), EMBEDDING)
    else:
        E = _matrix(embedding, "embedding")
    if E.ndim != 2 or E.shape[0] != data.GetNumberOfPoints():
        raise BaryLabError(f"the embedding has {E.shape[0]} rows but the surface has "
                           f"{data.GetNumberOfPoints()} points (one row per point)")
    copy = _copy(data)
    copy.GetPointData().AddArray(_vtk_array(E, EMBEDDING))
    return copy


def _on_surface(points_data):
    """(points, valid) of a filter's output: NaN rows where ``Valid`` is 0."""
    valid = point_array(points_data, "Valid")[:, 0] != 0
    return points_of(points_data), valid


# --- forward and inverse problems -------------------------------------------------------------

def average_data(surface, anchors, weights, embedding=None, brute_force=False,
                 warm_start=False, max_triangles=None, surface_tolerance=None, threads=None,
                 output=None):
    """The ``barylab average`` job (forward problems, vtkBaryWeightedAverage) as a vtkPolyData:
    one point per row of ``weights`` ((n_queries, n_anchors), rows summing to 1; or a text
    file), with point data ``FaceId``, ``Barycentric`` and ``Valid`` (0: no Phong projection
    found, NaN coordinates)."""
    W = _matrix(weights, "weights")
    filter_ = vtkBaryWeightedAverage()
    filter_.SetInputData(with_embedding(surface, embedding))
    filter_.SetAnchorsData(_surface_points(anchors, "anchors"))
    filter_.SetWeights(_vtk_array(W, "Weights"))
    filter_.SetBruteForce(bool(brute_force))
    filter_.SetWarmStart(bool(warm_start))
    _set(filter_.SetMaximumTriangles, max_triangles, int)
    _set(filter_.SetSurfaceTolerance, surface_tolerance)
    _set(filter_.SetNumberOfThreads, threads, int)
    filter_.SetEmbeddingArrayName(EMBEDDING)
    run(filter_)
    return _finish(_copy(filter_.GetOutput()), output)


def average(surface, anchors, weights, embedding=None, **settings):
    """Weighted averages of ``anchors`` on ``surface``: an (n_queries, 3) array, one row per row
    of ``weights``, NaN where a query failed (see average_data)."""
    points, valid = _on_surface(average_data(surface, anchors, weights, embedding, **settings))
    points[~valid] = np.nan
    return points


def inverse_average_data(surface, anchors, points, embedding=None, gamma=None,
                         round_trip_tolerance=None, surface_tolerance=None, anchor_uv=None,
                         threads=None, output=None):
    """The ``barylab average --inverse`` job (vtkBarySurfaceWeights, with the round trip) as a
    VTK data set: ``points`` with point data ``Weights`` (one component per anchor),
    ``FaceId``, ``Barycentric``, ``RoundTripError``, ``Defined`` and, given ``anchor_uv``
    ((n_anchors, 2)), ``TCoords``."""
    filter_ = vtkBarySurfaceWeights()
    filter_.SetInputData(0, _surface_points(points, "points"))
    filter_.SetSurfaceData(with_embedding(surface, embedding))
    filter_.SetAnchorsData(_surface_points(anchors, "anchors"))
    filter_.SetEmbeddingArrayName(EMBEDDING)
    filter_.SetWeightsArrayName("Weights")
    _set(filter_.SetGamma, gamma)
    _set(filter_.SetRoundTripTolerance, round_trip_tolerance)
    _set(filter_.SetSurfaceTolerance, surface_tolerance)
    _set(filter_.SetNumberOfThreads, threads, int)
    if anchor_uv is not None:
        uv = _matrix(anchor_uv, "anchor_uv")
        if uv.ndim != 2 or uv.shape[1] != 2:
            raise BaryLabError(f"anchor_uv must be an (n_anchors, 2) array, not {uv.shape}")
        filter_.SetAnchorTextureCoordinates(_vtk_array(uv, "AnchorUV"))
    run(filter_)
    return _finish(_copy(filter_.GetOutputDataObject(0)), output)


def inverse_average(surface, anchors, points, embedding=None, **settings):
    """Weights of ``points`` on ``surface`` w.r.t. ``anchors`` (the inverse problem): a dict with
    "weights" (n_points, n_anchors), "defined" (bool: the round trip came back, §4.4; elsewhere
    the weights are meaningless), "round_trip_error", "face_id", "barycentric" and, with
    ``anchor_uv``, "tcoords" (see inverse_average_data for the settings)."""
    data = inverse_average_data(surface, anchors, points, embedding, **settings)
    result = {
        "weights": point_array(data, "Weights"),
        "defined": point_array(data, "Defined")[:, 0] != 0,
        "round_trip_error": point_array(data, "RoundTripError")[:, 0],
        "face_id": point_array(data, "FaceId")[:, 0].astype(np.int64),
        "barycentric": point_array(data, "Barycentric"),
    }
    if data.GetPointData().GetArray("TCoords") is not None:
        result["tcoords"] = point_array(data, "TCoords")
    return result


# --- curves, remeshing, transfer --------------------------------------------------------------

def curve_data(surface, controls, embedding=None, samples=None, closed=False,
               surface_tolerance=None, threads=None, output=None):
    """The ``barylab curve`` job (vtkBarySurfaceCurve): the uniform cubic B-spline on the
    surface with control points ``controls`` (on the surface, in curve order), as a vtkPolyData
    of samples and polylines with ``FaceId``, ``Barycentric``, ``Valid``."""
    filter_ = vtkBarySurfaceCurve()
    filter_.SetInputData(with_embedding(surface, embedding))
    filter_.SetControlPointsData(_surface_points(controls, "controls"))
    _set(filter_.SetSamplesPerSegment, samples, int)
    filter_.SetClosed(bool(closed))
    _set(filter_.SetSurfaceTolerance, surface_tolerance)
    _set(filter_.SetNumberOfThreads, threads, int)
    filter_.SetEmbeddingArrayName(EMBEDDING)
    run(filter_)
    return _finish(_copy(filter_.GetOutput()), output)


def curve(surface, controls, embedding=None, **settings):
    """The curve's samples as an (n_samples, 3) array, NaN where a sample failed (see
    curve_data)."""
    points, valid = _on_surface(curve_data(surface, controls, embedding, **settings))
    points[~valid] = np.nan
    return points


def _cells(data):
    """The polygons of a vtkPolyData as an (m, k) array (all of one size) or a list."""
    polys = data.GetPolys()
    offsets = numpy_support.vtk_to_numpy(polys.GetOffsetsArray()).astype(np.int64)
    connectivity = numpy_support.vtk_to_numpy(polys.GetConnectivityArray()).astype(np.int64)
    sizes = np.diff(offsets)
    if len(sizes) and np.all(sizes == sizes[0]):
        return connectivity.reshape(-1, int(sizes[0]))
    return [connectivity[offsets[i]:offsets[i + 1]] for i in range(len(sizes))]


def remesh_data(surface, coarse, embedding=None, levels=None, smooth=None,
                surface_tolerance=None, threads=None, output=None):
    """The ``barylab remesh`` job (vtkBarySurfaceRemesh): the semiregular quad mesh from the
    coarse quad layout ``coarse`` (a vtkPolyData of quads on the surface, or a file) after
    ``levels`` subdivisions and ``smooth`` smoothing steps, with ``FaceId``, ``Barycentric``,
    ``Valid``."""
    filter_ = vtkBarySurfaceRemesh()
    filter_.SetInputData(with_embedding(surface, embedding))
    filter_.SetCoarseMeshData(_surface(coarse, "coarse quad layout"))
    _set(filter_.SetLevels, levels, int)
    _set(filter_.SetSmoothingSteps, smooth, int)
    _set(filter_.SetSurfaceTolerance, surface_tolerance)
    _set(filter_.SetNumberOfThreads, threads, int)
    filter_.SetEmbeddingArrayName(EMBEDDING)
    run(filter_)
    return _finish(_copy(filter_.GetOutput()), output)


def remesh(surface, coarse, embedding=None, **settings):
    """The quad mesh as (points (n, 3), NaN where a forward problem failed; quads (m, 4))
    (see remesh_data)."""
    data = remesh_data(surface, coarse, embedding, **settings)
    points, valid = _on_surface(data)
    points[~valid] = np.nan
    return points, _cells(data)


def _transfer(source, source_anchors, target, target_anchors, source_embedding, target_embedding,
              arrays, gamma, round_trip_tolerance, surface_tolerance, threads):
    src = with_embedding(source, source_embedding)
    filter_ = vtkBarySurfaceCorrespondence()
    if isinstance(arrays, dict):
        src = _copy(src)
        for name, values in arrays.items():
            v = np.asarray(values, dtype=np.float64)
            if v.shape[0] != src.GetNumberOfPoints():
                raise BaryLabError(f"array '{name}' has {v.shape[0]} rows but the source has "
                                   f"{src.GetNumberOfPoints()} points")
            src.GetPointData().AddArray(_vtk_array(v, name))
    for name in (arrays or []):
        filter_.AddArrayName(str(name))
    filter_.SetInputData(0, with_embedding(target, target_embedding))
    filter_.SetTargetAnchorsData(_surface_points(target_anchors, "target anchors"))
    filter_.SetSourceData(src)
    filter_.SetSourceAnchorsData(_surface_points(source_anchors, "source anchors"))
    filter_.SetEmbeddingArrayName(EMBEDDING)
    _set(filter_.SetGamma, gamma)
    _set(filter_.SetRoundTripTolerance, round_trip_tolerance)
    _set(filter_.SetSurfaceTolerance, surface_tolerance)
    _set(filter_.SetNumberOfThreads, threads, int)
    run(filter_)
    figures = {
        "undefined": filter_.GetNumberOfUndefined(),
        "flipped": filter_.GetNumberOfFlipped(),
        "flipped_area_fraction": filter_.GetFlippedAreaFraction(),
        "stretch_all": filter_.GetStretch(),
        "stretch_best95": filter_.GetStretchBest95(),
    }
    return _copy(filter_.GetOutput()), figures


def transfer_data(source, source_anchors, target, target_anchors, source_embedding=None,
                  target_embedding=None, arrays=None, gamma=None, round_trip_tolerance=None,
                  surface_tolerance=None, threads=None, output=None):
    """The ``barylab transfer`` job (vtkBarySurfaceCorrespondence) as a vtkPolyData: the target
    with the source's point arrays transferred through corresponding anchors (NaN where
    undefined), ``Defined``, ``SourcePosition``, ``SourceFaceId``, ``SourceBarycentric``,
    ``RoundTripError``; cell data ``Stretch``, ``Flipped``. ``arrays``: names of the source's
    point arrays to transfer (default: all but the embedding), or a dict name ->
    (n_source_points, k) array, attached to the source and transferred."""
    data, _ = _transfer(source, source_anchors, target, target_anchors, source_embedding,
                        target_embedding, arrays, gamma, round_trip_tolerance,
                        surface_tolerance, threads)
    return _finish(data, output)


def morph_frames(transferred, frames):
    """The ``barylab transfer --morph N`` frames: the target's points moved linearly to their
    images on the source (``SourcePosition``) in ``frames`` + 1 steps, t = f / frames; undefined
    points stay put. An (frames + 1, n_points, 3) array."""
    if int(frames) < 1:
        raise BaryLabError(f"a morph needs at least 1 frame, got {frames}")
    X = points_of(transferred)
    Y = point_array(transferred, "SourcePosition")
    Y = np.where(np.isnan(Y), X, Y)
    t = np.arange(int(frames) + 1, dtype=np.float64) / int(frames)
    return (1 - t)[:, None, None] * X[None] + t[:, None, None] * Y[None]


def transfer(source, source_anchors, target, target_anchors, source_embedding=None,
             target_embedding=None, arrays=None, gamma=None, round_trip_tolerance=None,
             surface_tolerance=None, threads=None, morph=None, morph_dir=None, output=None):
    """Transfer of point data from ``source`` to ``target`` (see transfer_data): a dict with
    "arrays" (name -> (n_target_points, k) array, NaN where undefined), "defined" (bool),
    "source_position" (n_target_points, 3), "stretch" and "flipped" (per target triangle), the
    figures "undefined", "flipped", "flipped_area_fraction", "stretch_all" and "stretch_best95"
    (the symmetric L2 stretch over all triangles and the best 95 %), and "data" (the
    vtkPolyData). ``morph`` = N adds "morph": morph_frames(data, N), written with ``morph_dir``
    as morph_000.vtp ... and morph.pvd, as ``barylab transfer --morph N --morph-dir``."""
    target = _surface(target, "target")
    data, figures = _transfer(source, source_anchors, target, target_anchors, source_embedding,
                              target_embedding, arrays, gamma, round_trip_tolerance,
                              surface_tolerance, threads)
    _finish(data, output)
    fixed = {"Defined", "SourcePosition", "SourceFaceId", "SourceBarycentric", "RoundTripError",
             EMBEDDING}
    pd = data.GetPointData()
    names = [pd.GetArrayName(i) for i in range(pd.GetNumberOfArrays())]
    target_names = {target.GetPointData().GetArrayName(i)
                    for i in range(target.GetPointData().GetNumberOfArrays())}
    result = dict(figures)
    result["arrays"] = {n: point_array(data, n) for n in names
                        if n not in fixed and n not in target_names}
    result["defined"] = point_array(data, "Defined")[:, 0] != 0
    result["source_position"] = point_array(data, "SourcePosition")
    cd = data.GetCellData()
    result["stretch"] = numpy_support.vtk_to_numpy(cd.GetArray("Stretch")).astype(np.float64)
    result["flipped"] = numpy_support.vtk_to_numpy(cd.GetArray("Flipped")) != 0
    result["data"] = data
    if morph is not None:
        frames = morph_frames(data, morph)
        result["morph"] = frames
        if morph_dir is not None:
            series = []
            for F in frames:
                frame = vtkPolyData()
                frame.ShallowCopy(data)
                frame.SetPoints(polydata(F).GetPoints())
                series.append(frame)
            result["morph_pvd"] = write_time_series(series, morph_dir, "morph", 1.0)
    return result
